"""Driving a portrait with a performance of the source person: frames in, frames out (Sec. IV, Fig. 18).

Each frame of the performance is a source expression; the source's neutral face is one
of its frames or a photo of the same person; the target is a neutral portrait.
:class:`Driver` renders any iterator of frames with their landmarks: a decoded file, a
webcam, frames arriving over a socket. A recorded performance, which can be read more
than once, is prepared by :func:`prepare`: one pass tracks and smooths the landmarks
(:mod:`exprclone.tracking`), which also tells which frames show the strongest expression
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

from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from . import geometry, global_warp, mouth, tracking
from .checks import check_image, check_lambda, check_options, options_from
from .cloner import Cloner, CloneResult
from .eigenface import Eigenfaces
from .errors import ExprCloneError, NoFaceError
from .landmarkers import DEFAULT, Landmarker, resolve
from .layout import DLIB68, Layout
from .methods import lookup
from .options import Options
from .roles import SOURCE_NEUTRAL, TARGET_NEUTRAL

#: frames on which the DB metric chooses lambda_k for the whole video.
LAMBDA_FRAMES = 5
#: the frames that choose lambda_k are at least this many seconds apart.
LAMBDA_SPACING = 0.5
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
    iod = geometry.interocular(neutral, layout)
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
    opening = np.array([mouth.opening(p, layout) if ok else np.inf for p, ok in zip(points, usable)])
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
    """A portrait driven by expression frames, frame by frame.

    Parameters
    ----------
    cloner : Cloner
        The source's neutral face and the portrait, prepared.
    method : str
        One of the methods of Fig. 11.
    lambda_k : float or "auto"
        The elasticity ratio for every frame; "auto" chooses it by the DB metric on
        every frame (:func:`choose_lambda` chooses one for a whole performance).
    head_motion : bool
        Carry the source's head motion over to the portrait as a similarity transform.
    mouth : bool
        Paste the source's mouth interior into an opened mouth (:mod:`exprclone.mouth_fill`).

    Attributes
    ----------
    lambda_k : float, "auto" or None
        None for methods without the elastic model.

    Raises
    ------
    ExprCloneError
        An unknown method, or a bad ``lambda_k``.

    See Also
    --------
    prepare : a recorded performance prepared, with its driver.

    Examples
    --------
    Frames from anywhere (here a photo of the source smiling), with their landmarks:

    >>> from exprclone import data
    >>> from exprclone.cloner import Cloner
    >>> from exprclone.models import default_detector
    >>> detect = default_detector().detect
    >>> source, portrait, smile = data.photo("126"), data.photo("003"), data.photo("126", "smile")
    >>> driver = Driver(Cloner(source, detect(source), portrait, detect(portrait)), "e+md", lambda_k=0)
    >>> out = driver.render(smile, detect(smile))
    >>> out.image.shape, out.result.method
    ((1350, 1350, 3), 'e+md')
    """

    def __init__(
        self, cloner: Cloner, method: str = "e+md", lambda_k: float | str = "auto", *, head_motion: bool = False, mouth: bool = True
    ) -> None:
        self.cloner, self.mouth, self.head_motion = cloner, mouth, head_motion
        self.method = lookup((method,))[0]
        self.lambda_k = check_lambda(lambda_k) if self.method.uses_lambda else None
        self._to_target = geometry.fit_rigid(cloner.s_neu, cloner.t_neu, cloner.layout)

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
        lambda_k = "auto" if self.lambda_k is None else self.lambda_k  # methods without the elastic model ignore it
        result = self.cloner.clone_methods(frame, points, (self.method.name,), lambda_k, mouth=self.mouth)[self.method.name]
        image = result.image
        if self.head_motion:
            h, w = image.shape[:2]
            image = cv2.warpAffine(image, self._head_motion(points), (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        return DrivenFrame(index, frame, result, image)

    def frames(self, frames: Iterable[np.ndarray], points: Sequence[np.ndarray] | np.ndarray) -> Iterator[DrivenFrame]:
        """Render frames in order, frame ``i`` with ``points[i]``; stops at the shorter of the two."""
        for i, (frame, p) in enumerate(zip(frames, points)):
            yield self.render(frame, p, i)

    def _head_motion(self, points: np.ndarray) -> np.ndarray:
        """The source's head motion from its neutral face to ``points``, as a similarity in the portrait's frame."""
        layout = self.cloner.layout
        return geometry.fit_rigid(geometry.apply(self._to_target, self.cloner.s_neu), geometry.apply(self._to_target, points), layout)


def choose_lambda(cloner: Cloner, frames: Sequence[np.ndarray], points: Sequence[np.ndarray]) -> float:
    """One lambda_k for a performance: the median of the DB metric's choices (Eq. 8) on ``frames``."""
    return float(np.median([cloner.clone_methods(f, p, ("elastic",), "auto")["elastic"].lambda_k for f, p in zip(frames, points)]))


def neutral_index(track: tracking.Track, points: np.ndarray, neutral_frame: int | str | None, layout: Layout, name: str) -> int:
    """The frame that shows the source's neutral face: ``neutral_frame`` (a number, or "closed" for
    :func:`closed_mouth_frame`), by default the first frame with a face; ExprCloneError about ``name``."""
    if neutral_frame is None:
        index = int(np.argmax(track.found))
    elif neutral_frame == "closed":
        index = closed_mouth_frame(points, track.found, layout)
    elif isinstance(neutral_frame, int):
        index = neutral_frame
    else:
        raise ExprCloneError(name, f"the neutral frame must be a frame number or 'closed', got {neutral_frame!r}")
    if not 0 <= index < len(points):
        raise ExprCloneError(name, f"no frame {index} (it has {len(points)} frames, numbered from 0)")
    if not track.found[index]:
        raise NoFaceError(name, f"no face found in frame {index}, which was to be the neutral face")
    return index


def open_frames_of(points: np.ndarray, usable: np.ndarray, fps: float, layout: Layout) -> list[int]:
    """The :data:`TEETH_FRAMES` usable frames whose mouth is the most open (:func:`mouth.opening`, at least
    ``mouth.OPENING[0]``), :data:`LAMBDA_SPACING` seconds apart."""
    opened = np.array([mouth.opening(p, layout) for p in points])
    return strongest_frames(opened, usable & (opened >= mouth.OPENING[0]), TEETH_FRAMES, max(1, round(LAMBDA_SPACING * fps)))


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
    neutral_frame: int | str | None = None,
    method: str = "e+md",
    lambda_k: float | str = "auto",
    lambda_per_frame: bool = False,
    smooth: bool = True,
    landmarker: str | Landmarker = DEFAULT,
    eigenfaces: Eigenfaces | None = None,
    layout: Layout = DLIB68,
    name: str = "driving_video",
    head_motion: bool = False,
    mouth: bool = True,
    options: Options | None = None,
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
        A neutral photo of the source person; by default a frame (``neutral_frame``).
    neutral_frame : int or "closed", optional
        See :func:`neutral_index`.
    method, lambda_k
        As for :class:`Driver`; with ``lambda_k="auto"`` it is chosen once for the
        performance (the module's notes), or per frame if ``lambda_per_frame``.
    smooth : bool
        Smooth the landmarks over time (:func:`tracking.smooth`); False uses the raw fits.
    landmarker, eigenfaces, layout
        As for :func:`exprclone.pipeline.clone_methods`; the landmarker also tracks the performance.
    name : str
        What the performance is, for errors (a role, or the caller's file name).
    head_motion, mouth : bool
        As for :class:`Driver`.
    options : Options, optional
        How every frame is cloned (:class:`exprclone.options.Options`); the defaults if None.
    **keywords
        The same options as keywords (``strength=0.5``), instead of ``options``.

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
    >>> from exprclone.io.frames import resize_portrait
    >>> from exprclone.io.video import read_frames
    >>> clip = str(data.clip())
    >>> first_second = lambda: itertools.islice(read_frames(clip), 25)
    >>> portrait, _ = resize_portrait(data.photo("003"), None, 256)
    >>> recording = prepare(portrait, None, first_second, 25.0, neutral_frame="closed", strength=0.8)
    >>> frames = [out.image for out in recording.frames(first_second())]
    >>> len(frames), frames[0].shape, recording.driver.cloner.options.strength
    (25, (256, 256, 3), 0.8)
    """
    elastic = lookup((method,))[0].uses_lambda
    check_lambda(lambda_k)
    target = check_image(target, TARGET_NEUTRAL)
    asked = check_options(options_from(options, keywords), layout.n_points, target.shape, tuple(layout.regions))
    detector = resolve(landmarker)
    track = tracking.track(open_frames(), detector, name)
    points = tracking.smooth(track.points, fps) if smooth else track.points
    index = None
    if source_neutral is not None:
        neutral_image = check_image(source_neutral[0], SOURCE_NEUTRAL)
        neutral_points = detector.detect(neutral_image, SOURCE_NEUTRAL) if source_neutral[1] is None else source_neutral[1]
    else:
        index = neutral_index(track, points, neutral_frame, layout, name)
        neutral_points = points[index]
    chosen = []
    if elastic and lambda_k == "auto" and not lambda_per_frame:
        strength = expression_strength(neutral_points, points, layout)
        chosen = strongest_frames(strength, track.found, LAMBDA_FRAMES, max(1, round(LAMBDA_SPACING * fps)))
    opened = open_frames_of(points, track.found, fps, layout) if mouth else []
    fetched = frames_at(open_frames(), ([] if index is None else [index]) + opened + chosen)
    if index is not None:
        neutral_image = fetched.pop(0)
    target_points = detector.detect(target, TARGET_NEUTRAL) if target_points is None else target_points
    cloner = Cloner(neutral_image, neutral_points, target, target_points, eigenfaces=eigenfaces, layout=layout, options=asked)
    if opened:  # the source's teeth and cavity read once: the paste's colour the same in every frame
        cloner.pool_interior(fetched[: len(opened)], [points[i] for i in opened])
    fetched = fetched[len(opened) :]
    if chosen:
        lambda_k = choose_lambda(cloner, fetched, [points[i] for i in chosen])
    return Recording(Driver(cloner, method, lambda_k, head_motion=head_motion, mouth=mouth), track, points, index, chosen)
