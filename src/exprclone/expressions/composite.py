"""Shape-normalised composites: the average of many people's photos, as face-research labs build them.

A composite is made in four steps (Benson and Perrett 1993; Tiddeman, Burt and Perrett
2001; WebMorph):

1. every photo's landmarks are placed in one frame by the similarity that best aligns
   their rigid points (``layout.rigid``) with the reference's, the reference itself the
   mean of the aligned points (generalised Procrustes analysis, :func:`reference`);
2. the average shape is the mean of the aligned landmarks;
3. every photo is warped to the average shape (the piecewise-affine warp over the mesh
   of :mod:`exprclone.imaging.piecewise`, forehead and border points included);
4. the warped photos' pixels are averaged.

A prototype expression is a pair of composites of the same people (:func:`build`): their
neutral photos and their expression photos, both aligned on the rigid points to one
reference, so that the difference of the two average shapes is the average expression's
motion with each head's own motion taken out (as :func:`exprclone.geometry.global_warp.remove_head_motion`
takes it out of one person's pair). Averaging keeps what the faces share (the smile's
motion, the folds it makes) and washes out what belongs to one of them (the shape of a
nose, a mole, the shape of a person's own smile).

Averaged teeth are a blur of many people's, never aligned tooth by tooth:
:func:`with_interior` replaces the composite's mouth interior by one real photo's,
warped to the average shape.

References
----------
P. J. Benson and D. I. Perrett, "Extracting prototypical facial images from exemplars",
Perception 22, 1993. B. Tiddeman, M. Burt and D. Perrett, "Prototyping and transforming
facial textures for perception research", IEEE Computer Graphics and Applications 21(5), 2001.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..imaging import piecewise, raster
from ..landmarks import align
from ..landmarks.layout import DLIB68, Layout
from ..mouth.measure import mouth_width
from ..mouth.paste import feathered

#: rounds of generalised Procrustes analysis: the reference moves by less than 1e-6 of its size after three.
PROCRUSTES_ROUNDS = 5
#: the composite's frame: its height and width in pixels, and the distance between the outer eye corners in it.
#: The London Set's faces have 241-327 pixels between the outer eye corners (median 282) in
#: their 1350-pixel photos; 256 keeps their detail, and the frame holds the face with its
#: forehead and the margin the ERI's box takes around it (2.8 and 2.5 such distances).
SIZE = (720, 640)
IOD = 256.0


@dataclass(frozen=True)
class Face:
    """A photo and its landmarks.

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    points : ndarray of shape (N, 2)
    """

    image: np.ndarray
    points: np.ndarray


@dataclass(frozen=True)
class Composite:
    """A prototype expression: the neutral and expression composites of the same people, in one frame."""

    neutral: Face
    expression: Face


def reference(shapes: list[np.ndarray], layout: Layout = DLIB68, size: tuple[int, int] = SIZE, iod: float = IOD) -> np.ndarray:
    """The reference of generalised Procrustes analysis on the rigid points, placed in the composite's frame.

    Each round aligns every shape's rigid points to the reference by a similarity and
    takes their mean as the new reference; the last reference is scaled to ``iod``
    between the outer eye corners, levelled, and centred in a frame of ``size`` (the
    box from :data:`exprclone.imaging.piecewise.FOREHEAD_HEIGHT` above the brows to the chin).

    Parameters
    ----------
    shapes : list of ndarray of shape (N, 2)
        Landmarks of every photo.
    layout : Layout
    size : (H, W)
    iod : float

    Returns
    -------
    ndarray of shape (N, 2)
        The mean aligned shape, in the frame's pixels.
    """
    rigid = list(layout.rigid)
    mean = shapes[0]
    for _ in range(PROCRUSTES_ROUNDS):
        mean = np.mean([align.apply(align.fit_similarity(s[rigid], mean[rigid]), s) for s in shapes], axis=0)
    i, j = layout.eye_corners
    axis = mean[j] - mean[i]
    angle, scale = np.arctan2(axis[1], axis[0]), iod / np.linalg.norm(axis)
    c, s = scale * np.cos(-angle), scale * np.sin(-angle)
    levelled = mean @ np.array([[c, -s], [s, c]]).T
    brows = levelled[list(layout.brows[0] + layout.brows[1])]
    top, bottom = brows[:, 1].min() - piecewise.FOREHEAD_HEIGHT * iod, levelled[:, 1].max()
    centre = np.array([(levelled[i, 0] + levelled[j, 0]) / 2, (top + bottom) / 2])
    return levelled - centre + (size[1] / 2, size[0] / 2)


def to_frame(points: np.ndarray, onto: np.ndarray, layout: Layout = DLIB68) -> np.ndarray:
    """The similarity taking a photo's landmarks into the frame of ``onto`` (their rigid points best aligned), ``(2, 3)``."""
    return align.fit_rigid(points, onto, layout)


def to_shape(face: Face, shape: np.ndarray, size: tuple[int, int] = SIZE, layout: Layout = DLIB68) -> np.ndarray:
    """One photo warped to ``shape`` in the composite's frame: float32 ``(H, W, 3)``.

    The photo is first brought to the frame's scale (area averaging, no aliasing), then
    warped over the mesh of ``shape`` (:func:`exprclone.imaging.piecewise.build_mesh`), its forehead
    and border points placed by the photo's alignment (:func:`to_frame`).
    """
    transform = to_frame(face.points, shape, layout)
    scale = float(np.hypot(*transform[:, 0]))
    image, points = face.image, np.asarray(face.points, float)
    if scale < 1.0:
        image = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
        points = points * (np.array(image.shape[1::-1]) / face.image.shape[1::-1])
        transform = to_frame(points, shape, layout)
    mesh = piecewise.build_mesh(shape, size, layout)
    into_photo = cv2.invertAffineTransform(transform)
    return piecewise.warp(image.astype(np.float32), mesh.control_points(points, into_photo), mesh.points, mesh.triangles, size)


def average(faces: list[Face], shape: np.ndarray, size: tuple[int, int] = SIZE, layout: Layout = DLIB68) -> np.ndarray:
    """Every photo warped to ``shape`` (:func:`to_shape`), the pixels averaged: uint8 ``(H, W, 3)``."""
    total = np.zeros((*size, 3), np.float64)
    for face in faces:
        total += to_shape(face, shape, size, layout)
    return np.clip(total / len(faces) + 0.5, 0, 255).astype(np.uint8)


def build(pairs: list[tuple[Face, Face]], layout: Layout = DLIB68, size: tuple[int, int] = SIZE, iod: float = IOD) -> Composite:
    """The prototype of an expression: the composites of the people's neutral photos and of their expression photos.

    Both are aligned on the rigid points to one reference (:func:`reference` of the
    neutral shapes), so each person's head motion between the two photos is taken out;
    each composite's landmarks are the mean of its aligned landmarks.

    Parameters
    ----------
    pairs : list of (Face, Face)
        Each person's neutral photo and expression photo, with their landmarks.
    layout : Layout
    size : (H, W)
        The composites' size in pixels.
    iod : float
        The distance between the outer eye corners in the composites.

    Returns
    -------
    Composite
    """
    frame = reference([n.points for n, _ in pairs], layout, size, iod)
    shapes = [np.mean([align.apply(to_frame(face.points, frame, layout), face.points) for face in faces], axis=0) for faces in zip(*pairs)]
    neutral, expression = (Face(average(list(faces), s, size, layout), s) for faces, s in zip(zip(*pairs), shapes))
    return Composite(neutral, expression)


def interior_mask(points: np.ndarray, size: tuple[int, int], layout: Layout = DLIB68) -> np.ndarray:
    """The inside of the inner lips, feathered as :func:`exprclone.mouth.paste.patch` feathers its paste
    (:func:`exprclone.mouth.paste.feathered`), but ending at the inner-lip line: ``(H, W)`` float32."""
    polygon = raster.fill_polygon(np.zeros(size, np.float32), points[list(layout.mouth_inner)], 1.0)
    return feathered(polygon, mouth_width(points, layout))


def with_interior(composite: Face, donor: Face, layout: Layout = DLIB68) -> Face:
    """The composite with the mouth interior (teeth, tongue, cavity) of one real photo, warped to its shape.

    Parameters
    ----------
    composite : Face
        An expression composite (:func:`build`).
    donor : Face
        A real photo of the expression, with its landmarks.
    layout : Layout

    Returns
    -------
    Face
        The same landmarks; inside the inner lips, the donor's pixels.
    """
    size = composite.image.shape[:2]
    warped = to_shape(donor, composite.points, size, layout)
    mask = interior_mask(composite.points, size, layout)[..., None]
    image = composite.image.astype(np.float32)
    return Face(np.clip(image + mask * (warped - image) + 0.5, 0, 255).astype(np.uint8), composite.points)


def mouth_distance(points: np.ndarray, shape: np.ndarray, layout: Layout = DLIB68) -> float:
    """How far a face's mouth is from ``shape``'s: the mean distance of the lip landmarks after a similarity
    alignment of the lips, in mouth widths of ``shape``.

    Examples
    --------
    >>> shape = np.random.default_rng(0).uniform(0, 100, (68, 2))
    >>> round(mouth_distance(2 * shape + 5, shape), 9)
    0.0
    """
    lips = list(layout.mouth_outer + layout.mouth_inner)
    aligned = align.apply(align.fit_similarity(points[lips], shape[lips]), points[lips])
    return float(np.linalg.norm(aligned - shape[lips], axis=1).mean() / mouth_width(shape, layout))
