"""End-to-end tests of clients/python/hexcover_client.py against the real hexcover-server.

usage: HEXCOVER_SERVER=path/to/hexcover-server python3 test_python_client.py
Exit status 0 pass, 1 fail, 77 when every test was skipped (the reason is printed).

The server runs on a free port (--port 0) with a fresh data directory. The input is an icosphere
that the test writes itself, so the test needs nothing beside the checkout.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
CLIENT_DIR = os.path.join(HERE, "..", "..", "clients", "python")
sys.path.insert(0, CLIENT_DIR)

try:
    import requests  # noqa: F401  (the client's one dependency: Debian python3-requests)
    import hexcover_client
except ImportError as error:  # pragma: no cover - reported as a skip with the reason
    hexcover_client = None
    IMPORT_ERROR = str(error)

SERVER = os.environ.get("HEXCOVER_SERVER", "")
JOB_TIMEOUT = 150.0


def write_icosphere(path: str, subdivisions: int = 3) -> tuple[int, int]:
    """Writes a unit icosphere as OBJ (V = 10·4^s + 2, F = 20·4^s); returns (V, F)."""
    t = (1 + math.sqrt(5)) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    vertices = [tuple(c / math.sqrt(1 + t * t) for c in v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoints: dict[tuple[int, int], int] = {}

        def midpoint(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = [(x + y) / 2 for x, y in zip(vertices[a], vertices[b])]
                norm = math.sqrt(sum(c * c for c in m))
                vertices.append(tuple(c / norm for c in m))
                midpoints[key] = len(vertices) - 1
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    with open(path, "w") as out:
        out.writelines(f"v {x:.9f} {y:.9f} {z:.9f}\n" for x, y, z in vertices)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    return len(vertices), len(faces)


def obj_counts(path: str) -> tuple[int, int, int]:
    """(vertices, faces, texture coordinates) of an OBJ file."""
    counts = {"v": 0, "f": 0, "vt": 0}
    with open(path) as f:
        for line in f:
            key = line.split(" ", 1)[0]
            if key in counts:
                counts[key] += 1
    return counts["v"], counts["f"], counts["vt"]


class ServerProcess:
    """hexcover-server on a free port with a fresh data directory."""

    def __init__(self, binary: str):
        self.data_dir = tempfile.mkdtemp(prefix="hexcover-py-")
        self.process = subprocess.Popen(
            [binary, "--port", "0", "--host", "127.0.0.1", "--data-dir", self.data_dir],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.log = []
        deadline = time.monotonic() + 20
        port = None
        while port is None:
            line = self.process.stdout.readline()
            if not line:
                raise RuntimeError("server exited:\n" + "".join(self.log))
            self.log.append(line)
            match = re.search(r'"port"\s*:\s*(\d+)', line)
            if match and "listening" in line:
                port = int(match.group(1))
            if time.monotonic() > deadline:
                raise RuntimeError("server did not report its port:\n" + "".join(self.log))
        self.url = f"http://127.0.0.1:{port}"
        while True:
            try:
                with urllib.request.urlopen(self.url + "/readyz", timeout=2) as response:
                    if response.status == 200:
                        break
            except OSError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError("server never became ready")
            time.sleep(0.1)

    def stop(self) -> int:
        self.process.send_signal(signal.SIGTERM)
        try:
            code = self.process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            code = self.process.wait()
        self.process.stdout.close()
        shutil.rmtree(self.data_dir, ignore_errors=True)
        return code


@unittest.skipIf(hexcover_client is None, f"the client cannot be imported: "
                 f"{globals().get('IMPORT_ERROR')} (install Debian's python3-requests)")
class PythonClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not SERVER or not os.path.exists(SERVER):
            raise unittest.SkipTest(f"HEXCOVER_SERVER ({SERVER!r}) is not a built hexcover-server")
        cls.server = ServerProcess(SERVER)
        cls.work = tempfile.mkdtemp(prefix="hexcover-py-work-")
        cls.mesh = os.path.join(cls.work, "icosphere.obj")
        cls.input_counts = write_icosphere(cls.mesh)

    def setUp(self):
        self.client = hexcover_client.Client(self.server.url)
        self.addCleanup(self.client.close)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)
        code = cls.server.stop()
        if code != 0:
            raise AssertionError(f"server exited with {code} after SIGTERM")

    def run_cli(self, *args: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, os.path.join(CLIENT_DIR, "hexcover_client.py"), "--url", self.server.url,
             *args], capture_output=True, text=True, timeout=JOB_TIMEOUT + 30)

    def test_cli_remesh_downloads_results_and_prints_the_metrics(self):
        out = os.path.join(self.work, "cli")
        result = self.run_cli("remesh", self.mesh, "--vertices", "300", "--out", out,
                              "--formats", "obj,ply,glb", "--timeout", str(JOB_TIMEOUT))
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertRegex(result.stderr, r"job \S+: succeeded")
        printed = json.loads(result.stdout)

        # The printed metrics are the service's metrics document for this job.
        job_id = re.search(r"submitted \S+ as job (\S+)", result.stderr).group(1)
        client = self.client
        self.assertEqual(printed, client.metrics(job_id))

        # The downloaded triangle mesh is the one the metrics describe.
        leaves = dict(_leaves(printed))
        vertices, faces, _ = obj_counts(os.path.join(out, "icosphere-triangles.obj"))
        self.assertEqual(vertices, _leaf(leaves, "vertices"))
        self.assertEqual(faces, _leaf(leaves, "faces"))
        # The textured result is the input with per-corner texture coordinates.
        textured = os.path.join(out, "icosphere-textured.obj")
        if os.path.exists(textured):
            tv, tf, tvt = obj_counts(textured)
            self.assertEqual((tv, tf), self.input_counts)
            self.assertGreater(tvt, 0)
        # Every requested format the job offers was written, and is not empty.
        offered = {(r["mesh"], r["format"]) for r in client.job(job_id)["links"]["results"]}
        for mesh in ("triangles", "hexagons", "textured"):
            for fmt in ("obj", "ply", "glb"):
                path = os.path.join(out, f"icosphere-{mesh}.{fmt}")
                self.assertEqual(os.path.exists(path), (mesh, fmt) in offered, path)
                if os.path.exists(path):
                    self.assertGreater(os.path.getsize(path), 0, path)
        with open(os.path.join(out, "icosphere-triangles.glb"), "rb") as glb:
            self.assertEqual(glb.read(4), b"glTF")

    def test_cli_remesh_prints_the_warnings_on_stderr(self):
        # 5 vertices are fewer than a closed lattice of the sphere takes: the count is missed.
        result = self.run_cli("remesh", self.mesh, "--vertices", "5", "--timeout", str(JOB_TIMEOUT))
        self.assertEqual(result.returncode, 0, result.stderr)
        warnings = json.loads(result.stdout)["warnings"]
        self.assertTrue(warnings)
        for warning in warnings:
            self.assertIn(f"warning: {warning}\n", result.stderr)

    def test_module_reports_progress_until_success(self):
        client = self.client
        job = client.submit(self.mesh, edge_length=0.25)
        self.assertIn(job["state"], ("queued", "running", "succeeded"))
        updates = []
        final = client.wait(job["id"], on_progress=updates.append, timeout=JOB_TIMEOUT)
        self.assertEqual(final["state"], "succeeded")
        self.assertEqual(updates[-1]["state"], "succeeded")
        progress = [u["progress"] for u in updates if u["state"] == "running"]
        self.assertEqual(progress, sorted(progress), "progress never goes back")
        self.assertTrue(all(0.0 <= p <= 1.0 for p in progress))

    def test_idempotency_key_returns_the_same_job(self):
        client = self.client
        first = client.submit(self.mesh, idempotency_key="py-client-test", vertices=200)
        again = client.submit(self.mesh, idempotency_key="py-client-test", vertices=200)
        self.assertEqual(first["id"], again["id"])
        client.cancel(first["id"])

    def test_bad_option_is_a_problem_naming_it(self):
        client = self.client
        with self.assertRaises(hexcover_client.HexcoverError) as caught:
            client.submit(self.mesh, rosy=5)
        self.assertEqual(caught.exception.problem["status"], 400)
        self.assertIn("rosy", json.dumps(caught.exception.problem))

    def test_cli_exit_status_and_message_for_a_refused_file(self):
        junk = os.path.join(self.work, "junk.obj")
        with open(junk, "w") as f:
            f.write("this is not a mesh\n")
        result = self.run_cli("remesh", junk, "--timeout", "60")
        self.assertEqual(result.returncode, 1, result.stdout)
        self.assertRegex(result.stderr, r"hexcover: 4\d\d ")
        self.assertEqual(result.stdout, "")

    def test_cli_usage_error(self):
        result = self.run_cli("remesh", self.mesh, "--rosy", "5")
        self.assertEqual(result.returncode, 2)


def _leaves(value, prefix=""):
    if isinstance(value, dict):
        for key, child in value.items():
            yield from _leaves(child, f"{prefix}.{key}" if prefix else key)
    else:
        yield prefix, value


def _leaf(leaves: dict, name: str):
    """The value of the shallowest leaf called `name` (the triangle mesh's own counts)."""
    paths = sorted((p for p in leaves if p.split(".")[-1] == name), key=lambda p: p.count("."))
    if not paths:
        raise AssertionError(f"the metrics have no '{name}'")
    return leaves[paths[0]]


if __name__ == "__main__":
    program = unittest.main(exit=False, verbosity=2)
    outcome = program.result
    if not outcome.wasSuccessful():
        sys.exit(1)
    if outcome.testsRun == 0 or len(outcome.skipped) == outcome.testsRun:
        print("SKIPPED: " + "; ".join(sorted({reason for _, reason in outcome.skipped})))
        sys.exit(77)
