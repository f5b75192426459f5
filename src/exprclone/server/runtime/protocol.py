"""The rules of the live protocol (:mod:`exprclone.server.routers.live`) that hold whatever the session does: the kinds and
shapes of messages, a frame's bounds, the session slots, and how a breach is answered (an error, then a close).

Everything here is checked at the door, in the event loop, before any work: a frame's size is read
from its header before it is decoded, a text message's length before it is parsed.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import json
import struct
from collections import Counter
from typing import Any, Literal, overload

from fastapi import WebSocket, WebSocketDisconnect
from PIL import Image, UnidentifiedImageError

from ...errors import ExprCloneError
from ...io.documents import parse_json
from ...io.images import check_size
from ...options import Framing, Options, expected, json_kinds
from .state import Work

#: the sequence number before each frame.
SEQUENCE = struct.Struct(">I")
#: seconds a new connection has to send its start message and its portrait; then it is closed.
START_SECONDS = 10.0
#: the text messages a client may send.
TYPES = ("start", "neutral", "options")
#: the longest text message, in characters.
MAX_TEXT = 4096
#: the JSON type(s) of each field a start or options message may carry: the options offered to JSON messages.
FIELDS = {"type": (str,), **json_kinds(Options), **json_kinds(Framing)}
#: close codes (RFC 6455, 7.4.1): a message of the wrong kind (text for binary, or the reverse); any other breach of the
#: protocol (a bad message, no start in time); every session slot taken.
UNSUPPORTED, POLICY, TRY_LATER = 1003, 1008, 1013
#: the longest close reason (a close frame's reason has at most 123 bytes).
MAX_REASON = 100


class Misuse(ExprCloneError):
    """A message the protocol does not allow where it came: answered with an error, then the connection closed with ``code``."""

    def __init__(self, subject: str, problem: str, code: int = POLICY) -> None:
        super().__init__(subject, problem)
        self.code = code


def check_message(message: dict[str, Any]) -> dict[str, Any]:
    """A start or options message whose fields have their JSON types (:data:`FIELDS`), or :class:`Misuse` about the first that has not."""
    for key, kinds in FIELDS.items():
        value = message.get(key)
        if value is None:
            continue
        if isinstance(value, bool) is not (kinds == (bool,)) or not isinstance(value, kinds):
            raise Misuse(key, f"must be {expected(kinds)}, got {json.dumps(value)[:40]}")
        if key == "only" and isinstance(value, list) and not all(isinstance(name, str) for name in value):
            raise Misuse(key, "must be a list of region names")
    return message


def parse_message(text: str) -> dict[str, Any]:
    """A text message: a JSON object with a known ``type`` and fields of the right types, or :class:`Misuse` about ``live``."""
    try:
        message = parse_json(text, "live") if len(text) <= MAX_TEXT else None
    except ExprCloneError:
        message = None
    if not isinstance(message, dict):
        raise Misuse("live", f"a text message must be a JSON object of at most {MAX_TEXT} characters")
    if message.get("type") not in TYPES:
        raise Misuse("live", f"unknown message type {json.dumps(message.get('type'))[:40]}; choose one of {', '.join(TYPES)}")
    return check_message(message)


def check_frame(content: bytes, max_pixels: int | None) -> None:
    """A frame message: a 4-byte number and a JPEG or PNG whose size, read from its header, passes an upload's checks
    (:func:`exprclone.io.images.check_size`) before it is decoded; else :class:`Misuse` about ``frame``."""
    image = content[SEQUENCE.size :]
    try:
        with Image.open(io.BytesIO(image)) as header:
            (width, height), kind = header.size, header.format
    except Image.DecompressionBombError:
        raise Misuse("frame", "image is too large (a decompression bomb: more pixels than Pillow decodes)") from None
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError):
        kind = None
    if kind not in ("JPEG", "PNG"):
        raise Misuse("frame", "a frame is a 4-byte sequence number and a JPEG or PNG image")
    try:
        check_size(width, height, "frame", max_pixels)
    except ExprCloneError as e:
        raise Misuse(e.subject, e.problem) from None


@overload
async def receive(websocket: WebSocket, kind: Literal["text"], deadline: float | None = None) -> str: ...
@overload
async def receive(websocket: WebSocket, kind: Literal["bytes"], deadline: float | None = None) -> bytes: ...
async def receive(websocket: WebSocket, kind: str, deadline: float | None = None) -> str | bytes:
    """The next message, which must be ``kind`` (text or bytes); by ``deadline`` (the loop's time), else :class:`Misuse`."""
    loop = asyncio.get_running_loop()
    try:
        message = await asyncio.wait_for(websocket.receive(), None if deadline is None else max(deadline - loop.time(), 0))
    except asyncio.TimeoutError:
        raise Misuse("live", f"no start message and portrait within {START_SECONDS:g} s") from None
    if message["type"] == "websocket.disconnect":
        raise WebSocketDisconnect(message.get("code", 1000))
    if message.get(kind) is None:
        what = {"text": "a JSON text message", "bytes": "a binary message (the portrait, or a frame)"}[kind]
        raise Misuse("live", f"expected {what}, got a {'binary' if kind == 'text' else 'text'} message", UNSUPPORTED)
    content: str | bytes = message[kind]
    return content


async def refuse(websocket: WebSocket, error: ExprCloneError, code: int) -> None:
    """The error as a message, then the close with ``code``; nothing if the client has gone already."""
    with contextlib.suppress(WebSocketDisconnect, RuntimeError, OSError):
        await websocket.send_json({"type": "error", "error": str(error)})
        await websocket.close(code, reason=error.problem[:MAX_REASON])


class Slots:
    """The live sessions of the server (``Work.live_sessions``, by client: at most ``Settings.max_live``, and
    ``Settings.max_live_per_client`` of one client): one taken by a connection from its start message, given back when it
    closes."""

    def __init__(self, work: Work, client: str) -> None:
        self.work, self.client, self.held = work, client, False

    def take(self) -> None:
        """A slot for this connection, or :class:`Misuse` (try again later) when every one is taken, or the client's share."""
        limit, share = self.work.settings.max_live, self.work.settings.max_live_per_client
        sessions = self.work.live_sessions
        if limit == 0:
            raise Misuse("live", "live mode is off on this server (serve --max-live 0)", POLICY)
        if sessions.total() >= limit:
            raise Misuse("live", f"{limit} sessions are running already; try again later", TRY_LATER)
        if sessions[self.client] >= share:
            raise Misuse("live", f"this client runs {share} sessions already, its share; try again later", TRY_LATER)
        sessions[self.client] += 1
        self.held = True

    def release(self) -> None:
        if self.held:
            self.work.live_sessions[self.client] -= 1
            self.work.live_sessions += Counter()  # (a client with none is forgotten)
            self.held = False
