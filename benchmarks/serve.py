"""Latency, throughput and memory of ``exprclone serve``'s POST /api/clone, on the real server.

    python benchmarks/serve.py [--data ../shared/data] [--requests 60] [--workers 2]
    python benchmarks/serve.py --scheduler [--data ../shared/data] [--requests 60]

Starts the server (``--workers``), then at 512 and 1350 pixels sends London pairs of
photos (20 ordered pairs of different people, seed 0; at 512 the photos are shrunk and
re-encoded as JPEG at quality 95):

- first sight: each pair once, by one client, photos the server has not seen (their
  landmarks are detected);
- then ``--requests`` requests by 1, 2 and 4 concurrent clients, cycling through the
  same pairs (the server remembers the landmarks of photos it has seen: the case of a
  portrait cloned with many expressions).

It prints p50 and p95 latency, throughput and errors, and the server's memory (its own
process and its workers, resident) before and after 200 more requests. Beside the one-client
run at 1350 pixels, the peer is measured in turn with the requests (so that both see the same
load): the naive scikit-image warp of the same target photo, ``PiecewiseAffineTransform``
estimated on the clone's mesh (landmarks, forehead and border points) and
``skimage.transform.warp`` of the whole photo (bilinear), as :mod:`run` measures it; the ratio
of the server's p50 to the peer's median is printed.

With ``--scheduler``, the server on a Dask cluster (``serve --scheduler``), each started as
the deploy docs say (``dask scheduler``, ``dask worker --nworkers N --nthreads 1``), on this
machine: a cluster of 1 worker process and one of 2, each with a server, and beside them
the plain server with 1 worker and with 2, its peer. At each size, once the workers have
seen the photos (a worker remembers their landmarks: the clusters' each told to place them,
the plain servers' after passes over the pairs), it prints:

- the latency of one client's requests, sent in turn to the plain server and to the
  server on the cluster, 1 worker each (so that both see the same load), and the ratio
  of their p50s;
- the throughput of 4 concurrent clients on each server, in turns of ``--requests``
  requests (3 turns each), and for each kind the ratio of 2 workers' to 1's: the plain
  server's says what this machine allows;
- beside each throughput, the CPU time a request took in each part: the server (its web
  process, and the plain server's workers), and the cluster's scheduler and workers (the
  ``dask worker`` command's processes): on 2 cores, what the parts other than the workers
  take is what 2 workers cannot have.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import numpy as np
from PIL import Image

from exprclone.data import sets as datasets

SIZES = (512, 1350)
CLIENTS = (1, 2, 4)
PAIRS = 20
MEMORY_REQUESTS = 200
#: ``--scheduler``: the concurrent clients whose throughput is measured, the turns of each server, and the passes over
#: the pairs before the plain server of 2 workers is measured.
CLUSTER_CLIENTS, CLUSTER_TURNS, PLAIN_PASSES = 4, 3, 4


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def children(pid: int) -> list[int]:
    """The child processes of a process, whichever of its threads started them (from /proc)."""
    return [int(c) for task in Path(f"/proc/{pid}/task").iterdir() for c in (task / "children").read_text().split()]


def resident_mb(pid: int) -> float:
    """Resident memory of a process and all its descendants, in MB (from /proc)."""
    rss = next(int(line.split()[1]) for line in Path(f"/proc/{pid}/status").read_text().splitlines() if line.startswith("VmRSS"))
    return rss / 1024 + sum(resident_mb(c) for c in children(pid))


def cpu_seconds(pid: int) -> float:
    """CPU time (user and system) of a process and all its live descendants, in seconds (from /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    own = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return own + sum(cpu_seconds(c) for c in children(pid))


def payloads(data: Path, size: int) -> list[dict]:
    """The multipart files of PAIRS ordered pairs of different London people at ``size`` pixels."""
    ids = sorted(p.name[:3] for p in (data / "london" / "neutral_front").glob("*_03.jpg"))
    every = [(a, b) for a in ids for b in ids if a != b]
    chosen = [every[i] for i in np.random.default_rng(0).choice(len(every), PAIRS, replace=False)]

    def photo(face: str, smile: bool = False) -> bytes:
        path = data / "london" / ("smiling_front" if smile else "neutral_front") / f"{face}_{'08' if smile else '03'}.jpg"
        if size == 1350:
            return path.read_bytes()
        out = io.BytesIO()
        Image.open(path).convert("RGB").resize((size, size), Image.LANCZOS).save(out, "JPEG", quality=95)
        return out.getvalue()

    return [
        {
            "source_neutral": ("a.jpg", photo(a, False)),
            "source_expression": ("b.jpg", photo(a, True)),
            "target_neutral": ("c.jpg", photo(b, False)),
        }
        for a, b in chosen
    ]


def run(url: str, files: list[dict], requests: int, clients: int) -> tuple[list[float], int, float]:
    """``requests`` POST /api/clone by ``clients`` threads; latencies (ms), errors, wall time (s)."""
    with httpx.Client(base_url=url, timeout=300, limits=httpx.Limits(max_connections=clients)) as client:

        def one(k: int) -> tuple[float, bool]:
            start = time.perf_counter()
            r = client.post("/api/clone", files=files[k % len(files)])
            return 1000 * (time.perf_counter() - start), r.status_code == 200 and r.content[:4] == b"\x89PNG"

        start = time.perf_counter()
        with ThreadPoolExecutor(clients) as pool:
            done = list(pool.map(one, range(requests)))
        wall = time.perf_counter() - start
    return [ms for ms, _ in done], sum(not ok for _, ok in done), wall


def with_peer(url: str, files: list[dict], requests: int, data: Path) -> tuple[list[float], int, float, list[float]]:
    """One client's requests, each followed by the peer (:func:`run.skimage_peer` on the first pair's target photo):
    latencies (ms), errors, the requests' wall time (s), the peer's times (ms)."""
    from run import skimage_peer

    from exprclone.io.images import load_image
    from exprclone.landmarks.backends import default_detector

    target = load_image(files[0]["target_neutral"][1])
    peer_warp = skimage_peer(target, default_detector().detect(target))
    latencies, peer, errors, wall = [], [], 0, 0.0
    for k in range(requests):
        ms, bad, seconds = run(url, files[k % len(files) :], 1, 1)
        latencies += ms
        errors, wall = errors + bad, wall + seconds
        start = time.perf_counter()
        peer_warp()
        peer.append(1000 * (time.perf_counter() - start))
    return latencies, errors, wall, peer


def line(name: str, latencies: list[float], errors: int, wall: float) -> str:
    p50, p95 = np.percentile(latencies, [50, 95])
    return f"  {name:34s} p50 {p50:6.0f} ms  p95 {p95:6.0f} ms  {len(latencies) / wall:5.2f} requests/s  errors {errors}"


@contextlib.contextmanager
def serving(*flags: str) -> Iterator[tuple[int, str]]:
    """``exprclone serve FLAGS`` on a free port, until the block ends (then Ctrl-C): its PID and URL once it answers."""
    port = free_port()
    # (what it prints, its address, would come among the figures; its errors do come, on stderr)
    server = subprocess.Popen([sys.executable, "-m", "exprclone", "serve", "--port", str(port), *flags], stdout=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}"
    try:
        while True:
            try:
                httpx.get(f"{url}/api/health", timeout=1)
                break
            except httpx.TransportError:
                time.sleep(0.2)
        yield server.pid, url
    finally:
        os.kill(server.pid, signal.SIGINT)
        server.wait(timeout=60)


@contextlib.contextmanager
def dask_cluster(workers: int) -> Iterator[tuple[str, dict[str, int]]]:
    """``dask scheduler`` and ``dask worker --nworkers WORKERS --nthreads 1`` on this machine, until the block ends: the
    scheduler's address once its workers have joined, and the PIDs of the two commands by name."""
    from distributed import Client

    address = f"tcp://127.0.0.1:{free_port()}"
    dask = [sys.executable, "-m", "dask"]
    started = [subprocess.Popen([*dask, "scheduler", "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1], "--no-dashboard"])]
    try:
        started.append(subprocess.Popen([*dask, "worker", address, "--nworkers", str(workers), "--nthreads", "1", "--no-dashboard"]))
        with Client(address, timeout=60) as client:
            client.wait_for_workers(workers, timeout=120)
        yield address, {"scheduler": started[0].pid, "workers": started[1].pid}
    finally:
        for process in reversed(started):
            process.send_signal(signal.SIGINT)
            process.wait(timeout=60)


def seen(address: str, files: list[dict]) -> None:
    """Every worker of the cluster at ``address`` places the landmarks of the photos of ``files`` as a clone does (and
    remembers them): a source photo's face, every face of a target photo."""
    from distributed import Client

    from exprclone.io.inputs import Source
    from exprclone.landmarks.backends import DEFAULT
    from exprclone.server import work

    uploads = [Source(field, content) for photos in files for field, (_, content) in photos.items()]
    with Client(address, timeout=60) as client:
        client.run(lambda: [(work.faces if u.name == "target_neutral" else work.landmarks)(u, None, DEFAULT) for u in uploads])


def on_clusters(args: argparse.Namespace) -> None:
    """The ``--scheduler`` benchmark (see the module's notes)."""
    with contextlib.ExitStack() as stack:
        (one, one_pids), (two, two_pids) = [stack.enter_context(dask_cluster(n)) for n in (1, 2)]
        flags = ("--max-live", "0", "--queue", "8")
        started = {
            ("plain server", 1): stack.enter_context(serving("--workers", "1", *flags)),
            ("plain server", 2): stack.enter_context(serving("--workers", "2", *flags)),
            ("cluster", 1): stack.enter_context(serving("--scheduler", one, "--workers", "1", *flags)),
            ("cluster", 2): stack.enter_context(serving("--scheduler", two, "--workers", "2", *flags)),
        }
        servers = {key: url for key, (_, url) in started.items()}
        # whose CPU time each server's requests take: the server's process tree (with the plain server's workers), and
        # the cluster's scheduler and workers
        tasks = {key: {"server": pid} for key, (pid, _) in started.items()}
        tasks["cluster", 1].update(one_pids)
        tasks["cluster", 2].update(two_pids)
        print(f"exprclone serve --scheduler benchmark: {os.cpu_count()} cores, POST /api/clone (e+md, PNG answer)")
        for size in SIZES:
            files = payloads(args.data, size)
            print(f"\n{size}x{size} photos")
            run(servers["plain server", 1], files, len(files), 1)
            run(servers["plain server", 2], files, PLAIN_PASSES * len(files), CLUSTER_CLIENTS)  # (its pool's processes at random)
            for address in (one, two):
                seen(address, files)
            alone = {name: servers[name, 1] for name in ("plain server", "cluster")}
            latencies: dict[str, list[float]] = {name: [] for name in alone}
            for k in range(args.requests):
                for name, url in alone.items():
                    latencies[name] += run(url, files[k % len(files) :], 1, 1)[0]
            p50 = {name: np.percentile(ms, 50) for name, ms in latencies.items()}
            print(f"  1 client, in turn, 1 worker each: plain server p50 {p50['plain server']:.0f} ms, cluster {p50['cluster']:.0f} ms")
            print(f"  p50 on the cluster / on the plain server: {p50['cluster'] / p50['plain server']:.2f}x")
            done: dict[tuple[str, int], list[tuple[list[float], int, float]]] = {key: [] for key in servers}
            cpu: dict[tuple[str, int], dict[str, float]] = {key: dict.fromkeys(tasks[key], 0.0) for key in servers}
            for _ in range(CLUSTER_TURNS):
                for key, url in servers.items():
                    before = {role: cpu_seconds(pid) for role, pid in tasks[key].items()}
                    done[key].append(run(url, files, args.requests, CLUSTER_CLIENTS))
                    for role, pid in tasks[key].items():
                        cpu[key][role] += cpu_seconds(pid) - before[role]
            throughput = {}
            for (name, workers), turns in done.items():
                every = [ms for times, _, _ in turns for ms in times]
                errors, wall = sum(e for _, e, _ in turns), sum(w for _, _, w in turns)
                throughput[name, workers] = len(every) / wall
                print(line(f"{name}, {workers} worker{'s' * (workers > 1)}, {CLUSTER_CLIENTS} clients", every, errors, wall))
                print(f"    CPU a request: {', '.join(f'{role} {1000 * t / len(every):.0f} ms' for role, t in cpu[name, workers].items())}")
            ratios = [f"{name} {throughput[name, 2] / throughput[name, 1]:.2f}x" for name in alone]
            print(f"  throughput on 2 workers / on 1: {', '.join(ratios)}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--requests", type=int, default=60)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--scheduler", action="store_true", help="the server on Dask clusters of 1 and 2 workers, against the plain server")
    args = parser.parse_args()
    if args.scheduler:
        return on_clusters(args)
    with serving("--workers", str(args.workers)) as (pid, url):
        print(f"exprclone serve benchmark: {os.cpu_count()} cores, {args.workers} workers, POST /api/clone (e+md, PNG answer)")
        for size in SIZES:
            files = payloads(args.data, size)
            print(f"\n{size}x{size} photos")
            print(line("first sight, 1 client", *run(url, files, len(files), 1)))
            throughput = {}
            for clients in CLIENTS:
                if clients == 1 and size == 1350:
                    latencies, errors, wall, peer = with_peer(url, files, args.requests, args.data)
                    print(f"  peer, naive scikit-image warp of the target photo: median {np.median(peer):.0f} ms")
                    print(f"  p50 of one client / the peer: {np.percentile(latencies, 50) / np.median(peer):.2f}x")
                else:
                    latencies, errors, wall = run(url, files, args.requests, clients)
                throughput[clients] = len(latencies) / wall
                print(line(f"seen before, {clients} client{'s' * (clients > 1)}", latencies, errors, wall))
            print(f"  throughput with 4 clients / with 1: {throughput[4] / throughput[1]:.2f}x")
        before = resident_mb(pid)
        latencies, errors, wall = run(url, payloads(args.data, 1350), MEMORY_REQUESTS, 4)
        after = resident_mb(pid)
        print(f"\nmemory (server and workers, resident): {before:.0f} MB, then {after:.0f} MB after {MEMORY_REQUESTS} more at 1350 px")
        print(f"  ({100 * (after / before - 1):+.1f}%; those requests: {errors} errors)")


if __name__ == "__main__":
    main()
