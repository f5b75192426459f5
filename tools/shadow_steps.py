"""The shadows' warmth per step of darkening: clones against real smiles (the analysis behind issue 38's notes).

    python tools/shadow_steps.py [--data ../shared/data/london] [--pairs 80] [--seed 0] [--method global+eri] [--jobs 2]

Over the skin that :func:`exprclone.evaluation.scores.warmth` counts (darker by more than 6 L* than the neutral
photo warped onto the face, :func:`exprclone.evaluation.scores.shadows`), each face gives

- *per step*: the median of ``log(warmth) / -log(L*/L*_neutral)``, how much warmer its shadows grow for each step
  darker (0 for a shading that dims R, G and B alike);
- *depth*: the median of ``-log(L*/L*_neutral)``; and for a clone the median of ``-log(ERI)`` there, how much of that
  darkening its ERI made;
- *the details' own* (for a method with ``+eri``): where its ERI is deeper than :data:`DEEP` on the counted skin, the
  per step of the clone against the same clone without details (its geometry's method: ``global`` for ``global+eri``),
  what the ERI and its tint alone do to the skin, printed with the 95% bootstrap interval of its median
  (:func:`exprclone.evaluation.statistics.median_interval`, as ``exprclone evaluate`` gives its medians).

Printed for the clones of ``--pairs`` pairs (a person's smile onto another's neutral photo, drawn as ``exprclone
evaluate`` draws them) and for every person cloned onto themselves, each beside the source's real smile; then the real
smiles' warmth where their own ERI (the person cloned onto themselves, carried onto the smile's landmarks) shades the
skin (below :data:`SHADED`) and where it does not (:data:`UNSHADED` and above): darkening that the ERI does not see is
the registration of the neutral photo onto the smile's landmarks, or detail finer than the ERI's filter. Last, on the
skin that a person's clone onto themselves shades deeper than :data:`DEEP` (carried onto the smile), the depth and the
log chroma ratio of the real smile and of the clone: how deep, and how much more saturated, the same skin gets.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from exprclone.data import sets as datasets
from exprclone.evaluation import runner, scores, statistics
from exprclone.evaluation.london import Dataset
from exprclone.imaging import piecewise
from exprclone.io.progress import Quiet
from exprclone.landmarks import align
from exprclone.landmarks.backends import shared
from exprclone.landmarks.layout import DLIB68

#: the ERI shades a pixel below this ratio, and leaves it alone from the next up.
SHADED, UNSHADED = 0.95, 0.98
#: where a person's clone onto themselves shades deeper than this, its skin is compared with their real smile's.
DEEP = 0.92
#: fewest counted pixels a median is taken over.
MIN_PIXELS = 30


def steps(found: scores.Shadows, eri: np.ndarray | None = None) -> tuple[float, float, float]:
    """(per step, depth, the ERI's depth) over the counted skin; NaN where too few pixels count."""
    if found.darker.sum() < MIN_PIXELS:
        return (np.nan,) * 3
    depth = -np.log(found.lighter[found.darker])
    per_step = float(np.median(np.log(found.warmer[found.darker]) / depth))
    return per_step, float(np.median(depth)), float(np.median(-np.log(eri[found.darker]))) if eri is not None else np.nan


def carried(eri: np.ndarray, final: np.ndarray, onto: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """A clone's ERI (in its final geometry ``final``) carried onto a photo of ``shape`` whose landmarks are ``onto``."""
    mesh = piecewise.build_mesh(final, eri.shape, DLIB68)
    control = mesh.control_points(onto, align.fit_rigid(final, onto, DLIB68))
    return piecewise.warp(eri, mesh.points, control, mesh.triangles, shape[:2])


def one(task: tuple[Dataset, dict[str, np.ndarray], str, str, str]) -> dict[str, float]:
    """One clone (``source``'s smile onto ``target``'s neutral photo) scored, and its source's real smile."""
    data, marks, method, source, target = task
    neutral, smile, onto = (data.path(source, False), data.path(source, True), data.path(target, False))
    geometry = method.split("+")[0] if method.endswith("+eri") else None
    results = runner.clone_pair(data, (source, target), (method,) if geometry is None else (method, geometry), marks)
    result = results[method]
    found = shared(runner.JUDGE).detect(result.image, "clone")
    clone_found = scores.shadows(result.image, found, runner.photo(onto), marks[onto], DLIB68)
    clone = steps(clone_found, result.eri)
    real = scores.shadows(runner.photo(smile), marks[smile], runner.photo(neutral), marks[neutral], DLIB68)
    row = dict(zip(("step", "depth", "eri_depth", "real_step", "real_depth"), (*clone, *steps(real)[:2])))
    if geometry is not None:  # the clone against itself without details, on the same landmarks
        details = scores.shadows(result.image, found, results[geometry].image, found, DLIB68)
        row["details_step"] = steps(details._replace(darker=clone_found.darker & (result.eri < DEEP)))[0]
    if source == target and real.darker.sum() >= MIN_PIXELS:
        own = carried(result.eri, result.landmarks["final"][: len(marks[smile])], marks[smile], runner.photo(smile).shape)
        for name, where in (("shaded", own < SHADED), ("unshaded", own >= UNSHADED)):
            counted = real.darker & where
            row[name] = float(np.median(real.warmer[counted])) if counted.sum() >= MIN_PIXELS else np.nan
            row[f"{name}_share"] = float(counted.sum() / real.darker.sum())
        deep = (real.skin & (own < DEEP) & (own > 0), clone_found.skin & (result.eri < DEEP))
        if min(m.sum() for m in deep) >= MIN_PIXELS:
            for name, face, where in (("real", real, deep[0]), ("clone", clone_found, deep[1])):
                row[f"{name}_deep"] = float(np.median(-np.log(face.lighter[where])))
                row[f"{name}_chroma"] = float(np.median(np.log(face.warmer[where] * face.lighter[where])))
    return row


def summary(rows: list[dict[str, float]], title: str) -> None:
    """The medians of a set of clones' measures."""
    both = [r for r in rows if np.isfinite(r["step"]) and np.isfinite(r["real_step"])]
    medians = [np.median([r[k] for r in both]) for k in ("step", "depth", "eri_depth", "real_step", "real_depth")]
    print(f"{title}: {len(both)} with counted skin on the clone and on the real smile")
    print("  per step: clone {:.3f}, source's real smile {:.3f}".format(medians[0], medians[3]))
    print("  depth: clone {:.3f} (its ERI's {:.3f}), source's real smile {:.3f}".format(medians[1], medians[2], medians[4]))
    details = np.array([r["details_step"] for r in rows if np.isfinite(r.get("details_step", np.nan))])
    if len(details):
        median, low, high = statistics.median_interval(details)
        print(f"  per step, the details' own where the ERI is deeper than {DEEP}: {median:.3f} [{low:.3f}, {high:.3f}]", end="")
        print(f" ({len(details)} clones)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, "london", holds="the London Set folder")
    parser.add_argument("--pairs", type=int, default=80)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--method", default="global+eri")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    data = Dataset.open(args.data)
    paths = [data.path(p, s) for p in data.ids for s in (False, True)]
    marks = {path: shared(runner.JUDGE).detect(runner.photo(path), path) for path in paths}  # as exprclone evaluate's
    pairs = data.pairs(args.pairs, args.seed)
    tasks = [(data, marks, args.method, a, b) for a, b in [*pairs, *((p, p) for p in data.ids)]]
    rows = list(runner.in_parallel(one, tasks, args.jobs, Quiet(len(tasks), "clones")))
    print(f"shadow steps: {args.method}, {args.data}, {len(pairs)} pairs (seed {args.seed}) and {len(data.ids)} people onto themselves\n")
    summary(rows[: len(pairs)], "onto another person")
    summary(rows[len(pairs) :], "onto themselves")
    own = [r for r in rows[len(pairs) :] if "shaded" in r]
    print(f"\nreal smiles ({len(own)} with counted skin), their warmth where their own ERI")
    for name, where in (("shaded", f"shades the skin (< {SHADED})"), ("unshaded", f"does not (>= {UNSHADED})")):
        values = [r[name] for r in own if np.isfinite(r[name])]
        share = np.median([r[f"{name}_share"] for r in own])
        print(f"  {where}: {np.median(values):.3f} ({len(values)} smiles, {share:.0%} of their counted skin)")
    same = [r for r in own if "real_deep" in r]
    print(f"\nwhere a person's clone onto themselves shades deeper than {DEEP} ({len(same)} people), on the same skin:")
    for name, title in (("real", "real smile"), ("clone", "clone onto themselves")):
        depth, chroma = (np.median([r[f"{name}_{k}"] for r in same]) for k in ("deep", "chroma"))
        print(f"  {title}: depth {depth:.3f}, log chroma ratio {chroma:+.3f}")


if __name__ == "__main__":
    main()
