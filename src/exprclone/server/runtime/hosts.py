"""The host processes live sessions render in: each session in a process of its own, off the web process's GIL.

A live session (:class:`exprclone.server.session.Session`) renders every camera frame in
Python and numpy; sessions run as threads of the web process would share one
interpreter lock, and two at once would each get about half the frames they get alone.
So each session's state and work live in a host process (:class:`Hosts`): the web
process keeps a stand-in (:class:`RemoteSession`) whose calls, made from the
connection's thread as before, send their arguments to the host and wait for the answer
(the wait releases the lock). A host serves one session at a time; hosts are
started with the server (each loads the models once, which takes seconds), another when
a session finds none idle, and each is kept for the next session when its own ends. The protocol
(:mod:`exprclone.server.routers.live`) is the same whichever process renders.

A host renders on one thread: OpenCV's own worker threads (one per core by default) would
compete with the other sessions' hosts for the same cores, and wait on each other. The gain
is small against this machine's noise: two sessions at 512 pixels, with and without in turn
(five runs of each, the browsers on the same two cores), delivered a median of 15.0 and
14.4 frames a second each.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
import weakref
from collections.abc import Callable
from multiprocessing.connection import Connection
from typing import Any

import cv2
import numpy as np

from ...errors import ExprCloneError
from ...io.images import load_image
from ...options import Options
from ..session import Session
from .lifeline import start_worker


def serve(connection: Connection, parent: int) -> None:
    """A host process's loop: ``("start", (portrait bytes, max_pixels, arguments of Session))``, then calls of the
    session's methods ``(name, arguments)``, then ``("end", ())``; each answered ``("ok", result)`` or ``("error", e)``.
    It ends with the server ``parent`` (:mod:`exprclone.server.runtime.lifeline`)."""
    cv2.setNumThreads(1)  # the session's frames are small: its other cores serve the other sessions (module docstring)
    start_worker(parent)
    session: Session | None = None
    while True:
        try:
            name, arguments = connection.recv()
        except EOFError:  # the web process went
            return
        try:
            if name == "start":
                session = None
                portrait, max_pixels, rest = arguments
                session = Session(load_image(portrait, name="portrait", max_pixels=max_pixels), *rest)
                result: Any = session.portrait.shape
            elif name == "end":
                session, result = None, None
            else:
                result = getattr(session, name)(*arguments)
            connection.send(("ok", result))
        except Exception as e:  # the session's errors go back to the connection that caused them
            connection.send(("error", e))


class Host:
    """One host process and the pipe to it."""

    def __init__(self) -> None:
        self.connection, child = multiprocessing.get_context("spawn").Pipe()
        spawned = multiprocessing.get_context("spawn")
        self.process = spawned.Process(target=serve, args=(child, os.getpid()), daemon=True, name="exprclone-live")
        self.process.start()
        child.close()
        self._lock = threading.Lock()  # one call at a time on the pipe, whichever thread makes it

    def call(self, name: str, *arguments: Any) -> Any:
        """Run ``name`` in the host and wait for its result; its exception is raised here."""
        try:
            with self._lock:
                self.connection.send((name, arguments))
                status, result = self.connection.recv()
        except (EOFError, OSError):
            raise ExprCloneError("live", "the session's renderer stopped; start the session again") from None
        if status == "error":
            raise result
        return result

    def stop(self) -> None:
        self.connection.close()
        self.process.join(timeout=5)
        if self.process.is_alive():
            self.process.kill()


class Hosts:
    """The host processes of a server's live sessions: at most ``size`` (``Settings.max_live``), kept between sessions."""

    def __init__(self, size: int) -> None:
        self.size = size
        self._idle: list[Host] = [Host() for _ in range(size)]  # started now: a process takes seconds to load the models
        self._lock = threading.Lock()

    def session(self, portrait: bytes, max_pixels: int | None, options: Options, size: int) -> RemoteSession:
        """A session started in an idle host (a new one if none is): ``options`` and ``size`` are :class:`Session`'s."""
        with self._lock:
            host = self._idle.pop() if self._idle else None
        host = host or Host()
        try:
            shape = host.call("start", portrait, max_pixels, (options, size))
        except BaseException:
            self.give_back(host)
            raise
        return RemoteSession(host, shape, options, self.give_back)

    def give_back(self, host: Host) -> None:
        """Keep a host whose session ended for the next one, if it is still alive and fewer than ``size`` are idle."""
        with self._lock:
            if host.process.is_alive() and len(self._idle) < self.size:
                self._idle.append(host)
                return
        host.stop()

    def close(self) -> None:
        """Stop every idle host (those still serving a session stop when their connection closes)."""
        with self._lock:
            idle, self._idle = self._idle, []
        for host in idle:
            host.stop()


class RemoteSession(Session):
    """A :class:`Session` that lives in a host process: the same methods, each run there.

    ``portrait`` has the portrait's shape only (its pixels stay in the host); ``options``
    follow :meth:`change`. :meth:`close` ends the session and gives the host back (also
    done when the stand-in is dropped without it).
    """

    def __init__(self, host: Host, shape: tuple[int, ...], options: Options, give_back: Callable[[Host], None]) -> None:
        self._host, self.options = host, options
        self.portrait = np.broadcast_to(np.zeros((1, 1, 3), np.uint8), shape)
        self._closer = weakref.finalize(self, RemoteSession._end, host, give_back)

    @staticmethod
    def _end(host: Host, give_back: Callable[[Host], None]) -> None:
        try:
            host.call("end")
        except ExprCloneError:
            host.stop()
            return
        give_back(host)

    def close(self) -> None:
        """End the session in its host and give the host back (once; later calls do nothing)."""
        self._closer()

    def process(self, content: bytes, t: float) -> tuple[bytes, dict[str, Any]]:
        result: tuple[bytes, dict[str, Any]] = self._host.call("process", content, t)
        return result

    def recapture(self, now: bool = False) -> None:
        self._host.call("recapture", now)

    def change(self, options: Options) -> None:
        self._host.call("change", options)
        self.options = options
