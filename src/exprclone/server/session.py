"""A live session: a portrait that follows a camera's frames, its neutral face captured from them (:class:`Session`).

It knows nothing of sockets: the WebSocket route (:mod:`exprclone.server.routers.live`) hands it each
frame, and it runs in a process of its own (:mod:`exprclone.server.runtime.hosts`).
"""

from __future__ import annotations

import dataclasses
from typing import Any, NamedTuple

import cv2
import numpy as np

from .. import drive
from ..drive import driver as driving
from ..drive import tracking
from ..drive.framing import resize_portrait
from ..errors import ExprCloneError, quoted
from ..io.record import json_number
from ..landmarks.backends import for_thread, name_of
from ..landmarks.layout import DLIB68
from ..mouth.measure import opening
from ..options import Options
from ..pipeline import request as door
from ..pipeline.cloner import Cloner
from ..pipeline.request import Photo, Request

#: the neutral face is the frame whose mouth is most closed over this many seconds from the first face.
NEUTRAL_SECONDS = 1.0
#: lambda_k "auto" is chosen once, by the DB metric, on the first frame whose expression is this strong (inter-ocular distances).
LAMBDA_STRENGTH = 0.03
#: quality of the JPEG frames sent back.
JPEG_QUALITY = 85
#: output sizes a session may ask for (the portrait's longest side).
SIZES = (256, 512)


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
    options : Options
        How each frame is cloned (:class:`~exprclone.options.Options`); ``lambda_k="auto"`` is chosen once
        (:data:`LAMBDA_STRENGTH`); its landmarker finds and tracks the faces.
    size : int
        The output's longest side (one of :data:`SIZES`).
    """

    def __init__(self, portrait: np.ndarray, options: Options, size: int) -> None:
        if size not in SIZES:
            raise ExprCloneError("size", f"must be one of {', '.join(map(str, SIZES))}, got {quoted(size)}")
        self.options = options
        self.detector = for_thread(name_of(options.landmarker))
        self.portrait, _ = resize_portrait(portrait, None, size)
        self.portrait_points = self.detector.detect(self.portrait, "portrait")
        self.tracker, self.filter = tracking.Tracker(self.detector), tracking.OneEuro()
        self.last = self.portrait
        #: the neutral face's capture (:meth:`recapture`), and the faces prepared once it is captured.
        self.driver: drive.Driver | None = None
        self.chosen: float | str = options.lambda_k
        self.window: Window | None = None
        self.now = False

    @property
    def method(self) -> str:
        return self.options.method

    def recapture(self, now: bool = False) -> None:
        """Capture the neutral face again: from the next frame with a face (``now``), or the most closed mouth of the next second."""
        self.driver, self.chosen, self.window, self.now = None, self.options.lambda_k, None, now

    def change(self, options: Options) -> None:
        """Other options for the same faces (a method, a strength, ...): the neutral face is kept, lambda_k chosen again
        if another is asked; the landmarker is the session's."""
        if name_of(options.landmarker) != name_of(self.options.landmarker):
            raise ExprCloneError("landmarker", "is chosen when the session starts")
        if options.lambda_k != self.options.lambda_k:
            self.chosen = options.lambda_k
        self.options = options
        if self.driver is not None:
            self.driver = drive.Driver(self.driver.cloner.changed(self._driving()))

    def _driving(self) -> Options:
        """The options of the driver's cloner: lambda_k 0 (GI) until "auto" is chosen (see the class's notes), else the
        number asked or chosen."""
        return dataclasses.replace(self.options, lambda_k=0.0 if self.chosen == "auto" else float(self.chosen))

    def _cloner(self, window: Window) -> Cloner:
        """The camera's neutral face (the window's frame) and the portrait, prepared with the session's options."""
        neutral, portrait = Photo(window.frame, "frame", window.points), Photo(self.portrait, "portrait", self.portrait_points)
        return door.pair(Request(neutral, None, portrait, self._driving()))

    def close(self) -> None:
        """Release what the session holds: nothing here (a :class:`~exprclone.server.runtime.hosts.RemoteSession` gives its
        process back)."""

    def status(self, face: bool) -> dict[str, Any]:
        return {"type": "status", "face": face, "neutral": self.driver is not None, "lambda_k": json_number(self.chosen)}

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
            self.driver = drive.Driver(self._cloner(self.window))

    def _choose_lambda(self, driver: drive.Driver, frame: np.ndarray, points: np.ndarray) -> drive.Driver:
        """lambda_k "auto": chosen once by the DB metric, on the first clearly expressive frame; the driver to use."""
        if self.chosen != "auto" or not driver.method.uses_lambda:
            return driver
        cloner = driver.cloner
        if driving.expression_strength(cloner.faces.s_neu, points[None], cloner.faces.layout)[0] >= LAMBDA_STRENGTH:
            self.chosen = cloner.choose_lambda([frame], [points])
            self.driver = driver = drive.Driver(cloner.changed(self._driving()))
        return driver
