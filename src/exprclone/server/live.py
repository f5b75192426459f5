"""Live: a portrait that follows a webcam, frame by frame, over a WebSocket (``/api/live``, the page ``/live``).

The protocol. The page sends a text message ``{"type": "start", "method", "mouth",
"size", "lambda"}`` (and any of ``strength``, ``only``, ``retarget``, ``global_warp``, ``image_warp``:
the options of :class:`exprclone.options.Options`), then the portrait as one binary message; the server answers
``{"type": "ready", "width", "height"}`` or ``{"type": "error", "error"}``. Then each
camera frame goes as a binary message: a 4-byte big-endian sequence number and a JPEG
(at most the output size); the answer is the same number and the output frame as JPEG.
``{"type": "neutral"}`` re-captures the neutral face from the next frame;
``{"type": "options", "method", "mouth"}`` changes the method (and with ``strength`` or
``only``, what is transferred: the same neutral face, prepared again). ``{"type": "status",
"face", "neutral", "lambda_k"}`` says when the face is lost or found, and when the
neutral face is captured.

No backlog: the server keeps only the newest frame of a connection, and drops the
older ones unanswered (the page sends the next frame once an answer arrives, with a
small window). Each connection's state (tracker, filter, prepared faces) lives in a
thread of its own, and goes when it closes; at most ``Settings.max_live`` run at once.
"""

from __future__ import annotations

import asyncio
import json
import struct
import time
from concurrent.futures import ThreadPoolExecutor

import cv2
import numpy as np
from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from .. import drive, tracking
from ..checks import check_lambda, check_options
from ..errors import ExprCloneError
from ..layout import DLIB68
from ..methods import lookup
from ..mouth import opening
from .api import parse_lambda

router = APIRouter()

#: the neutral face is the frame whose mouth is most closed over this many seconds from the first face.
NEUTRAL_SECONDS = 1.0
#: lambda_k "auto" is chosen once, by the DB metric, on the first frame whose expression is this strong (inter-ocular distances).
LAMBDA_STRENGTH = 0.03
#: quality of the JPEG frames sent back.
JPEG_QUALITY = 85
#: output sizes a session may ask for (the portrait's longest side).
SIZES = (256, 512)
#: the sequence number before each frame.
SEQUENCE = struct.Struct(">I")
#: the options of :class:`exprclone.options.Options` a start or options message may carry (GI from a file aside).
TRANSFER = ("global_warp", "image_warp", "strength", "only", "retarget")


def decode_jpeg(content: bytes) -> np.ndarray:
    """A camera frame (JPEG or PNG) as ``(H, W, 3)`` uint8 RGB, or ExprCloneError about ``frame``."""
    image = cv2.imdecode(np.frombuffer(content, np.uint8), cv2.IMREAD_COLOR)
    if image is None:
        raise ExprCloneError("frame", "not a JPEG or PNG image")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def encode_jpeg(image: np.ndarray) -> bytes:
    return cv2.imencode(".jpg", cv2.cvtColor(image, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])[1].tobytes()


class Session:
    """One camera following one portrait: the state of one connection, used from one thread.

    Parameters
    ----------
    portrait : ndarray of shape (H, W, 3), uint8 RGB
    method, mouth, lambda_k
        As for :class:`exprclone.drive.Driver`; ``lambda_k="auto"`` is chosen once (:data:`LAMBDA_STRENGTH`).
    size : int
        The output's longest side.
    transfer : dict, optional
        Options of :class:`exprclone.options.Options` (:data:`TRANSFER`) for the prepared faces.
    """

    def __init__(
        self, portrait: np.ndarray, method: str, mouth: bool, lambda_k: float | str, size: int, transfer: dict | None = None
    ) -> None:
        from ..pipeline import default_detector

        self.method, self.mouth, self.lambda_k = lookup((method,))[0].name, mouth, check_lambda(lambda_k)
        self.detector = default_detector()
        self.portrait, _ = drive.resize_portrait(portrait, None, size)
        self.transfer = self._checked(transfer or {})
        self.portrait_points = self.detector.detect(self.portrait, "portrait")
        self.tracker, self.filter = tracking.Tracker(self.detector), tracking.OneEuro()
        self.last = self.portrait
        self.recapture()

    def recapture(self, now: bool = False) -> None:
        """Capture the neutral face again: from the next frame with a face (``now``), or the most closed mouth of the next second."""
        self.driver: drive.Driver | None = None
        self.chosen: float | str = self.lambda_k
        self.window: tuple[float, float, np.ndarray, np.ndarray] | None = None  # (start, opening, frame, points) of the best so far
        self.now = now

    def _checked(self, transfer: dict) -> dict:
        """The transfer options, checked on the portrait as a :class:`~exprclone.pipeline.Cloner` would (ExprCloneError)."""
        check_options(transfer, DLIB68.n_points, self.portrait.shape, tuple(DLIB68.regions))
        return transfer

    def options(self, method: str, mouth: bool, transfer: dict | None = None) -> None:
        """Another method or mouth setting, for the same faces; other transfer options prepare the same faces again."""
        self.method, self.mouth = lookup((method,))[0].name, mouth
        changed = transfer is not None and transfer != self.transfer
        if changed:
            self.transfer = self._checked(transfer)
        if self.driver is not None:
            cloner = self._cloner() if changed else self.driver.cloner
            self.driver = drive.Driver(cloner, self.method, self._lambda_for_driver(), mouth=self.mouth)

    def _cloner(self):
        """The camera's neutral face (the window's frame) and the portrait, prepared with the transfer options."""
        from ..pipeline import Cloner

        return Cloner(self.window[2], self.window[3], self.portrait, self.portrait_points, **self.transfer)

    def _lambda_for_driver(self) -> float:
        return 0.0 if self.chosen == "auto" else float(self.chosen)

    def status(self, face: bool) -> dict:
        return {"type": "status", "face": face, "neutral": self.driver is not None, "lambda_k": self.chosen}

    def process(self, content: bytes, t: float) -> tuple[bytes, dict]:
        """The output frame, as JPEG, for a camera frame (JPEG) arriving at ``t`` seconds; and the session's status."""
        frame = decode_jpeg(content)
        points = self.tracker.update(frame)
        if points is None:
            self.filter.reset()
            return encode_jpeg(self.last), self.status(False)
        points = self.filter(points, t)
        if self.driver is None:
            self._capture(frame, points, t)
        else:
            self._choose_lambda(frame, points)
            self.last = self.driver.render(frame, points).image
        return encode_jpeg(self.last), self.status(True)

    def _capture(self, frame: np.ndarray, points: np.ndarray, t: float) -> None:
        """Keep the frame with the most closed mouth; at the end of the window (or at once, if asked) it is the neutral face."""
        closed = opening(points, DLIB68)
        if self.window is None or closed < self.window[1]:
            self.window = (self.window[0] if self.window else t, closed, frame, points)
        if self.now or t - self.window[0] >= NEUTRAL_SECONDS:
            self.driver = drive.Driver(self._cloner(), self.method, self._lambda_for_driver(), mouth=self.mouth)

    def _choose_lambda(self, frame: np.ndarray, points: np.ndarray) -> None:
        """lambda_k "auto": chosen once by the DB metric, on the first clearly expressive frame."""
        if self.chosen != "auto" or not lookup((self.method,))[0].uses_lambda:
            return
        cloner = self.driver.cloner
        if drive.expression_strength(cloner.s_neu, points[None], cloner.layout)[0] >= LAMBDA_STRENGTH:
            self.chosen = drive.choose_lambda(cloner, [frame], [points])
            self.driver = drive.Driver(cloner, self.method, self.chosen, mouth=self.mouth)


async def _start(websocket: WebSocket, executor: ThreadPoolExecutor) -> Session:
    """Read the start message and the portrait; prepare the session (in its thread)."""
    from ..io.images import load_image

    start = _parse(await websocket.receive_text())
    if start.get("type") != "start":
        raise ExprCloneError("live", 'the first message must be {"type": "start", ...}')
    size = start.get("size", 512)
    if size not in SIZES:
        raise ExprCloneError("size", f"must be one of {', '.join(map(str, SIZES))}, got {size!r}")
    portrait = await websocket.receive_bytes()
    max_pixels = websocket.app.state.work.settings.max_pixels
    options = (start.get("method", "e+md"), bool(start.get("mouth", True)), parse_lambda(str(start.get("lambda", "auto"))), size)
    loop = asyncio.get_running_loop()
    return await loop.run_in_executor(
        executor, lambda: Session(load_image(portrait, name="portrait", max_pixels=max_pixels), *options, transfer_of(start))
    )


def transfer_of(message: dict) -> dict:
    """The transfer options a message gives (:data:`TRANSFER`; a list of regions as a tuple)."""
    given = {key: message[key] for key in TRANSFER if message.get(key) is not None}
    if isinstance(given.get("only"), list):
        given["only"] = tuple(given["only"])
    return given


@router.websocket("/api/live")
async def live(websocket: WebSocket) -> None:
    """A live session (the protocol is in the module's notes)."""
    await websocket.accept()
    work = websocket.app.state.work
    if work.live_sessions >= work.settings.max_live:
        await websocket.send_json(
            {"type": "error", "error": f"live: {work.settings.max_live} sessions are running already; try again later"}
        )
        return await websocket.close()
    work.live_sessions += 1
    executor = ThreadPoolExecutor(1, thread_name_prefix="live")
    try:
        session = await _start(websocket, executor)
        await websocket.send_json({"type": "ready", "width": session.portrait.shape[1], "height": session.portrait.shape[0]})
        await _follow(websocket, session, executor)
    except ExprCloneError as e:
        await websocket.send_json({"type": "error", "error": str(e)})
        await websocket.close()
    except WebSocketDisconnect:
        pass
    finally:
        work.live_sessions -= 1
        executor.shutdown(wait=False, cancel_futures=True)


async def _follow(websocket: WebSocket, session: Session, executor: ThreadPoolExecutor) -> None:
    """Receive frames, keep only the newest, answer each one processed; until the page goes."""
    newest: list[bytes] = []
    arrived = asyncio.Event()
    loop = asyncio.get_running_loop()

    async def receive() -> None:
        while True:
            message = await websocket.receive()
            if message["type"] == "websocket.disconnect":
                raise WebSocketDisconnect(message.get("code", 1000))
            if message.get("bytes") is not None:
                newest[:] = [message["bytes"]]  # an older frame not yet taken is dropped
                arrived.set()
            elif message.get("text"):
                try:
                    await _control(session, executor, message["text"])
                except ExprCloneError as e:
                    await websocket.send_json({"type": "error", "error": str(e)})

    async def answer() -> None:
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

    tasks = [asyncio.create_task(receive()), asyncio.create_task(answer())]
    try:
        done, _ = await asyncio.wait(tasks, return_when=asyncio.FIRST_EXCEPTION)
        for task in done:
            task.result()
    finally:
        for task in tasks:
            task.cancel()


def _parse(text: str) -> dict:
    """A text message: a JSON object, or ExprCloneError about ``live``."""
    try:
        message = json.loads(text)
    except ValueError:
        message = None
    if not isinstance(message, dict):
        raise ExprCloneError("live", "a text message must be a JSON object")
    return message


async def _control(session: Session, executor: ThreadPoolExecutor, text: str) -> None:
    """A text message after the start: ``neutral`` or ``options`` (run in the session's thread, between frames)."""
    message = _parse(text)
    loop = asyncio.get_running_loop()
    if message.get("type") == "neutral":
        await loop.run_in_executor(executor, lambda: session.recapture(now=True))
    elif message.get("type") == "options":
        transfer = transfer_of(message) if any(key in message for key in TRANSFER) else None
        await loop.run_in_executor(
            executor, session.options, message.get("method", session.method), bool(message.get("mouth", True)), transfer
        )
