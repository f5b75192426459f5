"""Video jobs: each in a folder of its own under the server's temporary folder, bounded in number, expiring.

A job is created with its inputs saved in its folder, runs in the video worker
(:func:`exprclone.server.work.video`), reports its progress in a file there, and is
removed :data:`Jobs.ttl` seconds after it ends (or at shutdown). A job that fails gives
its place back at once: its files are removed then, and only its error is kept (until it
expires, and at most :data:`FAILED_KEPT` of them). Job ids are random
(128 bits) and checked against their form before any path is built from them: a job's state
and result are read with its id alone, which only the client that made it is told.

Each job counts in its client's share (:mod:`exprclone.server.runtime.clients`) as in the
store's bound. The rules on a store of jobs (:func:`check_room`, :func:`expired`, :func:`job_error`) are
also those of the jobs a Dask cluster keeps for several servers (:mod:`exprclone.server.runtime.shared_jobs`).
"""

from __future__ import annotations

import asyncio
import json
import math
import re
import secrets
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ...errors import ExprCloneError, quoted
from .limits import Busy, share

#: a job id: 32 hex digits.
JOB_ID = re.compile(r"[0-9a-f]{32}")
#: failed jobs whose error is kept to be read (the oldest beyond are forgotten).
FAILED_KEPT = 64
#: seconds a client is told to wait when every job kept is still queued or running.
RETRY_RUNNING = 30


class NoSuchJob(Exception):
    """An id that is malformed, unknown or expired: answered 404."""

    @classmethod
    def of(cls, job_id: str, ttl: float) -> NoSuchJob:
        """The error about ``job_id``, in a store whose jobs expire ``ttl`` seconds after they end."""
        return cls(f"no job {quoted(job_id)} (unknown, or expired after {ttl:g} s)")


class JobNotDone(Exception):
    """A job's result asked for before the job is done: answered 409."""


@dataclass
class Job:
    """One video job.

    Attributes
    ----------
    id : str
    folder : Path
        Holds the driving video, the progress file and the result.
    client : str
        Whose it is (:mod:`exprclone.server.runtime.clients`).
    created : float
        When it was created (``time.time()``).
    future : asyncio.Future or None
        The work, once submitted.
    ended : float or None
        When its work ended.
    """

    id: str
    folder: Path
    client: str = ""
    created: float = field(default_factory=time.time)
    future: asyncio.Future[dict[str, Any]] | None = None
    ended: float | None = None

    @property
    def video(self) -> Path:
        return self.folder / "driving"

    @property
    def result(self) -> Path:
        return self.folder / "result.mp4"

    @property
    def progress_file(self) -> Path:
        return self.folder / "progress.json"

    def state(self) -> dict[str, Any]:
        """``{"id", "state", "progress", "error", "info"}``: state is queued, running, done or failed; progress in [0, 1]."""
        report = json.loads(self.progress_file.read_text()) if self.progress_file.exists() else {}
        if self.future is not None and self.future.done():
            error = self.future.exception()
            if error is None:
                report["info"] = self.future.result()
            else:
                report["error"] = job_error(error)
        return answer(self.id, report)

    @property
    def failed(self) -> bool:
        """Whether its work has ended with an error."""
        future = self.future
        return future is not None and future.done() and (future.cancelled() or future.exception() is not None)

    def ended_now(self) -> None:
        """Its work has ended: the time to live starts; a failed job's files go at once (its error is kept)."""
        self.ended = time.time()
        if self.failed:
            for path in (self.video, self.result):
                path.unlink(missing_ok=True)


class Jobs:
    """The server's video jobs, at most ``limit`` of them kept and ``per_client`` of one client, each for ``ttl`` seconds
    after it ends.

    Parameters
    ----------
    root : Path
        The server's temporary folder; jobs live in ``root/jobs/<id>``.
    limit : int
    ttl : float
    per_client : int
    """

    def __init__(self, root: Path, limit: int, ttl: float, per_client: int | None = None) -> None:
        self.root, self.limit, self.ttl, self.per_client = root / "jobs", limit, ttl, per_client or limit
        self.root.mkdir(parents=True, exist_ok=True)
        self._jobs: dict[str, Job] = {}

    def create(self, client: str = "") -> Job:
        """A new job of ``client`` with its folder, or :class:`Busy` when ``limit`` jobs are kept already (failed ones
        aside), :class:`~exprclone.server.runtime.limits.TooMany` when the client's share is."""
        self.expire()
        kept = [(job.ended, job.client) for job in self._jobs.values() if not job.failed]
        check_room(kept, self.limit, self.ttl, client, self.per_client)
        job = Job(secrets.token_hex(16), Path(), client)
        job.folder = self.root / job.id
        job.folder.mkdir()
        self._jobs[job.id] = job
        return job

    def get(self, job_id: str) -> Job:
        """The job, or :class:`NoSuchJob`."""
        if not JOB_ID.fullmatch(job_id) or job_id not in self._jobs:
            raise NoSuchJob.of(job_id, self.ttl)
        return self._jobs[job_id]

    def discard(self, job: Job) -> None:
        """Remove a job and its folder (a job that could not be started)."""
        self._jobs.pop(job.id, None)
        shutil.rmtree(job.folder, ignore_errors=True)

    def expire(self, now: float | None = None) -> None:
        """Remove the jobs that ended more than ``ttl`` seconds ago."""
        kept = [(job.id, job.ended, job.failed) for job in self._jobs.values()]
        for job_id in expired(kept, self.ttl, time.time() if now is None else now):
            self.discard(self._jobs[job_id])

    def start(self, job: Job, future: asyncio.Future[dict[str, Any]]) -> None:
        """Follow the job's work; it ends (and its time to live starts) when the work does."""
        job.future = future
        future.add_done_callback(lambda _: job.ended_now())

    def close(self) -> None:
        """Cancel the work of every job not ended (the server stops)."""
        for job in self._jobs.values():
            if job.future is not None:
                job.future.cancel()


def answer(job_id: str, report: dict[str, Any]) -> dict[str, Any]:
    """A job's state, ``{"id", "state", "progress", "error", "info"}``, from its report: ``{}`` while queued, the frames
    ``{"done", "total"}`` while running, then ``"info"`` (what :func:`exprclone.server.work.video` returned) when done
    or ``"error"`` (:func:`job_error`) when failed. State is queued, running, done or failed; progress in [0, 1]."""
    out = {"id": job_id, "state": "queued", "progress": 0.0, "error": None, "info": None}
    if "total" in report:
        out.update(state="running", progress=report["done"] / max(report["total"], 1))
    if "info" in report:
        out.update(state="done", progress=1.0, info=report["info"])
    elif "error" in report:
        out.update(state="failed", error=report["error"])
    return out


def check_room(kept: list[tuple[float | None, str]], limit: int, ttl: float, client: str = "", per_client: int | None = None) -> None:
    """:class:`Busy` when ``limit`` jobs are kept (failed ones aside; ``kept`` is when each ended, None while queued or
    running, and whose it is), :class:`~exprclone.server.runtime.limits.TooMany` when ``per_client`` of them are
    ``client``'s: ``Retry-After`` the seconds until the first done one (of those that count) expires, or
    :data:`RETRY_RUNNING` while none is."""
    if len(kept) >= limit:
        wait, why = _room_in([ended for ended, _ in kept], ttl)
        raise Busy(f"{limit} video jobs are queued, running or kept; try again in {wait} s (when {why})", wait)
    own = [ended for ended, whose in kept if whose == client]
    if per_client is not None and len(own) >= per_client:
        wait, why = _room_in(own, ttl)
        raise share(per_client, "video jobs (queued, running or kept)", wait, why)


def _room_in(kept: list[float | None], ttl: float) -> tuple[int, str]:
    """Seconds until one of the jobs ``kept`` (when each ended, None while queued or running) gives its place, and when."""
    ends = [ended + ttl for ended in kept if ended is not None]
    wait = max(1, math.ceil(min(ends) - time.time())) if ends else RETRY_RUNNING
    return wait, "the first done one expires" if ends else "one ends"


def expired(jobs: list[tuple[str, float | None, bool]], ttl: float, now: float) -> list[str]:
    """The ids of the jobs to remove, of ``jobs`` (each ``(id, ended, failed)``, the oldest first): those that ended more
    than ``ttl`` seconds before ``now``, and the oldest failed ones beyond :data:`FAILED_KEPT`."""
    gone = [job_id for job_id, ended, _ in jobs if ended is not None and now - ended > ttl]
    failed = [job_id for job_id, _, failed in jobs if failed and job_id not in gone]
    return gone + failed[: max(len(failed) - FAILED_KEPT, 0)]


def job_error(error: BaseException) -> str:
    """What a failed job's state says of the error that ended it: a user's error (ExprCloneError) or a worker lost
    (:class:`~exprclone.server.runtime.limits.Busy`) as it is worded, any other as an internal error (its details are
    the server's log's, not a client's)."""
    return str(error) if isinstance(error, (ExprCloneError, Busy)) else "the job failed (internal error)"
