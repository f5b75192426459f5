"""Two ``exprclone evaluate`` reports compared pair by pair: each method's scores after a change against before it.

    python tools/compare_reports.py BEFORE/pairs.csv AFTER/pairs.csv [--methods global+eri,e+md]

For every method and score (mouth error, identity distance, teeth shown when the source shows them, judged smiling,
shadow warmth, the blendshape judge's distance to the source's expression, overall and the mouth's, the change's, the rise kept)
over the pairs both reports scored: the mean before and after and the mean paired difference with its 95% interval
(a t interval on the differences; for the shares, on the per-pair 0/1 outcomes). A change that is not meant to move a
score should leave its interval around 0.
"""

from __future__ import annotations

import argparse
import csv

import numpy as np

from exprclone.evaluation.judge import SMILING
from exprclone.evaluation.scores import TEETH_SHOWN

#: the scores compared: (name, how a row gives it, or None when the row does not count).
SCORES = {
    "mouth error": lambda r: float(r["mouth"]),
    "identity": lambda r: float(r["identity"]),
    "teeth shown, source shows": lambda r: float(float(r["teeth"]) >= TEETH_SHOWN) if float(r["source_teeth"]) >= TEETH_SHOWN else None,
    "judged smiling": lambda r: float(float(r["smiling"]) >= SMILING) if r.get("smiling") else None,
    "shadow warmth": lambda r: float(r["warmth"]) if r.get("warmth") else None,
    "expression to the source's (blendshapes)": lambda r: float(r["to_source"]) if r.get("to_source") else None,
    "mouth's expression to the source's": lambda r: float(r["to_source_mouth"]) if r.get("to_source_mouth") else None,
    "change against the source's (blendshapes)": lambda r: float(r["change"]) if r.get("change") else None,
    "source's rise kept": lambda r: float(r["rise_kept"]) if r.get("rise_kept") else None,
}


def rows(path: str) -> dict[tuple[str, str, str], dict[str, str]]:
    with open(path, newline="") as f:
        return {(r["source"], r["target"], r["method"]): r for r in csv.DictReader(f) if not r["failed"]}


def paired(before: dict, after: dict, method: str, score: str) -> tuple[int, float, float, float, float]:
    """Pairs, mean before, mean after, mean difference and its 95% half-width."""
    take = SCORES[score]
    values = [(take(before[k]), take(after[k])) for k in before if k[2] == method and k in after]
    values = [(b, a) for b, a in values if b is not None and a is not None]
    if len(values) < 2:
        return len(values), float("nan"), float("nan"), float("nan"), float("nan")
    b, a = np.array(values).T
    d = a - b
    return len(d), float(b.mean()), float(a.mean()), float(d.mean()), float(1.96 * d.std(ddof=1) / np.sqrt(len(d)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--methods", help="comma-separated (default: every method of both)")
    args = parser.parse_args()
    before, after = rows(args.before), rows(args.after)
    methods = args.methods.split(",") if args.methods else list(dict.fromkeys(k[2] for k in before if k in after))
    print(f"`python tools/compare_reports.py {args.before} {args.after}`\n")
    print("| method | score | pairs | before | after | after - before (95% interval) |\n|---|---|---|---|---|---|")
    for method in methods:
        for score in SCORES:
            n, b, a, d, half = paired(before, after, method, score)
            if n:
                print(f"| {method} | {score} | {n} | {b:.4f} | {a:.4f} | {d:+.4f} ± {half:.4f} |")


if __name__ == "__main__":
    main()
