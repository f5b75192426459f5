"""Where a plain ``exprclone serve`` works (:class:`Processes`): pools of worker processes on its own machine, and its
video jobs in its temporary folder.

The other place is a Dask cluster (``serve --scheduler``, :class:`exprclone.server.runtime.cluster.Cluster`); both offer the
server the same calls.
"""

from __future__ import annotations

import asyncio
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any, TypeVar

from .. import work
from ..settings import Settings
from . import lifeline
from .jobs import Jobs
from .limits import Gate
from .pools import Pool

T = TypeVar("T")


class Processes:
    """The clone workers and the video workers (each a :class:`~exprclone.server.runtime.pools.Pool` that heals), each
    loading the models once; the video jobs (:class:`~exprclone.server.runtime.jobs.Jobs`) under the server's temporary
    folder (:func:`~exprclone.server.runtime.lifeline.own_folder`: swept at the next start if this server is killed).

    Parameters
    ----------
    settings : Settings
    gate : Gate
        The server's bound on requests at work or waiting, which the clone workers' requests pass.
    """

    def __init__(self, settings: Settings, gate: Gate) -> None:
        self.settings, self.gate = settings, gate
        self.folder, self._lock = lifeline.own_folder()
        self.jobs = Jobs(self.folder, settings.max_jobs, settings.job_ttl, settings.max_jobs_per_client)
        self.pool = Pool(settings.workers, "clone")
        self.video_pool = Pool(settings.video_workers, "video")

    async def start(self) -> None:
        """Start every clone worker now (each loads the models as it starts); the video workers start with the first job."""
        await self.pool.start()

    async def run(self, client: str, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` in a clone worker, past the gate as ``client``'s request; a worker that dies under it: 503
        (:class:`~exprclone.server.runtime.pools.WorkerLost`), and it is replaced."""
        with self.gate.entered(client):
            return await self.pool.run(function, *args)

    async def submit_video(self, client: str, request: work.VideoRequest, video: IO[bytes]) -> str:
        """A new video job of ``client`` driving ``request``'s portrait by ``video`` (an upload's file), its id; refused
        when ``--max-jobs`` are kept, or the client's share. The video is saved in the job's folder and probed in a clone
        worker first: one that is not a video, or is over the limits, fails now, not in the job."""
        job = self.jobs.create(client)
        try:
            with job.video.open("wb") as out:
                await asyncio.to_thread(shutil.copyfileobj, video, out)
            fps = await self.run(client, work.probe_video, str(job.video), request.limits)
            clip = work.Clip(str(job.video), fps, str(job.result))
            progress = work.ProgressFile(str(job.progress_file))
            self.jobs.start(job, asyncio.ensure_future(self.video_pool.run(work.video, request, clip, progress, what="this job")))
        except BaseException:
            self.jobs.discard(job)
            raise
        return job.id

    async def video_state(self, job_id: str) -> dict[str, Any]:
        """A job's state (:meth:`exprclone.server.runtime.jobs.Job.state`), or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        self.jobs.expire()
        return self.jobs.get(job_id).state()

    async def video_result(self, job_id: str) -> Path:
        """A done job's MP4, or :class:`~exprclone.server.runtime.jobs.NoSuchJob`."""
        return self.jobs.get(job_id).result

    async def problems(self) -> list[str]:
        """Why the server cannot serve now (:mod:`exprclone.server.routers.health`): no clone worker ready, or no video
        worker once they have started."""
        return [problem for pool in (self.pool, self.video_pool) if pool.workers and (problem := pool.problem())]

    async def close(self) -> None:
        """Stop the workers and remove the temporary folder. A video job still queued is cancelled, and one still
        running is stopped: its result would go with the folder, and a Ctrl-C should not wait for it."""
        self.jobs.close()
        for pool in (self.pool, self.video_pool):
            pool.close()
        shutil.rmtree(self.folder, ignore_errors=True)
        self._lock.close()
