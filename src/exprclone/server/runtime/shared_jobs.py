"""Video jobs kept on a Dask cluster (:class:`SharedJobs`), shared by every server started on it: a job submitted to
one is followed and fetched from any other.

A job lives on the scheduler under a name made from its id (``exprclone-job-<id>``):

- a published dataset of its two futures: the task (:func:`exprclone.server.work.video_sent`, the driving video's
  bytes sent with it, the MP4's bytes and the info its result) and a small one that takes the info from it. Any server
  fetches the result from there; the dataset keeps both alive until the job expires.
- two Dask ``Variable`` objects: its progress, the frames ``{"done", "total"}`` as the worker renders them
  (:class:`Progress`), and its ending: ``{}`` until it ends, then ``"info"`` or ``"error"`` and the time it
  ``"ended"``, written by a server that watched it end. (A done job whose worker is lost later is run again at once,
  its result wanted: its progress is written again, its ending stays.)

Every server watches the jobs it submits and those it sees unfinished (it awaits their info), and the first to see
one end writes its ending: a job ends while any server lives that has seen it, and a server started later takes over
the jobs of one that stopped, when it first lists them. A worker lost while it runs a job: Dask runs the task again on
another (the scheduler's ``allowed-failures``, 3 by default), then gives up (``KilledWorker``), and the job fails
with an error that says so (:data:`WORKER_LOST`); it is never left running.

The bound (``--max-jobs``) counts the published jobs, checked and published under a Dask ``Lock``, so that it holds
across the servers; what a full store answers, when a job expires (``--job-ttl`` after it ends) and how many failed
ones are kept are the rules of one server's store (:func:`~exprclone.server.runtime.jobs.check_room`,
:func:`~exprclone.server.runtime.jobs.expired`).
"""

from __future__ import annotations

import asyncio
import math
import operator
import secrets
import time
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from distributed import KilledWorker, Lock, Variable, get_client
from distributed.client import FutureCancelledError

from .. import work
from .jobs import JOB_ID, NoSuchJob, answer, check_room, expired, job_error

#: the start of a job's names on the scheduler (its dataset, its ending and its progress); its id follows.
PREFIX = "exprclone-job-"
#: a job's error when the workers that ran it were lost, each while it ran.
WORKER_LOST = "the job failed: its worker stopped unexpectedly while running it ({tries} tries on the cluster); submit it again"


@dataclass(frozen=True)
class Progress:
    """A job's progress, written into its Variable ``name`` by the worker that renders it
    (:data:`exprclone.server.work.Report`)."""

    name: str

    def __call__(self, done: int, total: int) -> None:
        Variable(self.name, client=get_client()).set({"done": done, "total": total})


class SharedJobs:
    """The video jobs on the cluster of ``client`` (a ``distributed.Client``, asynchronous), at most ``limit`` kept by
    all its servers together, each ``ttl`` seconds after it ends.

    Parameters
    ----------
    client : distributed.Client
    limit : int
    ttl : float
    """

    def __init__(self, client: Any, limit: int, ttl: float) -> None:
        self.client, self.limit, self.ttl = client, limit, ttl
        self.lock = Lock("exprclone-jobs", scheduler_rpc=client.scheduler, loop=client.loop)
        self.endings: dict[str, dict[str, Any]] = {}  # the reports of ended jobs read (an ending is written once)
        self.watched: dict[str, asyncio.Task[None]] = {}

    def _ending(self, job_id: str) -> Any:
        return Variable(PREFIX + job_id, client=self.client)

    def _progress(self, job_id: str) -> Any:
        return Variable(f"{PREFIX}{job_id}-progress", client=self.client)

    async def _read(self, job_id: str) -> dict[str, Any] | None:
        """A job's report: its ending, or while it has none its progress; None once it is removed."""
        try:
            ending: dict[str, Any] = await self._ending(job_id).get(timeout=0)
            return ending or await self._progress(job_id).get(timeout=0)
        except asyncio.TimeoutError:  # (both are set before the job is published, and deleted after it is removed)
            return None

    async def check(self) -> None:
        """:class:`~exprclone.server.runtime.limits.Busy` when ``limit`` jobs are kept now: checked before a job's video is
        received and probed, and again as it is submitted."""
        self._check_room(await self.reports())

    def _check_room(self, reports: dict[str, dict[str, Any]]) -> None:
        check_room([report.get("ended") for report in reports.values() if "error" not in report], self.limit, self.ttl)

    async def submit(self, request: work.VideoRequest, content: bytes, fps: Fraction) -> str:
        """A new job driving ``request``'s portrait by the video of ``content`` (its frame rate ``fps``), its id; Busy
        when ``limit`` jobs are kept."""
        job_id = secrets.token_hex(16)
        async with self.lock:
            self._check_room(await self.reports())
            await asyncio.gather(self._ending(job_id).set({}), self._progress(job_id).set({}))
            progress = Progress(self._progress(job_id).name)
            task = self.client.submit(work.video_sent, request, content, fps, progress, key=f"exprclone-video-{job_id}")
            info = self.client.submit(operator.itemgetter(0), task, key=f"exprclone-video-info-{job_id}")
            await self.client.publish_dataset((task, info), name=PREFIX + job_id)
        self._watch(job_id, info)
        return job_id

    async def reports(self) -> dict[str, dict[str, Any]]:
        """Every job's report, by id, once the expired ones are removed; the unfinished ones watched."""
        ids = [str(name).removeprefix(PREFIX) for name in await self.client.list_datasets() if str(name).startswith(PREFIX)]
        unread = [job_id for job_id in ids if job_id not in self.endings]
        found = {job_id: self.endings[job_id] for job_id in ids if job_id in self.endings}
        read = await asyncio.gather(*map(self._read, unread))
        found.update({job_id: report for job_id, report in zip(unread, read) if report is not None})
        oldest_first = sorted(found.items(), key=lambda item: item[1].get("ended", math.inf))
        gone = expired([(job_id, report.get("ended"), "error" in report) for job_id, report in oldest_first], self.ttl, time.time())
        for job_id in gone:
            await self.client.unpublish_dataset(PREFIX + job_id)
            self._ending(job_id).delete()
            self._progress(job_id).delete()
        kept = {job_id: report for job_id, report in found.items() if job_id not in gone}
        self.endings = {job_id: report for job_id, report in kept.items() if "ended" in report}
        for job_id in [job_id for job_id in kept if job_id not in self.endings and job_id not in self.watched]:
            _, info = await self.client.get_dataset(PREFIX + job_id, default=(None, None))
            if info is not None:
                self._watch(job_id, info)
        return kept

    def _watch(self, job_id: str, info: Any) -> None:
        if job_id not in self.watched:
            self.watched[job_id] = asyncio.create_task(self._end(job_id, info))

    async def _end(self, job_id: str, info: Any) -> None:
        """Await a job's end (its ``info`` future), and write it in its report: done with its info, or failed with
        what ended it."""
        try:
            try:
                ending = {"info": await info}
            except KilledWorker as e:
                ending = {"error": WORKER_LOST.format(tries=e.allowed_failures + 1)}
            except FutureCancelledError:  # this server lost the scheduler, not the job its worker: watched again when seen
                return
            except Exception as e:
                ending = {"error": job_error(e)}
            await self._ending(job_id).set({**ending, "ended": time.time()})
        finally:
            self.watched.pop(job_id, None)

    async def state(self, job_id: str) -> dict[str, Any]:
        """A job's state (:func:`~exprclone.server.runtime.jobs.answer`), or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        reports = await self.reports() if JOB_ID.fullmatch(job_id) else {}
        if job_id not in reports:
            raise NoSuchJob.of(job_id, self.ttl)
        return answer(job_id, reports[job_id])

    async def result(self, job_id: str) -> bytes:
        """A done job's MP4, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        task, _ = await self.client.get_dataset(PREFIX + job_id, default=(None, None)) if JOB_ID.fullmatch(job_id) else (None, None)
        if task is None:
            raise NoSuchJob.of(job_id, self.ttl)
        _, mp4 = await task
        return mp4

    def close(self) -> None:
        """Stop watching (the jobs go on, on the cluster: another server, or this one started again, ends them)."""
        for watch in self.watched.values():
            watch.cancel()
