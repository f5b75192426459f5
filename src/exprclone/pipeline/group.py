"""Every face of a group photo: found and numbered, chosen, each cloned in its own region, the regions blended back.

A clone is of one face on one photo: the target's mesh reaches the photo's border
(:func:`exprclone.imaging.piecewise.build_mesh`), and its light is read from the photo
(the mouth's tone, the ERI's box). A photo of several faces is cloned face by face:

1. :func:`find`: every face, small or large (:func:`exprclone.landmarks.crowd.find`), its
   landmarks fitted in its box, numbered in reading order; one that cannot be cloned
   says why (:func:`problem_of`: too small, turned too far, cut by the frame) and is left
   as it is.
2. :func:`choose`: the faces the options' ``faces`` asks for (all, the largest, or numbers).
3. :func:`region`: each chosen face's region, its landmarks' box grown by :data:`MARGIN`
   of its width on every side, inside the photo, is the target photo of one ordinary clone
   (:func:`exprclone.prepare`): each face is cloned at its own scale, with its own light.
4. :func:`weights` and :meth:`Group.render`: the clones go back into the photo,
   ``input + sum_i w_i (clone_i - input)``, with weights ``w_i`` that are 1 inside region
   ``i`` and fall smoothly to 0 at its edges inside the photo (over :data:`FEATHER` of its
   face's width), and to 0 over every other face (:func:`ownership`), normalised by their sum
   where regions overlap and it exceeds 1. Overlapping or touching regions so blend without
   a seam, each face is its own clone's, and outside the chosen faces' regions, and over the
   faces not chosen, the photo is the input bit for bit.

A photo of one face is cloned whole, as it always was, not in a region (its output is the
same bit for bit); so is a photo whose target landmarks are given.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from ..errors import ExprCloneError
from ..landmarks import crowd
from ..landmarks.backends import Landmarker, shared
from ..landmarks.facemesh import MeshDetector
from ..landmarks.layout import Layout
from ..methods import Method
from ..options import Options
from .checks import check_face
from .cloner import Prepared
from .result import CloneResult, FaceResult

#: a region grows its face's landmark box by this many of the face's widths on every side (a London photo's clone made
#: on its face's region so differs from its clone made on the whole photo by at most 10 levels, 63 dB).
MARGIN = 0.75
#: a region's weight rises from 0 at its edge to 1 over this many of its face's widths.
FEATHER = 0.25
#: a face's core, an ellipse over its landmarks' box and its forehead (this share of the box's height above it),...
FOREHEAD = 0.35
#: ...grown by this factor, is its own: other faces' clones fade out over this much more of its radii.
CORE_GROW, CORE_FEATHER = 1.1, 0.3
#: where two faces' cores meet, the nearer one (in core radii) takes over within this much of either.
HANDOVER = 0.15
#: the narrowest face cloned, pixels across its box.
MIN_ACROSS = 80
#: a face turned further than this (its nose this share of the way from its cheeks' midpoint to a cheek) is left.
MAX_TURN = 0.5
#: a face whose landmarks come within this share of its width of the photo's edge is cut by the frame.
CUT = 0.05

#: a face box ``(left, top, right, bottom)``; a region ``(x0, y0, x1, y1)``.
Box = tuple[float, float, float, float]
Region = tuple[int, int, int, int]


@dataclass(frozen=True, eq=False)
class Found:
    """A face found in a photo.

    Attributes
    ----------
    number : int
        From 1, in reading order (:func:`exprclone.landmarks.crowd.reading_order`).
    box : tuple of float
        ``(left, top, right, bottom)``, pixels.
    points : ndarray of shape (N, 2)
        Its landmarks.
    problem : str
        Why it cannot be cloned (:func:`problem_of`); empty when it can.
    """

    number: int
    box: Box
    points: np.ndarray
    problem: str = ""

    @property
    def across(self) -> float:
        """Its box's width, pixels."""
        return self.box[2] - self.box[0]


def find(image: np.ndarray, landmarker: Landmarker, subject: str, layout: Layout) -> tuple[Found, ...]:
    """Every face of ``image`` with its landmarks, in reading order (see the module's notes).

    A photo with one face gives it as the landmarker's :meth:`~Landmarker.detect` finds it
    (a clone of it is the same as before faces were looked for); with several, each face's
    landmarks are fitted in the box :func:`exprclone.landmarks.crowd.find` gives it (a
    landmarker of one's own that cannot fit a box gives the face it detects).

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    landmarker : Landmarker
    subject : str
        What the photo is, for errors (its role).
    layout : Layout
        The landmarks' layout.

    Returns
    -------
    tuple of Found

    Raises
    ------
    NoFaceError
        The photo shows no face.
    """
    mesh = landmarker if isinstance(landmarker, MeshDetector) else shared("mesh")
    boxes = crowd.find(image, mesh)  # type: ignore[arg-type]  # (the shared mesh landmarker is a MeshDetector)
    if len(boxes) <= 1 or not callable(getattr(landmarker, "fit", None)):  # (a landmarker of one's own may only detect)
        points = landmarker.detect(image, subject)
        return (Found(1, boxes[0] if boxes else _box_of(points), points),)
    faces = []
    for number, box in enumerate(boxes, 1):
        points = landmarker.fit(image, box)
        faces.append(Found(number, box, points, problem_of(points, box, image.shape, layout)))
    return tuple(faces)


def _box_of(points: np.ndarray) -> Box:
    low, high = points.min(0), points.max(0)
    return (float(low[0]), float(low[1]), float(high[0]), float(high[1]))


def turn(points: np.ndarray, layout: Layout) -> float:
    """How far a face is turned from the camera: the nose's offset from the midpoint of the jaw's two ends, along the
    eye line, as a share of half their distance (0 facing the camera, 1 in profile)."""
    right = points[layout.eye_corners[1]] - points[layout.eye_corners[0]]
    right = right / max(float(np.linalg.norm(right)), 1e-12)
    ends = points[[layout.jaw[0], layout.jaw[-1]]] @ right
    nose = float(points[list(layout.nose)].mean(0) @ right)
    return abs(nose - float(ends.mean())) / max(abs(float(ends[1] - ends[0])) / 2, 1e-12)


def problem_of(points: np.ndarray, box: Box, shape: tuple[int, ...], layout: Layout) -> str:
    """Why a face (its landmarks and box in a photo of ``shape``) cannot be cloned, or "" when it can: narrower than
    :data:`MIN_ACROSS`, cut by the frame (:data:`CUT`), turned further than :data:`MAX_TURN` (:func:`turn`), or
    landmarks that make no face (:func:`exprclone.pipeline.checks.check_face`)."""
    across = box[2] - box[0]
    if across < MIN_ACROSS:
        return f"too small ({across:.0f} px across, at least {MIN_ACROSS})"
    low, high = points.min(0), points.max(0)
    edge = CUT * float(high[0] - low[0])
    if (low < edge).any() or high[0] > shape[1] - 1 - edge or high[1] > shape[0] - 1 - edge:
        return "cut by the frame"
    turned = turn(points, layout)
    if turned > MAX_TURN:
        return f"turned too far from the camera (its nose {turned:.2f} of the way to a cheek, at most {MAX_TURN})"
    try:
        check_face(points, layout, "face")
    except ExprCloneError as e:
        return e.problem
    return ""


def choose(faces: Sequence[Found], asked: str | tuple[int, ...]) -> tuple[Found, ...]:
    """The faces the option ``faces`` asks for: ``"all"``, ``"largest"`` (the widest box), or numbers (:func:`check_count`)."""
    check_count(asked, len(faces))
    if asked == "all":
        return tuple(faces)
    if isinstance(asked, str):  # "largest"
        return (max(faces, key=lambda f: f.across),)
    return tuple(f for f in faces if f.number in asked)


def check_count(asked: str | tuple[int, ...], count: int) -> None:
    """ExprCloneError about ``faces`` when it asks for a face number beyond the ``count`` faces of the photo."""
    missing = [] if isinstance(asked, str) else [n for n in asked if n > count]
    if missing:
        shown = f"{count} face" + ("s" if count > 1 else "")
        raise ExprCloneError("faces", f"no face {missing[0]}: the photo shows {shown} (exprclone faces numbers them)")


def region(points: np.ndarray, shape: tuple[int, ...]) -> Region:
    """A face's region ``(x0, y0, x1, y1)``: its landmarks' box grown by :data:`MARGIN` of its width on every side,
    inside a photo of ``shape``.

    >>> region(np.array([[100.0, 100], [200, 220]]), (300, 1000))
    (25, 25, 276, 296)
    """
    low, high = points.min(0), points.max(0)
    grow = MARGIN * float(high[0] - low[0])
    x0, y0 = (max(0, int(np.floor(v - grow))) for v in low)
    return x0, y0, min(shape[1], int(np.ceil(high[0] + grow)) + 1), min(shape[0], int(np.ceil(high[1] + grow)) + 1)


def _smooth(t: np.ndarray) -> np.ndarray:
    """0 below 0, 1 above 1, and the smoothstep ``3t^2 - 2t^3`` between."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3 - 2 * t)


def core(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A face's core: the centre ``(x, y)`` and the half-axes of an ellipse over its landmarks' box and its forehead
    (:data:`FOREHEAD` of the box's height above it), grown by :data:`CORE_GROW`."""
    low, high = points.min(0), points.max(0)
    top = low[1] - FOREHEAD * (high[1] - low[1])
    centre = np.array([(low[0] + high[0]) / 2, (top + high[1]) / 2])
    return centre, CORE_GROW * np.array([(high[0] - low[0]) / 2, (high[1] - top) / 2])


def core_radius(points: np.ndarray, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """Each pixel's distance from a face's centre in radii of its :func:`core`, 1 on the core's edge; float32 of the
    grid ``ys``, ``xs`` broadcast."""
    centre, radii = core(points)
    return np.sqrt(((xs - centre[0]) / radii[0]) ** 2 + ((ys - centre[1]) / radii[1]) ** 2).astype(np.float32)


def ownership(rho_own: np.ndarray, rho_other: np.ndarray) -> np.ndarray:
    """How much of a pixel belongs to another face rather than to one's own, given its distance from each in core
    radii (:func:`core_radius`): 1 over the other's core where it is the nearer, fading out over
    :data:`CORE_FEATHER` beyond it and over :data:`HANDOVER` across the line where the two are equally near."""
    inside = _smooth((1 + CORE_FEATHER - rho_other) / CORE_FEATHER)
    return (inside * _smooth((rho_own - rho_other + HANDOVER) / (2 * HANDOVER))).astype(np.float32)


def weights(faces: Sequence[Found], chosen: Sequence[Found], regions: Sequence[Region], shape: tuple[int, ...]) -> list[np.ndarray]:
    """Each chosen face's weight over its region (see the module's notes), normalised where regions overlap.

    Parameters
    ----------
    faces : sequence of Found
        Every face of the photo (each keeps its own pixels from the others' clones).
    chosen : sequence of Found
        The faces cloned, each in its region of ``regions``.
    regions : sequence of tuple of int
    shape : tuple of int
        The photo's.

    Returns
    -------
    list of ndarray of shape (y1 - y0, x1 - x0), float32
        In ``[0, 1]``; their sum at a pixel is at most 1.
    """
    raw = [_weight(face, r, faces, shape) for face, r in zip(chosen, regions)]
    totals = [w.copy() for w in raw]
    for i, own in enumerate(regions):
        for j, other in enumerate(regions):
            if i != j and (parts := _shared(own, other)):
                totals[i][parts[0]] += raw[j][parts[1]]
    return [w / np.maximum(total, 1.0) for w, total in zip(raw, totals)]


def _shared(a: Region, b: Region) -> tuple[tuple[slice, slice], tuple[slice, slice]] | None:
    """Where two regions overlap, as ``(rows, columns)`` of each; None where they do not."""
    x0, y0, x1, y1 = max(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), min(a[3], b[3])
    if x0 >= x1 or y0 >= y1:
        return None
    return (slice(y0 - a[1], y1 - a[1]), slice(x0 - a[0], x1 - a[0])), (slice(y0 - b[1], y1 - b[1]), slice(x0 - b[0], x1 - b[0]))


def _weight(face: Found, region: Region, faces: Sequence[Found], shape: tuple[int, ...]) -> np.ndarray:
    """One chosen face's weight over its region before the regions are normalised (:func:`weights`): its edges
    inside the photo faded, every other face's pixels taken out (:func:`ownership`), each over its core's reach."""
    x0, y0, x1, y1 = region
    ys, xs = np.arange(y0, y1, dtype=np.float32)[:, None], np.arange(x0, x1, dtype=np.float32)[None, :]
    feather = FEATHER * float(np.ptp(face.points[:, 0]))
    fade_y = _smooth((ys - y0) / feather if y0 > 0 else np.ones_like(ys)) * _smooth(
        (y1 - 1 - ys) / feather if y1 < shape[0] else np.ones_like(ys)
    )
    fade_x = _smooth((xs - x0) / feather if x0 > 0 else np.ones_like(xs)) * _smooth(
        (x1 - 1 - xs) / feather if x1 < shape[1] else np.ones_like(xs)
    )
    w = (fade_y * fade_x).astype(np.float32)
    for other in faces:
        centre, radii = core(other.points)
        reach = (1 + CORE_FEATHER) * radii
        a0, b0 = (max(lo, int(np.floor(c - r))) for lo, c, r in zip((x0, y0), centre, reach))
        a1, b1 = (min(hi, int(np.ceil(c + r)) + 1) for hi, c, r in zip((x1, y1), centre, reach))
        if other.number != face.number and a0 < a1 and b0 < b1:
            window_y, window_x = ys[b0 - y0 : b1 - y0], xs[:, a0 - x0 : a1 - x0]
            own = core_radius(face.points, window_y, window_x)
            w[b0 - y0 : b1 - y0, a0 - x0 : a1 - x0] *= 1 - ownership(own, core_radius(other.points, window_y, window_x))
    return w


def blend(image: np.ndarray, clones: Sequence[np.ndarray], regions: Sequence[Region], weights: Sequence[np.ndarray]) -> np.ndarray:
    """``image`` with each clone (of its region) added where its weight says (see the module's notes); a new array.

    Each region is written once, with every region overlapping it added in the same order, so that a pixel of two
    regions gets the same value from either.
    """
    out = image.copy()
    changes = [w[..., None] * (c.astype(np.float32) - image[y0:y1, x0:x1]) for c, w, (x0, y0, x1, y1) in zip(clones, weights, regions)]
    for own in regions:
        x0, y0, x1, y1 = own
        acc = image[y0:y1, x0:x1].astype(np.float32)
        for change, other in zip(changes, regions):
            if parts := _shared(own, other):
                acc[parts[0]] += change[parts[1]]
        out[y0:y1, x0:x1] = cv2.convertScaleAbs(acc)  # rounded to the nearest level, within 0 to 255 (acc is never below 0)
    return out


@dataclass(frozen=True)
class Group:
    """A clone of several faces of one photo, prepared: each chosen face's own clone on its region, rendered as often
    as asked (as :class:`~exprclone.pipeline.cloner.Prepared` is for one face).

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
        The target photo.
    faces : tuple of Found
        Every face found in it.
    methods : tuple of Method
        The methods prepared.
    options : Options
        The clone's options.
    cloned : tuple of tuple
        ``(face, region, prepared)`` of each face cloned.
    weights : tuple of ndarray
        Each cloned face's weight over its region (:func:`weights`).
    left : dict of int to str
        Why each face not cloned was left as it is, by number.
    landmarker : str or None
        Which landmarker placed the photos' landmarks.
    warnings : tuple of str
        What looked wrong with the photos, and each face asked for that was left as it is.
    """

    image: np.ndarray
    faces: tuple[Found, ...]
    methods: tuple[Method, ...]
    options: Options
    cloned: tuple[tuple[Found, Region, Prepared], ...]
    weights: tuple[np.ndarray, ...]
    left: dict[int, str]
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()

    @property
    def target_size(self) -> tuple[int, int]:
        """The target photo's ``(height, width)``."""
        height, width = self.image.shape[:2]
        return height, width

    @property
    def lambda_k(self) -> None:
        """None: each face's clone has its own (:attr:`CloneResult.face_results`)."""
        return None

    def render(self, **changes: Any) -> dict[str, CloneResult]:
        """Each method's image of the whole photo: every face cloned rendered (:meth:`Prepared.render`, with the same
        ``changes``: the cheap part of the options) and blended back (:func:`blend`); its ``face_results`` each face's own
        result, or why it was left as it is.

        Raises
        ------
        ExprCloneError
            As :meth:`Prepared.render`.
        """
        options = Options.of(self.options, changes)
        rendered = [prepared.render(**changes) for _, _, prepared in self.cloned]
        regions = [r for _, r, _ in self.cloned]
        results = {}
        for method in self.methods:
            own = {face.number: (r, done[method.name]) for (face, r, _), done in zip(self.cloned, rendered)}
            image = blend(self.image, [result.image for _, result in own.values()], regions, self.weights)
            faces = tuple(
                FaceResult(f.number, f.box, *own[f.number])
                if f.number in own
                else FaceResult(f.number, f.box, (0, 0, 0, 0), None, self.left[f.number])
                for f in self.faces
            )
            shown = dataclasses.replace(options, method=method.name)
            results[method.name] = CloneResult(
                image, method.name, {}, options=shown, landmarker=self.landmarker, warnings=self.warnings, face_results=faces
            )
        return results
