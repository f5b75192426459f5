"""Where ``exprclone serve --scheduler`` works (:class:`Cluster`): a Dask cluster, shared by every server started on it.

The work of each request (landmarks, a clone, a compare sheet, an edit's preparation, a video's probe) is a task
submitted to the cluster and awaited on the event loop: the web process only receives, checks and answers. A worker
loads the models once, as it joins (:class:`Models`, a worker plugin that every server registers, once). The bound on
the requests at work or waiting (``--workers`` + ``--queue``) is a Dask ``Semaphore`` on the scheduler, so it holds
across the servers; beyond it, the answer of one machine (503 and ``Retry-After``); a client's share of it is counted
by each server. The video jobs are the cluster's too (:mod:`exprclone.server.runtime.shared_jobs`).

What heals, and how a request hears of what does not:

- a worker lost while it runs a request: Dask runs the task again on another (the scheduler's ``allowed-failures``),
  then gives up (``KilledWorker``): 503, try again;
- no worker at all: a request's task waits for one at most ``--worker-wait`` seconds, then is cancelled: 503, saying so
  (:meth:`Cluster.problems` says it to the readiness probe meanwhile);
- the scheduler lost: once the Dask client has ended its own tries to reach it again, the connection (:class:`Link`:
  the client, the gate, the jobs) is dropped, and a new one is tried with a growing wait between tries
  (:data:`BACKOFF`) for as long as the server runs; meanwhile every request is answered 503 with the wait until the
  next try. A scheduler started again is known by its new id, even when the client reached it by itself, and joined
  afresh: the worker plugin registered, the gate and the jobs made again on it (its jobs were lost with it).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import IO, Any, TypeVar

import dask
from distributed import KilledWorker, Semaphore, WorkerPlugin
from distributed.client import FutureCancelledError

from ...cluster import CONNECT_TIMEOUT, connect_async, keep_buffers
from .. import work
from ..settings import Settings
from .limits import Busy, Gate, full
from .pools import WorkerLost
from .shared_jobs import SharedJobs

log = logging.getLogger("exprclone.server")
T = TypeVar("T")

#: the Dask priority of a request's task: ahead of the video jobs' (0) waiting for a worker, as a request is answered
#: while its client waits.
REQUEST_PRIORITY = 1
#: seconds between two looks at the connection to the scheduler.
WATCH_SECONDS = 0.5
#: seconds between tries to reach a lost scheduler: the first wait, doubled after each failed try up to the second.
BACKOFF = (0.5, 10.0)
#: seconds one try to reach a lost scheduler may take.
RECONNECT_TIMEOUT = 5.0
#: seconds between two looks at the cluster's workers while a request's task waits.
WORKER_POLL = 1.0


class Models(WorkerPlugin):  # type: ignore[misc]  # (distributed's classes are not followed: Any)
    """On each worker as it joins the cluster: the models loaded (:func:`exprclone.server.work.load_models`), the image
    buffers kept (:func:`exprclone.cluster.keep_buffers`)."""

    name = "exprclone-models"
    idempotent = True  # registered by each server; loaded once

    def setup(self, worker: Any) -> None:
        keep_buffers()
        work.load_models()
        if worker.state.nthreads > 1:
            log.warning(
                "worker %s runs %d threads: start it with --nthreads 1 (a process's threads wait on its landmarkers, one at a time)",
                worker.address,
                worker.state.nthreads,
            )


@dataclass
class Link:
    """A connection to the scheduler, and what the server keeps through it: the asynchronous ``distributed.Client``, the
    gate (a ``distributed.Semaphore`` of ``settings.workers + settings.queue`` leases, shared by the servers that have
    those settings), the jobs, and the id of the scheduler it was made with."""

    client: Any
    gate: Any
    jobs: SharedJobs
    scheduler: str

    @classmethod
    async def open(cls, settings: Settings, timeout: float) -> Link:
        """Connect to ``settings.scheduler`` within ``timeout`` seconds, and have every worker load the models (those
        that join later too); ExprCloneError if it cannot be reached."""
        assert settings.scheduler is not None
        client = await connect_async(settings.scheduler, settings.tls, timeout)
        try:
            await client.register_plugin(Models())
            limit = settings.workers + settings.queue
            gate = await Semaphore(limit, f"exprclone-requests-{limit}", scheduler_rpc=client.scheduler, loop=client.loop)
        except BaseException:
            await client.close()
            raise
        jobs = SharedJobs(client, settings.max_jobs, settings.job_ttl, settings.max_jobs_per_client)
        return cls(client, gate, jobs, client.scheduler_info().get("id"))

    @property
    def up(self) -> bool:
        """Connected, to the scheduler it was made with (not one started again since, which the client reached again)."""
        return bool(self.client.status == "running" and self.client.scheduler_info().get("id") == self.scheduler)

    async def close(self) -> None:
        self.jobs.close()
        self.gate.refresh_callback.stop()  # (not the gate's close: the other servers share it)
        with contextlib.suppress(Exception):
            await self.client.close()


class Cluster:
    """The Dask cluster of ``settings.scheduler``, connected when the server starts (:meth:`start`) and again whenever
    its scheduler is lost (see the module's notes); ``gate`` counts each client's share of the requests."""

    def __init__(self, settings: Settings, gate: Gate) -> None:
        self.settings, self.shares = settings, gate
        self.link: Link | None = None
        self.lost: float | None = None  # when the scheduler was lost (time.monotonic()), None while it is not
        self.next_try = 0.0  # when the next try to reach it is
        self.keeper: asyncio.Task[None] | None = None

    async def start(self) -> None:
        """Connect to the scheduler, and keep connected."""
        # a request's task carries its uploads: up to --max-upload-mb is what it is meant to send
        dask.config.set({"distributed.admin.large-graph-warning-threshold": f"{self.settings.max_upload_mb + 1}MiB"})
        self.link = await Link.open(self.settings, CONNECT_TIMEOUT)
        self.keeper = asyncio.create_task(self._keep())

    async def _keep(self) -> None:
        """Watch the link; once it is down and the client has stopped trying to reach the scheduler by itself (its tries
        cannot be stopped cleanly), open a new one (:meth:`_reopen`)."""
        while True:
            await asyncio.sleep(WATCH_SECONDS)
            link = self.link
            if link is not None and link.up and self.lost is not None:
                self.lost = None
                log.warning("reconnected to the Dask scheduler at %s", self.settings.scheduler)
            if link is None or link.up:
                continue
            if self.lost is None:
                self.lost = time.monotonic()
                log.error("lost the Dask scheduler at %s; reconnecting", self.settings.scheduler)
            if link.client.status != "connecting":
                await self._reopen(link)

    async def _reopen(self, old: Link) -> None:
        """Drop the link ``old``, and make a new one, the waits between tries growing (:data:`BACKOFF`)."""
        self.link = None
        await old.close()
        wait = BACKOFF[0]
        while self.link is None:
            self.next_try = time.monotonic() + wait
            await asyncio.sleep(wait)
            try:
                self.link = await Link.open(self.settings, RECONNECT_TIMEOUT)
            except Exception as e:  # (whatever stops this try: the next may succeed)
                log.info("the Dask scheduler is still unreachable (%s)", e)
                wait = min(2 * wait, BACKOFF[1])

    def _link(self) -> Link:
        """The link, or :class:`Busy` while the scheduler is lost: the wait until the next try to reach it."""
        if self.link is not None and self.link.up:
            return self.link
        now = time.monotonic()
        wait = max(1, math.ceil(self.next_try - now)) if self.link is None else 1
        since = f" {now - self.lost:.0f} s ago" if self.lost is not None else ""
        raise Busy(f"the server lost its cluster's scheduler{since} and is reconnecting; try again in {wait} s", wait)

    @contextlib.contextmanager
    def _reaching(self) -> Iterator[None]:
        """A block that talks to the scheduler: losing it there is :class:`Busy` (:meth:`_link`), not an internal error."""
        try:
            yield
        except OSError as e:  # (distributed's CommClosedError too)
            log.warning("a call to the scheduler failed (%s)", e)
            raise self._lost() from None

    def _lost(self) -> Busy:
        wait = max(1, math.ceil(BACKOFF[0]))
        return Busy(f"the server lost its cluster's scheduler and is reconnecting; try again in {wait} s", wait)

    async def run(self, client: str, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` on a worker of the cluster, past the cluster's gate as ``client``'s request; a lost worker's
        request refused (503), and one that waits for a worker on a cluster without any (:meth:`_awaited`)."""
        link = self._link()
        with self.shares.entered(client), self._reaching():
            if not await link.gate.acquire(timeout=0):
                raise full(link.gate.max_leases, self.shares.timing.retry_after(self.settings.workers))
            try:
                future = link.client.submit(function, *args, pure=False, priority=REQUEST_PRIORITY)
                result: T = await self._awaited(link, future)
                return result
            finally:
                with contextlib.suppress(Exception):
                    await link.gate.release()

    async def _awaited(self, link: Link, future: Any) -> Any:
        """A request's task's result; :class:`Busy` if its worker is lost (after Dask's tries), if the scheduler is, or if
        the cluster has had no worker for ``--worker-wait`` seconds while it waits (the task is then cancelled)."""
        task = asyncio.ensure_future(_result(future))
        alone: float | None = None  # since when the cluster has had no worker
        try:
            while not (await asyncio.wait({task}, timeout=WORKER_POLL))[0]:
                alone = await self._alone(link, alone)
            return task.result()
        except KilledWorker as e:
            raise WorkerLost(detail=f"{e.allowed_failures + 1} tries on the cluster") from None
        except FutureCancelledError as e:
            raise self._lost() if e.reason == "scheduler-connection-lost" else WorkerLost(detail=e.reason) from None
        finally:
            if not task.done():
                task.cancel()
                with contextlib.suppress(Exception):
                    await link.client.cancel([future])

    async def _alone(self, link: Link, since: float | None) -> float | None:
        """Since when the cluster has had no worker (None: it has some); :class:`Busy` once that is ``--worker-wait`` ago."""
        if (await link.client.scheduler.identity(n_workers=0))["n_workers"]:
            return None
        now = time.monotonic()
        wait = self.settings.worker_wait
        if since is not None and now - since >= wait:
            raise Busy(f"the cluster has no worker (none for {wait:g} s); try again in {math.ceil(wait)} s", math.ceil(wait))
        return now if since is None else since

    async def submit_video(self, client: str, request: work.VideoRequest, video: IO[bytes]) -> str:
        """A new video job of ``client`` (:class:`~exprclone.server.runtime.shared_jobs.SharedJobs`), its id; the driving
        video is probed first on a worker, sent as bytes: one that is not a video, or is over the limits, fails now, not
        in the job."""
        with self._reaching():
            await self._link().jobs.check(client)
        content = await asyncio.to_thread(video.read)
        fps = await self.run(client, work.probe_sent, content, request.limits)
        with self._reaching():
            return await self._link().jobs.submit(client, request, content, fps)

    async def video_state(self, job_id: str) -> dict[str, Any]:
        """A job's state, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        with self._reaching():
            return await self._link().jobs.state(job_id)

    async def video_result(self, job_id: str) -> bytes:
        """A done job's MP4, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        with self._reaching():
            return await self._link().jobs.result(job_id)

    async def problems(self) -> list[str]:
        """Why the server cannot serve now: the scheduler lost, or no worker on the cluster."""
        try:
            link = self._link()
            with self._reaching():
                workers = (await link.client.scheduler.identity(n_workers=0))["n_workers"]
        except Busy as e:
            return [str(e).split(";")[0]]
        return [] if workers else ["the cluster has no worker"]

    async def close(self) -> None:
        """Leave the cluster; the jobs go on there (:meth:`exprclone.server.runtime.shared_jobs.SharedJobs.close`)."""
        if self.keeper is not None:
            self.keeper.cancel()
        if self.link is not None:
            await self.link.close()


async def _result(future: Any) -> Any:
    return await future
