"""The state of a running ``exprclone serve`` (:class:`Work`): its temporary folder, worker pools, queue and jobs.

Kept below the application and its routes (:mod:`exprclone.server.app`, :mod:`exprclone.server.api`,
:mod:`exprclone.server.live`), which reach it through the FastAPI dependency :data:`Server`.
"""

from __future__ import annotations

import asyncio
import logging
import multiprocessing
import shutil
import tempfile
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Annotated, Any, TypeVar

from fastapi import Depends
from starlette.requests import HTTPConnection

from . import work
from .edits import Edits
from .jobs import Jobs
from .limits import Busy, Gate
from .rendering import Hosts
from .settings import Settings

log = logging.getLogger("exprclone.server")
T = TypeVar("T")


class Work:
    """The server's state: its temporary folder, the worker pools, the work queue's gate, the video jobs and the edits."""

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self.folder = Path(tempfile.mkdtemp(prefix="exprclone-serve-"))
        self.gate = Gate(settings.workers + settings.queue)
        self.jobs = Jobs(self.folder, settings.max_jobs, settings.job_ttl)
        self.pool = self._pool(settings.workers)
        self.video_pool = self._pool(settings.video_workers)
        self.edits = Edits(settings.max_edits, settings.edit_ttl)
        self.renders = ThreadPoolExecutor(settings.workers, thread_name_prefix="render")  # edits render in this process
        self.live_sessions = 0
        self.live_hosts = Hosts(settings.max_live)

    @staticmethod
    def _pool(workers: int) -> ProcessPoolExecutor:
        # spawned, not forked: the web process runs threads (the event loop, the pools' own)
        return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=work.load_models)

    def warm_up(self) -> None:
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

    async def render(self, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` on a render thread of this process (an edit's render, which holds its prepared clone), past
        the gate."""
        with self.gate:
            return await asyncio.get_running_loop().run_in_executor(self.renders, function, *args)

    def close(self) -> None:
        """Stop the workers and remove the temporary folder. The requests have been answered by then (uvicorn waits for
        them); a video job still queued is cancelled, and one still running is stopped: its result would go with the
        folder, and a Ctrl-C should not wait for it."""
        for pool in (self.pool, self.video_pool):
            processes = list(pool._processes.values())  # (Python 3.14's terminate_workers does this)
            pool.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                process.terminate()
                process.join()
        self.live_hosts.close()
        self.renders.shutdown(wait=False, cancel_futures=True)
        shutil.rmtree(self.folder, ignore_errors=True)


def the_server(connection: HTTPConnection) -> Work:
    """The server's state (:class:`Work`, made when it starts), for a route or a WebSocket: a FastAPI dependency."""
    work: Work = connection.app.state.work
    return work


#: a route's parameter for the server's state (:func:`the_server`).
Server = Annotated[Work, Depends(the_server)]
