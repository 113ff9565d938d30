// Starts the real hexcover-server on a free port with a fresh data directory, for the end-to-end
// tests; the server picks the port itself (--port 0) and its "listening" log record names it.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

/** Exit status that ctest reports as "skipped" (SKIP_RETURN_CODE in tests/e2e/CMakeLists.txt). */
export const kSkipStatus = 77;

export function skip(reason) {
  console.log(`SKIPPED: ${reason}`);
  process.exit(kSkipStatus);
}

/** `--name value` pairs of the command line as an object. */
export function parseArgs(argv, required) {
  const args = {};
  for (let i = 0; i < argv.length; i += 2) {
    if (!argv[i].startsWith('--') || i + 1 >= argv.length) throw new Error(`bad argument ${argv[i]}`);
    args[argv[i].slice(2)] = argv[i + 1];
  }
  for (const name of required) if (!args[name]) throw new Error(`missing --${name}`);
  return args;
}

/**
 * Starts `binary` and resolves to { url, stop(), log() } once /readyz answers 200.
 * stop() sends SIGTERM and resolves to the exit code; the data directory is removed.
 */
export async function startServer(binary, { timeoutMs = 20000, extraArgs = [] } = {}) {
  if (!fs.existsSync(binary)) throw new Error(`server binary ${binary} does not exist`);
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'hexcover-e2e-'));
  const child = spawn(binary, ['--port', '0', '--host', '127.0.0.1', '--data-dir', dataDir, ...extraArgs], {
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let output = '';
  let exited = null;
  const exitPromise = new Promise((resolve) => child.on('exit', (code, signal) => {
    exited = { code, signal };
    resolve(exited);
  }));

  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`server did not report its port:\n${output}`)), timeoutMs);
    const onData = (chunk) => {
      output += chunk;
      const match = output.match(/"port"\s*:\s*(\d+)/);
      if (match && output.includes('listening')) {
        clearTimeout(timer);
        resolve(`http://127.0.0.1:${match[1]}`);
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    exitPromise.then((e) => reject(new Error(`server exited (${JSON.stringify(e)}):\n${output}`)));
  });

  const deadline = Date.now() + timeoutMs;
  for (;;) {
    const ready = await fetch(`${url}/readyz`).then((r) => r.status === 200, () => false);
    if (ready) break;
    if (Date.now() > deadline || exited) throw new Error(`server never became ready:\n${output}`);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }

  return {
    url,
    log: () => output,
    async stop() {
      if (!exited) child.kill('SIGTERM');
      const timer = setTimeout(() => child.kill('SIGKILL'), 15000);
      const result = await exitPromise;
      clearTimeout(timer);
      fs.rmSync(dataDir, { recursive: true, force: true });
      return result.code;
    },
  };
}
