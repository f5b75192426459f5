"""``exprclone evaluate``'s summary for a person (:mod:`exprclone.evaluation.digest`): the best method on each score,
the methods the pairs cannot tell from it, and the next one they can."""

import re
from pathlib import Path

import numpy as np

from exprclone.evaluation.digest import SCORES, digest, ranked

MOUTH, TEETH = SCORES[0], SCORES[3]


def flat(text: str) -> str:
    """The summary's text on one line (its lines are wrapped)."""
    return " ".join(text.split())


def rows_of(scores: dict[str, list[float]], teeth: dict[str, list[float]] | None = None, source_teeth=None) -> list[dict]:
    """Rows of ``len(values)`` pairs: each method's mouth error on each pair (and its teeth, and the sources' teeth)."""
    rows = []
    for method, values in scores.items():
        for k, value in enumerate(values):
            row = {"source": f"s{k}", "target": f"t{k}", "method": method, "failed": "", "mouth": value, "eyes_brows": value}
            row.update(identity=0.2, widening="", to_source="", teeth=(teeth or {}).get(method, [0.0] * len(values))[k])
            row["source_teeth"] = (source_teeth or [0.0] * len(values))[k]
            rows.append(row)
    return rows


def test_a_method_better_on_every_pair_is_best_and_the_next_is_told_apart():
    spread = np.random.default_rng(0).uniform(0.02, 0.06, 30)  # the pairs differ far more than the methods
    said = flat(ranked(MOUTH, rows_of({"global": list(spread + 0.002), "e+md": list(spread)})))
    assert said.startswith(f"- {MOUTH.name} (lower is better): best e+md {np.mean(spread):.4f} [")
    then = re.search(r"then global by \+0\.0020 \[\+(\S+), \+(\S+)\]", said)
    assert then and float(then[1]) == float(then[2]) == 0.002 and "not told apart" not in said, said


def test_methods_whose_difference_is_noise_are_not_told_apart():
    rng = np.random.default_rng(1)
    spread = rng.uniform(0.02, 0.06, 30)
    noise = rng.normal(0, 0.002, 30)
    said = flat(ranked(MOUTH, rows_of({"global": list(spread), "song": list(spread + noise - noise.mean() + 0.0001)})))
    assert "best global" in said and re.search(r"not told apart from it: song \(\+0\.0001 \[-\S+, \+\S+\]\)", said), said


def test_methods_that_score_alike_are_named_together_and_the_references_only_for_scale():
    spread = list(np.linspace(0.02, 0.05, 10))
    rows = rows_of({"no change": [0.5] * 10, "real": [0.0] * 10, "global": spread, "elastic": spread, "e+md": [v + 0.01 for v in spread]})
    said = flat(ranked(MOUTH, rows))
    ranking = said.split("is better): ")[1]
    assert ranking.startswith("best global=elastic") and "then e+md by +0.0100" in said
    assert "real" not in ranking and "no change" not in ranking  # the references are for scale only
    wrapped = digest(rows, "somewhere", Path("report"), ["elastic scores exactly as global on all 10 pairs."])
    text = flat(wrapped)
    assert "(no change) and its real expression (real): mouth shape 0.5000 and 0.0000" in text
    assert "elastic scores exactly as global" in text and "report/summary.md (or --full)" in text
    assert max(len(line) for line in wrapped.splitlines()) <= 118


def test_teeth_count_over_the_pairs_whose_source_shows_teeth():
    rows = rows_of(
        {"global": [0.03] * 4, "e+md": [0.03] * 4},
        teeth={"global": [0.0, 0.0, 0.0, 0.02], "e+md": [0.02, 0.02, 0.0, 0.0]},
        source_teeth=[0.03, 0.03, 0.0, 0.0],  # two sources show teeth; on the others a result's teeth do not count
    )
    said = flat(ranked(TEETH, rows))
    assert said.startswith(f"- {TEETH.name} (higher is better): best e+md 100% [100%, 100%] of 2 pairs"), said
    assert "then global by -100%" in said
    nothing = flat(ranked(TEETH, rows_of({"global": [0.03] * 3})))
    assert nothing == f"- {TEETH.name}: nothing to measure (no pair has it)"
