"""A pool of worker processes that heals (:class:`Pool`): a worker that dies (killed, or out of memory) fails only the
work it was running, and is replaced.

Python's :class:`~concurrent.futures.ProcessPoolExecutor` is broken for good once one of its processes dies, and fails
every piece of work it holds, running or waiting. So each worker here is an executor of one process
(:class:`Worker`), and the work waits in the pool's own queue for an idle worker (first come, first served): a death
breaks one executor, fails the one piece of work it ran (:class:`WorkerLost`), and that worker is started again, its
models loaded as at start-up. A worker found dead while idle is replaced too, by the pool's watch (every
:data:`WATCH_SECONDS`) or when work is given to it. Workers are started on the event loop's thread, and tied to the
server's life (:mod:`.lifeline`).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import multiprocessing
import os
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing.process import BaseProcess
from typing import Any, TypeVar

from .. import work
from . import lifeline
from .limits import Busy

log = logging.getLogger("exprclone.server")
T = TypeVar("T")

#: seconds between two looks of a pool at its idle workers.
WATCH_SECONDS = 1.0
#: seconds a client is told to wait after a worker died under its request: about the time a new one takes to start.
RETRY_LOST = 5


class WorkerLost(Busy):
    """A worker process died while it ran the work (killed, or out of memory): answered 503, or a video job's error."""

    def __init__(self, what: str = "this request", detail: str = "killed, or out of memory") -> None:
        super().__init__(f"a worker stopped unexpectedly while running {what} ({detail}); try again", RETRY_LOST)


@dataclass
class Worker:
    """One worker process, in an executor of its own; ``started`` is its first task (its models loaded), its PID."""

    executor: ProcessPoolExecutor
    process: BaseProcess
    started: asyncio.Future[int]

    @classmethod
    def spawn(cls) -> Worker:
        """A new worker, starting (from the running event loop)."""
        spawned = multiprocessing.get_context("spawn")  # not forked: the web process runs threads
        executor = ProcessPoolExecutor(1, mp_context=spawned, initializer=lifeline.start_worker, initargs=(os.getpid(),))
        started = asyncio.wrap_future(executor.submit(work.ready))  # (the submit starts the process)
        started.add_done_callback(lambda f: f.cancelled() or f.exception())  # (a failed start is seen by ready, not logged)
        (process,) = executor._processes.values()
        return cls(executor, process, started)

    @property
    def loaded(self) -> bool:
        """It started, and loaded its models."""
        return self.started.done() and not self.started.cancelled() and self.started.exception() is None

    @property
    def ready(self) -> bool:
        """Alive, its models loaded."""
        return self.loaded and self.process.is_alive()

    def stop(self) -> None:
        """End the process now (a video job it runs is stopped)."""
        self.executor.shutdown(wait=False, cancel_futures=True)
        self.process.terminate()
        self.process.join()


class Pool:
    """``size`` worker processes (:class:`Worker`) that load the models once each, healed as the module's notes say;
    ``name`` says what they run, in the log and in the readiness."""

    def __init__(self, size: int, name: str) -> None:
        self.size, self.name = size, name
        self.workers: list[Worker] = []
        self.idle: asyncio.Queue[int] = asyncio.Queue()
        self.busy: set[int] = set()
        self.watch: asyncio.Task[None] | None = None

    def spawn(self) -> None:
        """Start every worker (each loads the models as it starts), once; the pool's watch with them."""
        if self.workers:
            return
        self.workers = [Worker.spawn() for _ in range(self.size)]
        for number in range(self.size):
            self.idle.put_nowait(number)
        self.watch = asyncio.create_task(self._watch())

    async def start(self) -> None:
        """Start every worker now (:meth:`spawn`), and return once each has loaded the models."""
        self.spawn()
        await asyncio.gather(*(worker.started for worker in self.workers))

    async def run(self, function: Callable[..., T], *args: Any, what: str = "this request") -> T:
        """``function(*args)`` in the next idle worker (the workers started if they are not: :meth:`spawn`);
        :class:`WorkerLost` (``what`` it was running) if it dies meanwhile."""
        self.spawn()
        number = await self.idle.get()
        self.busy.add(number)
        try:
            worker = self._alive(number)
            try:
                future = worker.executor.submit(function, *args)
            except BrokenProcessPool:  # died since: nothing of this work ran
                future = self._replace(number).executor.submit(function, *args)
            try:
                return await asyncio.wrap_future(future)
            except BrokenProcessPool:
                log.error("a %s worker died while running %s; starting another", self.name, what)
                self._replace(number)
                raise WorkerLost(what) from None
        finally:
            self.busy.discard(number)
            self.idle.put_nowait(number)

    def _alive(self, number: int) -> Worker:
        worker = self.workers[number]
        return worker if worker.process.is_alive() or not worker.started.done() else self._replace(number)

    def _replace(self, number: int) -> Worker:
        with contextlib.suppress(Exception):
            self.workers[number].stop()
        self.workers[number] = Worker.spawn()
        return self.workers[number]

    async def _watch(self) -> None:
        """Replace the idle workers found dead once they had started (a worker at work is replaced when its work fails;
        one that could not start, when work is given to it)."""
        while True:
            await asyncio.sleep(WATCH_SECONDS)
            for number in set(range(self.size)) - self.busy:
                worker = self.workers[number]
                if worker.loaded and not worker.process.is_alive():
                    log.error("an idle %s worker died; starting another", self.name)
                    self._replace(number)

    def problem(self) -> str | None:
        """Why this pool cannot work now (none of its workers ready), None when it can."""
        ready = sum(worker.ready for worker in self.workers)
        return None if ready else f"no {self.name} worker is ready ({len(self.workers)} starting)"

    def close(self) -> None:
        """Stop every worker now (the work they run is stopped)."""
        if self.watch is not None:
            self.watch.cancel()
        for worker in self.workers:
            worker.stop()
