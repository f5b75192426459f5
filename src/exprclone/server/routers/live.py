"""Live: a portrait that follows a webcam, frame by frame, over a WebSocket (``/api/live``, the page ``/live``).

The protocol. The page sends a text message ``{"type": "start", "method", "mouth",
"size", "lambda", "landmarker"}`` (and any of ``strength``, ``only``, ``retarget``, ``global_warp``, ``image_warp``:
the options of :class:`exprclone.options.Options`), then the portrait as one binary message; the server answers
``{"type": "ready", "width", "height"}`` or ``{"type": "error", "error"}``. Then each
camera frame goes as a binary message: a 4-byte big-endian sequence number and a JPEG
(at most the output size); the answer is the same number and the output frame as JPEG.
``{"type": "neutral"}`` re-captures the neutral face from the next frame;
``{"type": "options", "method", "mouth"}`` changes the method (and with ``strength`` or
``only``, what is transferred: the same neutral face, prepared again). ``{"type": "status",
"face", "neutral", "lambda_k"}`` says when the face is lost or found, when the
neutral face is captured, and when lambda_k is chosen.

lambda_k "auto" is chosen once, by the DB metric, on the first frame whose expression
is clearly strong (:data:`LAMBDA_STRENGTH`); until then the status says ``"auto"`` and
the elastic model runs with ``lambda_k = 0``, which gives the global positions GI
(:class:`Session`).

Misuse. A connection holds a session slot from its start message on, and must send that
message and the portrait within :data:`START_SECONDS`, and then a frame at least every
``Settings.live_idle`` seconds (``--live-idle``). A message of the wrong kind (binary
where text goes, or the reverse), text that is not a JSON object of a known ``type`` with
fields of the right JSON types (:data:`FIELDS`, nested at most
:data:`exprclone.io.documents.MAX_DEPTH` deep), a frame that is not a JPEG or PNG within
the uploads' size bounds (read from its header, before decoding), a start the server cannot
use (a bad option, a portrait without a face), no frame for ``live_idle`` seconds, or a start when every slot is taken is
answered by ``{"type": "error", "error"}``, then the connection is closed with a code of
RFC 6455: 1003 (wrong kind), 1013 (no slot free: try again later) or 1008 (anything else).
A bad value in an ``options`` message (an unknown method, a strength out of range) is
answered by the error alone, and the session goes on as it was.

No backlog: the server keeps only the newest frame of a connection, and drops the
older ones unanswered (the page sends the next frame once an answer arrives, with a
small window). Each connection's state (tracker, filter, prepared faces) lives in a
process of its own (:mod:`exprclone.server.runtime.hosts`: off the web process's interpreter
lock, so that sessions at once do not share one core), and goes when it closes; the
process is kept for the next session; at most ``Settings.max_live`` run at once.
"""

from __future__ import annotations

import asyncio
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from ...errors import ExprCloneError, quoted
from ...options import Framing, Options, from_json
from ..runtime.clients import HEADER, client_of
from ..runtime.protocol import POLICY, SEQUENCE, START_SECONDS, Misuse, Slots, check_frame, parse_message, receive, refuse
from ..runtime.state import Server
from ..session import SIZES, Session

router = APIRouter()


async def _start(websocket: WebSocket, executor: ThreadPoolExecutor, slots: Slots) -> Session:
    """Read the start message (which takes a slot) and the portrait, within :data:`START_SECONDS`; prepare the session
    (in its host process, :mod:`exprclone.server.runtime.hosts`)."""
    deadline = asyncio.get_running_loop().time() + START_SECONDS
    start = parse_message(await receive(websocket, "text", deadline))
    if start["type"] != "start":
        raise Misuse("live", 'the first message must be {"type": "start", ...}')
    options, size = Options.from_json(start), from_json(Framing, start).size
    if size not in SIZES:
        raise ExprCloneError("size", f"must be one of {', '.join(map(str, SIZES))}, got {quoted(size)}")
    slots.take()
    portrait = await receive(websocket, "bytes", deadline)
    loop = asyncio.get_running_loop()
    hosts, max_pixels = slots.work.live_hosts, slots.work.settings.max_pixels
    session: Session = await loop.run_in_executor(executor, lambda: hosts.session(portrait, max_pixels, options, size))
    return session


@router.websocket("/api/live")
async def live(websocket: WebSocket, server: Server) -> None:
    """A live session (the protocol is in the module's notes)."""
    await websocket.accept()
    slots = Slots(server, "")
    executor = ThreadPoolExecutor(1, thread_name_prefix="live")
    try:
        slots.client = client_of(websocket, websocket.headers.get(HEADER), server.settings.api_keys)
        session = await _start(websocket, executor, slots)
        await websocket.send_json({"type": "ready", "width": session.portrait.shape[1], "height": session.portrait.shape[0]})
        await _follow(websocket, session, executor, server.settings.max_pixels, server.settings.live_idle)
    except ExprCloneError as e:
        await refuse(websocket, e, e.code if isinstance(e, Misuse) else POLICY)
    except WebSocketDisconnect:
        pass
    finally:
        slots.release()
        executor.shutdown(wait=False, cancel_futures=True)


async def _follow(websocket: WebSocket, session: Session, executor: ThreadPoolExecutor, max_pixels: int | None, idle: float) -> None:
    """Receive frames, keep only the newest, answer each one processed; until the page goes, breaks the protocol, or
    sends no frame for ``idle`` seconds."""
    newest: list[bytes] = []
    arrived = asyncio.Event()
    loop = asyncio.get_running_loop()
    tasks = [
        asyncio.create_task(_receive(websocket, session, executor, max_pixels, idle, newest, arrived)),
        asyncio.create_task(_answer(websocket, session, executor, newest, arrived)),
    ]
    try:
        done, _ = await asyncio.wait(tasks, return_when=asyncio.FIRST_EXCEPTION)
        for task in done:
            task.result()
    finally:
        for task in tasks:
            task.cancel()
        loop.run_in_executor(None, session.close)  # after the frame in hand, if any: its host is free for the next session


async def _receive(
    websocket: WebSocket,
    session: Session,
    executor: ThreadPoolExecutor,
    max_pixels: int | None,
    idle: float,
    newest: list[bytes],
    arrived: asyncio.Event,
) -> None:
    """Take each message: a frame checked and kept as the ``newest`` (an older one not yet taken is dropped), ``arrived``
    set; a text message handled between frames (:func:`_control`); :class:`Misuse` after ``idle`` seconds without a frame."""
    loop = asyncio.get_running_loop()
    last = loop.time()
    while True:
        try:
            message = await asyncio.wait_for(websocket.receive(), timeout=max(last + idle - loop.time(), 0.0))
        except asyncio.TimeoutError:
            raise Misuse("live", f"no frame for {idle:g} s: the session ends and its slot is free") from None
        if message["type"] == "websocket.disconnect":
            raise WebSocketDisconnect(message.get("code", 1000))
        if message.get("bytes") is not None:
            last = loop.time()
            check_frame(message["bytes"], max_pixels)
            newest[:] = [message["bytes"]]
            arrived.set()
        elif message.get("text") is not None:
            try:
                await _control(session, executor, parse_message(message["text"]))
            except Misuse:
                raise
            except ExprCloneError as e:
                await websocket.send_json({"type": "error", "error": str(e)})


async def _answer(
    websocket: WebSocket, session: Session, executor: ThreadPoolExecutor, newest: list[bytes], arrived: asyncio.Event
) -> None:
    """Process the newest frame each time one arrives, and send its output (and the session's status when it changes)."""
    loop = asyncio.get_running_loop()
    shown = None
    while True:
        await arrived.wait()
        arrived.clear()
        content = newest.pop()
        sequence = content[: SEQUENCE.size]
        try:
            image, status = await loop.run_in_executor(executor, session.process, content[SEQUENCE.size :], time.monotonic())
        except ExprCloneError as e:
            await websocket.send_json({"type": "error", "error": str(e)})
            continue
        if status != shown:
            await websocket.send_json(status)
            shown = status
        await websocket.send_bytes(sequence + image)


async def _control(session: Session, executor: ThreadPoolExecutor, message: dict[str, Any]) -> None:
    """A text message after the start: ``neutral`` or ``options`` (run between frames, where the session renders)."""
    loop = asyncio.get_running_loop()
    if message["type"] == "neutral":
        await loop.run_in_executor(executor, lambda: session.recapture(now=True))
    elif message["type"] == "options":
        options = Options.from_json(message, session.options)
        await loop.run_in_executor(executor, session.change, options)
    else:
        raise Misuse("live", f"a {message['type']} message comes only first")
