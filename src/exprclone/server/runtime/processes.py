"""Where a plain ``exprclone serve`` works (:class:`Processes`): pools of worker processes on its own machine, and its
video jobs in its temporary folder.

The other place is a Dask cluster (``serve --scheduler``, :class:`exprclone.server.runtime.cluster.Cluster`); both offer the
server the same calls.
"""

from __future__ import annotations

import asyncio
import logging
import multiprocessing
import shutil
import tempfile
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import IO, Any, TypeVar

from .. import work
from ..settings import Settings
from .jobs import Jobs
from .limits import Busy, Gate

log = logging.getLogger("exprclone.server")
T = TypeVar("T")


class Processes:
    """The clone workers and the video workers (:class:`~concurrent.futures.ProcessPoolExecutor`), each loading the
    models once; the video jobs (:class:`~exprclone.server.runtime.jobs.Jobs`) under a temporary folder.

    Parameters
    ----------
    settings : Settings
    gate : Gate
        The server's bound on requests at work or waiting, which the clone workers' requests pass.
    """

    def __init__(self, settings: Settings, gate: Gate) -> None:
        self.settings, self.gate = settings, gate
        self.folder = Path(tempfile.mkdtemp(prefix="exprclone-serve-"))
        self.jobs = Jobs(self.folder, settings.max_jobs, settings.job_ttl)
        self.pool = self._pool(settings.workers)
        self.video_pool = self._pool(settings.video_workers)

    @staticmethod
    def _pool(workers: int) -> ProcessPoolExecutor:
        # spawned, not forked: the web process runs threads (the event loop, the pools' own)
        return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=work.load_models)

    async def start(self) -> None:
        """Start every clone worker now (each loads the models as it starts)."""
        for future in [self.pool.submit(work.ready) for _ in range(self.settings.workers)]:
            future.result()

    async def run(self, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` in a clone worker, past the gate; a broken pool is replaced and the request refused (503)."""
        with self.gate:
            try:
                return await asyncio.get_running_loop().run_in_executor(self.pool, function, *args)
            except BrokenProcessPool:
                log.error("a worker process died; starting new ones")
                self.pool.shutdown(wait=False, cancel_futures=True)
                self.pool = self._pool(self.settings.workers)
                raise Busy("a worker stopped unexpectedly; try again") from None

    async def submit_video(self, request: work.VideoRequest, video: IO[bytes]) -> str:
        """A new video job driving ``request``'s portrait by ``video`` (an upload's file), its id; :class:`Busy` when
        ``--max-jobs`` are kept. The video is saved in the job's folder and probed in a clone worker first: one that
        is not a video, or is over the limits, fails now, not in the job."""
        job = self.jobs.create()
        try:
            with job.video.open("wb") as out:
                await asyncio.to_thread(shutil.copyfileobj, video, out)
            fps = await self.run(work.probe_video, str(job.video), request.limits)
            clip = work.Clip(str(job.video), fps, str(job.result))
            self.jobs.start(job, self.video_pool.submit(work.video, request, clip, work.ProgressFile(str(job.progress_file))))
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

    async def close(self) -> None:
        """Stop the workers and remove the temporary folder. A video job still queued is cancelled, and one still
        running is stopped: its result would go with the folder, and a Ctrl-C should not wait for it."""
        for pool in (self.pool, self.video_pool):
            processes = list(pool._processes.values())  # (Python 3.14's terminate_workers does this)
            pool.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                process.terminate()
                process.join()
        shutil.rmtree(self.folder, ignore_errors=True)
