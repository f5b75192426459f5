"""Run every method on every ordered pair of people of the London Set, with every combination of the options; report failures.

    python tools/all_pairs.py [--data ../shared/data] [--jobs 2] [--limit N] [--paper-only]

Source A's neutral and smiling photos and target B's neutral photo, for every A != B.
Landmarks are detected once per photo. Every pair runs all seven methods under each
combination of the global warp (similarity, rbf, and given landmarks: B's own real
smile's, as another method's result would be) and the image warp (mesh, tps): six
configurations. Each configuration also takes a strength and regions (``only``) from
:data:`TRANSFERS`, in turn from pair to pair, so that every combination of global warp,
image warp and transfer runs on one pair in eight (639 pairs). ``--paper-only`` runs the
paper's setting alone.

Prints a line per failure and, per global and image warp and per strength and regions, a
summary: pairs run, failures, pairs whose mesh needed unfolding; and per global and image
warp, the distribution of the lambda_k e+md chose.
"""

import argparse
import collections
import functools
import itertools
import multiprocessing
import time
import warnings
from pathlib import Path

import numpy as np

from exprclone import METHODS, clone_methods
from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector

#: the global warps and image warps, every combination run on every pair.
GEOMETRY = list(itertools.product(("similarity", "rbf", "given"), ("mesh", "tps")))
#: strength and regions, one for each configuration of a pair, in turn.
TRANSFERS = [(1.0, None), (0.0, None), (0.5, None), (2.0, None), (1.5, "mouth"), (1.0, "eyes"), (0.5, "brows"), (2.0, "mouth,eyes")]


@functools.cache
def photo(path: str) -> np.ndarray:
    return load_image(path)


def configurations(k: int, paper_only: bool) -> list[tuple[str, dict]]:
    """The configurations of the ``k``-th pair: ``(name, options)``; ``given`` stands for B's real smile's landmarks."""
    if paper_only:
        return [("similarity mesh S=1", {})]
    out = []
    for c, (global_warp, image_warp) in enumerate(GEOMETRY):
        strength, only = TRANSFERS[(k + c) % len(TRANSFERS)]
        name = f"{global_warp} {image_warp} S={strength:g}" + (f" only={only}" if only else "")
        given = global_warp == "given"
        options = dict(image_warp=image_warp, strength=strength, only=only, **{"global_landmarks" if given else "global_warp": global_warp})
        out.append((name, options))
    return out


def run_pair(job):
    data, k, (a, b), landmarks, paper_only = job
    paths = (data.path(a, False), data.path(a, True), data.path(b, False))
    out = []
    for name, options in configurations(k, paper_only):
        if options.get("global_landmarks") == "given":
            options = dict(options, global_landmarks=landmarks[data.path(b, True)])
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                results = clone_methods(*(photo(p) for p in paths), landmarks=tuple(landmarks[p] for p in paths), **options)
            wrong = [m for m, r in results.items() if r.image.shape != photo(paths[2]).shape]
            error = f"output of the wrong size for {wrong}" if wrong else None
            out.append((name, error, max(r.unfolded_points for r in results.values()), results["e+md"].lambda_k))
        except Exception as e:  # a failure is counted, never hidden
            out.append((name, f"{type(e).__name__}: {e}", 0, None))
    return a, b, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--limit", type=int, default=0, help="only N pairs drawn at random, seed 0 (0: all)")
    parser.add_argument("--paper-only", action="store_true", help="only the paper's setting (similarity, mesh, strength 1)")
    args = parser.parse_args()
    data = Dataset.open(Path(args.data) / "london")
    landmarks = {p: default_detector().detect(photo(p), p) for i in data.ids for p in (data.path(i, False), data.path(i, True))}
    pairs = data.pairs(args.limit, seed=0)
    start = time.time()
    failures, unfolded, lambdas, runs = (
        collections.Counter(),
        collections.Counter(),
        collections.defaultdict(collections.Counter),
        collections.Counter(),
    )
    with multiprocessing.get_context("fork").Pool(args.jobs) as pool:
        jobs = [(data, k, pair, landmarks, args.paper_only) for k, pair in enumerate(pairs)]
        for k, (a, b, out) in enumerate(pool.imap_unordered(run_pair, jobs, chunksize=4), 1):
            for name, error, n_unfolded, lam in out:
                geometry = " ".join(name.split()[:2])
                runs[name] += 1
                if error:
                    failures[name] += 1
                    print(f"FAIL {a} -> {b} ({name}): {error}", flush=True)
                unfolded[name] += n_unfolded > 0
                lambdas[geometry][lam] += 1
            if k % 200 == 0:
                print(f"{k}/{len(pairs)} pairs, {time.time() - start:.0f} s", flush=True)
    print(f"{len(pairs)} ordered pairs x {len(METHODS)} methods in {time.time() - start:.0f} s: {sum(failures.values())} failures")
    for part, title in ((slice(0, 2), "global and image warp"), (slice(2, None), "strength and regions")):
        for group in sorted({" ".join(n.split()[part]) for n in runs}):
            names = [n for n in runs if " ".join(n.split()[part]) == group]
            counts = [sum(c[n] for n in names) for c in (runs, failures, unfolded)]
            print(f"  {title} {group}: {counts[0]} runs, {counts[1]} failures, {counts[2]} needed unfolding")
    for geometry, counts in sorted(lambdas.items()):
        chosen = ", ".join(f"{k}: {v}" for k, v in sorted(counts.items(), key=lambda kv: (kv[0] is None, kv[0] or 0)))
        print(f"e+md lambda_k chosen, {geometry}: {chosen}")


if __name__ == "__main__":
    main()
