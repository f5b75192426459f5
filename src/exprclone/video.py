"""Driving a portrait from a video of the source person (the paper's Sec. IV, Fig. 18).

Each frame of the driving video is a source expression; the source's neutral face is a
frame of the same video (by default the first with a face) or a photo of the same
person; the target is a neutral portrait. The video is read three times: to track and
smooth the landmarks (:mod:`exprclone.tracking`), which also tells which frames show
the strongest expression; to fetch the neutral frame and those frames; to render.

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

from collections.abc import Iterator
from dataclasses import dataclass

import cv2
import numpy as np

from . import geometry, global_warp, mouth, tracking, video_io
from .eigenface import Eigenfaces
from .errors import ExprCloneError
from .landmarks import Detector
from .layout import DLIB68, Layout
from .pipeline import Cloner, CloneResult, check_image, check_request, default_detector

#: frames on which the DB metric chooses lambda_k for the whole video.
LAMBDA_FRAMES = 5
#: methods that use the elastic model, hence lambda_k.
ELASTIC_METHODS = ("elastic", "elastic+eri", "e+md")


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


def resize_portrait(image: np.ndarray, points: np.ndarray | None, size: int | None) -> tuple[np.ndarray, np.ndarray | None]:
    """The portrait (and its landmarks) scaled so that its longest side is ``size`` pixels."""
    if size is None or size == max(image.shape[:2]):
        return image, points
    scale = size / max(image.shape[:2])
    shape = (max(1, round(image.shape[1] * scale)), max(1, round(image.shape[0] * scale)))
    resized = cv2.resize(image, shape, interpolation=cv2.INTER_AREA if scale < 1 else cv2.INTER_CUBIC)
    return resized, None if points is None else points * (np.array(shape) / image.shape[1::-1])


def side_by_side(driving: np.ndarray, result: np.ndarray) -> np.ndarray:
    """``driving | result``, the driving frame scaled to the result's height."""
    height = result.shape[0]
    width = max(1, round(driving.shape[1] * height / driving.shape[0]))
    return np.hstack([cv2.resize(driving, (width, height), interpolation=cv2.INTER_LINEAR), result])


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
    """A target portrait driven by a video of the source person.

    Parameters
    ----------
    target : ndarray of shape (H, W, 3), uint8 RGB
        The target's neutral portrait; output frames have its size.
    target_points : ndarray of shape (N, 2) or None
        Its landmarks (detected if None).
    video : str
        The driving video.
    source_neutral : tuple of (image, points or None), optional
        A neutral photo of the source person; by default a frame of the video.
    neutral_frame : int or "closed", optional
        The video frame showing the source's neutral face: its number, "closed" for the
        frame with a face whose mouth is most closed (:func:`closed_mouth_frame`), or by
        default the first frame with a face.
    method : str
        One of the methods of Fig. 11.
    lambda_k : float or "auto"
        Fixed, or chosen once for the video (see the module's notes).
    lambda_per_frame : bool
        Choose lambda_k by the DB metric on every frame instead.
    head_motion : bool
        Carry the source's head motion over to the portrait as a similarity transform.
    smooth : bool
        Smooth the landmarks over time (:func:`tracking.smooth`); False uses the raw fits.
    mouth : bool
        Paste the source's mouth interior into an opened mouth (:mod:`exprclone.mouth`).
    detector, eigenfaces, layout
        As for :func:`exprclone.pipeline.clone_methods`.

    Attributes
    ----------
    info : video_io.VideoInfo
    track : tracking.Track
        Raw per-frame landmarks, and which frames had a face.
    points : ndarray of shape (T, N, 2)
        The landmarks that drive the portrait (smoothed unless ``smooth=False``).
    neutral_index : int or None
        The frame used as the source's neutral face (None with a neutral photo).
    lambda_k : float, "auto" or None
        The elasticity ratio used for every frame; "auto" when it is chosen per frame,
        None for methods without the elastic model.
    lambda_frames : list of int
        The frames whose DB choice gave ``lambda_k``.
    """

    def __init__(
        self,
        target: np.ndarray,
        target_points: np.ndarray | None,
        video: str,
        *,
        source_neutral: tuple[np.ndarray, np.ndarray | None] | None = None,
        neutral_frame: int | str | None = None,
        method: str = "e+md",
        lambda_k: float | str = "auto",
        lambda_per_frame: bool = False,
        head_motion: bool = False,
        smooth: bool = True,
        mouth: bool = True,
        detector: Detector | None = None,
        eigenfaces: Eigenfaces | None = None,
        layout: Layout = DLIB68,
        target_name: str = "target",
    ) -> None:
        check_request((method,), lambda_k)
        target = check_image(target, target_name)
        detector = detector or default_detector()
        self.video, self.method, self.layout, self.mouth, self.head_motion = video, method, layout, mouth, head_motion
        self.info = video_io.probe(video)
        self.track = tracking.track(video_io.read_frames(video), detector, video)
        self.points = tracking.smooth(self.track.points, float(self.info.fps)) if smooth else self.track.points
        n = len(self.points)

        if source_neutral is not None:
            image, points = source_neutral
            neutral_image = check_image(image, "source neutral")
            neutral_points = detector.detect(neutral_image, "source neutral") if points is None else points
            self.neutral_index = None
        else:
            if neutral_frame is None:
                neutral_frame = int(np.argmax(self.track.found))
            elif neutral_frame == "closed":
                neutral_frame = closed_mouth_frame(self.points, self.track.found, layout)
            if not 0 <= neutral_frame < n:
                raise ExprCloneError(f"{video}: no frame {neutral_frame} (it has {n} frames, numbered from 0)")
            if not self.track.found[neutral_frame]:
                raise ExprCloneError(f"{video}: no face found in frame {neutral_frame}, which was to be the neutral face")
            self.neutral_index, neutral_points = neutral_frame, self.points[neutral_frame]

        self.lambda_frames: list[int] = []
        self.lambda_k: float | str | None = None if method not in ELASTIC_METHODS else lambda_k
        if self.lambda_k == "auto" and not lambda_per_frame:
            strength = expression_strength(neutral_points, self.points, layout)
            self.lambda_frames = strongest_frames(strength, self.track.found, LAMBDA_FRAMES, max(1, round(float(self.info.fps) / 2)))
        # one more pass over the video fetches the neutral frame and the frames that choose lambda_k
        fetched = self.frames_at(([] if self.neutral_index is None else [self.neutral_index]) + self.lambda_frames)
        if self.neutral_index is not None:
            neutral_image = fetched.pop(0)

        if target_points is None:
            target_points = detector.detect(target, target_name)
        self.cloner = Cloner(neutral_image, neutral_points, target, target_points, eigenfaces=eigenfaces, layout=layout)
        rigid = list(layout.rigid)
        self._to_target = geometry.fit_similarity(self.cloner.s_neu[rigid], self.cloner.t_neu[rigid])
        if self.lambda_frames:
            chosen = [
                self.cloner.clone_methods(frame, self.points[i], ("elastic",), "auto")["elastic"].lambda_k
                for i, frame in zip(self.lambda_frames, fetched)
            ]
            self.lambda_k = float(np.median(chosen))

    def frames_at(self, indices: list[int]) -> list[np.ndarray]:
        """The driving video's frames at ``indices``, in that order (no pass over the video if none)."""
        wanted = set(indices)
        if not wanted:
            return []
        found = {}
        for i, frame in enumerate(video_io.read_frames(self.video)):
            if i in wanted:
                found[i] = frame
                if len(found) == len(wanted):
                    break
        return [found[i] for i in indices]

    def _head_motion(self, points: np.ndarray) -> np.ndarray:
        """The source's head motion from its neutral face to ``points``, as a similarity in the portrait's frame."""
        rigid = list(self.layout.rigid)
        return geometry.fit_similarity(
            geometry.apply(self._to_target, self.cloner.s_neu[rigid]), geometry.apply(self._to_target, points[rigid])
        )

    def frames(self) -> Iterator[DrivenFrame]:
        """Render every frame of the driving video, in order."""
        lambda_k = "auto" if self.lambda_k is None else self.lambda_k  # methods without the elastic model ignore it
        for i, frame in enumerate(video_io.read_frames(self.video)):
            if i >= len(self.points):
                break
            result = self.cloner.clone_methods(frame, self.points[i], (self.method,), lambda_k, mouth=self.mouth)[self.method]
            image = result.image
            if self.head_motion:
                h, w = image.shape[:2]
                image = cv2.warpAffine(
                    image, self._head_motion(self.points[i]), (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
                )
            yield DrivenFrame(i, frame, result, image)
