#!/usr/bin/env python3
"""Client of the hexcover remeshing service (HTTP API v1), as a module and a command-line program.

Module::

    from hexcover_client import Client
    with Client("http://localhost:8080") as client:
        job = client.submit("bunny.obj", vertices=5000)
        job = client.wait(job["id"], on_progress=print)
        client.download(job["id"], "remesh.obj", mesh="triangles", format="obj")
        print(client.metrics(job["id"])["hausdorff_pct"])

Command line (metrics go to stdout as JSON, progress to stderr)::

    hexcover_client.py --url http://localhost:8080 remesh bunny.obj --vertices 5000 --out results/
    hexcover_client.py status JOB_ID | metrics JOB_ID | download JOB_ID FILE | cancel JOB_ID

Exit status: 0 success, 1 the service refused the request or the job failed, 2 bad usage.
Needs only Debian's python3-requests.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any, Callable, Iterable, Optional
from urllib.parse import quote

import requests

TERMINAL_STATES = frozenset({"succeeded", "failed", "canceled"})
RESULT_MESHES = ("triangles", "quads", "hexagons", "textured")
RESULT_FORMATS = ("obj", "ply", "off", "stl", "glb")
OPTION_NAMES = ("edge_length", "vertices", "rosy", "sizing", "placement", "feature_angle",
                "d_sing")


class HexcoverError(Exception):
    """A refused request or a failed job; `problem` is the RFC 9457 problem document."""

    def __init__(self, problem: dict[str, Any]):
        self.problem = problem
        title = problem.get("title") or "error"
        detail = problem.get("detail")
        status = problem.get("status")
        text = f"{status} {title}" if status else title
        super().__init__(f"{text}: {detail}" if detail else text)


def _problem_of(response: requests.Response) -> dict[str, Any]:
    try:
        problem = response.json()
        if isinstance(problem, dict):
            problem.setdefault("status", response.status_code)
            return problem
    except ValueError:
        pass
    return {"status": response.status_code, "title": response.reason}


class Client:
    """One service at `base_url`; `timeout` bounds each HTTP request (seconds)."""

    def __init__(self, base_url: str = "http://localhost:8080", timeout: float = 60.0):
        self.base_url = base_url.rstrip("/")
        self.timeout = timeout
        self.session = requests.Session()
        self.session.headers["Accept"] = "application/json"

    def close(self) -> None:
        """Closes the pooled connections."""
        self.session.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    def _url(self, path: str) -> str:
        return self.base_url + path

    def _job_path(self, job_id: str, suffix: str = "") -> str:
        return f"/v1/jobs/{quote(job_id, safe='')}{suffix}"

    def _get_json(self, path: str, **params: Any) -> Any:
        response = self.session.get(self._url(path), params=params or None, timeout=self.timeout)
        if not response.ok:
            raise HexcoverError(_problem_of(response))
        return response.json()

    def submit(self, mesh_path: str, idempotency_key: Optional[str] = None, **options: Any) -> dict:
        """Uploads a mesh file (streamed as the raw body; the server detects the format from the
        bytes) with options edge_length, vertices, rosy, sizing, placement, feature_angle, d_sing.
        Returns the job document."""
        unknown = set(options) - set(OPTION_NAMES)
        if unknown:
            raise ValueError(f"unknown option(s) {sorted(unknown)}; known: {OPTION_NAMES}")
        params = {name: value for name, value in options.items() if value is not None}
        headers = {"Content-Type": "application/octet-stream"}
        if idempotency_key:
            headers["Idempotency-Key"] = idempotency_key
        with open(mesh_path, "rb") as body:
            response = self.session.post(self._url("/v1/jobs"), params=params, data=body,
                                         headers=headers, timeout=self.timeout)
        if response.status_code not in (200, 202):
            raise HexcoverError(_problem_of(response))
        return response.json()

    def job(self, job_id: str) -> dict:
        """The job document: state, stage, progress, timings, links to the results."""
        return self._get_json(self._job_path(job_id))

    def wait(self, job_id: str, on_progress: Optional[Callable[[dict], None]] = None,
             poll_interval: float = 0.5, timeout: Optional[float] = None) -> dict:
        """Polls until the job is succeeded, failed or canceled; returns its last document.
        Raises HexcoverError with the job's problem when it failed, TimeoutError after `timeout`."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            job = self.job(job_id)
            if on_progress:
                on_progress(job)
            if job["state"] in TERMINAL_STATES:
                if job["state"] == "failed":
                    raise HexcoverError(job.get("error") or {"title": "job failed"})
                return job
            if deadline is not None and time.monotonic() > deadline:
                raise TimeoutError(f"job {job_id} is still {job['state']} after {timeout} s")
            time.sleep(poll_interval)

    def metrics(self, job_id: str) -> dict:
        """The quality metrics of a succeeded job."""
        return self._get_json(self._job_path(job_id, "/metrics"))

    def download(self, job_id: str, destination: str, mesh: str = "triangles",
                 format: str = "obj") -> int:
        """Streams one result to `destination`; returns the number of bytes written."""
        response = self.session.get(self._url(self._job_path(job_id, "/result")),
                                    params={"mesh": mesh, "format": format},
                                    stream=True, timeout=self.timeout)
        with response:
            if not response.ok:
                raise HexcoverError(_problem_of(response))
            written = 0
            partial = destination + ".part"
            with open(partial, "wb") as out:
                for chunk in response.iter_content(chunk_size=1 << 16):
                    out.write(chunk)
                    written += len(chunk)
            os.replace(partial, destination)
        return written

    def cancel(self, job_id: str) -> None:
        """Cancels a queued or running job, or deletes a finished one and its files."""
        response = self.session.delete(self._url(self._job_path(job_id)), timeout=self.timeout)
        if not response.ok:
            raise HexcoverError(_problem_of(response))


# ---- command line --------------------------------------------------------------------------

def _progress_line(job: dict) -> str:
    parts = [job["state"]]
    if job.get("stage"):
        parts.append(job["stage"])
    if job["state"] == "running":
        parts.append(f"{100 * job.get('progress', 0):.0f}%")
    if job["state"] == "queued" and job.get("queue_position") is not None:
        parts.append(f"queue position {job['queue_position']}")
    return f"job {job['id']}: " + " · ".join(parts)


def _available(job: dict, meshes: Iterable[str], formats: Iterable[str]) -> list[tuple[str, str]]:
    offered = {(r["mesh"], r["format"]) for r in job.get("links", {}).get("results", [])}
    return [(m, f) for m in meshes for f in formats if (m, f) in offered]


def _remesh(client: Client, args: argparse.Namespace) -> int:
    options = {"edge_length": args.edge_length, "vertices": args.vertices, "rosy": args.rosy,
               "sizing": args.sizing, "placement": args.placement,
               "feature_angle": args.feature_angle, "d_sing": args.d_sing}
    job = client.submit(args.mesh, idempotency_key=args.idempotency_key, **options)
    print(f"submitted {args.mesh} as job {job['id']}", file=sys.stderr)
    last = [""]

    def report(update: dict) -> None:
        line = _progress_line(update)
        if line != last[0]:
            print(line, file=sys.stderr)
            last[0] = line

    job = client.wait(job["id"], on_progress=report, timeout=args.timeout)
    if job["state"] != "succeeded":
        print(f"job {job['id']} was {job['state']}", file=sys.stderr)
        return 1
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        stem = os.path.splitext(os.path.basename(args.mesh))[0]
        for mesh, fmt in _available(job, args.meshes.split(","), args.formats.split(",")):
            path = os.path.join(args.out, f"{stem}-{mesh}.{fmt}")
            size = client.download(job["id"], path, mesh=mesh, format=fmt)
            print(f"wrote {path} ({size} bytes)", file=sys.stderr)
    metrics = client.metrics(job["id"])
    for warning in metrics.get("warnings", []):
        print(f"warning: {warning}", file=sys.stderr)
    json.dump(metrics, sys.stdout, indent=2)
    print()
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description="Client of the hexcover remeshing service.")
    parser.add_argument("--url", default=os.environ.get("HEXCOVER_URL", "http://localhost:8080"),
                        help="service URL (default $HEXCOVER_URL or http://localhost:8080)")
    commands = parser.add_subparsers(dest="command", required=True)

    remesh = commands.add_parser("remesh", help="upload a mesh, wait, download results, print metrics")
    remesh.add_argument("mesh", help="OBJ, OFF, PLY or STL file")
    target = remesh.add_mutually_exclusive_group()
    target.add_argument("--edge-length", type=float, help="target edge length (model units)")
    target.add_argument("--vertices", type=int, help="target number of output vertices")
    remesh.add_argument("--rosy", type=int, choices=(4, 6), help="6 triangles (default), 4 quads")
    remesh.add_argument("--sizing", choices=("uniform", "curvature"))
    remesh.add_argument("--placement", choices=("balanced", "on_surface"))
    remesh.add_argument("--feature-angle", type=float,
                        help="creases of at least this dihedral angle (degrees, default 70) are "
                             "followed; 0 turns this off")
    remesh.add_argument("--d-sing", type=float, help="singularity clustering distance")
    remesh.add_argument("--out", help="folder for the downloaded results (none: only metrics)")
    remesh.add_argument("--meshes", default="triangles,quads,hexagons,textured",
                        help="comma list of result meshes to download")
    remesh.add_argument("--formats", default="obj", help="comma list of formats (obj,ply,off,stl,glb)")
    remesh.add_argument("--idempotency-key", help="makes a retried submission return the same job")
    remesh.add_argument("--timeout", type=float, help="give up waiting after this many seconds")

    for name, text in (("status", "print the job document"), ("metrics", "print the metrics"),
                       ("cancel", "cancel or delete a job")):
        commands.add_parser(name, help=text).add_argument("job_id")
    download = commands.add_parser("download", help="download one result")
    download.add_argument("job_id")
    download.add_argument("file")
    download.add_argument("--mesh", choices=RESULT_MESHES, default="triangles")
    download.add_argument("--format", choices=RESULT_FORMATS, help="default: the file's extension")
    return parser


def main(argv: Optional[list[str]] = None) -> int:
    args = _parser().parse_args(argv)
    with Client(args.url) as client:
        return _run(client, args)


def _run(client: Client, args: argparse.Namespace) -> int:
    try:
        if args.command == "remesh":
            return _remesh(client, args)
        if args.command == "status":
            print(json.dumps(client.job(args.job_id), indent=2))
        elif args.command == "metrics":
            print(json.dumps(client.metrics(args.job_id), indent=2))
        elif args.command == "cancel":
            client.cancel(args.job_id)
        elif args.command == "download":
            fmt = args.format or os.path.splitext(args.file)[1].lstrip(".").lower()
            if fmt not in RESULT_FORMATS:
                print(f"cannot tell the format of {args.file}; pass --format", file=sys.stderr)
                return 2
            client.download(args.job_id, args.file, mesh=args.mesh, format=fmt)
        return 0
    except HexcoverError as error:
        print(f"hexcover: {error}", file=sys.stderr)
        return 1
    except (requests.ConnectionError, requests.Timeout, TimeoutError, OSError) as error:
        print(f"hexcover: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
