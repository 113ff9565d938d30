// End-to-end test of the web front-end in headless Chromium (playwright-core, /usr/bin/chromium)
// against the real hexcover-server:
//   load the page, upload a mesh, wait for the job to succeed and the viewer to show it; check the
//   metrics table against GET /v1/jobs/{id}/metrics, the irregular-vertex counts computed by the
//   page against the metrics, every download link, and that both halves of the WebGL canvas show
//   a model; save a screenshot of the page; a second job at a vertex count too small for the mesh
//   lists its warnings.
// usage: node web.spec.mjs --server BIN --mesh MESH --screenshot PNG
// Exit status 0 pass, 1 fail, 77 skipped (no Chromium, or no test mesh: the message says which).

import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { parseArgs, skip, startServer } from './server_process.mjs';

const kChromium = '/usr/bin/chromium';
const kChromiumFlags = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
];
const kJobTimeoutMs = 150_000;
const kBackground = [0xf4, 0xf5, 0xf7]; // viewer.js kBackground

const args = parseArgs(process.argv.slice(2), ['server', 'mesh', 'screenshot']);
if (!fs.existsSync(kChromium)) skip(`${kChromium} is absent (install Debian's chromium, or run scripts/setup with HEXCOVER_BROWSER_TESTS=1)`);
if (!fs.existsSync(args.mesh)) skip(`test mesh ${args.mesh} is absent (../shared/meshes is not beside the checkout)`);
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  skip('playwright-core is not installed (run scripts/setup, which runs npm ci)');
}

/** Leaves of a JSON document as dotted paths; arrays of scalars are one leaf. */
function leaves(value, prefix = '', out = new Map()) {
  const scalarArray = Array.isArray(value) && value.every((x) => x === null || typeof x !== 'object');
  if (value !== null && typeof value === 'object' && !scalarArray) {
    for (const [key, child] of Object.entries(value)) leaves(child, prefix ? `${prefix}.${key}` : key, out);
  } else {
    out.set(prefix, value);
  }
  return out;
}

/** The shown text of a number agrees with the value to its 4 significant digits. */
function assertShownNumber(key, shown, value) {
  if (Number.isInteger(value)) return assert.equal(shown, String(value), key);
  const parsed = Number(shown);
  assert.ok(Math.abs(parsed - value) <= 5e-4 * Math.abs(value) + 1e-300, `${key}: shown ${shown}, metrics ${value}`);
}

/** Pixel statistics of a PNG, decoded by the browser itself in a blank page. */
async function pixelStatistics(context, png) {
  const page = await context.newPage();
  try {
    return await page.evaluate(async ({ base64, background }) => {
      const image = new Image();
      image.src = `data:image/png;base64,${base64}`;
      await image.decode();
      const canvas = document.createElement('canvas');
      canvas.width = image.width;
      canvas.height = image.height;
      const ctx = canvas.getContext('2d');
      ctx.drawImage(image, 0, 0);
      const { data } = ctx.getImageData(0, 0, image.width, image.height);
      // Per half (side by side: input left, remesh right): share of pixels that are not the
      // background, and the number of distinct colours (shading of a lit surface gives many).
      const halves = [0, 1].map(() => ({ covered: 0, total: 0, colours: new Set() }));
      for (let y = 0; y < image.height; ++y) {
        for (let x = 0; x < image.width; ++x) {
          const i = 4 * (y * image.width + x);
          const half = halves[x < image.width / 2 ? 0 : 1];
          half.total += 1;
          const off = Math.max(...[0, 1, 2].map((c) => Math.abs(data[i + c] - background[c])));
          if (off > 24) half.covered += 1;
          half.colours.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]);
        }
      }
      return halves.map((h) => ({ coverage: h.covered / h.total, colours: h.colours.size }));
    }, { base64: png.toString('base64'), background: kBackground });
  } finally {
    await page.close();
  }
}

const server = await startServer(path.resolve(args.server));
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'hexcover-chromium-'));
let context;
let failed = false;
try {
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: kChromium,
    args: kChromiumFlags,
    headless: true,
    viewport: { width: 1400, height: 860 },
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const pageErrors = [];
  page.on('pageerror', (error) => pageErrors.push(error.message));

  const response = await page.goto(`${server.url}/`);
  assert.equal(response.status(), 200, 'GET / serves the page');
  await page.setInputFiles('#mesh-file', args.mesh);
  await page.waitForFunction(() => document.getElementById('status').textContent.startsWith('Ready'), null, { timeout: 20_000 });
  const uploadStarted = Date.now();
  await page.click('#submit');

  // Success shows the results; failure or an error puts the message in #status.
  await page.waitForFunction(
    () => document.body.dataset.state === 'shown' || document.getElementById('status').classList.contains('error'),
    null, { timeout: kJobTimeoutMs, polling: 250 });
  const status = await page.textContent('#status');
  assert.equal(await page.getAttribute('body', 'data-state'), 'shown', `job did not succeed: ${status}`);
  console.log(`job done in ${((Date.now() - uploadStarted) / 1000).toFixed(1)} s: ${status}`);
  assert.equal(await page.evaluate(() => document.getElementById('upload-progress').value), 1);
  assert.equal(await page.evaluate(() => document.getElementById('job-progress').value), 1);
  const jobId = await page.getAttribute('body', 'data-job-id');

  // The metrics table shows every leaf of GET /v1/jobs/{id}/metrics, with the same value.
  const metrics = await (await fetch(`${server.url}/v1/jobs/${jobId}/metrics`)).json();
  const expected = leaves(metrics);
  const rows = await page.$$eval('#metrics tr', (trs) => trs.map((tr) => ({
    key: tr.dataset.key, value: tr.dataset.value, shown: tr.cells[1].textContent,
  })));
  assert.deepEqual(rows.map((r) => r.key).sort(), [...expected.keys()].sort(), 'table rows = metrics leaves');
  for (const row of rows) {
    const value = expected.get(row.key);
    assert.deepEqual(JSON.parse(row.value), value, row.key);
    if (typeof value === 'number') assertShownNumber(row.key, row.shown, value);
  }
  console.log(`metrics table: ${rows.length} rows agree with the metrics document`);

  // The warnings list shows the metrics' warnings, one item each, and is hidden without any.
  const warnings = await page.$$eval('#warnings li', (lis) => lis.map((li) => li.textContent));
  assert.deepEqual(warnings, metrics.warnings, 'warnings list = metrics warnings');
  assert.equal(await page.evaluate(() => document.getElementById('warnings').hidden), warnings.length === 0,
    'the warnings list is hidden exactly when there are none');
  console.log(`warnings: ${warnings.length} shown`);

  // The page's own valence count (from the downloaded OBJ) agrees with the server's.
  const countOf = async (id) => Number((await page.textContent(id)).split(':')[1]);
  const pageIrregular = (await countOf('#count-below')) + (await countOf('#count-above'));
  const irregularKeys = [...expected.keys()].filter((k) => k.endsWith('irregular_interior'));
  assert.ok(irregularKeys.length > 0, 'metrics name irregular_interior');
  const serverIrregular = expected.get(irregularKeys.sort((a, b) => a.length - b.length)[0]);
  assert.equal(pageIrregular, serverIrregular, `irregular vertices: page ${pageIrregular}, metrics ${serverIrregular}`);
  console.log(`irregular interior vertices: ${pageIrregular} (page) = ${serverIrregular} (metrics)`);

  // Every download link answers with a non-empty file.
  const links = await page.$$eval('#downloads a', (as) => as.map((a) => a.getAttribute('href')));
  assert.ok(links.length >= 5, `at least the five triangle formats are offered (got ${links.length})`);
  for (const href of links) {
    const download = await fetch(new URL(href, server.url));
    const bytes = (await download.arrayBuffer()).byteLength;
    assert.equal(download.status, 200, href);
    assert.ok(bytes > 0, `${href} is empty`);
  }
  console.log(`downloads: ${links.length} links answer 200 with content`);

  // Both halves of the canvas (input | remesh) show a lit model, not the bare background.
  await page.waitForTimeout(500);
  const stats = await pixelStatistics(context, await page.locator('#viewer').screenshot());
  console.log(`canvas: ${JSON.stringify(stats)}`);
  for (const [half, s] of [['input', stats[0]], ['remesh', stats[1]]]) {
    assert.ok(s.coverage > 0.03, `${half} half of the canvas is blank (coverage ${s.coverage})`);
    assert.ok(s.colours > 50, `${half} half of the canvas is flat (${s.colours} colours)`);
  }

  // The screenshot for the README: textured input beside the remesh's hexagonal dual.
  await page.check('#show-texture');
  await page.uncheck('#show-wireframe');
  await page.check('#show-dual');
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.waitForTimeout(500);
  fs.mkdirSync(path.dirname(args.screenshot), { recursive: true });
  await page.screenshot({ path: args.screenshot });
  console.log(`screenshot: ${args.screenshot}`);

  // A second job at 20 vertices, fewer than the shape allows: its warnings (the count missed,
  // and why) are listed above the metrics.
  // Submits the form again and waits until the page shows a job other than `previous`; returns
  // that job's id and metrics.
  const submitAgain = async (previous, what) => {
    await page.click('#submit');
    await page.waitForFunction(
      (shown) => (document.body.dataset.state === 'shown' && document.body.dataset.jobId !== shown) ||
        document.getElementById('status').classList.contains('error'),
      previous, { timeout: kJobTimeoutMs, polling: 250 });
    const id = await page.getAttribute('body', 'data-job-id');
    assert.notEqual(id, previous, `${what} did not succeed: ${await page.textContent('#status')}`);
    return { id, metrics: await (await fetch(`${server.url}/v1/jobs/${id}/metrics`)).json() };
  };
  await page.fill('#target-value', '20');
  const { id: coarseId, metrics: coarse } = await submitAgain(jobId, 'second job');
  const coarseWarnings = await page.$$eval('#warnings li', (lis) => lis.map((li) => li.textContent));
  assert.ok(coarse.warnings.length > 0, 'a remesh at 20 vertices has warnings');
  assert.deepEqual(coarseWarnings, coarse.warnings, 'warnings list = metrics warnings');
  assert.equal(await page.evaluate(() => document.getElementById('warnings').hidden), false);
  console.log(`warnings at 20 vertices: ${coarseWarnings.length} shown`);

  // A third job with quads (rosy 4): the viewer shows the quad remesh, and its valence counts
  // (3 and 5 around a regular 4) are the metrics' irregular vertices.
  await page.fill('#target-value', '');
  await page.selectOption('#rosy', '4');
  const { metrics: quadMetrics } = await submitAgain(coarseId, 'quad job');
  assert.ok(quadMetrics.quads > 0.9 * quadMetrics.faces, `mostly quads: ${quadMetrics.quads} of ${quadMetrics.faces}`);
  assert.ok((await page.textContent('#count-below')).startsWith('valence ≤3'), 'quads count valence 3 as below');
  const quadIrregular = (await countOf('#count-below')) + (await countOf('#count-above'));
  assert.equal(quadIrregular, quadMetrics.irregular_interior,
    `quad irregular vertices: page ${quadIrregular}, metrics ${quadMetrics.irregular_interior}`);
  console.log(`quads: ${quadMetrics.quads} of ${quadMetrics.faces} faces, ${quadIrregular} irregular vertices`);
  assert.deepEqual(pageErrors, [], 'no uncaught errors in the page');
  console.log('PASS');
} catch (error) {
  failed = true;
  console.error(`FAIL: ${error.stack ?? error}`);
  console.error(`--- server log ---\n${server.log().slice(-4000)}`);
} finally {
  await context?.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
  const code = await server.stop();
  if (code !== 0) {
    console.error(`server exited with ${code} after SIGTERM`);
    failed = true;
  }
}
process.exit(failed ? 1 : 0);
