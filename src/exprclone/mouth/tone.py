"""The target photo's light, sharpness and noise, measured once, and the tone match of pixels taken from the source photo.

Not in the paper. The source's mouth interior is pasted into the target photo
(:mod:`exprclone.mouth.paste`); its colour is first mapped from the source's light to the
target's (:func:`tone_gain`, a per-channel gain from :mod:`exprclone.mouth.illuminant`: the
two photos' skin and eye whites, each cue weighted by how much it shows and how
reliable it is), so that the photo's exposure and colour cast carry over but not the
source's light: teeth filmed under a warm lamp are not pasted orange into a white-lit
portrait. The source's light is read on its neutral photo (a smile often squints) and
carried over to the expression by the change of exposure. Never so bright that teeth
the source photo shows unclipped turn flat white. Where the source's light is doubtful
(a small, compressed, strongly lit video), the colour is pulled toward that of real
teeth and mouth cavities in the target's light (:func:`exprclone.mouth.teeth.recolour`; the
source's teeth and cavity read once per driving video, :attr:`Reference.source_interior`).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..landmarks import align
from ..landmarks.layout import Layout
from . import illuminant, teeth
from .camera import blur_sigma, noise_sigma

#: the tone match's gain is held within this range, channel by channel: a channel scaled
#: by 4 has lost 2 of its 8 bits and shows 4 times its noise. The strongest cast of the
#: GRID clips (lbax4n, lrwp9a, swiz3n: skin with a third of its blue) needs about 3.
GAIN_RANGE = (0.25, 4.0)


@dataclass(frozen=True)
class Reference:
    """What a paste is matched to, measured once for a pair of faces.

    The target photo and the source's neutral photo are the same for every expression
    cloned between two people (every frame of a driving video), so their lights,
    sharpness and noise are measured once; only the expression's own measures change,
    and of those the tone match takes only the change of exposure from the neutral
    face, a brightness: nothing in the colour of the paste changes from frame to frame.

    Attributes
    ----------
    light : illuminant.Light
        The cues to the light on the target photo (:class:`exprclone.mouth.illuminant.Light`).
    blur : float
        Its face's edge blur (:func:`exprclone.mouth.camera.blur_sigma` of :func:`face_box`).
    noise : ndarray of shape (3,)
        Its face's noise (:func:`exprclone.mouth.camera.noise_sigma`).
    source_light : illuminant.Light or None
        The same cues on the source's neutral photo, when it is given.
    source_face : ndarray of shape (3,) or None
        That photo's face colour (:func:`face_colour`), to carry its light over to an expression photo taken at
        another exposure.
    source_interior : teeth.Interior or None
        The source's teeth and cavity read once for every expression (a driving video's
        most open frames), for the pull of their colour toward real ones'
        (:func:`exprclone.mouth.teeth.recolour`); None: read on each expression photo.
    source_grain : tuple of (float, ndarray of shape (3,)) or None
        The source camera's grain read once for every expression (the same frames): the blur a paste needs and the
        noise left in it (:func:`exprclone.mouth.paste.grain`, medians); None: read on each expression photo.
    """

    light: illuminant.Light
    blur: float
    noise: np.ndarray
    source_light: illuminant.Light | None = None
    source_face: np.ndarray | None = None
    source_interior: teeth.Interior | None = None
    source_grain: tuple[float, np.ndarray] | None = None

    @classmethod
    def measure(
        cls,
        target: np.ndarray,
        target_landmarks: np.ndarray,
        layout: Layout,
        source_neutral: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> Reference:
        """Measure the target photo (and the source's neutral photo with its landmarks, if given)."""
        face = face_box(target, target_landmarks)
        light, blur, noise = illuminant.Light.measure(target, target_landmarks, layout), blur_sigma(face), noise_sigma(face)
        if source_neutral is None:
            return cls(light, blur, noise)
        neutral, neutral_landmarks = source_neutral
        return cls(
            light, blur, noise, illuminant.Light.measure(neutral, neutral_landmarks, layout), face_colour(neutral, neutral_landmarks)
        )


def tone_gain(
    source: np.ndarray,
    source_landmarks: np.ndarray,
    reference: Reference,
    layout: Layout,
    pasted: np.ndarray | None = None,
    light: illuminant.Light | None = None,
) -> np.ndarray:
    """Per-channel gain that gives the source photo's pixels the target photo's exposure and light.

    The gain from the source's light to the target's (:func:`exprclone.mouth.illuminant.gain`),
    within :data:`GAIN_RANGE`, lowered (all channels alike) until the brightest
    ``pasted`` pixels (99th percentile) stay below white: teeth the source photo shows
    unclipped never turn flat white. A smiling source often squints, hiding its eye
    whites behind lashes (on the London Set they read 5% darker in the smile than in the
    neutral photo at the median, 19% at the 5th percentile, 55% for one person), so when
    the reference holds the source's neutral photo its light is read there and carried
    over to the expression photo by the change of exposure (:func:`source_light`). The
    colour of the light is read once, on the neutral face: in a video, the paste's
    colour is the same in every frame.

    Parameters
    ----------
    source : ndarray of shape (H, W, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    reference : Reference
        The target photo (and the source's neutral photo), measured.
    layout : Layout
    pasted : ndarray of shape (K, 3), optional
        The source pixels the gain is for.
    light : illuminant.Light, optional
        The source's light (:func:`source_light`), when the caller has read it.

    Returns
    -------
    ndarray of shape (3,)
    """
    light = source_light(source, source_landmarks, reference, layout) if light is None else light
    gain = np.clip(illuminant.gain(reference.light, light), *GAIN_RANGE)
    return gain if pasted is None else below_white(gain, pasted)


def source_light(source: np.ndarray, source_landmarks: np.ndarray, reference: Reference, layout: Layout) -> illuminant.Light:
    """The cues to the light on the source's expression photo.

    Its own; or, when the reference holds the source's neutral photo, that photo's
    carried over by the change of exposure: the ratio of the two photos' face colours
    (:func:`face_colour`; one person's face, so what differs between them is the
    exposure), as a brightness (the mean of the channels' log ratios).
    """
    if reference.source_light is None or reference.source_face is None:  # measured together, or neither
        return illuminant.Light.measure(source, source_landmarks, layout)
    face = face_colour(source, source_landmarks)
    exposure = np.log(np.maximum(face, 1.0) / np.maximum(reference.source_face, 1.0)).mean()
    return reference.source_light.scaled(np.exp(exposure))


def below_white(gain: np.ndarray, pasted: np.ndarray) -> np.ndarray:
    """``gain`` lowered, all channels alike, until the brightest ``pasted`` pixels (99th percentile) stay below white.

    Examples
    --------
    >>> below_white(np.array([2.0, 2.0, 1.0]), np.array([[100, 150, 200]])).round(2).tolist()
    [1.7, 1.7, 0.85]
    """
    if not len(pasted):
        return gain
    return gain * min(1.0, 255.0 / max(float((gain * np.percentile(pasted, 99, axis=0)).max()), 1.0))


def face_colour(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """The face's colour: the :func:`~exprclone.mouth.illuminant.midmean` of the pixels of the landmarks' bounding box (brows to chin)."""
    return illuminant.midmean(image[align.box(landmarks, image.shape)].reshape(-1, 3))


def face_box(image: np.ndarray, landmarks: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """The bounding box of the landmarks (brows to chin), float32, resized by ``scale``.

    Resizing is bilinear, as the warp samples, so a face brought to another photo's scale
    is as sharp and as noisy as its warped pixels are there.
    """
    box = image[align.box(landmarks, image.shape)].astype(np.float32)
    if scale == 1.0:
        return box
    size = (max(int(round(box.shape[1] * scale)), 8), max(int(round(box.shape[0] * scale)), 8))
    return cv2.resize(box, size, interpolation=cv2.INTER_LINEAR)
