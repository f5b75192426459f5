"""Video jobs: each in a folder of its own under the server's temporary folder, bounded in number, expiring.

A job is created with its inputs saved in its folder, runs in the video worker
(:func:`exprclone.server.work.video`), reports its progress in a file there, and is
removed :data:`Jobs.ttl` seconds after it ends (or at shutdown). Job ids are random
(128 bits) and checked against their form before any path is built from them.
"""

from __future__ import annotations

import json
import re
import secrets
import shutil
import time
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .limits import Busy

#: a job id: 32 hex digits.
JOB_ID = re.compile(r"[0-9a-f]{32}")


class NoSuchJob(Exception):
    """An id that is malformed, unknown or expired: answered 404."""


@dataclass
class Job:
    """One video job.

    Attributes
    ----------
    id : str
    folder : Path
        Holds the driving video, the progress file and the result.
    created : float
        When it was created (``time.time()``).
    future : Future or None
        The work, once submitted.
    ended : float or None
        When its work ended.
    """

    id: str
    folder: Path
    created: float = field(default_factory=time.time)
    future: Future[dict[str, Any]] | None = None
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
        from ..errors import ExprCloneError

        out = {"id": self.id, "state": "queued", "progress": 0.0, "error": None, "info": None}
        if self.progress_file.exists():
            report = json.loads(self.progress_file.read_text())
            out.update(state="running", progress=report["done"] / max(report["total"], 1))
        if self.future is not None and self.future.done():
            error = self.future.exception()
            if error is None:
                out.update(state="done", progress=1.0, info=self.future.result())
            else:
                out.update(state="failed", error=str(error) if isinstance(error, ExprCloneError) else "the job failed (internal error)")
        return out


class Jobs:
    """The server's video jobs, at most ``limit`` of them kept, each for ``ttl`` seconds after it ends.

    Parameters
    ----------
    root : Path
        The server's temporary folder; jobs live in ``root/jobs/<id>``.
    limit : int
    ttl : float
    """

    def __init__(self, root: Path, limit: int, ttl: float) -> None:
        self.root, self.limit, self.ttl = root / "jobs", limit, ttl
        self.root.mkdir(parents=True, exist_ok=True)
        self._jobs: dict[str, Job] = {}

    def create(self) -> Job:
        """A new job with its folder, or :class:`Busy` when ``limit`` jobs are kept already."""
        self.expire()
        if len(self._jobs) >= self.limit:
            raise Busy(f"{self.limit} video jobs are kept already; try again when one has expired (after {self.ttl:g} s)")
        job = Job(secrets.token_hex(16), Path())
        job.folder = self.root / job.id
        job.folder.mkdir()
        self._jobs[job.id] = job
        return job

    def get(self, job_id: str) -> Job:
        """The job, or :class:`NoSuchJob`."""
        if not JOB_ID.fullmatch(job_id) or job_id not in self._jobs:
            raise NoSuchJob(f"no job {job_id!r} (unknown, or expired after {self.ttl:g} s)")
        return self._jobs[job_id]

    def discard(self, job: Job) -> None:
        """Remove a job and its folder (a job that could not be started)."""
        self._jobs.pop(job.id, None)
        shutil.rmtree(job.folder, ignore_errors=True)

    def expire(self, now: float | None = None) -> None:
        """Remove the jobs that ended more than ``ttl`` seconds ago."""
        now = time.time() if now is None else now
        for job in list(self._jobs.values()):
            if job.ended is not None and now - job.ended > self.ttl:
                self.discard(job)

    def start(self, job: Job, future: Future[dict[str, Any]]) -> None:
        """Follow the job's work; it ends (and its time to live starts) when the work does."""
        job.future = future
        future.add_done_callback(lambda _: setattr(job, "ended", time.time()))
