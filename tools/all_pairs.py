"""Run every method on every ordered pair of people of the London Set; report failures.

    python tools/all_pairs.py [--data ../shared/data] [--jobs 2] [--limit N]

Source A's neutral and smiling photos and target B's neutral photo, for every A != B.
Landmarks are detected once per photo. Prints a line per failure and a summary: pairs
run, failures, pairs whose mesh needed unfolding, the distribution of the chosen lambda_k.
"""

import argparse
import collections
import functools
import multiprocessing
import os
import time
import warnings
from pathlib import Path

import numpy as np

from exprclone import METHODS, clone_methods
from exprclone.evaluation.london import Dataset
from exprclone.io.images import load_image
from exprclone.pipeline import default_detector


@functools.cache
def photo(path: str) -> np.ndarray:
    return load_image(path)


def run_pair(job):
    data, (a, b), landmarks = job
    paths = (data.path(a, False), data.path(a, True), data.path(b, False))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            results = clone_methods(*(photo(p) for p in paths), landmarks=tuple(landmarks[p] for p in paths))
        wrong = [m for m, r in results.items() if r.image.shape != photo(paths[2]).shape]
        return (
            a,
            b,
            f"output of the wrong size for {wrong}" if wrong else None,
            max(r.unfolded_points for r in results.values()),
            results["e+md"].lambda_k,
        )
    except Exception as e:  # a failure is counted, never hidden
        return a, b, f"{type(e).__name__}: {e}", 0, None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("EXPRCLONE_DATA", "../shared/data"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--limit", type=int, default=0, help="only the first N pairs (0: all)")
    args = parser.parse_args()
    data = Dataset.open(Path(args.data) / "london")
    landmarks = {p: default_detector().detect(photo(p), p) for i in data.ids for p in (data.path(i, False), data.path(i, True))}
    pairs = data.pairs(0, seed=0)
    if args.limit:
        pairs = pairs[: args.limit]
    start = time.time()
    failures, unfolded, lambdas = [], 0, collections.Counter()
    with multiprocessing.get_context("fork").Pool(args.jobs) as pool:
        jobs = [(data, pair, landmarks) for pair in pairs]
        for k, (a, b, error, n_unfolded, lam) in enumerate(pool.imap_unordered(run_pair, jobs, chunksize=4), 1):
            if error:
                failures.append((a, b, error))
                print(f"FAIL {a} -> {b}: {error}", flush=True)
            unfolded += n_unfolded > 0
            lambdas[lam] += 1
            if k % 200 == 0:
                print(f"{k}/{len(pairs)} pairs, {time.time() - start:.0f} s", flush=True)
    elapsed = time.time() - start
    print(f"{len(pairs)} ordered pairs x {len(METHODS)} methods in {elapsed:.0f} s:", end=" ")
    print(f"{len(failures)} failures; {unfolded} pairs needed unfolding")
    print("e+md lambda_k chosen:", ", ".join(f"{k}: {v}" for k, v in sorted(lambdas.items(), key=lambda kv: (kv[0] is None, kv[0] or 0))))


if __name__ == "__main__":
    main()
