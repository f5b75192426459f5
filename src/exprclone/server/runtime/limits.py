"""What keeps a user from making the server hold unbounded memory or work, and one client from taking every place: the
upload limit, the work queue with each client's share of it, a client's pace, and how a refusal says when to come back."""

from __future__ import annotations

import contextlib
import json
import math
import statistics
import threading
import time
from collections import Counter, deque
from collections.abc import Iterator

from starlette.types import ASGIApp, Message, Receive, Scope, Send

#: seconds a client is told to wait (``Retry-After``) when the work queue is full and no request has been timed yet.
RETRY_AFTER = 2
#: the requests whose times :class:`Timing` keeps.
TIMED = 32


class Busy(Exception):
    """The server cannot take the request now (its work queue is full, a worker stopped, no worker is there): answered
    503 with ``Retry-After: retry_after`` (seconds; the message says why, and the same wait)."""

    def __init__(self, message: str, retry_after: int = RETRY_AFTER) -> None:
        super().__init__(message)
        self.retry_after = retry_after


class Timing:
    """How long the last :data:`TIMED` requests took at work or waiting, to say honestly when a full queue has room:
    about when one of those at work ends (:meth:`retry_after`)."""

    def __init__(self) -> None:
        self.seconds: deque[float] = deque(maxlen=TIMED)

    @contextlib.contextmanager
    def timed(self) -> Iterator[None]:
        start = time.monotonic()
        try:
            yield
        finally:
            self.seconds.append(time.monotonic() - start)

    def retry_after(self, workers: int) -> int:
        """Seconds until a place is likely free: a typical request's time (the median) shared by ``workers`` at work."""
        if not self.seconds:
            return RETRY_AFTER
        return max(1, math.ceil(statistics.median(self.seconds) / max(workers, 1)))


def full(limit: int, wait: int = RETRY_AFTER) -> Busy:
    """What a request is answered when ``limit`` requests are at work or waiting already (on this server, or on a Dask
    cluster: :class:`exprclone.server.runtime.cluster.Cluster`), told to come back in ``wait`` seconds."""
    return Busy(f"the server is busy ({limit} requests at work or waiting); try again in {wait} s", wait)


def share(client_limit: int, what: str, wait: int, when: str = "") -> TooMany:
    """What a client is answered when it holds ``client_limit`` of ``what`` already (its share), told to come back in
    ``wait`` seconds (``when`` says what frees a place): 429, whatever the others hold."""
    said = f" (when {when})" if when else ""
    return TooMany(f"this client holds {client_limit} {what} already, its share; try again in {wait} s{said}", wait)


class Paced:
    """At most ``count`` of a kind of request per client address in ``seconds``; the next is refused, answered 429 with
    ``Retry-After`` (:class:`TooMany`). At most ``clients`` addresses are remembered (the oldest forgotten first).

    Routes that count run in FastAPI's thread pool: one lock makes each count whole (parallel requests of one client
    are counted one after another, not all against the same past).
    """

    def __init__(self, count: int, seconds: float, clients: int = 10_000) -> None:
        self.count, self.seconds, self.clients = count, seconds, clients
        self.seen: dict[str, list[float]] = {}
        self.lock = threading.Lock()

    def admit(self, client: str, now: float) -> None:
        """Count a request of ``client`` at ``now`` (seconds), or :class:`TooMany` if it has had ``count`` already."""
        with self.lock:
            self._admit(client, now)

    def _admit(self, client: str, now: float) -> None:
        times = [t for t in self.seen.pop(client, []) if t > now - self.seconds]
        if len(times) >= self.count:
            self.seen[client] = times
            raise TooMany(f"at most {self.count} per {self.seconds:g} s from one address", int(times[0] + self.seconds - now) + 1)
        self.seen[client] = times + [now]
        while len(self.seen) > self.clients:
            del self.seen[next(iter(self.seen))]


class TooMany(Exception):
    """A client asked too often (:class:`Paced`): answered 429 with ``Retry-After: retry_after`` seconds."""

    def __init__(self, message: str, retry_after: int) -> None:
        super().__init__(message)
        self.retry_after = retry_after


class Gate:
    """At most ``limit`` requests at work or waiting for a worker, and ``per_client`` of one client; the next is refused
    (:class:`Busy`, or for the client :class:`TooMany`), told when a place is likely free (:class:`Timing`:
    ``workers`` work at once).

    Used from the event loop only, so plain counters are safe.
    """

    def __init__(self, limit: int, workers: int, per_client: int) -> None:
        self.limit, self.workers, self.per_client = limit, workers, per_client
        self.inside: Counter[str] = Counter()
        self.timing = Timing()

    @contextlib.contextmanager
    def entered(self, client: str) -> Iterator[None]:
        """Inside the gate for the block, as ``client``'s request."""
        wait = self.timing.retry_after(self.workers)
        if self.inside[client] >= self.per_client:
            raise share(self.per_client, "requests at work or waiting", wait)
        if self.inside.total() >= self.limit:
            raise full(self.limit, wait)
        self.inside[client] += 1
        try:
            with self.timing.timed():
                yield
        finally:
            self.inside[client] -= 1
            if not self.inside[client]:
                del self.inside[client]


async def _answer(send: Send, status: int, error: str) -> None:
    body = json.dumps({"error": error}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


class UploadLimit:
    """ASGI middleware: a request body over ``max_bytes`` is answered 413, as it streams in.

    A declared ``Content-Length`` over the limit is refused before any of the body is
    read; otherwise the bytes are counted as they arrive, and at the first byte over the
    limit reading stops and the answer is 413, whatever the application was doing with
    the body (its own answer, if any, is dropped).
    """

    def __init__(self, app: ASGIApp, max_bytes: int) -> None:
        self.app, self.max_bytes = app, max_bytes
        size = f"{max_bytes / 2**20:g} MB" if max_bytes >= 2**20 else f"{max_bytes / 2**10:g} KB"
        self.error = f"upload too large: at most {size} per request"

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        declared = dict(scope["headers"]).get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.max_bytes:
            return await _answer(send, 413, self.error)
        state: dict[str, int | bool] = {"received": 0, "over": False, "answered": False}

        async def counted() -> Message:
            message = await receive()
            state["received"] += len(message.get("body", b""))
            if state["received"] > self.max_bytes:
                state["over"] = True
                raise OverLimit
            return message

        async def guarded(message: Message) -> None:
            if not state["over"]:
                return await send(message)
            if not state["answered"] and message["type"] == "http.response.start":
                state["answered"] = True
                await _answer(send, 413, self.error)

        try:
            await self.app(scope, counted, guarded)
        except Exception:
            if not state["over"]:
                raise
        if state["over"] and not state["answered"]:
            await _answer(send, 413, self.error)


class OverLimit(Exception):
    """Raised into the application when the body grows over the limit, to stop it reading."""
