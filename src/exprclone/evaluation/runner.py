"""``exprclone evaluate``'s runner: every method on many cross-person pairs, scored against real smiles.

For an ordered pair (A, B) of different people, A's neutral-to-smile change is cloned
onto B's neutral photo by every method, and each result is scored against B's own real
smile (:mod:`exprclone.evaluation.scores`). Two references share the table: ``no change`` (B's
neutral photo taken as the result: the floor) and ``real`` (B's real smile: the
ceiling, zero landmark error by construction, its identity distance the natural one).

Every row also says how much tooth shows in its image and in A's real smile
(:func:`exprclone.evaluation.scores.teeth`): of the pairs whose source shows teeth, the
summary gives the share of results that show teeth too, and of the others, the share
that shows teeth where the source showed none.

Every row also says how likely the expression judge (:mod:`exprclone.evaluation.judge`, a
classifier on the landmarks detected on the image, trained on the data set's other people:
neither the source nor the target) finds that it smiles; the summary gives the share judged
smiling.

Every row also gives the blendshape judge's distances of its image's expression to the source's
expression and to the target's real one, per region, and how much of the source's rise it keeps
(:mod:`exprclone.evaluation.blendshape_judge`); its 52 scores ride along (``blendshapes``) for
``blendshapes.csv``. The photos' own scores are read once per process while they are recent
(:func:`photo_scores`), as the photos are.

Each row says how strongly the target smiles (:func:`smile_strength`), so that the
statistics (:mod:`exprclone.evaluation.statistics`) can be given for the strong smiles
alone; :mod:`exprclone.evaluation.report` writes them out.

Variants: every method may also run with other options of the clone (another global
warp, the TPS image warp, another strength, the paper's stages without retargeting;
:func:`variants`), its rows named after the method and the variant (``e+md [rbf]``,
``e+md [no retarget]``). Each row's paired mouth difference is to global
warping in the same variant (is the elastic model better than the GI it starts from?),
and :func:`exprclone.evaluation.statistics.contrasts` pairs each method in a variant with
the same method in the default setting (is the RBF transfer better than the similarity
one? does retargeting help?).
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import itertools
import multiprocessing
import time
import warnings
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import numpy as np

from ..errors import ExprCloneError, NoFaceError, naming
from ..geometry import global_warp
from ..geometry.expression_shape import ExpressionShape
from ..io.images import load_image
from ..io.progress import Display, Progress, Quiet
from ..landmarks import align, blendshapes
from ..landmarks.backends import DEFAULT, shared
from ..landmarks.layout import DLIB68
from ..mouth.measure import mouth_width
from ..options import GLOBAL_WARPS, IMAGE_WARPS, Options
from ..pipeline import request as door
from ..pipeline.request import Request
from ..pipeline.result import CloneResult
from ..pipeline.role_check import descriptor, identity_distance
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from . import blendshape_judge
from .blendshape_judge import COLUMNS, Faces
from .judge import trained_without
from .london import Dataset
from .scores import landmark_error, teeth, warmth

#: the landmarker that scores every result (on it, on the real smile, for the identity descriptor), whichever
#: landmarker placed the clone's own landmarks (:func:`run`'s ``landmarker``): so that scores of both compare.
JUDGE = "dlib"
#: one variant of the clone's options: the label its rows' names carry (:func:`variant_label`), and the options.
Variant = tuple[str, Options]
T = TypeVar("T")
U = TypeVar("U")
#: one row of scores (:data:`FIELDS`).
Row = dict[str, Any]
#: the two references scored beside the methods: the target's neutral photo (the floor) and its real smile (the ceiling).
REFERENCES = ("no change", "real")
#: photos kept in memory per process (5.5 MB each at 1350 px): pairs come sorted by source,
#: so a source's two photos are read once for all its targets.
PHOTO_CACHE = 8
#: the columns of a row (one method in one variant, or a reference, on one pair).
FIELDS = (
    "source",
    "target",
    "method",
    "target_smile",
    "failed",
    "overall",
    "mouth",
    "eyes_brows",
    "identity",
    "teeth",
    "source_teeth",
    "lambda_k",
    "variant",
    "smiling",
    "warmth",
    "widening",
    *COLUMNS,
)
#: a result to score, by its row's name: ``(image or None, failure, lambda_k, variant label)``.
Candidate = tuple[np.ndarray | None, str, float | None, str]
#: the default setting: the variant of no options (retargeting on), whose rows carry the methods' bare names.
PAPER: Variant = ("", Options())


@functools.lru_cache(maxsize=PHOTO_CACHE)
def photo(path: str) -> np.ndarray:
    """A photo, read once while it is among the last :data:`PHOTO_CACHE` used (pairs come sorted by source)."""
    return load_image(path)


@functools.lru_cache(maxsize=PHOTO_CACHE)
def photo_scores(path: str) -> np.ndarray | None:
    """A photo's blendshape scores (:mod:`exprclone.landmarks.blendshapes`), None where no face is found; read once
    while among the last :data:`PHOTO_CACHE` used."""
    return scores_of(photo(path), path)


def scores_of(image: np.ndarray, subject: str) -> np.ndarray | None:
    """An image's blendshape scores ``(52,)`` by the process's judge, None where it finds no face."""
    try:
        return blendshapes.shared().scores(image, subject)
    except NoFaceError:
        return None


def smile_strength(neutral: np.ndarray, smile: np.ndarray) -> float:
    """Relative widening of the mouth from ``neutral`` to ``smile`` landmarks (head motion removed)."""
    aligned = global_warp.remove_head_motion(neutral, smile, DLIB68)
    return float(_relative_width(aligned) / _relative_width(neutral) - 1.0)


def _relative_width(landmarks: np.ndarray) -> float:
    """The mouth's width over the outer-eye-corner distance."""
    return mouth_width(landmarks, DLIB68) / align.interocular(landmarks, DLIB68)


#: the word of a variant's mark for the paper's stages (``retarget`` off).
NO_RETARGET = "no retarget"


def marks(label: str) -> set[str]:
    """The words of a variant's mark: ``" [rbf, no retarget]"`` -> ``{"rbf", "no retarget"}`` (none for the default).

    >>> sorted(marks(" [rbf, no retarget]")), marks("")
    (['no retarget', 'rbf'], set())
    """
    return {word.strip() for word in label.strip().strip("[]").split(",") if word.strip()}


def variant_label(options: Options) -> str:
    """What follows a method's name in a variant's rows: nothing in the default setting, else ``" [rbf, tps, S=1.5]"``.

    Examples
    --------
    >>> variant_label(Options()), variant_label(Options(global_warp="rbf", strength=1.5)), variant_label(Options(image_warp="mesh"))
    ('', ' [rbf, S=1.5]', '')
    >>> variant_label(Options(global_warp="rbf", retarget=False))
    ' [rbf, no retarget]'
    """
    said = [word for word in (options.global_warp, options.image_warp) if word not in (GLOBAL_WARPS[0], IMAGE_WARPS[0])]
    if options.strength != 1.0:
        said.append(f"S={options.strength:g}")
    if not options.retarget:
        said.append(NO_RETARGET)
    return f" [{', '.join(said)}]" if said else ""


def variants(
    global_warps: tuple[str, ...] = GLOBAL_WARPS[:1],
    image_warps: tuple[str, ...] = IMAGE_WARPS[:1],
    strengths: tuple[float, ...] = (1.0,),
    retargets: tuple[bool, ...] = (True,),
) -> tuple[Variant, ...]:
    """Every combination of the options, each ``(label, clone options)`` (:func:`variant_label`), the default setting first if asked."""
    combinations = itertools.product(global_warps, image_warps, strengths, retargets)
    options = [Options(global_warp=g, image_warp=i, strength=s, retarget=r) for g, i, s, r in combinations]
    return tuple(sorted(((variant_label(o), o) for o in options), key=lambda v: v[0] != ""))


def clone_pair(
    data: Dataset, pair: tuple[str, str], methods: tuple[str, ...], landmarks: dict[str, np.ndarray], options: Options | None = None
) -> dict[str, CloneResult]:
    """A's smile cloned onto B by ``methods`` (with the clone ``options``), with the landmarks already found: the
    request :func:`exprclone.clone_methods` makes, its roles vouched for (the data's roles are known; the role check's
    descriptors would cost as much as a clone)."""
    sn, se, tn = data.path(pair[0], False), data.path(pair[0], True), data.path(pair[1], False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with naming({SOURCE_NEUTRAL: sn, SOURCE_EXPRESSION: se, TARGET_NEUTRAL: tn}):
            given = (landmarks[sn], landmarks[se], landmarks[tn])
            request = Request.of(photo(sn), photo(se), photo(tn), landmarks=given, options=options, check_roles=False)
            return door.prepare(request, methods).render()


def _candidates(
    data: Dataset, pair: tuple[str, str], methods: tuple[str, ...], landmarks: dict[str, np.ndarray], variant: Variant
) -> dict[str, Candidate]:
    """Each method's result in one variant, by its row's name: ``(image or None, failure, lambda_k, variant label)``."""
    label, options = variant
    try:
        results = clone_pair(data, pair, methods, landmarks, options)
        return {f"{m}{label}": (r.image, "", r.lambda_k, label) for m, r in results.items()}
    except Exception as e:  # counted as a failure of every method, never dropped
        return {f"{m}{label}": (None, f"{type(e).__name__}: {e}", None, label) for m in methods}


def score_pair(
    data: Dataset,
    pair: tuple[str, str],
    methods: tuple[str, ...],
    landmarks: dict[str, np.ndarray],
    variants: tuple[Variant, ...] = (PAPER,),
    inputs: dict[str, np.ndarray] | None = None,
) -> list[Row]:
    """Clone A's smile onto B by each method in each variant (:func:`variants`) and score it; also the two references.

    ``landmarks`` are the :data:`JUDGE`'s, by path; the clones start from ``inputs`` (another
    landmarker's, by path), or from ``landmarks`` too when it is None.

    Returns
    -------
    list of dict
        One row of :data:`FIELDS` per method and variant, and per reference.
    """
    a, b = pair
    source_smile = data.path(a, True)
    source_teeth = teeth(photo(source_smile), landmarks[source_smile], DLIB68)
    source_faces = (photo_scores(data.path(a, False)), photo_scores(source_smile))
    candidates: dict[str, Candidate] = {
        "no change": (photo(data.path(b, False)), "", None, ""),
        "real": (photo(data.path(b, True)), "", None, ""),
    }
    for variant in variants:
        candidates.update(_candidates(data, pair, methods, landmarks if inputs is None else inputs, variant))
    return scored_rows(data, pair, candidates, source_teeth, landmarks, source_faces)


def scored_rows(
    data: Dataset,
    pair: tuple[str, str],
    candidates: dict[str, Candidate],
    source_teeth: float,
    landmarks: dict[str, np.ndarray],
    source_faces: Faces,
) -> list[Row]:
    """Each of ``candidates`` (by row name; ``real`` and ``no change`` the target's own photos) scored against the real
    smile of ``pair``'s target, a row of :data:`FIELDS` each; the source (a person, or a built-in expression's name)
    shows ``source_teeth``, and its neutral face and expression score ``source_faces`` on the blendshape judge
    (:func:`blendshape_columns`); the expression judge is trained without either (:func:`exprclone.evaluation.judge.trained_without`)."""
    source, target = pair
    tn, ts = data.path(target, False), data.path(target, True)
    truth, known = landmarks[ts], {"real": landmarks[ts], "no change": landmarks[tn]}
    target_descriptor = descriptor(photo(tn), landmarks[tn])
    target_smile = smile_strength(landmarks[tn], truth)
    judged = trained_without(data, landmarks, pair)
    rows = []
    for method, (image, failed, lam, label) in candidates.items():
        row: Row = dict.fromkeys(FIELDS, "")
        row.update(source=source, target=target, method=method, target_smile=round(target_smile, 4), lambda_k="" if lam is None else lam)
        row["variant"] = label
        row["source_teeth"] = round(source_teeth, 5)
        if image is not None:
            try:
                found = known[method] if method in known else shared(JUDGE).detect(image, f"{method} result")
                row.update(landmark_error(found, truth, DLIB68))
                row["identity"] = identity_distance(descriptor(image, found), target_descriptor)
                row["widening"] = round(smile_strength(landmarks[tn], found), 4)
                row["teeth"] = round(teeth(image, found, DLIB68), 5)
                row["smiling"] = "" if judged is None else round(judged(found), 4)
                warm = warmth(image, found, photo(tn), landmarks[tn], DLIB68)
                row["warmth"] = "" if np.isnan(warm) else round(warm, 4)
            except ExprCloneError as e:
                failed = str(e)
        if image is not None and not failed:
            row.update(blendshape_columns(method, image, source_faces, (tn, ts)))
        row["failed"] = failed
        rows.append(row)
    return rows


def blendshape_columns(method: str, image: np.ndarray, source: Faces, target: tuple[str, str]) -> Row:
    """The blendshape judge's columns of one result (:func:`exprclone.evaluation.blendshape_judge.judged`), against
    the source's faces' scores and the target's photos (paths of its neutral and real expression), and its own
    52 scores as ``blendshapes`` (None where no face is found); the references' are their photos'."""
    faces = (photo_scores(target[0]), photo_scores(target[1]))
    mine = dict(zip(REFERENCES, faces))[method] if method in REFERENCES else scores_of(image, f"{method} result")
    return {**blendshape_judge.judged(mine, source, faces), "blendshapes": mine}


def _score(
    args: tuple[Dataset, tuple[str, str], tuple[str, ...], dict[str, np.ndarray], tuple[Variant, ...], dict[str, np.ndarray]],
) -> list[Row]:
    return score_pair(*args)


def run(
    data: Dataset,
    pairs: list[tuple[str, str]],
    methods: tuple[str, ...],
    jobs: int = 1,
    progress: Progress = Quiet,
    variants: tuple[Variant, ...] = (PAPER,),
    landmarker: str | None = None,
    folds: tuple[tuple[str, ...], ...] | None = None,
) -> tuple[list[Row], dict[str, np.ndarray]]:
    """Score every pair (in ``jobs`` processes), each method in each of ``variants`` (:func:`variants`), the clones'
    landmarks placed by ``landmarker`` (:data:`exprclone.landmarks.backends.LANDMARKERS`), the scores' by the :data:`JUDGE`.

    With ``folds`` of the people (:meth:`Dataset.folds`; each pair within one), what the clones learn from people (the
    shape of the expression, :mod:`exprclone.geometry.expression_shape`) is learnt once per fold, from the other
    folds' people alone, and each pair is cloned with its fold's: no clone is judged on people it learnt from.

    ``progress(total, what)`` makes a display of how many of ``total``
    things are done (:data:`exprclone.io.progress.Progress`): one for the photos'
    landmarks, one for the pairs.

    Returns
    -------
    rows : list of dict
        :func:`score_pair`'s rows of every pair.
    landmarks : dict of str to ndarray
        The judge's landmarks on each photo, by path (detected once, shared by all pairs).
    """
    chosen = landmarker or DEFAULT
    people = data.ids  # all of them: the expression judge learns from the people not in a pair
    paths = [data.path(p, s) for p in people for s in (False, True)]
    landmarks: dict[str, np.ndarray] = {}
    inputs: dict[str, np.ndarray] = {}
    bar = progress(len(paths), "landmarks")
    for k, path in enumerate(paths, 1):
        landmarks[path] = shared(JUDGE).detect(photo(path), path)
        inputs[path] = landmarks[path] if chosen == JUDGE else shared(chosen).detect(photo(path), path)
        bar.update(k)
    learnt = {p: model for f in folds or () for model in (held_out(data, f, landmarks),) for p in f}
    tasks = [(data, pair, methods, landmarks, with_shape(variants, learnt.get(pair[0])), inputs) for pair in pairs]
    rows = [row for pair_rows in in_parallel(_score, tasks, jobs, progress(len(pairs), "pairs")) for row in pair_rows]
    return rows, landmarks


def held_out(data: Dataset, fold: tuple[str, ...], landmarks: dict[str, np.ndarray]) -> ExpressionShape:
    """The shape of the expression learnt from the people outside ``fold`` alone (their judge's landmarks, as the model
    shipped is learnt: ``tools/train_expression_shape.py``)."""
    others = [p for p in data.ids if p not in fold]
    return ExpressionShape.learn([(landmarks[data.path(p, False)], landmarks[data.path(p, True)]) for p in others], DLIB68)


def with_shape(variants: tuple[Variant, ...], model: ExpressionShape | None) -> tuple[Variant, ...]:
    """``variants`` whose clones take the shape of the expression ``model`` (as they are if None)."""
    return variants if model is None else tuple((label, dataclasses.replace(o, expression_shape=model)) for label, o in variants)


def in_parallel(function: Callable[[T], U], tasks: list[T], jobs: int, bar: Display) -> Iterator[U]:
    """``function`` of each task, in order, in ``jobs`` processes (forked: they share what is loaded); ``bar`` told of each."""
    start = time.perf_counter()
    with multiprocessing.get_context("fork").Pool(jobs) if jobs > 1 else contextlib.nullcontext() as pool:
        for k, out in enumerate(pool.imap(function, tasks) if pool else map(function, tasks), 1):
            yield out
            bar.update(k, f"{(time.perf_counter() - start) / k:.1f} s each")
