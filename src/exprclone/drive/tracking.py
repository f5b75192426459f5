"""Landmarks through a video: detect once, follow the face, smooth over time.

The paper drives its portraits from AAM-tracked video (Sec. IV, Fig. 18). We track with
either landmarker (:mod:`exprclone.landmarks.backends`): its face detector finds the face once,
then each frame's 68 landmarks are fitted inside a box predicted from the previous
frame's landmarks, which costs a few milliseconds instead of a detection. The detector runs again when the fit says the face
was lost (the fitted landmarks disagree with the box they were fitted in), and every
:data:`CHECK_EVERY` frames on a small crop around the face, to notice a face that has
gone. Frames where no face is found keep the last good landmarks and are counted.

The raw fits jitter by a pixel or two from frame to frame. The video is processed
offline, so the landmarks are smoothed by a zero-phase Savitzky-Golay filter
(a local quadratic fit over :data:`SMOOTH_SECONDS`), which removes jitter without any
lag: a fast mouth opening is neither delayed nor, being near-quadratic over a few
frames, flattened.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.signal import savgol_filter

from ..errors import NoFaceError
from ..landmarks.backends import Landmarker
from ..landmarks.layout import DLIB68, Layout

#: every this many frames the detector confirms that the tracked face is still there.
CHECK_EVERY = 5
#: a fit whose own box moved by more than this share of the box side, or changed size by
#: more than this share, from the box it was fitted in, means the face was lost.
MAX_BOX_CHANGE = 0.25
#: the detector's check runs on a crop this many box sides across around the tracked face...
CHECK_CROP = 1.5
#: ...shrunk until the face is this many pixels wide (about 2 ms a check)...
CHECK_FACE = 100
#: ...unless the crop is then smaller than the HOG detector's 80-pixel window.
DETECTOR_WINDOW = 80
#: span of the smoothing window, in seconds: 5 frames at 25 fps, where the quadratic
#: Savitzky-Golay filter passes motion up to 6 Hz (-3 dB), the fast end of lip motion in
#: speech (a 7-frame window, -3 dB at 4 Hz, was seen to round off quick lip closures).
SMOOTH_SECONDS = 0.2
#: the live filter's cut-off at rest (Hz) and its rise with speed (Hz per inter-ocular distance per second), :class:`OneEuro`.
#: On the 11 GRID clips (``tools/live_filter.py``) they leave 0.49 of the raw mouth jitter (the offline filter 0.50)
#: and delay the mouth opening by 16 ms (median); 1.5 Hz and 4 left 0.39 but delayed it 24 ms and flattened it more.
ONE_EURO_MIN_CUTOFF, ONE_EURO_BETA = 1.0, 10.0


@dataclass
class Track:
    """Landmarks of every frame of a video.

    Attributes
    ----------
    points : ndarray of shape (T, N, 2)
        Per-frame landmarks as fitted (frames without a face hold the nearest good ones).
    found : ndarray of shape (T,), bool
        Whether a face was fitted on each frame.
    detections, checks : int
        How many times the face detector ran on whole frames, and on crops around the face.
    """

    points: np.ndarray
    found: np.ndarray
    detections: int
    checks: int

    @property
    def missing(self) -> int:
        """Frames without a face."""
        return int((~self.found).sum())


def _scale(points: np.ndarray) -> float:
    """Root-mean-square spread of the landmarks about their centroid: their size."""
    return float(np.sqrt(((points - points.mean(0)) ** 2).sum(1).mean()))


class Tracker:
    """Follows one face through consecutive frames.

    The detector's box is kept in the landmarks' own terms (the box centre's offset from
    the landmarks' centroid and the box side, both over the landmarks' spread), so that
    the next frame's box can be predicted from the landmarks alone. Every
    :data:`CHECK_EVERY` frames the detector confirms that a face is still inside the
    predicted box, on a small crop around it (a few milliseconds).

    Parameters
    ----------
    detector : Landmarker

    Attributes
    ----------
    detections : int
        Detector runs on the whole frame.
    checks : int
        Detector runs on a crop around the tracked face.
    confirmed : bool
        Whether the detector saw the face on the last frame (a check or a detection).
    """

    def __init__(self, detector: Landmarker) -> None:
        self.detector = detector
        self.detections = 0
        self.checks = 0
        self.confirmed = False
        self._points: np.ndarray | None = None
        self._relation: tuple[np.ndarray, float] | None = None
        self._since_check = 0

    @staticmethod
    def _box(points: np.ndarray, relation: tuple[np.ndarray, float]) -> np.ndarray:
        """The detector box ``(left, top, right, bottom)`` predicted from landmarks, by the box's ``relation`` to them."""
        offset, side = relation
        scale = _scale(points)
        cx, cy = points.mean(0) + offset * scale
        half = 0.5 * side * scale
        return np.array([cx - half, cy - half, cx + half, cy + half])

    def _detect(self, frame: np.ndarray) -> np.ndarray | None:
        """Landmarks of the largest face the detector finds in the whole frame; the box relation re-learnt."""
        self.detections += 1
        boxes = self.detector.faces(frame)
        if not boxes:
            return None
        box = np.array(boxes[0], float)
        points = self.detector.fit(frame, tuple(box))
        scale = _scale(points)
        self._relation = ((0.5 * (box[:2] + box[2:]) - points.mean(0)) / scale, float(box[2] - box[0]) / scale)
        return points

    def _face_in(self, frame: np.ndarray, box: np.ndarray) -> bool:
        """Whether the detector finds a face in a :data:`CHECK_CROP`-box crop around ``box``, the face shrunk to :data:`CHECK_FACE` px."""
        self.checks += 1
        side = box[2] - box[0]
        centre = 0.5 * (box[:2] + box[2:])
        x0, y0 = np.maximum(np.floor(centre - CHECK_CROP / 2 * side), 0).astype(int)
        x1, y1 = np.ceil(centre + CHECK_CROP / 2 * side).astype(int)
        crop = frame[y0:y1, x0:x1]
        scale = min(1.0, CHECK_FACE / side)
        if min(crop.shape[:2]) * scale < DETECTOR_WINDOW:  # ask the whole frame
            return False
        small = cv2.resize(crop, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA) if scale < 1 else crop
        return bool(self.detector.faces(small))

    def _lost(self, box: np.ndarray, points: np.ndarray, shape: tuple[int, ...], relation: tuple[np.ndarray, float]) -> bool:
        """Whether a fit strayed from the box it was fitted in, or off the frame."""
        fitted = self._box(points, relation)
        side = box[2] - box[0]
        moved = np.linalg.norm(0.5 * (fitted[:2] + fitted[2:]) - 0.5 * (box[:2] + box[2:])) / side
        resized = abs((fitted[2] - fitted[0]) / side - 1)
        centre = points.mean(0)
        off_frame = not (0 <= centre[0] < shape[1] and 0 <= centre[1] < shape[0])
        return moved > MAX_BOX_CHANGE or resized > MAX_BOX_CHANGE or off_frame

    def update(self, frame: np.ndarray) -> np.ndarray | None:
        """The landmarks on the next frame, or None where no face is found.

        Parameters
        ----------
        frame : ndarray of shape (H, W, 3), uint8 RGB

        Returns
        -------
        ndarray of shape (N, 2) or None
        """
        self._since_check += 1
        self.confirmed = False
        if self._points is not None and self._relation is not None:  # both are learnt by the first detection
            box = self._box(self._points, self._relation)
            points = self.detector.fit(frame, tuple(box))
            if not self._lost(box, points, frame.shape, self._relation):
                if self._since_check < CHECK_EVERY:
                    self._points = points
                    return points
                if self._face_in(frame, box):
                    self._since_check, self.confirmed, self._points = 0, True, points
                    return points
        found = self._detect(frame)
        if found is not None:
            self._since_check, self.confirmed, self._points = 0, True, found
        return found


def track(frames: Iterable[np.ndarray], detector: Landmarker, name: str = "video") -> Track:
    """Landmarks of every frame, as fitted by a :class:`Tracker`.

    When the detector finds no face, the frames since it last saw one count as without a
    face too (the face may have gone on any of them). Frames without a face take the
    landmarks of the last frame with one (or, before the first face, of the first).

    Raises
    ------
    NoFaceError
        No face in any frame.
    """
    tracker = Tracker(detector)
    fitted: list[np.ndarray | None] = []
    last_seen = -1
    for i, frame in enumerate(frames):
        points = tracker.update(frame)
        if points is None:
            fitted[last_seen + 1 :] = [None] * (i - last_seen - 1)
        elif tracker.confirmed:
            last_seen = i
        fitted.append(points)
    found = np.array([p is not None for p in fitted], bool)
    if not found.any():
        raise NoFaceError(name, f"no face found in any of its {len(fitted)} frames")
    last = fitted[int(np.argmax(found))]
    held = []
    for p in fitted:
        last = p if p is not None else last
        held.append(last)
    return Track(np.array(held), found, tracker.detections, tracker.checks)


def jitter(points: np.ndarray, indices: Iterable[int], layout: Layout = DLIB68, frames: np.ndarray | None = None) -> float:
    """Frame-to-frame jitter of some landmarks: the mean length of their second difference over time.

    A steady motion has none; noise of standard deviation ``s`` per coordinate gives about
    ``3.1 s`` (``sqrt(3 pi) s``). In eye distances (their mean over the frames).

    Parameters
    ----------
    points : ndarray of shape (T, N, 2)
    indices : iterable of int
        The landmarks to measure (e.g. ``layout.mouth_outer + layout.mouth_inner``).
    frames : ndarray of shape (T,), bool, optional
        The frames to measure over: a second difference counts where its three frames all are (NaN if none does).

    Returns
    -------
    float
    """
    chosen = points[:, list(indices)]
    i, j = layout.eye_corners
    iod = np.linalg.norm(points[:, j] - points[:, i], axis=1).mean()
    second = np.linalg.norm(chosen[2:] - 2 * chosen[1:-1] + chosen[:-2], axis=2)
    if frames is not None:
        second = second[frames[2:] & frames[1:-1] & frames[:-2]]
    return float(second.mean() / iod) if second.size else float("nan")


def smooth(points: np.ndarray, fps: float) -> np.ndarray:
    """Landmarks smoothed over time with no lag (Savitzky-Golay, quadratic, zero-phase).

    Parameters
    ----------
    points : ndarray of shape (T, N, 2)
    fps : float
        Frame rate; the window spans :data:`SMOOTH_SECONDS` (at least 5 frames, odd).

    Returns
    -------
    ndarray of shape (T, N, 2)

    Examples
    --------
    A motion that is quadratic in time passes unchanged (so does anything slower than
    about 6 Hz at 25 fps); what is left is jitter, and it is reduced.

    >>> t = np.arange(50.0)
    >>> path = np.stack([0.01 * t**2, t], -1)[:, None, :]
    >>> bool(np.allclose(smooth(path, 25), path))
    True
    """
    window = max(5, int(round(SMOOTH_SECONDS * fps)) | 1)
    if len(points) < window:
        return points.copy()
    return savgol_filter(points, window, 2, axis=0, mode="interp")


class OneEuro:
    """Causal smoothing of landmarks as they arrive (live), by the 1-euro filter of Casiez, Roussel and Vogel.

    Live frames cannot wait for future ones, as the zero-phase filter of :func:`smooth`
    does. The 1-euro filter is a first-order low-pass filter whose cut-off rises with the
    speed of the signal: a still face is smoothed hard (jitter removed), a fast lip motion
    passes with little lag. Each landmark is filtered on its own; its speed is measured in
    inter-ocular distances per second, so the same settings suit any face size.

    Parameters
    ----------
    min_cutoff : float
        Cut-off (Hz) at rest.
    beta : float
        How fast the cut-off rises with speed (Hz per inter-ocular distance per second).
    d_cutoff : float
        Cut-off (Hz) of the speed estimate.
    layout : Layout

    References
    ----------
    G. Casiez, N. Roussel and D. Vogel, "1 Euro Filter: A Simple Speed-based Low-pass
    Filter for Noisy Input in Interactive Systems", CHI 2012.

    Examples
    --------
    A still face stays where it is; after a step, the filter converges to the new place.

    >>> rng = np.random.default_rng(0)
    >>> face = rng.uniform(0, 300, (68, 2)); face[36], face[45] = (100, 100), (200, 100)
    >>> f = OneEuro()
    >>> bool(np.allclose(f(face, 0.0), face))
    True
    >>> moved = [f(face + 10, t / 25) for t in range(1, 50)]
    >>> bool(np.allclose(moved[-1], face + 10, atol=0.01))
    True
    """

    def __init__(
        self, min_cutoff: float = ONE_EURO_MIN_CUTOFF, beta: float = ONE_EURO_BETA, d_cutoff: float = 1.0, layout: Layout = DLIB68
    ) -> None:
        self.min_cutoff, self.beta, self.d_cutoff, self.layout = min_cutoff, beta, d_cutoff, layout
        #: the last time, filtered landmarks and their speed; None before the first landmarks (or after :meth:`reset`)
        self._last: tuple[float, np.ndarray, np.ndarray] | None = None

    def reset(self) -> None:
        """Forget the past: the next landmarks pass unfiltered (a face found again after it was lost)."""
        self._last = None

    @staticmethod
    def _alpha(cutoff: np.ndarray | float, dt: float) -> np.ndarray | float:
        """The smoothing factor of a first-order low-pass filter at ``cutoff`` Hz for a step of ``dt`` seconds."""
        tau = 1.0 / (2 * np.pi * cutoff)
        return 1.0 / (1.0 + tau / dt)

    def __call__(self, points: np.ndarray, t: float) -> np.ndarray:
        """The filtered landmarks at time ``t`` (seconds), from the raw ``points`` ``(N, 2)``."""
        if self._last is None or t <= self._last[0]:
            self._last = (t, points.astype(float), np.zeros(len(points)))
            return self._last[1].copy()
        t0, previous, speed0 = self._last
        dt = t - t0
        i, j = self.layout.eye_corners
        iod = max(float(np.linalg.norm(previous[j] - previous[i])), 1e-6)
        raw_speed = np.linalg.norm(points - previous, axis=1) / dt / iod
        speed = speed0 + self._alpha(self.d_cutoff, dt) * (raw_speed - speed0)
        alpha = np.asarray(self._alpha(self.min_cutoff + self.beta * speed, dt))[:, None]
        filtered = previous + alpha * (points - previous)
        self._last = (t, filtered, speed)
        return filtered.copy()
