"""The light on a face, read from its skin and its eye whites; the map from one light to another.

Not in the paper: it serves the mouth interior (:mod:`exprclone.mouth.paste`), which is pasted
from the source's photo or video frame into the target's and must leave the source's
light behind. A pixel's value is, channel by channel, the colour of a surface times the
colour of the light (von Kries' diagonal model, used on the photos' own gamma-encoded
values, where a diagonal map stays diagonal). Two parts of every face show in nearly
every photo and differ little in colour between people, and each is a *cue* to the
light: the skin of the cheeks and the eye whites (sclera). The ratio of one cue between
two photos is the ratio of their lights, up to

- how much the two people's skin, or eye whites, differ: measured on the 72 neutral
  photos of the London Set, one studio and one light (:data:`SKIN_SPREAD`,
  :data:`SCLERA_SPREAD`). Skin ranges from pale to dark, so its brightness tells the
  light's brightness poorly, but its colour varies less than twice as much as the eye
  whites';
- how well the cue could be read on each photo (:func:`read`): the spread of its
  pixels over their number (a small face, glare on glasses, lashes), and for the eye
  whites how open the eyes are (:func:`eye_openness`: a blink or a downward glance
  shows lids, not whites).

Each cue's ratio is split into brightness (the mean of its log channels) and colour (the
rest), and the cues are averaged by inverse variance, brightness and colour apart
(:func:`gain`): the eye whites set three quarters of the brightness and of the colour,
the skin the rest; with closed eyes, or eye whites too few or too spread to read, the
skin takes over. A cue that a photo does not show has no weight; with none on either
photo the map is the identity. As far as it is keyed on skin, the map gives the pasted
interior the relation to the target's skin that it had to the source's; as far as it is
keyed on the eye whites, the relation to the target's eye whites.

Teeth are not a cue: they are what the map is for, and their own colour (white to
yellow) is the person's to keep; nor are they seen on the neutral face, which is where
the light is read once per pair of faces (once per driving video).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..details import muscle
from ..landmarks import align
from ..landmarks.layout import Layout

#: between-people standard deviation of the skin cue's log brightness and log colour (per
#: degree of freedom) on the 72 neutral London photos (``tools/colour_check.py --spread``).
SKIN_SPREAD = (0.225, 0.055)
#: the same for the eye whites.
SCLERA_SPREAD = (0.123, 0.031)
#: the muscle areas whose centres are the skin cue (:data:`exprclone.landmarks.layout.DLIB68`'s
#: cheeks over the cheekbones), read in discs of this share of their radius: below the
#: eyes and glasses rims, above beards and the nasolabial folds.
SKIN_AREAS, SKIN_RADIUS = ("cheek_right", "cheek_left"), 0.5
#: share of the pixels inside the eyes, the brightest, taken as the eye whites.
SCLERA_SHARE = 0.25
#: a pixel with a channel at or above this is clipped, and says nothing of the light.
SATURATED = 250
#: fewest pixels a cue is read from.
MIN_PIXELS = 8
#: the 8-bit levels, for the histograms of :func:`midmean`.
LEVELS = np.arange(256)
#: eye aspect ratio (Soukupova and Cech, 2016) at which the eyes show no white, and at
#: which they are fully open (the least open of the 72 neutral London photos: 0.255).
EYE_CLOSED, EYE_OPEN = 0.15, 0.25
#: variance of the mean of the middle half of normally spread values (:func:`midmean`)
#: over that of their mean.
MIDMEAN_VARIANCE = 1.19


@dataclass(frozen=True)
class Light:
    """The cues to the light on one photo of a face.

    Attributes
    ----------
    log_colour : ndarray of shape (C, 3)
        Each cue's log RGB (0 where the photo does not show it).
    variance : ndarray of shape (C, 2)
        How far each cue's log brightness and log colour (per degree of freedom) may be
        from the light's: the cue's between-people spread and its reading's noise, over
        its visibility (infinite where the photo does not show it).
    """

    log_colour: np.ndarray
    variance: np.ndarray

    @classmethod
    def measure(cls, image: np.ndarray, landmarks: np.ndarray, layout: Layout) -> Light:
        """Read the skin and the eye whites of the face with these landmarks (:func:`read`).

        Parameters
        ----------
        image : ndarray of shape (H, W, 3), uint8 RGB
        landmarks : ndarray of shape (N, 2)
        layout : Layout
        """
        skin, sclera = read(skin_pixels(image, landmarks, layout)), read(sclera_pixels(image, landmarks, layout))
        spread = np.square([SKIN_SPREAD, SCLERA_SPREAD])
        visible = np.array([1.0, eye_openness(landmarks, layout)])
        log_colour = np.array([skin[0], sclera[0]])
        with np.errstate(divide="ignore"):
            variance = (spread + np.array([skin[1], sclera[1]])) / visible[:, None]
        return cls(log_colour, variance)

    def scaled(self, factor: np.ndarray | float) -> Light:
        """The same cues under a light ``factor`` (per channel, or for all) times as strong."""
        return Light(self.log_colour + np.log(factor), self.variance)


def read(pixels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A cue's log colour (the log of its pixels' :func:`midmean`) and the variance of that reading.

    Pixels with a clipped channel (:data:`SATURATED`) are left out. The variance is that
    of the midmean of the pixels' log brightness, and of their log colour per degree of
    freedom (:func:`split`).

    Parameters
    ----------
    pixels : ndarray of shape (K, 3), uint8

    Returns
    -------
    log_colour : ndarray of shape (3,)
        Zeros when fewer than :data:`MIN_PIXELS` are left.
    variance : ndarray of shape (2,)
        Infinite when fewer than :data:`MIN_PIXELS` are left.

    Examples
    --------
    >>> grey = np.full((100, 3), 128, np.uint8)
    >>> colour, variance = read(grey)
    >>> np.exp(colour).round().tolist(), variance.tolist()
    ([128.0, 128.0, 128.0], [0.0, 0.0])
    >>> read(np.full((100, 3), 255, np.uint8))[1].tolist()
    [inf, inf]
    """
    pixels = pixels[pixels.max(1) < SATURATED]
    if len(pixels) < MIN_PIXELS:
        return np.zeros(3), np.full(2, np.inf)
    brightness, colour = split(np.log(np.maximum(pixels.astype(np.float32), 1.0)))
    spread = np.array([brightness.var(), colour.var(0).sum() / 2])
    return np.log(np.maximum(midmean(pixels), 1.0)), MIDMEAN_VARIANCE * spread / len(pixels)


def midmean(values: np.ndarray) -> np.ndarray:
    """Per-column mean of the middle half of 8-bit values (between the quartiles).

    As robust as a median to the odd glint, lash or hair, but not held to the steps of
    8-bit values: a channel that a strong cast has dimmed to a few tens of levels still
    reads to a fraction of a level. Computed from each column's histogram: the quartiles
    as :func:`numpy.percentile` takes them (linear between order statistics), the mean
    exact; 18 times faster than sorting a face's two million values.

    Parameters
    ----------
    values : ndarray of shape (K, C), uint8

    Returns
    -------
    ndarray of shape (C,)

    Examples
    --------
    >>> midmean(np.array([[1], [2], [3], [4], [100]], np.uint8)).tolist()
    [3.0]
    """
    values = np.asarray(values)
    ranks = np.array([0.25, 0.75]) * (len(values) - 1)
    below = np.floor(ranks).astype(int)
    out = np.empty(values.shape[1])
    for c in range(values.shape[1]):
        hist = histogram(values, c)
        count = np.cumsum(hist)
        low_value, next_value = np.searchsorted(count, [below, np.minimum(below + 1, len(values) - 1)], side="right")
        low, high = low_value + (ranks - below) * (next_value - low_value)
        middle = (LEVELS >= low) & (LEVELS <= high)
        out[c] = (LEVELS * hist)[middle].sum() / max(hist[middle].sum(), 1)
    return out


def histogram(values: np.ndarray, column: int) -> np.ndarray:
    """The counts of each 8-bit level in one column of ``values`` (``(K, C)`` uint8), ``(256,)`` int.

    OpenCV's, a fifth of the time of :func:`numpy.bincount` on a column, whose counts it gives exactly while they are
    whole float32 numbers (below 2**24 pixels).
    """
    if len(values) >= 1 << 24 or not len(values):
        return np.bincount(values[:, column], minlength=256)
    return cv2.calcHist([values.reshape(len(values), 1, -1)], [column], None, [256], [0, 256]).reshape(-1).astype(int)


def split(log_rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Log brightness (the mean of the log channels) and log colour (the rest, summing to 0).

    Examples
    --------
    >>> b, c = split(np.log([4.0, 2.0, 1.0]))
    >>> float(np.exp(b)), np.exp(c).round(3).tolist()
    (2.0, [2.0, 1.0, 0.5])
    """
    brightness = log_rgb.mean(-1)
    return brightness, log_rgb - brightness[..., None]


def skin_pixels(image: np.ndarray, landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """The pixels of the cheeks: discs at the :data:`SKIN_AREAS` muscle areas, ``(K, 3)``."""
    centres, radii = muscle.areas(landmarks, layout)
    box = align.box(centres, image.shape, float(radii.max()) + 1)  # the discs' pixels only, not the whole photo's
    corner = np.array([box[1].start, box[0].start])
    mask = np.zeros(image[box].shape[:2], np.uint8)
    for area, centre, radius in zip(layout.muscle_areas, centres, radii):
        if area.name in SKIN_AREAS:
            cv2.circle(mask, tuple(int(v) for v in np.round(centre) - corner), max(1, int(round(SKIN_RADIUS * radius))), 1, -1)
    return image[box][mask > 0]


def sclera_pixels(image: np.ndarray, landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """The eye whites: the brightest :data:`SCLERA_SHARE` of the unclipped pixels inside both eyes, ``(K, 3)``.

    Brightest by the mean of the log channels (:func:`split`), which a coloured light
    shifts alike for every pixel, so that the same pixels are chosen under any light (by
    luma, an orange light would favour the reddest).
    """
    box = align.box(landmarks[[i for eye in layout.eyes for i in eye]], image.shape)
    corner = np.array([box[1].start, box[0].start])
    mask = np.zeros(image[box].shape[:2], np.uint8)
    for eye in layout.eyes:
        cv2.fillPoly(mask, [np.round(landmarks[list(eye)]).astype(np.int32) - corner], 1)
    pixels = image[box][mask > 0]
    pixels = pixels[pixels.max(1) < SATURATED]
    if not len(pixels):
        return pixels
    brightness = split(np.log(np.maximum(pixels, 1).astype(np.float32)))[0]
    return pixels[brightness >= np.percentile(brightness, 100 * (1 - SCLERA_SHARE))]


def eye_openness(landmarks: np.ndarray, layout: Layout) -> float:
    """How much eye white the eyes can show: 0 closed, 1 open, from their mean aspect ratio.

    The aspect ratio of an eye of six landmarks (corner, two upper-lid points, corner,
    two lower-lid points) is the mean of the two lid-to-lid distances over the
    corner-to-corner one; it maps linearly from 0 at :data:`EYE_CLOSED` to 1 at
    :data:`EYE_OPEN`.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> eye = np.array([[0, 0], [1, -0.3], [2, -0.3], [3, 0], [2, 0.3], [1, 0.3]])  # aspect ratio 0.2
    >>> points = np.zeros((68, 2))
    >>> points[36:42], points[42:48] = eye, eye + [10, 0]
    >>> round(eye_openness(points, DLIB68), 3)
    0.5
    """
    ratios = []
    for eye in layout.eyes:
        p = landmarks[list(eye)]
        width = max(float(np.linalg.norm(p[3] - p[0])), 1e-9)
        ratios.append((np.linalg.norm(p[1] - p[5]) + np.linalg.norm(p[2] - p[4])) / (2 * width))
    return float(np.clip((np.mean(ratios) - EYE_CLOSED) / (EYE_OPEN - EYE_CLOSED), 0.0, 1.0))


def gain(target: Light, source: Light) -> np.ndarray:
    """Per-channel gain that takes colours under the source's light to the target's.

    Each cue's log ratio, target over source, split into brightness and colour
    (:func:`split`), weighted by the inverse of the sum of its variances on the two
    photos; brightness and colour averaged apart, then joined (:func:`log_gain`).

    Parameters
    ----------
    target, source : Light

    Returns
    -------
    ndarray of shape (3,)
        Ones when no cue shows on both photos.

    Examples
    --------
    A cast on the source, orange on both cues, is undone whatever the faces:

    >>> face = Light(np.log([[150.0, 110.0, 90.0], [180.0, 170.0, 170.0]]), np.full((2, 2), 0.01))
    >>> orange = face.scaled(np.array([1.0, 0.8, 0.5]))
    >>> gain(face, orange).round(3).tolist()
    [1.0, 1.25, 2.0]
    """
    return np.exp(log_gain(target, source)[0])


def log_gain(target: Light, source: Light) -> tuple[np.ndarray, float]:
    """The log of :func:`gain`, and the variance of its colour (per degree of freedom).

    The variance is that of an inverse-variance mean, ``1 / sum(weights)``, times the
    cues' disagreement when they disagree more than their variances allow (the Birge
    ratio: their weighted squared spread about the mean over its degrees of freedom,
    when above 1): two cues that tell different lights say that the light is not well
    read, whichever is wrong.

    Parameters
    ----------
    target, source : Light

    Returns
    -------
    log_gain : ndarray of shape (3,)
        Zeros when no cue shows on both photos.
    variance : float
        Infinite when no cue's colour shows on both photos.

    Examples
    --------
    >>> face = Light(np.log([[150.0, 110.0, 90.0], [180.0, 170.0, 170.0]]), np.full((2, 2), 0.01))
    >>> [round(v, 3) for v in log_gain(face, face)[1:]]
    [0.01]
    >>> skin_orange = Light(face.log_colour + np.log([[1.0, 0.8, 0.5], [1.0, 1.0, 1.0]]), face.variance)
    >>> round(log_gain(face, skin_orange)[1], 3)  # the eye whites say white, the skin orange
    0.031
    """
    weight = 1.0 / (target.variance + source.variance)
    brightness, colour = split(target.log_colour - source.log_colour)
    total = weight.sum(0)
    log_gain = np.zeros(3)
    if total[0] > 0:
        log_gain += (weight[:, 0] * brightness).sum() / total[0]
    if total[1] == 0:
        return log_gain, np.inf
    mean = (weight[:, 1:] * colour).sum(0) / total[1]
    shown = weight[:, 1] > 0
    birge = (weight[:, 1] * np.square(colour - mean).sum(1))[shown].sum() / (2 * max(int(shown.sum()) - 1, 1))
    return log_gain + mean, float(max(birge, 1.0) / total[1])
