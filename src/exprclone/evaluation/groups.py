"""Group photos made from the London Set: several people at chosen face widths, in two rows, before a made background.

No open group photo of neutral faces is at hand to test a clone of every face in a photo
(:mod:`exprclone.pipeline.group`) on, so one is made: each person's London photo is scaled
so that their face (the jaw's width, dlib's points 0 to 16 of the manual template,
:func:`exprclone.io.frl_template.frl_to_68`) is as wide as asked, cut out by a soft
silhouette (an ellipse over the head and hair, a wider one over the shoulders, their
union blurred), and laid over a background: a wall whose colour varies slowly (a vertical
gradient and blurred noise) with a darker floor. The people stand in two rows, the smaller
faces behind (higher in the photo, drawn first), each of the front row between two of
the back row's, so that no face covers another.

The made photo says where each person is (:class:`Person`): their scale and the
offset of their London photo, so that their template's landmarks, or any point of their
own photo, can be placed in the group's.

>>> layout_rows([120, 400, 200, 300])
([0, 2], [3, 1])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from ..io.frl_template import frl_to_68
from ..io.images import load_image
from ..io.landmarks import read_tem
from .london import LONDON

#: the silhouette's head ellipse: its centre above the eyes' midpoint and its half-axes, in face widths.
HEAD = (0.2, 0.75, 0.95)
#: the shoulders' ellipse: its centre below the eyes and its half-axes, in face widths.
SHOULDERS = (1.9, 1.45, 1.3)
#: the blur of the silhouette's edge, in face widths.
SOFTNESS = 0.02
#: the columns at each side of a London photo that show the wall alone, pixels.
EDGE = 40
#: how far from the wall's colour a pixel of the person is, levels (in one channel at least).
WALL = 16
#: over how many face widths the cut-out fades before the London photo's bottom edge.
FADE = 0.3
#: where the floor starts, in the photo's heights.
FLOOR = 0.82
#: a row's hair reaches this many of its widest face's widths above its eyes, and its chins this many below.
ABOVE, BELOW = 1.1, 0.95
#: the margin above the first row, in the photo's heights.
MARGIN = 0.04


@dataclass(frozen=True)
class Person:
    """One person in a made group photo.

    Attributes
    ----------
    face_id : str
        Their London Set id.
    scale : float
        Their London photo's scale in the group.
    offset : ndarray of shape (2,)
        Where their photo's pixel (0, 0) lies in the group's, ``(x, y)``.
    landmarks : ndarray of shape (68, 2)
        Their template's 68 points (:func:`exprclone.io.frl_template.frl_to_68`) in the group photo.
    """

    face_id: str
    scale: float
    offset: np.ndarray
    landmarks: np.ndarray

    @property
    def width(self) -> float:
        """The face's width in the group photo (the jaw's, points 0 to 16), pixels."""
        return float(np.linalg.norm(self.landmarks[16] - self.landmarks[0]))

    def place(self, points: np.ndarray) -> np.ndarray:
        """Points ``(N, 2)`` of the person's own London photo, in the group photo."""
        return (np.asarray(points, float) + 0.5) * self.scale - 0.5 + self.offset


def face_of(london: str | Path, face_id: str, smiling: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """A London person's photo (neutral, or smiling) and the 68 points of their neutral photo's manual template."""
    folder, ending = LONDON[int(smiling)]
    image = load_image(Path(london) / folder / f"{face_id}{ending}.jpg")
    template = Path(london) / LONDON[0][0] / f"{face_id}{LONDON[0][1]}.tem"
    return image, frl_to_68(read_tem(template))


def background(size: tuple[int, int], seed: int) -> np.ndarray:
    """A made wall and floor of ``size`` ``(width, height)``: uint8 RGB, its colours varying slowly (see the module's notes)."""
    width, height = size
    rng = np.random.default_rng(seed)
    top, bottom = rng.uniform(90, 200, 3), rng.uniform(60, 160, 3)
    ramp = np.linspace(0, 1, height)[:, None, None]
    coarse = rng.normal(0, 1, (max(2, height // 200), max(2, width // 200))).astype(np.float32)
    texture = cv2.GaussianBlur(cv2.resize(coarse, (width, height), interpolation=cv2.INTER_CUBIC), (0, 0), 20)
    wall = (top * (1 - ramp) + bottom * ramp) * (1 + 0.12 * texture[..., None])
    wall[int(FLOOR * height) :] *= 0.6
    return np.clip(wall, 0, 255).astype(np.uint8)


def silhouette(image: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The soft cut-out of a person from their London photo: 1 over the head and shoulders where the pixel is not the
    grey studio wall, 0 elsewhere, float32 ``(H, W)``; ``points`` the face's 68 landmarks.

    A pixel within :data:`WALL` levels of the wall's colour (:func:`studio_wall`) in every channel, joined to the
    photo's top or sides by such pixels, is the wall."""
    width = float(np.linalg.norm(points[16] - points[0]))
    eyes = points[36:48].mean(0)
    shape = np.zeros(image.shape[:2], np.uint8)
    for below, half_width, half_height in ((-HEAD[0], HEAD[1], HEAD[2]), SHOULDERS):
        centre = (int(round(eyes[0])), int(round(eyes[1] + below * width)))
        cv2.ellipse(shape, centre, (int(half_width * width), int(half_height * width)), 0, 0, 360, 255, -1)
    wall = np.abs(image.astype(np.float32) - studio_wall(image)).max(2) <= WALL
    count, labels = cv2.connectedComponents(wall.astype(np.uint8), connectivity=4)
    edges = np.unique(np.r_[labels[0], labels[:, 0], labels[:, -1]])
    person = np.where(np.isin(labels, edges[edges > 0]), 0, 255).astype(np.uint8)  # a patch of grey inside the person stays
    cv2.fillConvexPoly(person, cv2.convexHull(points.astype(np.int32)), 255)
    soft = SOFTNESS * width
    mask = cv2.GaussianBlur((shape & person).astype(np.float32) / 255, (0, 0), soft)
    fade = np.clip((image.shape[0] - np.arange(image.shape[0])) / (FADE * width), 0, 1)  # the photo's bottom edge
    return mask * fade[:, None].astype(np.float32)


def studio_wall(image: np.ndarray) -> np.ndarray:
    """The colour the studio wall of a London photo would have at every pixel, float32 ``(H, W, 3)``: a quadratic in
    ``x`` and ``y`` fitted, channel by channel, to the :data:`EDGE` pixels along the photo's top and sides (its light
    falls off towards the corners)."""
    h, w = image.shape[:2]
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    x, y = x / w - 0.5, y / h - 0.5
    terms = np.stack([np.ones_like(x), x, y, x * x, y * y, x * y], -1)
    band = np.zeros((h, w), bool)
    band[:EDGE], band[:, :EDGE], band[:, -EDGE:] = True, True, True
    band[int(0.6 * h) :] = False  # the shoulders reach the sides lower down
    fit = np.linalg.lstsq(terms[band], image[band].astype(np.float32), rcond=None)[0]
    return (terms @ fit).astype(np.float32)


def layout_rows(widths: Sequence[float]) -> tuple[list[int], list[int]]:
    """The people (by index of ``widths``) of the back row and of the front row, each left to right: the smaller
    half behind, the larger in front, each row alternating small and large so that sizes are mixed across the photo."""
    order = sorted(range(len(widths)), key=lambda k: widths[k])
    back, front = order[: len(order) // 2], order[len(order) // 2 :]
    return _mixed(back), _mixed(front)


def row_heights(rows: Sequence[Sequence[float]], height: int) -> list[float]:
    """Where each row's eyes are, from the top of a photo ``height`` pixels high, given each row's face widths: the
    first row's hair (:data:`ABOVE` of its widest face above its eyes) a margin below the photo's top, each next
    row's hair below the chins (:data:`BELOW`) of the row before; ValueError when the last row's chins fall out of
    the photo.

    >>> row_heights([[100, 200], [300]], 1200)
    [268.0, 788.0]
    """
    heights, bottom = [], MARGIN * height
    for row in rows:
        eyes = bottom + ABOVE * max(row)
        heights.append(float(eyes))
        bottom = eyes + BELOW * max(row)
    if bottom > height:
        raise ValueError(f"a photo {height} pixels high is too low for faces {', '.join(f'{max(r):g}' for r in rows)} wide in rows")
    return heights


def _mixed(row: list[int]) -> list[int]:
    """A row's people, small and large taking turns from the left."""
    return [row[k // 2] if k % 2 == 0 else row[-1 - k // 2] for k in range(len(row))]


def make(
    london: str | Path,
    people: Sequence[str],
    widths: Sequence[float],
    size: tuple[int, int],
    seed: int = 0,
    smiling: bool = False,
    tilts: Sequence[float] | None = None,
) -> tuple[np.ndarray, list[Person]]:
    """A group photo of ``people`` (London Set ids) whose faces are ``widths`` pixels wide, in a photo of ``size``.

    Parameters
    ----------
    london : str or Path
        The London Set's folder.
    people : sequence of str
    widths : sequence of float
        Each person's face width in the photo, pixels (the jaw's, see the module's notes).
    size : tuple of int
        ``(width, height)`` of the photo.
    seed : int
        The background's.
    smiling : bool
        Their smiling photos instead of their neutral ones (placed by the neutral photos' templates).
    tilts : sequence of float, optional
        Each person's head turned in the photo's plane by so many degrees (counter-clockwise as seen), about the eyes;
        upright by default.

    Returns
    -------
    image : ndarray of shape (height, width, 3), uint8 RGB
    people : list of Person
        In the order given.
    """
    width, height = size
    canvas = background(size, seed).astype(np.float32)
    rows = layout_rows(widths)
    placed: dict[int, Person] = {}
    for row, eyes_y in zip(rows, row_heights([[widths[k] for k in row] for row in rows], height)):
        for slot, k in enumerate(row):
            image, points = face_of(london, people[k], smiling)
            if tilts is not None and tilts[k]:
                image, points = turned(image, points, tilts[k])
            eyes = np.array([width * (slot + 0.5) / len(row), eyes_y])
            placed[k] = _paste(canvas, image, points, widths[k], eyes, people[k])
    return np.clip(np.round(canvas), 0, 255).astype(np.uint8), [placed[k] for k in range(len(people))]


def turned(image: np.ndarray, points: np.ndarray, degrees: float) -> tuple[np.ndarray, np.ndarray]:
    """A London photo and its landmarks turned by ``degrees`` about the eyes' midpoint (the wall's colour drawn in at
    the corners, so that the cut-out still finds it there)."""
    eyes = points[36:48].mean(0)
    matrix = cv2.getRotationMatrix2D((float(eyes[0]), float(eyes[1])), degrees, 1.0)
    image = cv2.warpAffine(image, matrix, image.shape[1::-1], flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return image, points @ matrix[:, :2].T + matrix[:, 2]


def _paste(canvas: np.ndarray, image: np.ndarray, points: np.ndarray, width: float, eyes: np.ndarray, face_id: str) -> Person:
    """One person laid over ``canvas`` (float32, in place), their face ``width`` pixels wide, their eyes' midpoint at
    ``eyes``."""
    scale = width / float(np.linalg.norm(points[16] - points[0]))
    small = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA).astype(np.float32)
    mask = cv2.resize(silhouette(image, points), small.shape[1::-1], interpolation=cv2.INTER_AREA)
    scale = small.shape[1] / image.shape[1]  # as resized
    offset = np.round(eyes - (points[36:48].mean(0) + 0.5) * scale + 0.5)
    x0, y0 = int(offset[0]), int(offset[1])
    h, w = canvas.shape[:2]
    top, left = max(0, y0), max(0, x0)
    bottom, right = min(h, y0 + small.shape[0]), min(w, x0 + small.shape[1])
    part = (slice(top - y0, bottom - y0), slice(left - x0, right - x0))
    alpha = mask[part][..., None]
    canvas[top:bottom, left:right] = canvas[top:bottom, left:right] * (1 - alpha) + small[part] * alpha
    person = Person(face_id, scale, offset.astype(float), np.zeros((68, 2)))
    return Person(face_id, scale, person.offset, person.place(points))
