"""Driving a portrait with a performance of the source person: frames in, frames out (Sec. IV, Fig. 18).

Each frame of the performance is a source expression; the source's neutral face is one
of its frames or a photo of the same person; the target is a neutral portrait.
:class:`Driver` renders any iterator of frames with their landmarks: a decoded file, a
webcam, frames arriving over a socket. A recorded performance, which can be read more
than once, is prepared by :func:`prepare`: one pass tracks and smooths the landmarks
(:mod:`exprclone.drive.tracking`), which also tells which frames show the strongest expression
and which one is neutral; a second fetches those frames; the caller then renders a third
(:meth:`Recording.frames`). Nothing here opens a file: the caller passes a function that
starts a new pass over the frames.

- Head motion. The source's rigid head motion is taken out of every frame before its
  expression is transferred (as for a pair of photos, :func:`global_warp.remove_head_motion`);
  with ``head_motion=True`` it is put back as a similarity of the whole output frame,
  rotated and scaled into the portrait's frame.
- lambda_k once per video. With ``lambda_k="auto"`` the DB metric (Eq. 8) chooses
  lambda_k on the :data:`LAMBDA_FRAMES` frames of strongest expression (the largest mean
  landmark motion from the neutral face, at least half a second apart), and the median
  of their choices is used for every frame: one elasticity for one pair of faces, and
  no flicker from a lambda_k that jumps between frames. ``lambda_per_frame=True`` runs
  the metric on every frame instead.
"""

from __future__ import annotations

import collections
import concurrent.futures
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from ..errors import ExprCloneError, NoFaceError
from ..geometry import global_warp
from ..landmarks import align
from ..landmarks.backends import resolve
from ..landmarks.layout import Layout
from ..methods import Method, lookup
from ..mouth import measure
from ..options import Driving, Options, changed, names
from ..pipeline import request as door
from ..pipeline.checks import check_for_target, check_image
from ..pipeline.cloner import Cloner
from ..pipeline.request import Photo, Request
from ..pipeline.result import CloneResult
from ..roles import SOURCE_NEUTRAL, TARGET_NEUTRAL
from . import tracking

#: frames on which the DB metric chooses lambda_k for the whole video.
LAMBDA_FRAMES = 5
#: the frames that choose lambda_k are at least this many seconds apart.
LAMBDA_SPACING = 0.5
#: threads that render a performance's frames at once (:meth:`Driver.frames`), and how many frames they may be ahead
#: of the one given out. On 2 cores (``benchmarks/video.py``) two made the whole video job about 1.2x faster.
RENDERERS, AHEAD = 2, 4
#: the most open frames (as far apart) on which the source's teeth and cavity are read once for the whole video.
TEETH_FRAMES = 5


@dataclass
class DrivenFrame:
    """One output frame.

    Attributes
    ----------
    index : int
        Frame number in the driving video.
    driving : ndarray of shape (h, w, 3), uint8
        The driving frame.
    result : CloneResult
        The portrait with this frame's expression.
    image : ndarray of shape (H, W, 3), uint8
        The output frame: ``result.image``, moved by the source's head motion if asked.
    """

    index: int
    driving: np.ndarray
    result: CloneResult
    image: np.ndarray


def expression_strength(neutral: np.ndarray, points: np.ndarray, layout: Layout) -> np.ndarray:
    """Mean landmark motion of each frame from the neutral face, head motion removed, in eye distances.

    Parameters
    ----------
    neutral : ndarray of shape (N, 2)
    points : ndarray of shape (T, N, 2)

    Returns
    -------
    ndarray of shape (T,)
    """
    iod = align.interocular(neutral, layout)
    return np.array([np.linalg.norm(global_warp.remove_head_motion(neutral, p, layout) - neutral, axis=1).mean() / iod for p in points])


def closed_mouth_frame(points: np.ndarray, usable: np.ndarray, layout: Layout) -> int:
    """The first usable frame whose mouth opening (:func:`mouth.opening`) is the smallest.

    Expression motion is measured from the neutral face, so a neutral frame with parted
    lips makes every later closing of the lips a "negative" opening that the portrait
    cannot show; the most closed mouth avoids that.

    Parameters
    ----------
    points : ndarray of shape (T, N, 2)
    usable : ndarray of shape (T,), bool

    Returns
    -------
    int
    """
    opening = np.array([measure.opening(p, layout) if ok else np.inf for p, ok in zip(points, usable)])
    return int(np.argmin(opening))


def strongest_frames(strength: np.ndarray, usable: np.ndarray, count: int, spacing: int) -> list[int]:
    """Up to ``count`` usable frames of greatest strength, at least ``spacing`` frames apart.

    Examples
    --------
    >>> strongest_frames(np.array([0, 5, 4, 0, 3, 9.0]), np.ones(6, bool), 3, 2)
    [5, 1, 3]
    """
    chosen: list[int] = []
    for i in np.argsort(-strength, kind="stable"):
        if usable[i] and all(abs(int(i) - j) >= spacing for j in chosen):
            chosen.append(int(i))
        if len(chosen) == count:
            break
    return chosen


class Driver:
    """A portrait driven by expression frames, frame by frame, as its cloner's options say (method, lambda_k, mouth...).

    Parameters
    ----------
    cloner : Cloner
        The source's neutral face and the portrait, prepared, with the options of every frame's clone. With
        ``lambda_k="auto"`` the DB metric chooses it on every frame
        (:meth:`Cloner.choose_lambda <exprclone.Cloner.choose_lambda>` chooses one for a whole performance, and
        :meth:`Cloner.changed <exprclone.Cloner.changed>` gives it to the cloner).
    driving : Driving, optional
        Its ``head_motion``: carry the source's head motion over to the portrait as a similarity transform.

    See Also
    --------
    prepare : a recorded performance prepared, with its driver.

    Examples
    --------
    Frames from anywhere (here a photo of the source smiling), with their landmarks:

    >>> from exprclone import data
    >>> from exprclone.landmarks.backends import default_detector
    >>> from exprclone.pipeline.request import Request, pair
    >>> source, portrait, smile = data.photo("126"), data.photo("003"), data.photo("126", "smile")
    >>> driver = Driver(pair(Request.of(source, None, portrait, lambda_k=0)))
    >>> out = driver.render(smile, default_detector().detect(smile))
    >>> out.image.shape, out.result.method
    ((1350, 1350, 3), 'e+md')
    """

    def __init__(self, cloner: Cloner, driving: Driving | None = None) -> None:
        self.cloner, self.head_motion = cloner, (driving or Driving()).head_motion
        self._to_target = align.fit_rigid(cloner.faces.s_neu, cloner.faces.t_neu, cloner.faces.layout)

    @property
    def method(self) -> Method:
        """The method every frame is cloned by."""
        return lookup((self.cloner.options.method,))[0]

    @property
    def lambda_k(self) -> float | str | None:
        """The elasticity ratio of every frame ("auto": chosen on each), None for methods without the elastic model."""
        return self.cloner.options.lambda_k if self.method.uses_lambda else None

    def render(self, frame: np.ndarray, points: np.ndarray, index: int = 0) -> DrivenFrame:
        """The portrait with the expression of one frame.

        Parameters
        ----------
        frame : ndarray of shape (h, w, 3), uint8 RGB
            The source person with an expression.
        points : ndarray of shape (N, 2)
            Its landmarks.
        index : int
            The frame's number, kept in the output.

        Returns
        -------
        DrivenFrame
        """
        result = self.cloner.clone_methods(frame, points)[self.cloner.options.method]
        image = result.image
        if self.head_motion:
            h, w = image.shape[:2]
            image = cv2.warpAffine(image, self._head_motion(points), (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        return DrivenFrame(index, frame, result, image)

    def frames(self, frames: Iterable[np.ndarray], points: Sequence[np.ndarray] | np.ndarray) -> Iterator[DrivenFrame]:
        """Render frames in order, frame ``i`` with ``points[i]``; stops at the shorter of the two.

        Frames are independent once their landmarks are known, so :data:`RENDERERS` threads render them
        at once (OpenCV and numpy's work on whole images runs outside Python's lock), at most
        :data:`AHEAD` frames ahead of the one given out, while the caller's thread reads the next
        frames and encodes the last ones. The frames are the same, bit for bit, as rendered one by one.
        """
        with concurrent.futures.ThreadPoolExecutor(RENDERERS) as pool:
            pending: collections.deque[concurrent.futures.Future[DrivenFrame]] = collections.deque()
            for i, (frame, p) in enumerate(zip(frames, points)):
                pending.append(pool.submit(self.render, frame, p, i))
                if len(pending) >= AHEAD:
                    yield pending.popleft().result()
            while pending:
                yield pending.popleft().result()

    def _head_motion(self, points: np.ndarray) -> np.ndarray:
        """The source's head motion from its neutral face to ``points``, as a similarity in the portrait's frame."""
        layout = self.cloner.faces.layout
        return align.fit_rigid(align.apply(self._to_target, self.cloner.faces.s_neu), align.apply(self._to_target, points), layout)


def neutral_index(track: tracking.Track, points: np.ndarray, neutral_frame: int | str, layout: Layout, name: str) -> int:
    """The frame that shows the source's neutral face: ``neutral_frame`` (a number, "closed" for
    :func:`closed_mouth_frame`, or "first": the first frame with a face); ExprCloneError about ``name``."""
    if neutral_frame == "first":
        index = int(np.argmax(track.found))
    elif neutral_frame == "closed":
        index = closed_mouth_frame(points, track.found, layout)
    else:  # a frame number (Driving has checked it)
        index = int(neutral_frame)
    if not 0 <= index < len(points):
        raise ExprCloneError(name, f"no frame {index} (it has {len(points)} frames, numbered from 0)")
    if not track.found[index]:
        raise NoFaceError(name, f"no face found in frame {index}, which was to be the neutral face")
    return index


def open_frames_of(points: np.ndarray, usable: np.ndarray, fps: float, layout: Layout) -> list[int]:
    """The :data:`TEETH_FRAMES` usable frames whose mouth is the most open (:func:`mouth.opening`, at least
    ``mouth.OPENING[0]``), :data:`LAMBDA_SPACING` seconds apart."""
    opened = np.array([measure.opening(p, layout) for p in points])
    return strongest_frames(opened, usable & (opened >= measure.OPENING[0]), TEETH_FRAMES, max(1, round(LAMBDA_SPACING * fps)))


def frames_at(frames: Iterable[np.ndarray], indices: list[int]) -> list[np.ndarray]:
    """The frames at ``indices``, in that order, taken from one pass (stopped as soon as all are found)."""
    wanted, found = set(indices), {}
    if wanted:
        for i, frame in enumerate(frames):
            if i in wanted:
                found[i] = frame
                if len(found) == len(wanted):
                    break
    return [found[i] for i in indices]


@dataclass(frozen=True)
class Recording:
    """A recorded performance prepared to drive a portrait (:func:`prepare`).

    Attributes
    ----------
    driver : Driver
    track : tracking.Track
        Raw per-frame landmarks, and which frames had a face.
    points : ndarray of shape (T, N, 2)
        The landmarks that drive the portrait (smoothed unless asked not to be).
    neutral_index : int or None
        The frame used as the source's neutral face (None with a neutral photo).
    lambda_frames : list of int
        The frames whose DB choice gave ``driver.lambda_k``.
    """

    driver: Driver
    track: tracking.Track
    points: np.ndarray
    neutral_index: int | None
    lambda_frames: list[int]

    def frames(self, frames: Iterable[np.ndarray]) -> Iterator[DrivenFrame]:
        """Render a new pass over the performance's frames."""
        return self.driver.frames(frames, self.points)


def prepare(
    target: np.ndarray,
    target_points: np.ndarray | None,
    open_frames: Callable[[], Iterable[np.ndarray]],
    fps: float,
    *,
    source_neutral: tuple[np.ndarray, np.ndarray | None] | None = None,
    name: str = "driving_video",
    options: Options | None = None,
    driving: Driving | None = None,
    **keywords: Any,
) -> Recording:
    """Prepare a recorded performance to drive the ``target`` portrait.

    Parameters
    ----------
    target : ndarray of shape (H, W, 3), uint8 RGB
        The target's neutral portrait; output frames have its size.
    target_points : ndarray of shape (N, 2) or None
        Its landmarks (detected if None).
    open_frames : callable
        Starts a new pass over the performance's frames (``(h, w, 3)`` uint8 RGB); called twice.
    fps : float
        The performance's frame rate (for the smoothing and the spacing of the lambda frames).
    source_neutral : tuple of (image, points or None), optional
        A neutral photo of the source person; by default a frame (``driving.neutral_frame``).
    name : str
        What the performance is, for errors (a role, or the caller's file name).
    options : Options, optional
        How every frame is cloned (:class:`~exprclone.options.Options`); its landmarker also tracks the
        performance, and with ``lambda_k="auto"`` lambda_k is chosen once for it (the module's notes), or per frame
        with ``driving.lambda_per_frame``.
    driving : Driving, optional
        How the performance drives the portrait (:class:`Driving`): its neutral frame, the smoothing, lambda_k per frame,
        the head motion.
    **keywords
        Options of either as keywords (``strength=0.5``, ``neutral_frame="first"``), changing those given.

    Returns
    -------
    Recording
        Its ``frames(...)`` renders a new pass over the performance; its ``driver`` renders any frame.

    Raises
    ------
    ExprCloneError
        A bad option or image; ``NoFaceError`` when the performance shows no face (or none
        in the neutral frame asked for), or the portrait has none.

    Examples
    --------
    The first second of the sample clip driving a portrait of 256 pixels:

    >>> import itertools
    >>> from exprclone import data
    >>> from exprclone.drive.framing import resize_portrait
    >>> from exprclone.io.video import read_frames
    >>> clip = str(data.clip())
    >>> first_second = lambda: itertools.islice(read_frames(clip), 25)
    >>> portrait, _ = resize_portrait(data.photo("003"), None, 256)
    >>> recording = prepare(portrait, None, first_second, 25.0, strength=0.8)
    >>> frames = [out.image for out in recording.frames(first_second())]
    >>> len(frames), frames[0].shape, recording.driver.cloner.options.strength
    (25, (256, 256, 3), 0.8)
    """
    own = set(names(Driving))
    driving = changed(Driving, driving, {k: v for k, v in keywords.items() if k in own})
    target = check_image(target, TARGET_NEUTRAL)
    asked = check_for_target(Options.of(options, {k: v for k, v in keywords.items() if k not in own}), target.shape)
    elastic, layout = lookup((asked.method,))[0].uses_lambda, asked.landmarks_layout
    detector = resolve(asked.landmarker)
    track = tracking.track(open_frames(), detector, name)
    points = tracking.smooth(track.points, fps) if driving.smooth else track.points
    index = None
    if source_neutral is not None:
        neutral_image = check_image(source_neutral[0], SOURCE_NEUTRAL)
        neutral_points = detector.detect(neutral_image, SOURCE_NEUTRAL) if source_neutral[1] is None else source_neutral[1]
    else:
        index = neutral_index(track, points, driving.neutral_frame, layout, name)
        neutral_points = points[index]
    chosen = []
    if elastic and asked.lambda_k == "auto" and not driving.lambda_per_frame:
        strength = expression_strength(neutral_points, points, layout)
        chosen = strongest_frames(strength, track.found, LAMBDA_FRAMES, max(1, round(LAMBDA_SPACING * fps)))
    opened = open_frames_of(points, track.found, fps, layout) if asked.mouth else []
    fetched = frames_at(open_frames(), ([] if index is None else [index]) + opened + chosen)
    if index is not None:
        neutral_image = fetched.pop(0)
    target_points = detector.detect(target, TARGET_NEUTRAL) if target_points is None else target_points
    cloner = door.pair(
        Request(Photo(neutral_image, SOURCE_NEUTRAL, neutral_points), None, Photo(target, TARGET_NEUTRAL, target_points), asked)
    )
    if opened:  # the source's teeth and cavity read once: the paste's colour the same in every frame
        cloner = cloner.changed(faces=cloner.faces.pooled(fetched[: len(opened)], [points[i] for i in opened]))
    fetched = fetched[len(opened) :]
    if chosen:
        cloner = cloner.changed(lambda_k=cloner.choose_lambda(fetched, [points[i] for i in chosen]))
    return Recording(Driver(cloner, driving), track, points, index, chosen)
