"""Video jobs kept on a Dask cluster (:class:`SharedJobs`), shared by every server started on it: a job submitted to
one is followed and fetched from any other.

A job lives on the scheduler under a name made from its id's SHA-256 digest (``exprclone-job-<digest>``, :func:`key_of`),
never its id: the id is what reads a job's state and result, and only the client that made the job is told it, while
the names on a scheduler show on its dashboard and to any of its clients.

- a published dataset of its two futures: the task (:func:`exprclone.server.work.video_sent`, the driving video's
  bytes sent with it, the MP4's bytes and the info its result) and a small one that takes the info from it. Any server
  fetches the result from there; the dataset keeps both alive until the job expires.
- two Dask ``Variable`` objects: its progress, the frames ``{"done", "total"}`` as the worker renders them
  (:class:`Progress`), and its ending: its ``"client"`` (the name of :mod:`exprclone.server.runtime.clients`, which
  counts the job in that client's share) until it ends, then also ``"info"`` or ``"error"`` and the time it
  ``"ended"``, written by a server that watched it end. (A done job whose worker is lost later is run again at once,
  its result wanted: its progress is written again, its ending stays.)

Every server watches the jobs it submits and those it sees unfinished (it awaits their info), and the first to see
one end writes its ending: a job ends while any server lives that has seen it, and a server started later takes over
the jobs of one that stopped, when it first lists them. A worker lost while it runs a job: Dask runs the task again on
another (the scheduler's ``allowed-failures``, 3 by default), then gives up (``KilledWorker``), and the job fails
with an error that says so (:class:`~exprclone.server.runtime.pools.WorkerLost`); it is never left running.

The bound (``--max-jobs``) and a client's share (``--max-jobs-per-client``) count the published jobs, checked and
published under a Dask ``Lock``, so that they hold across the servers; what a full store answers, when a job expires
(``--job-ttl`` after it ends) and how many failed ones are kept are the rules of one server's store
(:func:`~exprclone.server.runtime.jobs.check_room`, :func:`~exprclone.server.runtime.jobs.expired`).
"""

from __future__ import annotations

import asyncio
import hashlib
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
from .pools import WorkerLost

#: the start of a job's names on the scheduler (its dataset, its ending and its progress); its key follows (:func:`key_of`).
PREFIX = "exprclone-job-"


def key_of(job_id: str) -> str:
    """What names a job on the scheduler: its id's SHA-256 digest (32 hex digits), from which the id cannot be found."""
    return hashlib.sha256(job_id.encode()).hexdigest()[:32]


@dataclass(frozen=True)
class Progress:
    """A job's progress, written into its Variable ``name`` by the worker that renders it
    (:data:`exprclone.server.work.Report`)."""

    name: str

    def __call__(self, done: int, total: int) -> None:
        Variable(self.name, client=get_client()).set({"done": done, "total": total})


class SharedJobs:
    """The video jobs on the cluster of ``client`` (a ``distributed.Client``, asynchronous), at most ``limit`` kept by
    all its servers together and ``per_client`` of one of their clients, each ``ttl`` seconds after it ends. Jobs are
    known here by their keys (:func:`key_of`), and found by their ids.

    Parameters
    ----------
    client : distributed.Client
    limit : int
    ttl : float
    per_client : int
    """

    def __init__(self, client: Any, limit: int, ttl: float, per_client: int | None = None) -> None:
        self.client, self.limit, self.ttl, self.per_client = client, limit, ttl, per_client or limit
        self.lock = Lock("exprclone-jobs", scheduler_rpc=client.scheduler, loop=client.loop)
        self.endings: dict[str, dict[str, Any]] = {}  # the reports of ended jobs read (an ending is written once)
        self.watched: dict[str, asyncio.Task[None]] = {}

    def _ending(self, key: str) -> Any:
        return Variable(PREFIX + key, client=self.client)

    def _progress(self, key: str) -> Any:
        return Variable(f"{PREFIX}{key}-progress", client=self.client)

    async def _read(self, key: str) -> dict[str, Any] | None:
        """A job's report: its ending once it has one, else its client and progress; None once it is removed."""
        try:
            ending: dict[str, Any] = await self._ending(key).get(timeout=0)
            return ending if "ended" in ending else {**ending, **await self._progress(key).get(timeout=0)}
        except asyncio.TimeoutError:  # (both are set before the job is published, and deleted after it is removed)
            return None

    async def check(self, client: str) -> None:
        """:class:`~exprclone.server.runtime.limits.Busy` when ``limit`` jobs are kept now, or ``TooMany`` when
        ``client``'s share is: checked before a job's video is received and probed, and again as it is submitted."""
        self._check_room(await self.reports(), client)

    def _check_room(self, reports: dict[str, dict[str, Any]], client: str) -> None:
        kept = [(report.get("ended"), report.get("client", "")) for report in reports.values() if "error" not in report]
        check_room(kept, self.limit, self.ttl, client, self.per_client)

    async def submit(self, client: str, request: work.VideoRequest, content: bytes, fps: Fraction) -> str:
        """A new job of ``client`` driving ``request``'s portrait by the video of ``content`` (its frame rate ``fps``),
        its id; refused when ``limit`` jobs are kept, or the client's share."""
        job_id = secrets.token_hex(16)
        key = key_of(job_id)
        async with self.lock:
            self._check_room(await self.reports(), client)
            await asyncio.gather(self._ending(key).set({"client": client}), self._progress(key).set({}))
            progress = Progress(self._progress(key).name)
            task = self.client.submit(work.video_sent, request, content, fps, progress, key=f"exprclone-video-{key}")
            info = self.client.submit(operator.itemgetter(0), task, key=f"exprclone-video-info-{key}")
            await self.client.publish_dataset((task, info), name=PREFIX + key)
        self._watch(key, client, info)
        return job_id

    async def reports(self) -> dict[str, dict[str, Any]]:
        """Every job's report, by key, once the expired ones are removed; the unfinished ones watched."""
        keys = [str(name).removeprefix(PREFIX) for name in await self.client.list_datasets() if str(name).startswith(PREFIX)]
        unread = [key for key in keys if key not in self.endings]
        found = {key: self.endings[key] for key in keys if key in self.endings}
        read = await asyncio.gather(*map(self._read, unread))
        found.update({key: report for key, report in zip(unread, read) if report is not None})
        oldest_first = sorted(found.items(), key=lambda item: item[1].get("ended", math.inf))
        gone = expired([(key, report.get("ended"), "error" in report) for key, report in oldest_first], self.ttl, time.time())
        for key in gone:
            await self.client.unpublish_dataset(PREFIX + key)
            self._ending(key).delete()
            self._progress(key).delete()
        kept = {key: report for key, report in found.items() if key not in gone}
        self.endings = {key: report for key, report in kept.items() if "ended" in report}
        for key in [key for key in kept if key not in self.endings and key not in self.watched]:
            _, info = await self.client.get_dataset(PREFIX + key, default=(None, None))
            if info is not None:
                self._watch(key, kept[key].get("client", ""), info)
        return kept

    def _watch(self, key: str, client: str, info: Any) -> None:
        if key not in self.watched:
            self.watched[key] = asyncio.create_task(self._end(key, client, info))

    async def _end(self, key: str, client: str, info: Any) -> None:
        """Await a job's end (its ``info`` future), and write it in its report: done with its info, or failed with
        what ended it (and still ``client``'s)."""
        try:
            try:
                ending = {"info": await info}
            except KilledWorker as e:
                ending = {"error": str(WorkerLost("this job", f"{e.allowed_failures + 1} tries on the cluster"))}
            except FutureCancelledError:  # this server lost the scheduler, not the job its worker: watched again when seen
                return
            except Exception as e:
                ending = {"error": job_error(e)}
            await self._ending(key).set({**ending, "client": client, "ended": time.time()})
        finally:
            self.watched.pop(key, None)

    async def state(self, job_id: str) -> dict[str, Any]:
        """A job's state (:func:`~exprclone.server.runtime.jobs.answer`), or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        reports = await self.reports() if JOB_ID.fullmatch(job_id) else {}
        if key_of(job_id) not in reports:
            raise NoSuchJob.of(job_id, self.ttl)
        return answer(job_id, reports[key_of(job_id)])

    async def result(self, job_id: str) -> bytes:
        """A done job's MP4, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        found = JOB_ID.fullmatch(job_id)
        task, _ = await self.client.get_dataset(PREFIX + key_of(job_id), default=(None, None)) if found else (None, None)
        if task is None:
            raise NoSuchJob.of(job_id, self.ttl)
        _, mp4 = await task
        return mp4

    def close(self) -> None:
        """Stop watching (the jobs go on, on the cluster: another server, or this one started again, ends them)."""
        for watch in self.watched.values():
            watch.cancel()
