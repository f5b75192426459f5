"""Where ``exprclone serve --scheduler`` works (:class:`Cluster`): a Dask cluster, shared by every server started on it.

The work of each request (landmarks, a clone, a compare sheet, an edit's preparation, a video's probe) is a task
submitted to the cluster and awaited on the event loop: the web process only receives, checks and answers. A worker
loads the models once, as it joins (:class:`Models`, a worker plugin that every server registers, once). The bound on
the requests at work or waiting (``--workers`` + ``--queue``) is a Dask ``Semaphore`` on the scheduler, so it holds
across the servers; beyond it, the answer of one machine (503 and ``Retry-After``). A worker lost while it runs a
request: Dask runs the task again on another (the scheduler's ``allowed-failures``), then gives up (``KilledWorker``):
503, try again. The video jobs are the cluster's too (:mod:`exprclone.server.runtime.shared_jobs`).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import IO, Any, TypeVar

import dask
from distributed import KilledWorker, Semaphore, WorkerPlugin
from distributed.client import FutureCancelledError

from ...cluster import connect_async, keep_buffers
from .. import work
from ..settings import Settings
from .limits import Busy, full
from .shared_jobs import SharedJobs

log = logging.getLogger("exprclone.server")
T = TypeVar("T")

#: the Dask priority of a request's task: ahead of the video jobs' (0) waiting for a worker, as a request is answered
#: while its client waits.
REQUEST_PRIORITY = 1


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
                "worker %s runs %d threads: start it with --nthreads 1 (a landmarker is shared by the threads of a process)",
                worker.address,
                worker.state.nthreads,
            )


class Cluster:
    """The Dask cluster of ``settings.scheduler``, connected when the server starts (:meth:`start`).

    Attributes
    ----------
    client : distributed.Client
        Asynchronous.
    gate : distributed.Semaphore
        ``settings.workers + settings.queue`` leases, shared by the servers that have those settings.
    jobs : SharedJobs
    """

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self.client: Any = None
        self.gate: Any = None
        self.jobs: SharedJobs

    async def start(self) -> None:
        """Connect to the scheduler, and have every worker load the models (those that join later too)."""
        assert self.settings.scheduler is not None
        # a request's task carries its uploads: up to --max-upload-mb is what it is meant to send
        dask.config.set({"distributed.admin.large-graph-warning-threshold": f"{self.settings.max_upload_mb + 1}MiB"})
        self.client = await connect_async(self.settings.scheduler)
        await self.client.register_plugin(Models())
        limit = self.settings.workers + self.settings.queue
        self.gate = await Semaphore(limit, f"exprclone-requests-{limit}", scheduler_rpc=self.client.scheduler, loop=self.client.loop)
        self.jobs = SharedJobs(self.client, self.settings.max_jobs, self.settings.job_ttl)

    async def run(self, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` on a worker of the cluster, past the cluster's gate; a lost worker's request refused (503)."""
        if not await self.gate.acquire(timeout=0):
            raise full(self.gate.max_leases)
        try:
            return await self.client.submit(function, *args, pure=False, priority=REQUEST_PRIORITY)
        except (KilledWorker, FutureCancelledError) as e:
            log.error("a request's task was lost (%s)", e)
            raise Busy("a worker stopped unexpectedly; try again") from None
        finally:
            await self.gate.release()

    async def submit_video(self, request: work.VideoRequest, video: IO[bytes]) -> str:
        """A new video job (:class:`~exprclone.server.runtime.shared_jobs.SharedJobs`), its id; the driving video is probed
        first on a worker, sent as bytes: one that is not a video, or is over the limits, fails now, not in the job."""
        await self.jobs.check()
        content = await asyncio.to_thread(video.read)
        fps = await self.run(work.probe_sent, content, request.limits)
        return await self.jobs.submit(request, content, fps)

    async def video_state(self, job_id: str) -> dict[str, Any]:
        """A job's state, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        return await self.jobs.state(job_id)

    async def video_result(self, job_id: str) -> bytes:
        """A done job's MP4, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        return await self.jobs.result(job_id)

    async def close(self) -> None:
        """Leave the cluster; the jobs go on there (:meth:`exprclone.server.runtime.shared_jobs.SharedJobs.close`)."""
        self.jobs.close()
        await self.client.close()  # (not the gate's close: the other servers share it)
