"""A batch job: the rows to do, each distinct photo's landmarks found once, the clones in tasks, a report.

1. Rows whose output exists are skipped (unless ``overwrite``): a job interrupted and run
   again does only what is left.
2. Each distinct photo (by content: the SHA-256 of its bytes) is detected once, however
   many rows use it: every face of it (:func:`exprclone.pipeline.group.find`; a target of several
   faces has the ones its row's ``faces`` chooses cloned, each in its own region, a source's
   photo its largest taken); with a cache folder its faces persist between runs.
3. Rows that share a source's neutral photo and a target go together, so the work that
   depends on the two neutral faces (:class:`exprclone.Cloner`) is done once.

The tasks run on a :class:`Local` pool of processes or on a Dask cluster (:class:`Dask`);
either way one bad row never stops the job, and the report has one row per manifest row.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import hashlib
import io
import json
import multiprocessing
import os
import signal
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..cluster import connect
from ..errors import ExprCloneError
from ..io.documents import csv_cell
from ..io.images import atomic_write
from ..io.progress import Display, Progress, Quiet
from ..landmarks.backends import name_of
from ..options import Options
from ..pipeline.group import Found
from .manifest import COLUMNS, Row
from .rows import Outcome, Task, clone_rows, detect

#: photos detected per task.
DETECT_CHUNK = 8
#: rows cloned per task at most (smaller tasks balance the workers and stop sooner after Ctrl-C).
CLONE_CHUNK = 4
#: how a backend runs tasks: ``map(function, items)`` gives ``(index, result)`` as results come.
Map = Callable[[Callable[[Any], Any], list[Any]], Iterator[tuple[int, Any]]]
#: the report's columns.
REPORT = ("row", *COLUMNS, "status", "error", "lambda_k", "seconds", "warnings")


def _ignore_interrupt() -> None:
    """A worker lets the job's process handle Ctrl-C: it finishes the row under way, and writes no half file."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


class Local:
    """Tasks on ``jobs`` worker processes of this machine (in this process for one job)."""

    def __init__(self, jobs: int) -> None:
        self.jobs = jobs

    @contextlib.contextmanager
    def running(self) -> Iterator[Map]:
        """``map(function, items)``: results as they come, as ``(index, result)``."""
        if self.jobs == 1:
            yield lambda function, items: ((k, function(item)) for k, item in enumerate(items))
            return
        pool = ProcessPoolExecutor(self.jobs, mp_context=multiprocessing.get_context("fork"), initializer=_ignore_interrupt)
        try:
            yield lambda function, items: _completed({pool.submit(function, item): k for k, item in enumerate(items)})
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


def _completed(futures: dict[Future[Any], int]) -> Iterator[tuple[int, Any]]:
    try:
        for future in as_completed(futures):
            yield futures[future], future.result()
    except BrokenProcessPool as e:
        raise ExprCloneError("batch", f"a worker process died ({e}); the rows finished are whole: run again to resume") from None


class Dask:
    """Tasks on a Dask distributed cluster (``distributed.Client``); its workers need exprclone and the files at the same paths."""

    def __init__(self, scheduler: str) -> None:
        self.scheduler = scheduler

    @contextlib.contextmanager
    def running(self) -> Iterator[Map]:
        client = connect(self.scheduler)
        from distributed import as_completed  # (Dask: an extra, loaded by a job on a cluster)

        with client:
            submitted: list[Any] = []

            def map_(function: Callable[[Any], Any], items: list[Any]) -> Iterator[tuple[int, Any]]:
                futures = client.map(function, items, pure=False)
                submitted.extend(futures)
                index = {future.key: k for k, future in enumerate(futures)}
                return ((index[f.key], f.result()) for f in as_completed(futures))

            try:
                yield map_
            finally:
                client.cancel(submitted)


def fingerprint(path: str) -> str | None:
    """The SHA-256 of a file's bytes (None if it cannot be read)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return None


def find_landmarks(
    photos: Iterable[str], run: Map, cache: Path | None, progress: Progress, landmarker: str
) -> tuple[dict[str, np.ndarray], dict[str, str], dict[str, tuple[Found, ...]]]:
    """Every photo's faces, their landmarks placed by ``landmarker``, each distinct content detected once (or read from
    ``cache``, where each landmarker's are kept apart).

    Returns
    -------
    landmarks : dict of path to ndarray
        Each photo's face's landmarks (of a photo of several, the largest's, as a source's photo is taken).
    problems : dict of path to str
        Why a photo has none (no such file, not an image, no face).
    groups : dict of path to tuple of Found
        Every face of each photo that shows several (:func:`exprclone.pipeline.group.find`).
    """
    digests = {p: fingerprint(p) for p in dict.fromkeys(photos)}
    problems = {p: "no such file, or it cannot be read" for p, d in digests.items() if d is None}
    readable = {p: d for p, d in digests.items() if d is not None}
    found: dict[str, tuple[Found, ...] | str | None] = {d: _cached(cache, d, landmarker) for d in set(readable.values())}
    missing = sorted(d for d, faces in found.items() if faces is None)
    first_path = {d: p for p, d in reversed(readable.items())}
    chunks = [missing[k : k + DETECT_CHUNK] for k in range(0, len(missing), DETECT_CHUNK)]
    bar, done = progress(len(missing), "photos"), 0
    for k, results in run(functools.partial(detect, landmarker=landmarker), [[first_path[d] for d in chunk] for chunk in chunks]):
        for digest, (faces, problem) in zip(chunks[k], results):
            found[digest] = faces if faces is not None else problem
            if cache is not None and faces is not None:
                (cache / f"{digest}-{landmarker}.json").write_text(json.dumps({"faces": [_face_record(f) for f in faces]}))
        done += len(chunks[k])
        bar.update(done)
    landmarks, groups = {}, {}
    for path, digest in readable.items():
        value = found[digest]
        if isinstance(value, str):
            problems[path] = value
        elif value is not None:
            landmarks[path] = max(value, key=lambda f: f.across).points
            if len(value) > 1:
                groups[path] = value
    return landmarks, problems, groups


def _face_record(face: Found) -> dict[str, Any]:
    return {"number": face.number, "box": list(face.box), "landmarks": face.points.tolist(), "problem": face.problem}


def _cached(cache: Path | None, digest: str, landmarker: str) -> tuple[Found, ...] | None:
    """The faces kept in ``cache`` of a photo by its digest, or None (a file of an older version kept no faces)."""
    path = None if cache is None else cache / f"{digest}-{landmarker}.json"
    if path is None or not path.is_file() or "faces" not in (document := json.loads(path.read_text())):
        return None
    return tuple(Found(f["number"], tuple(f["box"]), np.array(f["landmarks"], float), f["problem"]) for f in document["faces"])


def make_tasks(
    rows: list[Row], landmarks: dict[str, np.ndarray], options: Options, several: dict[str, tuple[Found, ...]] | None = None
) -> list[Task]:
    """Rows grouped by source neutral photo and target, in tasks of at most :data:`CLONE_CHUNK` rows; with the faces of
    their targets that show several (``several``, by path)."""
    groups: dict[tuple[str, str], list[Row]] = {}
    for row in rows:
        groups.setdefault((row.source_neutral, row.target_neutral), []).append(row)
    tasks = []
    for group in groups.values():
        for k in range(0, len(group), CLONE_CHUNK):
            chunk = tuple(group[k : k + CLONE_CHUNK])
            shown = {row.target_neutral: faces for row in chunk if (faces := (several or {}).get(row.target_neutral))}
            tasks.append(Task(chunk, {p: landmarks[p] for row in chunk for p in row.photos}, options, shown))
    return tasks


def run(
    rows: list[Row],
    options: Options,
    backend: Local | Dask,
    outcomes: dict[int, Outcome],
    *,
    overwrite: bool = False,
    cache: Path | None = None,
    progress: Progress = Quiet,
    known: dict[str, np.ndarray] | None = None,
) -> None:
    """Do the job, recording the outcome of every row in ``outcomes`` by its number (skipped, done or failed) as it comes.

    ``progress(total, what)`` makes a display with ``update(done, note)`` (:data:`exprclone.io.progress.Progress`).
    ``known`` landmarks (by path: a built-in expression's photos) are taken as they are, not detected.
    After Ctrl-C, ``outcomes`` holds what finished.
    """
    known = known or {}
    outcomes.update({row.number: Outcome(row.number, "skipped") for row in rows if not overwrite and os.path.exists(row.output)})
    to_do = [row for row in rows if row.number not in outcomes]
    for row in to_do:
        os.makedirs(os.path.dirname(row.output), exist_ok=True)
    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
    with backend.running() as map_:
        photos = (p for row in to_do for p in row.photos if p not in known)
        landmarks, problems, groups = find_landmarks(photos, map_, cache, progress, name_of(options.landmarker))
        landmarks.update(known)
        ready = []
        for row in to_do:
            bad = next((p for p in row.photos if p in problems), None)
            if bad is None:
                ready.append(row)
            else:
                outcomes[row.number] = Outcome(row.number, "failed", f"{bad}: {problems[bad]}")
        _clone(make_tasks(ready, landmarks, options, groups), map_, outcomes, progress(len(ready), "pairs"))


def _clone(tasks: list[Task], map_: Map, outcomes: dict[int, Outcome], bar: Display) -> None:
    """Run the clone tasks, recording each row's outcome as it comes (so that Ctrl-C keeps what finished)."""
    start, done, failed = time.perf_counter(), 0, 0
    total = sum(len(t.rows) for t in tasks)
    for _, results in map_(clone_rows, tasks):
        for outcome in results:
            outcomes[outcome.number] = outcome
            done, failed = done + 1, failed + (outcome.status == "failed")
        rate = done / max(time.perf_counter() - start, 1e-9)
        bar.update(done, f"{failed} failed, {rate:.1f}/s, {max(total - done, 0) / rate:.0f} s left")


def write_report(path: str, rows: list[Row], outcomes: dict[int, Outcome]) -> None:
    """The report: one CSV row per manifest row (rows not reached, after Ctrl-C, say ``not run``)."""

    def lines(f: IO[bytes]) -> None:
        text = io.TextIOWrapper(f, encoding="utf-8", newline="")
        writer = csv.writer(text)
        writer.writerow(REPORT)
        for row in rows:
            o = outcomes.get(row.number, Outcome(row.number, "not run"))
            lam = "" if o.lambda_k is None else f"{o.lambda_k:g}"
            cells = [*row.photos, row.output, o.status, o.error, lam, f"{o.seconds:.3f}", "; ".join(o.warnings)]
            writer.writerow([row.number, *map(csv_cell, cells)])
        text.flush()
        text.detach()

    atomic_write(path, lines)
