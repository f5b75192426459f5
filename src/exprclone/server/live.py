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
message and the portrait within :data:`START_SECONDS`. A message of the wrong kind (binary
where text goes, or the reverse), text that is not a JSON object of a known ``type`` with
fields of the right JSON types (:data:`FIELDS`), a frame that is not a JPEG or PNG within
the uploads' size bounds (read from its header, before decoding), a start the server cannot
use (a bad option, a portrait without a face) or a start when every slot is taken is
answered by ``{"type": "error", "error"}``, then the connection is closed with a code of
RFC 6455: 1003 (wrong kind), 1013 (no slot free: try again later) or 1008 (anything else).
A bad value in an ``options`` message (an unknown method, a strength out of range) is
answered by the error alone, and the session goes on as it was.

No backlog: the server keeps only the newest frame of a connection, and drops the
older ones unanswered (the page sends the next frame once an answer arrives, with a
small window). Each connection's state (tracker, filter, prepared faces) lives in a
process of its own (:mod:`exprclone.server.rendering`: off the web process's interpreter
lock, so that sessions at once do not share one core), and goes when it closes; the
process is kept for the next session; at most ``Settings.max_live`` run at once.
"""

from __future__ import annotations

import asyncio
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, NamedTuple

import cv2
import numpy as np
from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from .. import drive, tracking
from ..checks import check_choices, check_lambda, options_from, parse_lambda
from ..cloner import Cloner
from ..errors import ExprCloneError
from ..io.frames import resize_portrait
from ..landmarkers import DEFAULT, check_landmarker, for_thread
from ..layout import DLIB68
from ..methods import lookup
from ..mouth import opening
from ..options import Options
from .app import Server
from .protocol import POLICY, SEQUENCE, START_SECONDS, Misuse, Slots, check_frame, parse_message, receive, refuse

router = APIRouter()

#: the neutral face is the frame whose mouth is most closed over this many seconds from the first face.
NEUTRAL_SECONDS = 1.0
#: lambda_k "auto" is chosen once, by the DB metric, on the first frame whose expression is this strong (inter-ocular distances).
LAMBDA_STRENGTH = 0.03
#: quality of the JPEG frames sent back.
JPEG_QUALITY = 85
#: output sizes a session may ask for (the portrait's longest side).
SIZES = (256, 512)
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


class Window(NamedTuple):
    """The neutral face's capture so far: when it started, and the frame with the most closed mouth."""

    start: float
    opening: float
    frame: np.ndarray
    points: np.ndarray


class Session:
    """One camera following one portrait: the state of one connection, used from one thread.

    Until lambda_k "auto" is chosen, once, on the first clearly expressive frame
    (:data:`LAMBDA_STRENGTH`), the elastic model runs with ``lambda_k = 0``, which gives
    GI (Eq. 6 with the springs to the local positions slack): a neutral or faint
    expression looks the same either way, and the DB metric is not run on every frame.

    Parameters
    ----------
    portrait : ndarray of shape (H, W, 3), uint8 RGB
    method, mouth, lambda_k
        As for :class:`exprclone.drive.Driver`; ``lambda_k="auto"`` is chosen once (:data:`LAMBDA_STRENGTH`).
    size : int
        The output's longest side.
    transfer : Options, optional
        The :class:`~exprclone.options.Options` (:data:`TRANSFER`) of the prepared faces; the defaults if None.
    landmarker : str
        Which landmarker finds and tracks the faces (:data:`exprclone.landmarkers.LANDMARKERS`).
    """

    def __init__(
        self,
        portrait: np.ndarray,
        method: str,
        mouth: bool,
        lambda_k: float | str,
        size: int,
        transfer: Options | None = None,
        landmarker: str = DEFAULT,
    ) -> None:
        self.method, self.mouth, self.lambda_k = lookup((method,))[0].name, mouth, check_lambda(lambda_k)
        self.detector = for_thread(landmarker)
        self.portrait, _ = resize_portrait(portrait, None, size)
        self.transfer = self._checked(transfer or Options())
        self.portrait_points = self.detector.detect(self.portrait, "portrait")
        self.tracker, self.filter = tracking.Tracker(self.detector), tracking.OneEuro()
        self.last = self.portrait
        #: the neutral face's capture (:meth:`recapture`), and the faces prepared once it is captured.
        self.driver: drive.Driver | None = None
        self.chosen: float | str = self.lambda_k
        self.window: Window | None = None
        self.now = False

    def recapture(self, now: bool = False) -> None:
        """Capture the neutral face again: from the next frame with a face (``now``), or the most closed mouth of the next second."""
        self.driver, self.chosen, self.window, self.now = None, self.lambda_k, None, now

    def _checked(self, transfer: Options) -> Options:
        """The transfer options, checked as a :class:`~exprclone.cloner.Cloner` checks them (ExprCloneError)."""
        return check_choices(transfer, tuple(DLIB68.regions))

    def options(self, method: str, mouth: bool, transfer: Options | None = None) -> None:
        """Another method or mouth setting, for the same faces; other transfer options prepare the same faces again."""
        self.method, self.mouth = lookup((method,))[0].name, mouth
        checked = None if transfer is None else self._checked(transfer)
        changed = checked is not None and any(getattr(checked, key) != getattr(self.transfer, key) for key in TRANSFER)
        if checked is not None:
            self.transfer = checked
        if self.driver is not None and self.window is not None:
            cloner = self._cloner(self.window) if changed else self.driver.cloner
            self.driver = drive.Driver(cloner, self.method, self._lambda_for_driver(), mouth=self.mouth)

    def _cloner(self, window: Window) -> Cloner:
        """The camera's neutral face (the window's frame) and the portrait, prepared with the transfer options."""
        return Cloner(window.frame, window.points, self.portrait, self.portrait_points, options=self.transfer)

    def _lambda_for_driver(self) -> float:
        """lambda_k for the driver: 0 (GI) until "auto" is chosen (see the class's notes), else the number asked or chosen."""
        return 0.0 if self.chosen == "auto" else float(self.chosen)

    def close(self) -> None:
        """Release what the session holds: nothing here (a :class:`~exprclone.server.rendering.RemoteSession` gives its process back)."""

    def status(self, face: bool) -> dict[str, Any]:
        return {"type": "status", "face": face, "neutral": self.driver is not None, "lambda_k": self.chosen}

    def process(self, content: bytes, t: float) -> tuple[bytes, dict[str, Any]]:
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
            driver = self._choose_lambda(self.driver, frame, points)
            self.last = driver.render(frame, points).image
        return encode_jpeg(self.last), self.status(True)

    def _capture(self, frame: np.ndarray, points: np.ndarray, t: float) -> None:
        """Keep the frame with the most closed mouth; at the end of the window (or at once, if asked) it is the neutral face."""
        closed = opening(points, DLIB68)
        if self.window is None or closed < self.window.opening:
            self.window = Window(self.window.start if self.window else t, closed, frame, points)
        if self.now or t - self.window.start >= NEUTRAL_SECONDS:
            self.driver = drive.Driver(self._cloner(self.window), self.method, self._lambda_for_driver(), mouth=self.mouth)

    def _choose_lambda(self, driver: drive.Driver, frame: np.ndarray, points: np.ndarray) -> drive.Driver:
        """lambda_k "auto": chosen once by the DB metric, on the first clearly expressive frame; the driver to use."""
        if self.chosen != "auto" or not lookup((self.method,))[0].uses_lambda:
            return driver
        cloner = driver.cloner
        if drive.expression_strength(cloner.s_neu, points[None], cloner.layout)[0] >= LAMBDA_STRENGTH:
            self.chosen = drive.choose_lambda(cloner, [frame], [points])
            self.driver = driver = drive.Driver(cloner, self.method, self.chosen, mouth=self.mouth)
        return driver


async def _start(websocket: WebSocket, executor: ThreadPoolExecutor, slots: Slots) -> Session:
    """Read the start message (which takes a slot) and the portrait, within :data:`START_SECONDS`; prepare the session
    (in its host process, :mod:`exprclone.server.rendering`)."""
    deadline = asyncio.get_running_loop().time() + START_SECONDS
    start = parse_message(await receive(websocket, "text", deadline))
    if start["type"] != "start":
        raise Misuse("live", 'the first message must be {"type": "start", ...}')
    size = start.get("size", 512)
    if size not in SIZES:
        raise ExprCloneError("size", f"must be one of {', '.join(map(str, SIZES))}, got {size!r}")
    landmarker = check_landmarker(start.get("landmarker", DEFAULT))
    slots.take()
    portrait = await receive(websocket, "bytes", deadline)
    options = (start.get("method", "e+md"), start.get("mouth", True), parse_lambda(str(start.get("lambda", "auto"))), size)
    loop = asyncio.get_running_loop()
    hosts, max_pixels = slots.work.live_hosts, slots.work.settings.max_pixels
    session: Session = await loop.run_in_executor(
        executor, lambda: hosts.session(portrait, max_pixels, *options, transfer_of(start), landmarker)
    )
    return session


def transfer_of(message: dict[str, Any]) -> Options:
    """The transfer options a message gives (:data:`TRANSFER`; a list of regions as a tuple), the others the defaults."""
    given = {key: message[key] for key in TRANSFER if message.get(key) is not None}
    if isinstance(given.get("only"), list):
        given["only"] = tuple(given["only"])
    return options_from(None, given)


@router.websocket("/api/live")
async def live(websocket: WebSocket, server: Server) -> None:
    """A live session (the protocol is in the module's notes)."""
    await websocket.accept()
    slots = Slots(server)
    executor = ThreadPoolExecutor(1, thread_name_prefix="live")
    try:
        session = await _start(websocket, executor, slots)
        await websocket.send_json({"type": "ready", "width": session.portrait.shape[1], "height": session.portrait.shape[0]})
        await _follow(websocket, session, executor, server.settings.max_pixels)
    except ExprCloneError as e:
        await refuse(websocket, e, e.code if isinstance(e, Misuse) else POLICY)
    except WebSocketDisconnect:
        pass
    finally:
        slots.release()
        executor.shutdown(wait=False, cancel_futures=True)


async def _follow(websocket: WebSocket, session: Session, executor: ThreadPoolExecutor, max_pixels: int | None) -> None:
    """Receive frames, keep only the newest, answer each one processed; until the page goes, or breaks the protocol."""
    newest: list[bytes] = []
    arrived = asyncio.Event()
    loop = asyncio.get_running_loop()

    async def receive() -> None:
        while True:
            message = await websocket.receive()
            if message["type"] == "websocket.disconnect":
                raise WebSocketDisconnect(message.get("code", 1000))
            if message.get("bytes") is not None:
                check_frame(message["bytes"], max_pixels)
                newest[:] = [message["bytes"]]  # an older frame not yet taken is dropped
                arrived.set()
            elif message.get("text") is not None:
                try:
                    await _control(session, executor, parse_message(message["text"]))
                except Misuse:
                    raise
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
        loop.run_in_executor(None, session.close)  # after the frame in hand, if any: its host is free for the next session


async def _control(session: Session, executor: ThreadPoolExecutor, message: dict[str, Any]) -> None:
    """A text message after the start: ``neutral`` or ``options`` (run between frames, where the session renders)."""
    loop = asyncio.get_running_loop()
    if message["type"] == "neutral":
        await loop.run_in_executor(executor, lambda: session.recapture(now=True))
    elif message["type"] == "options":
        transfer = transfer_of(message) if any(key in message for key in TRANSFER) else None
        await loop.run_in_executor(executor, session.options, message.get("method", session.method), message.get("mouth", True), transfer)
    else:
        raise Misuse("live", f"a {message['type']} message comes only first")
