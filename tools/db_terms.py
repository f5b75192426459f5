"""The DB metric's terms on London pairs with the paper's stages: which lambda_k it picks, and why.

    python tools/db_terms.py [--data ../shared/data] [--pairs 300] [--seed 0] [--held-out 4] [--out db_terms.csv]

For each ordered pair drawn as ``exprclone evaluate`` draws them (the same --pairs, --seed and --held-out give the
same pairs), the source's smile is cloned onto the target by the elastic model with ``retarget=False`` (the paper's
stages) and the DB curve is read (Eq. 7, :mod:`exprclone.geometry.db_metric`): the distances to the source's
expression and to GI, in the basis's unit, at lambda_k = 0, at the lambda_k chosen and at LI (lambda_k = inf).

Why lambda_k = 0 wins or not: along the way from GI to LI the second term rises from 1 as ``exp(to_global)``, and the
first falls from ``exp(to_source(0))`` as the candidate nears the source. A first step of length ``d`` towards LI
lowers ``to_source`` by about ``cos d`` (``cos``: how directly LI lies towards the source in face space, measured as
``(to_source(0) - to_source(inf)) / to_global(inf)``) and raises ``to_global`` by ``d``; it lowers DB when
``exp(to_source(0)) cos > 1``, i.e. ``cos > exp(-to_source(0))``, the column ``needed``.

With --held-out K the people are dealt into K folds (as evaluate deals them), and each pair is also scored with a
basis learnt without its fold's people (``lambda_held``), the shipped basis having seen every London person.

Prints how many pairs pick lambda_k > 0 with each basis, and the quartiles of the terms; writes one row per pair.

    python tools/db_terms.py --evaluated REPORT/pairs.csv

reads instead the pairs that ``exprclone evaluate --retargets true,false`` scored, and prints, pair by pair with the
paper's stages (``[no retarget]``), the elastic model against its GI (elastic - global, elastic+eri - global+eri, e+md -
global+eri) on every pair and on the pairs whose lambda_k is above 0 alone: the mouth's landmark error against the
target's real smile, and identity; then each method of the paper's stages against the default's. Means with 95%
intervals (1.96 standard errors of the paired differences).
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.geometry import eigenface
from exprclone.geometry.eigenface import Eigenfaces, default_eigenfaces
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline.cloner import Cloner

#: the elastic model's methods and the GI method each is compared with, pair by pair.
AGAINST_GI = (("elastic", "global"), ("elastic+eri", "global+eri"), ("e+md", "global+eri"))
#: the paper's stages' rows in evaluate's pairs.csv.
PAPER = " [no retarget]"
COLUMNS = ("source", "target", "lambda_k", "to_source_0", "to_source_best", "to_global_best", "to_source_inf", "to_global_inf")


def row_of(source: str, target: str, curve) -> dict:
    """One pair's terms from its DB curve (:class:`exprclone.geometry.db_metric.DBCurve`)."""
    best = int(np.flatnonzero(curve.lambdas == curve.best)[0])
    values = (curve.best, curve.to_source[0], curve.to_source[best], curve.to_global[best], curve.to_source[-1], curve.to_global[-1])
    row = dict(zip(COLUMNS, (source, target, *(round(float(v), 4) for v in values))))
    row["cos"] = round(float((curve.to_source[0] - curve.to_source[-1]) / max(curve.to_global[-1], 1e-12)), 4)
    row["needed"] = round(float(np.exp(-curve.to_source[0])), 4)
    return row


def paired(rows: dict[tuple[str, str, str], dict], a: str, b: str, column: str, pairs: list[tuple[str, str]]) -> str:
    """``a - b`` on ``column`` over ``pairs`` (both scored), mean with a 95% interval, and how many."""
    d = np.array([float(rows[s, t, a][column]) - float(rows[s, t, b][column]) for s, t in pairs if (s, t, a) in rows and (s, t, b) in rows])
    if len(d) < 2:
        return f"{'-':>26s}"
    half = 1.96 * d.std(ddof=1) / np.sqrt(len(d))
    return f"{d.mean():+.4f} [{d.mean() - half:+.4f}, {d.mean() + half:+.4f}]"


def evaluated(path: str) -> None:
    """The paired differences of the module's notes, from evaluate's ``pairs.csv`` at ``path``."""
    with open(path, newline="") as f:
        rows = {(r["source"], r["target"], r["method"]): r for r in csv.DictReader(f) if not r["failed"]}
    every = sorted({(s, t) for s, t, m in rows if m == "e+md" + PAPER})
    moved = [(s, t) for s, t in every if float(rows[s, t, "elastic" + PAPER]["lambda_k"] or 0) > 0]
    print(f"{len(every)} pairs; lambda_k > 0 on {len(moved)} ({100 * len(moved) / max(len(every), 1):.0f}%), the paper's stages")
    for subset, pairs in (("all pairs", every), ("lambda_k > 0", moved)):
        print(f"  {subset}: {'mouth':>26s} {'identity':>26s}")
        for a, b in AGAINST_GI:
            said = " ".join(paired(rows, a + PAPER, b + PAPER, column, pairs) for column in ("mouth", "identity"))
            print(f"    {a} - {b}{PAPER}: {said}")
    print(f"  the paper's stages against the default's, all pairs: {'mouth':>20s} {'identity':>26s} {'judged smiling':>26s}")
    for method in ("global", "elastic", "global+eri", "elastic+eri", "e+md"):
        said = " ".join(paired(rows, method + PAPER, method, column, every) for column in ("mouth", "identity", "smiling"))
        print(f"    {method}{PAPER} - {method}: {said}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--pairs", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--held-out", type=int, default=0, metavar="K")
    parser.add_argument("--out", default="db_terms.csv")
    parser.add_argument("--evaluated", metavar="PAIRS_CSV", help="evaluate's pairs.csv: its paired differences instead")
    args = parser.parse_args()
    if args.evaluated:
        evaluated(args.evaluated)
        return 0
    data = Dataset.open(Path(args.data) / "london")
    folds = data.folds(args.held_out, args.seed) if args.held_out > 1 else None
    pairs = data.pairs(args.pairs, args.seed, folds)
    detect = default_detector().detect
    seen = {(who, smiling): load_image(data.path(who, smiling)) for who in {p for pair in pairs for p in pair} for smiling in (False, True)}
    points = {key: detect(image, data.path(*key)) for key, image in seen.items()}
    held: dict[str, Eigenfaces] = {}
    if folds is not None:  # a basis per fold, learnt on the photos of the other folds' people
        everyone = {(who, s): load_image(data.path(who, s)) for who in data.ids for s in (False, True)}
        for fold in folds:
            others = [key for key in everyone if key[0] not in fold]
            faces = [(everyone[k], points.get(k) if k in points else detect(everyone[k], data.path(*k))) for k in others]
            basis = eigenface.train(faces, DLIB68, people=[k[0] for k in others])
            held.update(dict.fromkeys(fold, basis))
    rows = []
    for k, (a, b) in enumerate(pairs, 1):
        cloner = Cloner(seen[a, False], points[a, False], seen[b, False], points[b, False], retarget=False)
        smile = (seen[a, True], points[a, True])
        row = row_of(a, b, cloner.clone_methods(*smile, ("elastic",))["elastic"].db_curve)
        if held:
            row["lambda_held"] = cloner.changed(eigenfaces=held[a]).clone_methods(*smile, ("elastic",))["elastic"].lambda_k
        rows.append(row)
        print(f"\r{k}/{len(pairs)}", end="", file=sys.stderr)
    print(file=sys.stderr)
    with open(args.out, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    report(rows, default_eigenfaces().unit)
    return 0


def report(rows: list[dict], unit: float) -> None:
    """How many pairs pick lambda_k > 0, the values picked, and the quartiles of the terms."""
    lam = np.array([r["lambda_k"] for r in rows], float)
    print(f"{len(rows)} pairs, the paper's stages, the shipped basis (unit {unit:.4f}):")
    picked = {float(v): int(n) for v, n in zip(*np.unique(lam, return_counts=True))}
    print(f"  lambda_k > 0 on {int((lam > 0).sum())} ({100 * np.mean(lam > 0):.0f}%); values picked: {picked}")
    if "lambda_held" in rows[0]:
        held = np.array([r["lambda_held"] for r in rows], float)
        print(f"  with a basis learnt without the pair's people: lambda_k > 0 on {int((held > 0).sum())} ({100 * np.mean(held > 0):.0f}%)")
    for column in ("to_source_0", "to_global_inf", "cos", "needed"):
        q = np.percentile([r[column] for r in rows], [25, 50, 75])
        print(f"  {column:14s} quartiles {q[0]:.3f} {q[1]:.3f} {q[2]:.3f}")
    wins = [r for r in rows if r["lambda_k"] > 0]
    if wins:
        gain = np.median([np.exp(r["to_source_0"]) - np.exp(r["to_source_best"]) for r in wins])
        cost = np.median([np.exp(r["to_global_best"]) - 1 for r in wins])
        print(f"  where lambda_k > 0: the first term falls by {gain:.3f} (median), the second rises by {cost:.3f}")
    print(f"  cos > needed (a first step towards LI lowers DB) on {sum(r['cos'] > r['needed'] for r in rows)} pairs")


if __name__ == "__main__":
    sys.exit(main())
