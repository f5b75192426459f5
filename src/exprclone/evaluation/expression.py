"""``exprclone evaluate --expression``: built-in expressions scored as the individual sources are, on the same targets.

A built-in expression (:mod:`exprclone.expressions`) is cloned onto every person of the
data set it was not made from (its ``people``: a prototype scored on the people it
averages would be judged on its own material), and each result is scored against that
person's real smile as :func:`exprclone.evaluation.runner.score_pair` scores a pair's: its
rows are named after the method and the expression (``e+md [smile]``). Several expressions
of one name, each made without some of the people (``tools/build_expressions.py
--folds``), score every person with the first one made without them.

:func:`against_sources` then sets each expression's results beside the individual
sources' on the same targets: per target the mean over the pairs that have it as their
target (every source, and the sources that smile broadly), compared target by target.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import ExprCloneError
from ..expressions import Expression
from ..io.images import save_image
from ..io.progress import Progress, Quiet
from ..landmarks.backends import DEFAULT, shared
from ..landmarks.layout import DLIB68
from ..pipeline.clone import clone_methods
from . import runner
from .figures import face_box
from .judge import SMILING
from .london import Dataset
from .panels import panel
from .runner import Candidate, Row, Variant
from .scores import TEETH_SHOWN, teeth
from .statistics import STRONG_SMILE

#: each target's scores, by target and score's name (:func:`per_target`).
Scores = dict[str, dict[str, float]]
#: what :func:`against_sources` compares: each score's name in the rows, and how a target's results are summed up.
SCORES = ("identity", "mouth", "teeth shown", "judged smiling")


def label(name: str, variant: str = "") -> str:
    """What follows a method's name in an expression's rows: ``" [smile]"``, or ``" [smile, rbf]"`` in a variant.

    Examples
    --------
    >>> label("smile"), label("smile", " [rbf, S=1.5]")
    (' [smile]', ' [smile, rbf, S=1.5]')
    """
    return f" [{name}{', ' + variant.strip()[1:-1] if variant else ''}]"


def held_out(expressions: list[Expression], data: Dataset) -> list[tuple[str, Expression]]:
    """``(person, expression)`` for each expression's name and each person of ``data``: the first expression of that
    name not made from them (people that none holds out are left out).

    Raises
    ------
    ExprCloneError
        About ``--expression``, if every person helped make every expression of a name.
    """
    chosen: list[tuple[str, Expression]] = []
    for name in dict.fromkeys(e.name for e in expressions):
        fits = [(p, e) for p in data.ids for e in [e for e in expressions if e.name == name and p not in e.people][:1]]
        if not fits:
            raise ExprCloneError(
                "--expression",
                f"every person in {data.root} helped make {name}: score it on other people, or on expressions made without"
                " some of them (python tools/build_expressions.py --folds 4 -o FOLDS; --expression FOLDS/fold-1/smile.json,...)",
            )
        chosen += fits
    return chosen


def score_target(
    data: Dataset,
    target: str,
    expression: Expression,
    methods: tuple[str, ...],
    landmarks: dict[str, np.ndarray],
    variants: tuple[Variant, ...],
    target_points: np.ndarray,
) -> list[Row]:
    """The expression cloned onto ``target`` (its landmarks ``target_points``) by each method in each variant, scored
    (:func:`runner.scored_rows`, with the :data:`~exprclone.evaluation.runner.JUDGE`'s ``landmarks``)."""
    images = (expression.neutral.image, expression.expression.image, runner.photo(data.path(target, False)))
    points = (expression.neutral.points, expression.expression.points, target_points)
    candidates: dict[str, Candidate] = {}
    for variant, options in variants:
        name = label(expression.name, variant)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                results = clone_methods(*images, methods, landmarks=points, options=options)
            candidates.update({f"{m}{name}": (r.image, "", r.lambda_k, name) for m, r in results.items()})
        except Exception as e:  # counted as a failure of every method, never dropped
            candidates.update({f"{m}{name}": (None, f"{type(e).__name__}: {e}", None, name) for m in methods})
    shown = teeth(expression.expression.image, expression.expression.points, DLIB68)
    neutral = runner.scores_of(expression.neutral.image, f"{expression.name} neutral")
    made = runner.scores_of(expression.expression.image, f"{expression.name} expression")
    return runner.scored_rows(data, (expression.name, target), candidates, shown, landmarks, (neutral, made))


def _score(args: tuple[Dataset, str, Expression, tuple[str, ...], dict[str, np.ndarray], tuple[Variant, ...], np.ndarray]) -> list[Row]:
    return score_target(*args)


def run(
    data: Dataset,
    held: list[tuple[str, Expression]],
    methods: tuple[str, ...],
    landmarks: dict[str, np.ndarray],
    jobs: int = 1,
    progress: Progress = Quiet,
    variants: tuple[Variant, ...] = (runner.PAPER,),
    inputs: dict[str, np.ndarray] | None = None,
) -> list[Row]:
    """Every held-out person with their expression (:func:`held_out`), scored (in ``jobs`` processes); ``landmarks``
    (the :data:`~exprclone.evaluation.runner.JUDGE`'s) of every photo by path, and the clones' landmarks ``inputs``
    (another landmarker's; ``landmarks`` if None)."""
    start = landmarks if inputs is None else inputs
    tasks = [(data, t, e, methods, landmarks, variants, start[data.path(t, False)]) for t, e in held]
    return [row for rows in runner.in_parallel(_score, tasks, jobs, progress(len(tasks), "expression")) for row in rows]


def per_target(rows: list[Row], method: str, sources: set[str] | None = None) -> Scores:
    """Each target's scores (:data:`SCORES`) of ``method``'s rows that succeeded, averaged over its sources (``sources`` only, if given)."""
    by_target: dict[str, list[Row]] = {}
    for r in rows:
        if r["method"] == method and not r["failed"] and (sources is None or r["source"] in sources):
            by_target.setdefault(r["target"], []).append(r)
    return {t: {k: float(np.mean([_score_of(r, k) for r in group])) for k in SCORES} for t, group in by_target.items()}


def _score_of(row: Row, score: str) -> float:
    """One of :data:`SCORES` of a row that succeeded: identity, mouth error, or whether teeth show and it is judged smiling."""
    if score in ("identity", "mouth"):
        return float(row[score])
    if score == "teeth shown":
        return float(float(row["teeth"]) >= TEETH_SHOWN)
    return float(float(row["smiling"]) >= SMILING) if row["smiling"] != "" else float("nan")


def against_sources(
    rows: list[Row], expression_rows: list[Row], methods: tuple[str, ...], variants: tuple[Variant, ...], broad: set[str]
) -> list[Row]:
    """Each expression's results beside the same method's from the individual sources, and the real smiles, on the same targets.

    Parameters
    ----------
    rows : list of dict
        The pairs' rows (:func:`runner.run`).
    expression_rows : list of dict
        :func:`run`'s rows.
    methods, variants
        As given to both.
    broad : set of str
        The sources whose own smile is broad (:data:`exprclone.evaluation.statistics.STRONG_SMILE`).

    Returns
    -------
    list of dict
        Per line: ``what``, ``targets`` and each of :data:`SCORES`, a mean over the targets
        that both the expression and the sources have; for the paired lines, the mean
        difference target by target and its standard error (``"identity se"``, ...).
    """
    lines = []
    for name in dict.fromkeys(r["source"] for r in expression_rows):
        for (variant, _), method in ((v, m) for v in variants for m in methods):
            mine_name, theirs_name = f"{method}{label(name, variant)}", f"{method}{variant}"
            mine = per_target(expression_rows, mine_name)
            every, broad_only = per_target(rows, theirs_name), per_target(rows, theirs_name, broad)
            targets = sorted(set(mine) & set(every))
            lines += [
                _mean(mine_name, mine, targets),
                _mean(f"{theirs_name}, every source", every, targets),
                _mean(f"{theirs_name}, broad-smile sources", broad_only, targets),
                _mean("real smile", per_target(rows, "real"), targets),
                _paired(f"{mine_name} - every source", mine, every, targets),
                _paired(f"{mine_name} - broad-smile sources", mine, broad_only, targets),
            ]
    return lines


def _mean(what: str, scores: Scores, targets: list[str]) -> Row:
    present = [t for t in targets if t in scores]
    line: Row = {"what": what, "targets": len(present)}
    line.update({k: float(np.nanmean([scores[t][k] for t in present])) if present else np.nan for k in SCORES})
    return line


def _paired(what: str, mine: Scores, theirs: Scores, targets: list[str]) -> Row:
    both = [t for t in targets if t in theirs]
    line: Row = {"what": what, "targets": len(both)}
    for k in SCORES:
        diff = np.array([mine[t][k] - theirs[t][k] for t in both])
        diff = diff[np.isfinite(diff)]
        line[k] = float(diff.mean()) if len(diff) else np.nan
        line[f"{k} se"] = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else np.nan
    return line


def table(lines: list[Row]) -> str:
    """A Markdown table of :func:`against_sources`' output."""
    out = ["| on the same targets | targets | " + " | ".join(SCORES) + " |", "|" + "---|" * (2 + len(SCORES))]
    for line in lines:
        cells = [f"{line[k]:+.4f} ± {line[k + ' se']:.4f}" if f"{k} se" in line else f"{line[k]:.4f}" for k in SCORES]
        out.append(f"| {line['what']} | {line['targets']} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def sheet(
    data: Dataset,
    held: dict[str, Expression],
    rows: list[Row],
    landmarks: dict[str, np.ndarray],
    method: str,
    broad: set[str],
    count: int = 8,
) -> np.ndarray:
    """A contact sheet of ``count`` held-out targets, evenly spread over them.

    Each row: the target's neutral photo, ``method``'s clone of its expression (``held``,
    :func:`held_out`), the clone from the pairs' source of that target whose result is the
    median by identity among the ``broad`` sources (among all, if none is), and the real
    smile; each captioned with its identity distance and the judge's probability that it
    smiles. ``rows`` holds the pairs' and the expressions' rows.
    """

    scored = {(r["source"], r["target"], r["method"]): r for r in rows if not r["failed"]}
    theirs = {t: [r for (_, target, m), r in scored.items() if m == method and target == t] for t in held}
    targets = [t for t in sorted(held) if theirs[t] and (held[t].name, t, f"{method}{label(held[t].name)}") in scored]
    strips = []
    for t in [targets[i] for i in np.linspace(0, len(targets) - 1, min(count, len(targets))).round().astype(int)]:
        expression, neutral = held[t], runner.photo(data.path(t, False))
        mine = scored[expression.name, t, f"{method}{label(expression.name)}"]
        made = clone_methods(
            expression.neutral.image,
            expression.expression.image,
            neutral,
            (method,),
            landmarks=(expression.neutral.points, expression.expression.points, landmarks[data.path(t, False)]),
        )[method]
        pool = [r for r in theirs[t] if r["source"] in broad] or theirs[t]
        source = sorted(pool, key=lambda r: (float(r["identity"]), r["source"]))[len(pool) // 2]
        real = scored[source["source"], t, "real"]
        cells = [
            (neutral, f"{t} neutral"),
            (made.image, f"{expression.name}: id {float(mine['identity']):.2f}, P {float(mine['smiling'] or 'nan'):.2f}"),
            (
                runner.clone_pair(data, (source["source"], t), (method,), landmarks)[method].image,
                f"from {source['source']}: id {float(source['identity']):.2f}, P {float(source['smiling'] or 'nan'):.2f}",
            ),
            (runner.photo(data.path(t, True)), f"real: id {float(real['identity']):.2f}, P {float(real['smiling'] or 'nan'):.2f}"),
        ]
        box = face_box(landmarks[data.path(t, False)], neutral.shape)
        strips.append(np.hstack([panel(image[box], text) for image, text in cells]))
    return np.vstack(strips)


def section(
    out: Path,
    data: Dataset,
    held: list[tuple[str, Expression]],
    rows: list[Row],
    landmarks: dict[str, np.ndarray],
    methods: tuple[str, ...],
    variants: tuple[Variant, ...],
    jobs: int,
    progress: Progress,
    landmarker: str | None = None,
) -> tuple[list[Row], list[str]]:
    """Score the held-out people with their expressions (:func:`run`), the clones' landmarks placed by ``landmarker``,
    and draw their contact sheet (``out/expressions.jpg``).

    Returns
    -------
    rows : list of dict
        The expressions' rows.
    section : list of str
        The report's paragraphs on them: a title, what was compared, :func:`table`, the sheet.
    """

    chosen = landmarker or DEFAULT
    inputs = landmarks if chosen == runner.JUDGE else {p: shared(chosen).detect(runner.photo(p), p) for p in landmarks}
    found = run(data, held, methods, landmarks, jobs, progress, variants, inputs)
    strength = {p: runner.smile_strength(*(landmarks[data.path(p, s)] for s in (False, True))) for p in data.ids}
    broad = {p for p, value in strength.items() if value >= STRONG_SMILE}
    lines = against_sources(rows, found, methods, variants, broad)
    out.mkdir(parents=True, exist_ok=True)
    first = {t: e for t, e in held if e.name == held[0][1].name}
    method = "e+md" if "e+md" in methods else methods[-1]
    save_image(out / "expressions.jpg", sheet(data, first, rows + found, inputs, method, broad))
    names = dict.fromkeys(e.name for _, e in held)
    counts = ", ".join(f"{name}: {sum(e.name == name for _, e in held)}" for name in names)
    return found, [
        "## Built-in expressions against the individual sources, on the same targets",
        f"Each person is scored with an expression made without them (held out, of {len(data.ids)} people: {counts}). Beside"
        " it, per target, the mean over the pairs that have that target: every source, and the sources whose own smile widens"
        f" the mouth by at least {STRONG_SMILE:.0%} ({len(broad)} people); then the differences target by target (± s.e.).",
        table(lines),
        "![expressions](expressions.jpg)",
    ]
