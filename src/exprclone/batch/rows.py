"""The work of a batch job, done in a worker: a local process or a Dask worker.

Tasks are plain functions over small, picklable arguments (paths, landmarks, options),
and read and write the files at the paths given. A worker loads the landmarker and the
eigenface basis once, on its first task (:func:`exprclone.landmarks.backends.shared` and
:func:`exprclone.geometry.eigenface.default_eigenfaces` keep them), and keeps them for every task after.

A Dask worker keeps freed image buffers as a local process does (:func:`exprclone.cluster.keep_buffers`).
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..cluster import keep_buffers
from ..errors import ExprCloneError, naming
from ..io.images import save_image
from ..io.inputs import Source, photo
from ..options import Options
from ..pipeline import request as door
from ..pipeline.cloner import Cloner
from ..pipeline.group import Found, check_count
from ..pipeline.request import Photo, Request
from ..roles import ROLES, SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from .manifest import Row


@dataclass(frozen=True)
class Task:
    """Rows that share a source's neutral photo and a target (prepared once for all of them), every photo's landmarks
    (of a photo of several faces, its largest's), and the faces of a target that shows several."""

    rows: tuple[Row, ...]
    landmarks: dict[str, np.ndarray] = field(repr=False)
    options: Options = Options()
    groups: dict[str, tuple[Found, ...]] = field(default_factory=dict, repr=False)


@dataclass(frozen=True)
class Outcome:
    """What became of a row: ``done`` or ``failed`` (with the one-line error), its lambda_k, its seconds, and what looked
    wrong with its source's photos (:func:`exprclone.pipeline.role_check.judge_roles`)."""

    number: int
    status: str
    error: str = ""
    lambda_k: float | None = None
    seconds: float = 0.0
    warnings: tuple[str, ...] = ()


def detect(paths: list[str], landmarker: str) -> list[tuple[tuple[Found, ...] | None, str]]:
    """Every face of each photo, its landmarks placed by ``landmarker`` (:func:`exprclone.pipeline.request.place`), or
    the problem that stopped them (no face, not an image)."""
    keep_buffers()
    options = Options(landmarker=landmarker)
    found: list[tuple[tuple[Found, ...] | None, str]] = []
    for path in paths:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                found.append((door.place(photo(Source(path), path, options), options, every=True).found, ""))
        except ExprCloneError as e:
            found.append((None, e.problem))
    return found


def clone_rows(task: Task) -> list[Outcome]:
    """Clone the task's rows, writing each output; a row that fails says why and the others go on."""
    keep_buffers()
    start, first = time.perf_counter(), task.rows[0]
    if first.target_neutral in task.groups:
        return [_clone_group_row(row, task, time.perf_counter()) for row in task.rows]
    try:
        with warnings.catch_warnings(), naming({SOURCE_NEUTRAL: first.source_neutral, TARGET_NEUTRAL: first.target_neutral}):
            warnings.simplefilter("ignore")
            neutral, target = (_placed(path, role, task, task.options) for path, role in zip(first.photos[::2], ROLES[::2]))
            # the rows' roles are checked (a manifest names its photos by hand): each photo looked at once, for every row
            request = Request(neutral, None, target, task.options, check_roles=True)
            cloner = door.pair(request)
    except ExprCloneError as e:
        return [Outcome(row.number, "failed", str(e)) for row in task.rows]
    outcomes = []
    for row in task.rows:
        outcomes.append(_clone_row(cloner, request, row, task, start))
        start = time.perf_counter()
    return outcomes


def _placed(path: str, role: str, task: Task, options: Options) -> Photo:
    """A row's photo read, with the landmarks the job's first pass placed (:func:`detect`; of a photo of several faces,
    its largest's)."""
    return photo(Source(path, points=task.landmarks[path]), role, options)


def _clone_group_row(row: Row, task: Task, start: float) -> Outcome:
    """One row whose target shows several faces: each face its options choose cloned in its own region
    (:mod:`exprclone.pipeline.group`), the output written."""
    names = dict(zip(ROLES, row.photos))
    try:
        with warnings.catch_warnings(), naming(names):
            warnings.simplefilter("ignore")
            options = Options.from_text(dict(row.cells), task.options)
            sn, se = (_placed(path, role, task, options) for path, role in zip(row.photos[:2], ROLES[:2]))
            target = photo(Source(row.target_neutral), TARGET_NEUTRAL, options).looked(task.groups[row.target_neutral])
            result = door.prepare(Request(sn, se, target, options)).render()[options.method]
            save_image(row.output, result.image, inputs=row.photos)
    except ExprCloneError as e:
        return Outcome(row.number, "failed", str(e), seconds=time.perf_counter() - start)
    except Exception as e:  # a bug, not the input's fault: the row fails, the job goes on
        return Outcome(row.number, "failed", f"internal error ({type(e).__name__}: {e})", seconds=time.perf_counter() - start)
    return Outcome(row.number, "done", "", None, time.perf_counter() - start, result.warnings)


def _clone_row(cloner: Cloner, request: Request, row: Row, task: Task, start: float) -> Outcome:
    """One row on the prepared faces (``request``'s, without an expression): its expression cloned by its method, the
    output written, its photos' roles checked (:func:`exprclone.pipeline.request.judge_roles`)."""
    try:
        with warnings.catch_warnings(), naming({SOURCE_EXPRESSION: row.source_expression}):
            warnings.simplefilter("ignore")
            own = cloner.changed(Options.from_text(dict(row.cells), task.options)) if row.cells else cloner
            check_count(own.options.faces, 1)
            method = own.options.method
            expression = _placed(row.source_expression, SOURCE_EXPRESSION, task, own.options)
            asked = dataclasses.replace(request, source_expression=expression, options=own.options)
            result = door.prepare(asked, cloner=own).render()[method]
            save_image(row.output, result.image, inputs=row.photos)
    except ExprCloneError as e:
        return Outcome(row.number, "failed", str(e), seconds=time.perf_counter() - start)
    except Exception as e:  # a bug, not the input's fault: the row fails, the job goes on
        return Outcome(row.number, "failed", f"internal error ({type(e).__name__}: {e})", seconds=time.perf_counter() - start)
    return Outcome(row.number, "done", "", result.lambda_k, time.perf_counter() - start, result.warnings)
