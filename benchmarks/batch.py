"""Pairs per second of ``exprclone batch`` at 1350 pixels, against a loop of ``exprclone clone`` processes.

    python benchmarks/batch.py [--data ../shared/data] [--pairs 100] [--loop 10] [--large 1000]

On ordered pairs of different London people (seed 0), e+md, PNG outputs, measured in
the same run:

- the peer: a loop of ``exprclone clone`` processes (on ``--loop`` pairs);
- ``batch --jobs 1`` and ``batch --jobs 2`` on ``--pairs`` pairs;
- a Dask ``LocalCluster`` of 2 worker processes (``batch --scheduler``);
- ``batch --jobs 2`` on ``--large`` pairs: does time grow linearly, and memory stay flat?

Each batch run starts from an empty output folder and no landmark cache. Peak memory is
the largest resident size a worker process reached (sampled every 0.1 s).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from exprclone.data import sets as datasets


def pairs(data: Path, n: int) -> list[tuple[str, str]]:
    ids = sorted(p.name[:3] for p in (data / "london" / "neutral_front").glob("*_03.jpg"))
    every = [(a, b) for a in ids for b in ids if a != b]
    return [every[i] for i in sorted(np.random.default_rng(0).choice(len(every), n, replace=False))]


def photos(data: Path, a: str, b: str) -> list[str]:
    london = data / "london"
    return [
        str(london / "neutral_front" / f"{a}_03.jpg"),
        str(london / "smiling_front" / f"{a}_08.jpg"),
        str(london / "neutral_front" / f"{b}_03.jpg"),
    ]


def write_manifest(folder: Path, data: Path, chosen: list) -> Path:
    lines = ["source_neutral,source_expression,target_neutral,output"]
    lines += [",".join([*photos(data, a, b), f"{a}-{b}.png"]) for a, b in chosen]
    path = folder / "manifest.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def resident_mb(pid: int) -> float:
    status = Path(f"/proc/{pid}/status").read_text().splitlines()
    return next(int(line.split()[1]) for line in status if line.startswith("VmRSS")) / 1024


def descendants(pid: int) -> list[int]:
    children = []
    for task in Path(f"/proc/{pid}/task").glob("*"):  # a child started by any of the process's threads
        try:
            children += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            pass
    return children + [d for c in children for d in descendants(c)]


def timed(command: list[str], watch: int | None = None) -> tuple[float, float]:
    """Run a command; its wall time (s) and the peak resident memory (MB) of the largest process under ``watch``
    (by default the command's own workers)."""
    peak, done = {}, threading.Event()
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def sample():
        while not done.is_set():
            root = process.pid if watch is None else watch
            for pid in [p for p in descendants(root) if p != process.pid] or [root]:
                try:
                    peak[pid] = max(peak.get(pid, 0.0), resident_mb(pid))
                except (OSError, StopIteration):
                    pass
            time.sleep(0.1)

    sampler = threading.Thread(target=sample)
    sampler.start()
    code = process.wait()
    done.set()
    sampler.join()
    if code not in (0, 1):
        raise RuntimeError(f"{command[:4]} failed with status {code}")
    return time.perf_counter() - start, max(peak.values(), default=0.0)


def batch(data: Path, chosen: list, *extra: str, watch: int | None = None) -> tuple[float, float]:
    with tempfile.TemporaryDirectory() as folder:
        return timed([sys.executable, "-m", "exprclone", "batch", str(write_manifest(Path(folder), data, chosen)), *extra], watch)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--pairs", type=int, default=100)
    parser.add_argument("--loop", type=int, default=10)
    parser.add_argument("--large", type=int, default=1000)
    args = parser.parse_args()
    chosen = pairs(args.data, max(args.pairs, args.large))
    print(f"exprclone batch benchmark: {os.cpu_count()} cores, e+md at 1350 px, PNG outputs")
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        for k, (a, b) in enumerate(chosen[: args.loop]):
            subprocess.run(
                [sys.executable, "-m", "exprclone", "clone", *photos(args.data, a, b), "-o", f"{folder}/{k}.png"],
                check=True,
                capture_output=True,
            )
        loop = args.loop / (time.perf_counter() - start)
    print(f"  a loop of `exprclone clone` processes ({args.loop} pairs): {loop:5.2f} pairs/s (1.0x)")
    rates = {}
    for name, extra in (("batch --jobs 1", ("--jobs", "1")), ("batch --jobs 2", ("--jobs", "2"))):
        seconds, peak = batch(args.data, chosen[: args.pairs], *extra)
        rates[name] = args.pairs / seconds
        print(f"  {name} ({args.pairs} pairs): {rates[name]:5.2f} pairs/s ({rates[name] / loop:.1f}x), worker peak {peak:.0f} MB")
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as cluster:
        seconds, peak = batch(args.data, chosen[: args.pairs], "--scheduler", cluster.scheduler_address, watch=os.getpid())
    rate = args.pairs / seconds
    share = rate / rates["batch --jobs 2"]
    print(f"  Dask LocalCluster, 2 workers ({args.pairs} pairs): {rate:5.2f} pairs/s ({share:.0%} of --jobs 2), worker peak {peak:.0f} MB")
    seconds, peak = batch(args.data, chosen[: args.large], "--jobs", "2")
    each = f"{seconds / args.large * 1000:.0f} ms a pair"
    print(f"  batch --jobs 2 ({args.large} pairs): {args.large / seconds:5.2f} pairs/s, {each}, worker peak {peak:.0f} MB")


if __name__ == "__main__":
    main()
