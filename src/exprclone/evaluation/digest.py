"""``exprclone evaluate``'s summary for a person: which method is best on each score, with its interval, and which
others the pairs cannot tell from it, in a screenful.

The full tables (every score of every method, the pairs whose target smiles broadly, the variants pair by pair) are in
``summary.md`` and printed with ``--full`` (:mod:`exprclone.evaluation.report`); this is what a person reads first.

A method's score is its mean over the pairs with a 95% bootstrap interval (:func:`~.statistics.mean_interval`). Two
methods are told apart pair by pair: the mean of their differences on the same pairs, with its own 95% interval; a
method whose difference to the best has an interval that holds 0 is "not told apart" from it (the pairs differ from
one another far more than the methods do, so pairing is what can tell them apart).
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .runner import REFERENCES, Row
from .scores import TEETH_SHOWN
from .statistics import identity_line, mean_interval, pair_of

#: the summary's lines are wrapped at this many characters.
WIDTH = 118


@dataclass(frozen=True)
class Score:
    """One score the summary ranks the methods by.

    Attributes
    ----------
    name : str
        What it is, in a few words (and its unit).
    lower : bool
        Whether a lower value is better.
    value : callable
        ``value(row, line)``: the row's value, or None where the row has none (``line``: the identity a real smile as
        wide has, :func:`~.statistics.identity_line`).
    shown : str
        The format of its values: ``"{:.4f}"``, ``"{:+.3f}"`` for a signed one, or ``"%"`` for a share.
    """

    name: str
    lower: bool
    value: Callable[[Row, tuple[float, float]], float | None]
    shown: str = "{:.4f}"

    def text(self, value: float, signed: bool = False) -> str:
        """A value as the score shows it; ``signed``: a difference, with its sign."""
        if self.shown == "%":
            return f"{100 * value:+.0f}%" if signed else f"{100 * value:.0f}%"
        return (self.shown.replace("{:", "{:+").replace("++", "+") if signed else self.shown).format(value)


def _number(key: str) -> Callable[[Row, tuple[float, float]], float | None]:
    return lambda row, line: None if row.get(key, "") == "" else float(row[key])


def _excess(row: Row, line: tuple[float, float]) -> float | None:
    """The row's identity distance beyond a real smile as wide (``line``: :func:`~.statistics.identity_line`)."""
    intercept, slope = line
    if row.get("widening", "") == "" or np.isnan(intercept):
        return None
    return float(row["identity"]) - (intercept + slope * float(row["widening"]))


def _teeth_kept(row: Row, line: tuple[float, float]) -> float | None:
    """1 where the result shows teeth, 0 where it does not, of a pair whose source shows teeth; None otherwise."""
    return float(float(row["teeth"]) >= TEETH_SHOWN) if float(row["source_teeth"]) >= TEETH_SHOWN else None


#: the scores of the summary, in its order.
SCORES = (
    Score("mouth shape: landmark error to the real expression, in eye distances", True, _number("mouth")),
    Score("eyes and brows: the same", True, _number("eyes_brows")),
    Score("identity: distance to the target's own face beyond a real smile's as wide", True, _excess, "{:+.3f}"),
    Score("teeth: shown where the source's show", False, _teeth_kept, "%"),
    Score("expression: the blendshape judge's distance to the source's", True, _number("to_source"), "{:.3f}"),
)


def values(score: Score, rows: list[Row]) -> dict[str, dict[tuple[str, str], float]]:
    """Each method's values of ``score`` by pair (its source and target), over the rows that succeeded; a variant's
    rows (``e+md [rbf]``) are a method of their own."""
    found: dict[str, dict[tuple[str, str], float]] = {}
    line = identity_line(rows)
    for row in rows:
        value = None if row["failed"] else score.value(row, line)
        if value is not None:
            found.setdefault(row["method"], {})[pair_of(row)[:2]] = value
    return found


def ranked(score: Score, rows: list[Row]) -> str:
    """One score's lines: the best method with its mean and interval, then each other method the pairs cannot tell
    from it (its paired difference to the best, with its interval), and the next one they can; methods whose values
    are the same on every pair are named together (``global=elastic``)."""
    groups: dict[tuple[tuple[tuple[str, str], float], ...], list[str]] = {}
    for method, found in values(score, rows).items():
        if method not in REFERENCES:
            groups.setdefault(tuple(sorted(found.items())), []).append(method)
    methods = {"=".join(names): dict(key) for key, names in groups.items()}
    if not methods:
        return f"- {score.name}: nothing to measure (no pair has it)"
    means = {m: mean_interval(np.array(list(v.values()))) for m, v in methods.items()}
    order = sorted(means, key=lambda m: means[m][0] if score.lower else -means[m][0])
    best = order[0]
    said = f"- {score.name} ({'lower' if score.lower else 'higher'} is better): best {best} {_interval(score, *means[best])}"
    if score.shown == "%":
        said += f" of {len(methods[best])} pairs"
    tied, ahead = [], None
    for other in order[1:]:
        shared = methods[best].keys() & methods[other].keys()
        diff = mean_interval(np.array([methods[other][p] - methods[best][p] for p in shared]))
        if diff[1] <= 0 <= diff[2]:
            tied.append(f"{other} ({_interval(score, *diff, signed=True)})")
        elif ahead is None:
            ahead = f"{other} by {_interval(score, *diff, signed=True)}"
    said += f"; not told apart from it: {', '.join(tied)}" if tied else ""
    said += f"; then {ahead}" if ahead else ""
    return wrapped(said)


def wrapped(line: str, indent: str = "  ") -> str:
    """A line of the summary wrapped at :data:`WIDTH`, its next lines indented by ``indent``."""
    return "\n".join(textwrap.wrap(line, WIDTH, subsequent_indent=indent, break_on_hyphens=False))


def _interval(score: Score, centre: float, low: float, high: float, signed: bool = False) -> str:
    return f"{score.text(centre, signed)} [{score.text(low, signed)}, {score.text(high, signed)}]"


def references(rows: list[Row]) -> str:
    """The references' means on each score, for scale: the target's neutral photo as it is, and its real expression."""
    parts = []
    for score in SCORES:
        found = values(score, rows)
        shown = [score.text(float(np.mean(list(found[r].values())))) if r in found else "-" for r in REFERENCES]
        parts.append(f"{score.name.split(':')[0]} {' and '.join(shown)}")
    return f"For scale, the target's neutral photo as it is ({REFERENCES[0]}) and its real expression ({REFERENCES[1]}): " + "; ".join(
        parts
    )


def digest(rows: list[Row], root: Path | str, out: Path | None, alike: list[str], held_out: int = 0) -> str:
    """The summary of ``rows`` (the pairs' rows, of people in ``root``): the pairs, the best method on each score
    (:func:`ranked`), the references for scale, the methods that score exactly alike (``alike``: their sentences), and
    where the full tables are (in the report folder ``out``; None: said nowhere, as in the report itself)."""
    pairs = len({(r["source"], r["target"]) for r in rows})
    within = f", within {held_out} folds of the people, each fold cloned with what was learnt without its people" if held_out else ""
    text = [
        wrapped(
            f"{pairs} ordered pairs of different people from {root}{within}: person A's expression cloned onto person B's"
            " neutral photo by each method, and the result scored against B's own photo with the expression. A score is a"
            " mean over the pairs [with its 95% interval]; a method is not told apart from the best when their difference,"
            " pair by pair, has an interval that holds 0 (shown: +difference [interval]).",
            "",
        ),
        "",
        *(ranked(score, rows) for score in SCORES),
        "",
        wrapped(references(rows) + " (-: nothing to measure)."),
        *(wrapped(sentence) for sentence in alike),
    ]
    if out is not None:
        text += [
            "",
            wrapped(
                f"The full tables, every score and what it measures: {out / 'summary.md'} (or --full); every result's"
                f" scores: {out / 'pairs.csv'}; the gallery: {out / 'gallery.jpg'}."
            ),
        ]
    return "\n".join(text)
