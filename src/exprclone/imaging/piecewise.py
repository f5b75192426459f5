"""Piecewise-affine image warping over a Delaunay mesh of the landmarks.

The paper warps the target photo "based on the triangulated mesh information"
(Sec. II, Fig. 2 b, after Wolberg and Liu et al.). Our mesh is the Delaunay
triangulation of the target's neutral landmarks plus two kinds of extra control points:

* forehead points above the brows, which move with the brows, so the forehead is
  carried along instead of being squeezed between the brows and the hair line;
* fixed points on the image border, so the whole image moves smoothly and the
  background stays put;
* a point half-way between each facing pair of inner-lip points, and a triangulation
  computed on a copy of the face whose closed mouth is slightly opened: the slit
  between closed lips is then cut into a regular strip of triangles, so a mouth that
  opens is stretched evenly instead of in the zig-zag of arbitrary slivers.

The warp is vectorised: each output pixel gets the index of its triangle from a label
image, then the inverse affine map of that triangle (:class:`PiecewiseAffine`);
``cv2.remap`` samples the source. Maps and sampling go strip by strip of rows, so the
maps never exist at full size: they stay in the CPU cache, and no large temporary
arrays are allocated (each costs page faults on first touch). Triangles that would
fold over are relaxed first (:func:`unfold`).
"""

from __future__ import annotations

import functools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.spatial import Delaunay

from ..landmarks import align
from ..landmarks.layout import Layout

#: forehead points sit this many inter-ocular distances above each brow point.
FOREHEAD_HEIGHT = 0.45
#: border control points per image side (corners included).
BORDER_POINTS = 5
#: for triangulating, closed lips are held this share of the mouth's width apart (:func:`opened_mouth`).
LIP_GAP = 0.1


@dataclass(frozen=True)
class Mesh:
    """Triangulated control points of one reference face (the target's neutral photo).

    Attributes
    ----------
    points : ndarray of shape (N, 2)
        Landmarks first, then forehead points, then mid-lip points, then border points.
    triangles : ndarray of shape (T, 3)
        Vertex indices into ``points``.
    n_landmarks : int
    brow_of_forehead : ndarray of shape (F,)
        For each forehead point, the brow landmark that carries it.
    lip_pairs : ndarray of shape (P, 2)
        For each mid-lip point, the two inner-lip landmarks it lies between.
    mouth : ndarray of shape (M,)
        The lips' control points: outer and inner lip landmarks, and the mid-lip points.
    """

    points: np.ndarray
    triangles: np.ndarray
    n_landmarks: int
    brow_of_forehead: np.ndarray
    lip_pairs: np.ndarray
    mouth: np.ndarray

    @property
    def forehead(self) -> slice:
        """Where the forehead points are in ``points``."""
        return slice(self.n_landmarks, self.n_landmarks + len(self.brow_of_forehead))

    @property
    def n_moving(self) -> int:
        """Landmarks, forehead and mid-lip points: the vertices that may move."""
        return self.n_landmarks + len(self.brow_of_forehead) + len(self.lip_pairs)

    def control_points(self, landmarks: np.ndarray, transform: np.ndarray | None = None) -> np.ndarray:
        """Control points for a new position of the landmarks.

        Parameters
        ----------
        landmarks : ndarray of shape (n_landmarks, 2)
            The landmarks, in the image where the mesh is placed.
        transform : ndarray of shape (2, 3), optional
            Similarity from the reference image into that image (for another person's
            photo); identity by default. Border points follow it; forehead points follow
            it plus the displacement of their brow point.

        Returns
        -------
        ndarray of shape (N, 2)
        """
        t = np.eye(2, 3) if transform is None else transform
        mapped = align.apply(t, self.points)
        out = mapped.copy()
        out[: self.n_landmarks] = landmarks
        brows = self.brow_of_forehead
        out[self.forehead] += landmarks[brows] - mapped[brows]
        out[self.forehead.stop : self.n_moving] = landmarks[self.lip_pairs].mean(axis=1)
        return out

    def neighbours(self) -> list[np.ndarray]:
        """For each landmark, the landmarks it shares a triangle edge with."""
        n = self.n_landmarks
        tri = self.triangles
        edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
        edges = edges[(edges < n).all(axis=1)]
        # each edge both ways as one sorted key (from * n + to): each landmark's neighbours in order, once each
        keys = np.unique(np.concatenate([edges[:, 0] * n + edges[:, 1], edges[:, 1] * n + edges[:, 0]]))
        return np.split((keys % n).astype(tri.dtype), np.searchsorted(keys // n, np.arange(1, n)))


def build_mesh(landmarks: np.ndarray, image_shape: tuple[int, ...], layout: Layout) -> Mesh:
    """Triangulate the landmarks of the reference face with forehead and border points.

    Parameters
    ----------
    landmarks : ndarray of shape (n_points, 2)
    image_shape : tuple
        ``(H, W, ...)`` of the reference image.
    layout : Layout
    """
    h, w = image_shape[:2]
    brows = np.array(layout.brows[0] + layout.brows[1])
    up = -align.face_axes(landmarks, layout)[1]
    forehead = landmarks[brows] + FOREHEAD_HEIGHT * align.interocular(landmarks, layout) * up
    forehead[:, 0] = np.clip(forehead[:, 0], 1.0, w - 2.0)
    forehead[:, 1] = np.clip(forehead[:, 1], 1.0, h - 2.0)
    xs = np.linspace(-0.5, w - 0.5, BORDER_POINTS)
    ys = np.linspace(-0.5, h - 0.5, BORDER_POINTS)[1:-1]
    border = np.concatenate(
        [
            np.stack([xs, np.full_like(xs, -0.5)], 1),
            np.stack([xs, np.full_like(xs, h - 0.5)], 1),
            np.stack([np.full_like(ys, -0.5), ys], 1),
            np.stack([np.full_like(ys, w - 0.5), ys], 1),
        ]
    )
    pairs = np.array(layout.lip_pairs)
    points = np.concatenate([landmarks, forehead, landmarks[pairs].mean(axis=1), border]).astype(float)
    n_moving = len(landmarks) + len(forehead) + len(pairs)
    # QJ joggles the input so that coincident points still become vertices.
    triangles = Delaunay(
        opened_mouth(points, pairs, len(landmarks) + len(forehead), landmarks, layout), qhull_options="QJ"
    ).simplices.astype(np.int32)
    # the joggle leaves slivers of zero area along the straight border: drop them
    on_border = (triangles >= n_moving).all(axis=1)
    area = np.abs(signed_areas(points, triangles))
    triangles = triangles[~on_border | (area > 1e-6 * area.max())]
    first_mid = len(landmarks) + len(forehead)
    mouth = np.array(layout.mouth_outer + layout.mouth_inner + tuple(range(first_mid, n_moving)))
    return Mesh(points, triangles, len(landmarks), brows, pairs, mouth)


def opened_mouth(points: np.ndarray, pairs: np.ndarray, first_mid: int, landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """A copy of the control points whose inner lips stand apart, for triangulating.

    Facing inner-lip points closer than :data:`LIP_GAP` of the mouth's width are pushed apart
    to that gap along the face's vertical, their mid-lip point between them.
    """
    out = points.copy()
    down = align.face_axes(landmarks, layout)[1]
    i, j = layout.mouth_corners
    gap = LIP_GAP * np.linalg.norm(landmarks[j] - landmarks[i])
    for k, (upper, lower) in enumerate(pairs):
        mid = (points[upper] + points[lower]) / 2
        half = max(gap, float((points[lower] - points[upper]) @ down)) / 2
        out[upper], out[lower], out[first_mid + k] = mid - half * down, mid + half * down, mid
    return out


def signed_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Twice the signed area of each triangle (positive when counter-clockwise in x-right, y-up)."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def folded(src: np.ndarray, dst: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Mask of triangles whose orientation flips from ``src`` to ``dst``.

    Triangles of (almost) no area in ``src``, such as those between the touching lips of
    a closed mouth, have no orientation to lose: they are slits that may open.
    """
    a0, a1 = signed_areas(src, triangles), signed_areas(dst, triangles)
    return (a0 * a1 < 0) & (np.abs(a0) > 1e-3 * np.abs(a0).max())


def unfold(
    src: np.ndarray, dst: np.ndarray, triangles: np.ndarray, n_moving: int, held: np.ndarray | None = None, max_iter: int = 100
) -> tuple[np.ndarray, int]:
    """Relax moving vertices of folded triangles until no triangle folds over.

    Each pass moves every movable vertex of a folded triangle half-way towards the
    mean of its mesh neighbours (a Laplacian step), which restores the orientation of
    the small triangles that fold first. The first ``n_moving`` vertices are movable, but for
    those in ``held`` (indices: a region held at its place, whose pixels must stay the photo's).

    Returns
    -------
    dst : ndarray of shape (N, 2)
        Corrected copy of ``dst``.
    n_fixed : int
        Number of vertices that were moved.
    """
    dst = dst.copy()
    moved = np.zeros(len(dst), bool)
    for _ in range(max_iter):
        bad = folded(src, dst, triangles)
        if not bad.any():
            break
        verts = np.unique(triangles[bad])
        verts = verts[(verts < n_moving) & ~np.isin(verts, () if held is None else held)]
        if len(verts) == 0:
            break
        for v in verts:
            ring = np.unique(triangles[(triangles == v).any(axis=1)])
            ring = ring[ring != v]
            dst[v] = 0.5 * dst[v] + 0.5 * dst[ring].mean(axis=0)
        moved[verts] = True
    return dst, int(moved.sum())


#: output rows mapped and sampled at a time: the maps of a strip stay in the CPU cache.
STRIP = 64


@functools.lru_cache(maxsize=8)
def strip_grid(rows: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Float32 x and y coordinates of a strip's pixels, y counted from the strip's top (cached, read-only)."""
    xs, ys = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(rows, dtype=np.float32))
    xs.flags.writeable = ys.flags.writeable = False
    return xs, ys


@dataclass(frozen=True)
class Labelling:
    """Which triangle each output pixel lies in: what a piecewise-affine warp takes of its destination alone.

    Warps of several images to the same control points (the ERI's photos) label the
    output once (:meth:`of`) and solve only their own affine maps (:meth:`affine`).

    Attributes
    ----------
    labels : ndarray of shape (H, W)
        For each output pixel, 1 + the index of its triangle in :attr:`triangles`; 0 outside every triangle.
        uint8 with fewer than 256 labels (looked up by ``cv2.LUT``), int32 otherwise.
    triangles : ndarray of shape (T, 3)
        The triangles that reach into the output, in the order they were drawn (a later one takes a shared edge).
    dst : ndarray of shape (N, 2)
        The control points in the output.
    """

    labels: np.ndarray
    triangles: np.ndarray
    dst: np.ndarray

    @classmethod
    def of(cls, dst: np.ndarray, triangles: np.ndarray, out_shape: tuple[int, int]) -> Labelling:
        """Label the pixels of an output of ``out_shape`` (H, W) by the triangle of ``dst`` (``(N, 2)``) each lies in."""
        h, w = out_shape
        dst = np.asarray(dst, float)
        # triangles wholly outside the output label no pixel (fillConvexPoly clips them)
        lo, hi = dst[triangles].min(axis=1), dst[triangles].max(axis=1)
        triangles = triangles[(hi[:, 0] >= -1) & (lo[:, 0] <= w) & (hi[:, 1] >= -1) & (lo[:, 1] <= h)]
        labels = np.zeros(out_shape, np.uint8 if len(triangles) < 256 else np.int32)
        shift = 4
        fixed = np.round(dst[triangles] * (1 << shift)).astype(np.int32)
        for label, tri in enumerate(fixed, 1):
            cv2.fillConvexPoly(labels, tri, label, cv2.LINE_8, shift)
        return cls(labels, triangles, dst)

    def affine(self, src: np.ndarray) -> PiecewiseAffine:
        """The warp from control points ``src`` (``(N, 2)``, in the source image) to :attr:`dst` over these labels."""
        return affines([self], src)[0]


def affines(labellings: Sequence[Labelling], src: np.ndarray) -> list[PiecewiseAffine]:
    """The warps from control points ``src`` (``(N, 2)``, in the source image) to each labelling's :attr:`~Labelling.dst`.

    Their triangles' affine maps are solved in one batch: one photo warped to many control points (the DB metric's
    candidates) pays the solver's call once, not once per warp; each map is the same as solved alone.
    """
    src = np.asarray(src, float)
    triangles = np.concatenate([lab.triangles for lab in labellings])
    dst = np.concatenate([lab.dst[lab.triangles] for lab in labellings])
    d = np.concatenate([dst, np.ones((len(triangles), 3, 1))], axis=2)
    # Affine dst -> src per triangle: d @ coeffs = src. Slivers of (almost) no area,
    # such as the slit between closed lips, get the least-squares map of pinv.
    solvable = np.concatenate([np.abs(signed_areas(lab.dst, lab.triangles)) > 1e-6 for lab in labellings])
    coeffs = np.empty((len(triangles), 3, 2))
    coeffs[solvable] = np.linalg.solve(d[solvable], src[triangles[solvable]])
    if not solvable.all():
        coeffs[~solvable] = np.linalg.pinv(d[~solvable]) @ src[triangles[~solvable]]
    out = []
    for lab, own in zip(labellings, np.split(coeffs, np.cumsum([len(lab.triangles) for lab in labellings])[:-1])):
        table = np.concatenate([np.full((1, 3, 2), -1e6), own])
        if lab.labels.dtype == np.uint8:
            table = np.resize(table, (256, 3, 2))  # a full table for cv2.LUT
        out.append(PiecewiseAffine(lab.labels, table))
    return out


@dataclass(frozen=True)
class PiecewiseAffine:
    """The inverse map of a triangle mesh, ready to be evaluated strip by strip.

    Attributes
    ----------
    labels : ndarray of shape (H, W)
        Each output pixel's triangle (:attr:`Labelling.labels`).
    coeffs : ndarray of shape (L, 3, 2)
        Per label, the affine map output -> source: ``[x y 1] @ coeffs[label] = [u v]``.
        Label 0 maps far outside the source. ``L = 256`` for uint8 labels, ``T + 1`` otherwise.
    """

    labels: np.ndarray
    coeffs: np.ndarray

    @classmethod
    def build(cls, src: np.ndarray, dst: np.ndarray, triangles: np.ndarray, out_shape: tuple[int, int]) -> PiecewiseAffine:
        """Label the output pixels by triangle and solve each triangle's affine map.

        Parameters
        ----------
        src, dst : ndarray of shape (N, 2)
            Control points in the source image and in the output image.
        triangles : ndarray of shape (T, 3)
        out_shape : (H, W)
        """
        return Labelling.of(dst, triangles, out_shape).affine(src)

    def strip_maps(self) -> Iterator[tuple[slice, np.ndarray, np.ndarray]]:
        """``(rows, map_x, map_y)`` for ``cv2.remap``, strip by strip of :data:`STRIP` output rows.

        Each map is ``a_x x + a_y (y - y0) + (a_0 + a_y y0)`` with the three coefficients
        looked up per pixel by its label (``y0`` the strip's first row, folded into the
        table so that the strip's coordinate grid is the same for every strip). The
        maps are float32 and are overwritten by the next strip's: one set of buffers
        serves every strip, since fresh arrays cost a page fault per 4 kB on first touch.
        """
        h, w = self.labels.shape
        map_x, map_y, scratch = (np.empty((min(STRIP, h), w), np.float32) for _ in range(3))

        def gather(labels: np.ndarray, table: np.ndarray, out: np.ndarray) -> np.ndarray:
            # cv2.LUT on 8-bit labels is several times faster than numpy's gather
            table = table.astype(np.float32)
            return cv2.LUT(labels, table, dst=out) if labels.dtype == np.uint8 else np.take(table, labels, out=out)

        for y0 in range(0, h, STRIP):
            rows = slice(y0, min(y0 + STRIP, h))
            labels = self.labels[rows]
            n = len(labels)
            xs, ys = strip_grid(n, w)
            for c, m in ((0, map_x[:n]), (1, map_y[:n])):
                ax, ay, a0 = self.coeffs[:, :, c].T
                gather(labels, a0 + ay * y0, m)
                cv2.accumulateProduct(gather(labels, ax, scratch[:n]), xs, m)
                cv2.accumulateProduct(gather(labels, ay, scratch[:n]), ys, m)
            yield rows, map_x[:n], map_y[:n]


def inverse_maps(src: np.ndarray, dst: np.ndarray, triangles: np.ndarray, out_shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Per-pixel maps ``(map_x, map_y)`` for ``cv2.remap``: output pixel -> source position.

    :func:`warp` evaluates the same maps strip by strip without keeping them whole.

    Parameters
    ----------
    src, dst : ndarray of shape (N, 2)
        Control points in the source image and in the output image.
    triangles : ndarray of shape (T, 3)
    out_shape : (H, W)

    Returns
    -------
    map_x, map_y : ndarray of shape (H, W), float32
        Pixels outside every triangle map outside the source (border handling of remap).
    """
    pa = PiecewiseAffine.build(src, dst, triangles, out_shape)
    map_x, map_y = np.empty(out_shape, np.float32), np.empty(out_shape, np.float32)
    for rows, strip_x, strip_y in pa.strip_maps():
        map_x[rows], map_y[rows] = strip_x, strip_y
    return map_x, map_y


def warp(
    image: np.ndarray, src: np.ndarray, dst: np.ndarray, triangles: np.ndarray, out_shape: tuple[int, int] | None = None
) -> np.ndarray:
    """Warp ``image`` so that control points ``src`` move to ``dst``.

    Parameters
    ----------
    image : ndarray of shape (H, W, C) or (H, W)
    src, dst : ndarray of shape (N, 2)
        Control points in ``image`` and in the output.
    triangles : ndarray of shape (T, 3)
    out_shape : (H, W), optional
        Output size; the input's by default.

    Returns
    -------
    ndarray
        Same dtype and channels as ``image``.

    Examples
    --------
    >>> img = np.arange(64 * 64 * 3, dtype=np.uint8).reshape(64, 64, 3)
    >>> pts = np.array([[-0.5, -0.5], [63.5, -0.5], [-0.5, 63.5], [63.5, 63.5], [30, 30]])
    >>> tri = Delaunay(pts).simplices
    >>> bool((warp(img, pts, pts, tri) == img).all())
    True
    """
    out_shape = tuple(image.shape[:2] if out_shape is None else out_shape)
    return sample(image, PiecewiseAffine.build(src, dst, triangles, out_shape))


def sample(image: np.ndarray, pa: PiecewiseAffine) -> np.ndarray:
    """``image`` sampled through the map ``pa`` (bilinear, the border repeated), at the size of its labels."""
    out = np.empty(pa.labels.shape + image.shape[2:], image.dtype)
    for rows, map_x, map_y in pa.strip_maps():
        cv2.remap(image, map_x, map_y, cv2.INTER_LINEAR, dst=out[rows], borderMode=cv2.BORDER_REPLICATE)
    return out
