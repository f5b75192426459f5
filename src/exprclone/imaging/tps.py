"""Thin-plate-spline image warping (Bookstein 1989): smooth where the mesh warp has kinks.

The piecewise-affine warp of :mod:`exprclone.imaging.piecewise` is continuous but its derivative jumps
at every triangle edge: a straight line across the face (a wrinkle, the edge of a lip)
bends at each edge it crosses. The thin-plate spline through the same control points
is the map of least bending energy: smooth everywhere, exact at the control points.

The output-to-source map ``g`` is fitted on the control points (output positions to
source positions) and evaluated on grids of nodes only: a coarse one over the whole
image, finer ones over the face and over the mouth, where it bends most (:data:`GRID_STEP`,
:data:`FACE_STEP`, :data:`MOUTH_STEP`). Between
the nodes it is interpolated by cubic convolution (``cv2.resize`` of the node grid); as
in :mod:`exprclone.imaging.piecewise`, the maps are made and the photo sampled (``cv2.remap``) strip
by strip of rows, in one buffer that stays in the CPU cache. The spline is smooth at the
grids' scales, so this costs little accuracy and most of the time of evaluating it at
every pixel.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

#: pixels between the grid nodes where the spline is evaluated over the whole image.
GRID_STEP = 32
#: the same over the face (the box of the control points that move), where it bends more,
#: and over the mouth, where it bends most: an opening mouth is squeezed onto the closed lip
#: line of the target's photo, a line a pixel or two high, so that errors of a fraction of
#: a pixel there show as bands across the opening (at 8 pixels plainly, at 4 faintly, at
#: 2 no more than with the spline evaluated at every pixel). ``python tools/tps_grid.py``:
#: on 20 London smiles cloned at 1350 pixels the map is then at most 0.46 pixel from the
#: spline over the face and the mouth (median 0.02), in 1.5 times the mesh warp's time;
#: with 8 pixels over the mouth too, 0.74 pixel off; with 4 over the face, 0.25 pixel off
#: in 2.4 times the mesh warp's time.
FACE_STEP, MOUTH_STEP = 8, 2
#: each finer grid covers the box of its control points grown by this share of its size.
REFINE_MARGIN = 0.1
#: output rows mapped and sampled at a time: each strip resizes the node rows around it,
#: four more than it spans, so tall strips waste less (256 rows: 1.5 times the rows
#: needed on the coarse grid), and its map (2.8 MB at 1350 pixels) still stays in the cache.
STRIP = 256
#: control points whose output positions are closer than this (pixels) are one point, at
#: their mean source position: the inner lips of a closed mouth and the point between
#: them coincide, and a spline cannot take one place to several (or nearly one place to
#: places far apart without a spike).
MERGE_DISTANCE = 1.0


def merged(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Control points with output positions closer than :data:`MERGE_DISTANCE` merged (:data:`MERGE_DISTANCE`'s note).

    Examples
    --------
    >>> src, dst = np.array([[0.0, 0], [0, 4], [9, 9]]), np.array([[0.0, 0], [0, 0.2], [9, 9]])
    >>> [a.tolist() for a in merged(src, dst)]
    [[[0.0, 2.0], [9.0, 9.0]], [[0.0, 0.1], [9.0, 9.0]]]
    """
    label = np.arange(len(dst))
    for i in range(len(dst)):
        close = np.flatnonzero(np.linalg.norm(dst - dst[i], axis=1) < MERGE_DISTANCE)
        label[close] = label[close].min()
    groups = np.unique(label)
    src_means, dst_means = (np.array([a[label == g].mean(axis=0) for g in groups]) for a in (src, dst))
    return src_means, dst_means


@dataclass(frozen=True)
class Grid:
    """The spline's displacement on the nodes of one box of the output, every ``step`` pixels.

    Node ``(j, i)`` is at pixel ``(left + (i - 1.5) step - 0.5, top + (j - 1.5) step - 0.5)``:
    where ``cv2.resize`` by ``step`` puts its input's samples, so that resizing the node
    grid (bicubic) interpolates it at every pixel; two nodes beyond the box on each side
    keep the resize's edges (where it repeats the last node) off the box.

    Attributes
    ----------
    left, top, step : int
    size : (int, int)
        The box's height and width.
    nodes : ndarray of shape (ny, nx, 2), float32
        The spline's x and y displacement at each node.
    """

    left: int
    top: int
    step: int
    size: tuple[int, int]
    nodes: np.ndarray

    @classmethod
    def evaluate(cls, spline: Callable[[np.ndarray], np.ndarray], box: tuple[slice, slice], step: int) -> "Grid":
        """The spline (points ``(K, 2)`` to displacements ``(K, 2)``) on the nodes of ``box`` (rows, columns)."""
        rows, cols = box
        h, w = rows.stop - rows.start, cols.stop - cols.start
        xs = cols.start + (np.arange(-(-w // step) + 4) - 1.5) * step - 0.5
        ys = rows.start + (np.arange(-(-h // step) + 4) - 1.5) * step - 0.5
        nodes = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        return cls(cols.start, rows.start, step, (h, w), spline(nodes).reshape(len(ys), len(xs), 2).astype(np.float32))

    def rows(self, y0: int, y1: int) -> np.ndarray:
        """The displacement of the box's pixels in rows ``y0`` to ``y1``, ``(y1 - y0, width, 2)``: the node rows around
        them resized (bicubic), cropped."""
        step, (top, width) = self.step, (y0 - self.top, self.size[1])
        first = int((top + 0.5) / step + 1.5) - 1  # the first node row that the first pixel row's four nodes take
        last = int((y1 - self.top - 0.5) / step + 1.5) + 3
        part = cv2.resize(self.nodes[first:last], (self.nodes.shape[1] * step, (last - first) * step), interpolation=cv2.INTER_CUBIC)
        r = top - (first - 2) * step
        return part[r : r + y1 - y0, 2 * step : 2 * step + width]


@dataclass(frozen=True)
class Spline:
    """The thin-plate spline through control points (Bookstein 1989), fitted in float64, evaluated in float32.

    ``f(p) = a0 + A p + sum_i w_i U(|p - c_i|)`` with ``U(r) = r**2 log r``, the weights
    and the affine part solved so that ``f(c_i) = v_i`` and the weights carry no affine
    part (the bordered system of Bookstein's Eq. 4). Points are measured from the centres'
    mean in units of their spread (the kernel's scale does not matter to the spline, but
    the system is better conditioned). On the control points of London smiles at 1350
    pixels, float32 evaluation is within 0.04 pixel of SciPy's float64
    ``RBFInterpolator``, in half its time.

    Attributes
    ----------
    centres : ndarray of shape (N, 2), float32
    weights : ndarray of shape (N, 2), float32
    affine : ndarray of shape (3, 2), float32
        ``[a0; A.T]``.
    origin : ndarray of shape (2,)
    unit : float
    """

    centres: np.ndarray
    weights: np.ndarray
    affine: np.ndarray
    origin: np.ndarray
    unit: float

    @classmethod
    def fit(cls, points: np.ndarray, values: np.ndarray) -> "Spline":
        """The spline that takes ``points`` ``(N, 2)`` (distinct, not all on one line) to ``values`` ``(N, 2)``."""
        origin, unit = points.mean(axis=0), max(float(points.std()), 1e-9)
        c = (points - origin) / unit
        n = len(c)
        system = np.zeros((n + 3, n + 3))
        system[:n, :n] = kernel(np.sum((c[:, None] - c[None]) ** 2, axis=2))
        affine = np.hstack([np.ones((n, 1)), c])
        system[:n, n:], system[n:, :n] = affine, affine.T
        solution = np.linalg.solve(system, np.vstack([values, np.zeros((3, 2))])).astype(np.float32)
        return cls(c.astype(np.float32), solution[:n], solution[n:], origin, unit)

    def __call__(self, points: np.ndarray) -> np.ndarray:
        """The spline's values at ``points`` ``(M, 2)``, ``(M, 2)`` float32."""
        p = ((points - self.origin) / self.unit).astype(np.float32)
        dx, dy = p[:, 0, None] - self.centres[:, 0], p[:, 1, None] - self.centres[:, 1]
        # OpenCV's product, not numpy's: OpenBLAS's threads wait long for a busy CPU (ten times a product's work)
        return (
            # OpenCV 5.0's stubs refuse None for src3, which the C++ API takes as noArray() (no third term); 5.1's admit it
            cv2.gemm(kernel(dx * dx + dy * dy), self.weights, 1.0, None, 0.0)  # type: ignore[call-overload, unused-ignore]
            + p[:, :1] * self.affine[1]
            + p[:, 1:] * self.affine[2]
            + self.affine[0]
        )


def kernel(squared: np.ndarray) -> np.ndarray:
    """``U(r) = r**2 log r`` from ``r**2`` (0 at 0)."""
    return 0.5 * squared * np.log(np.maximum(squared, np.finfo(squared.dtype).tiny))


def grids(src: np.ndarray, dst: np.ndarray, out_shape: tuple[int, int], refine: Sequence[tuple[np.ndarray, int]]) -> list[Grid]:
    """The spline of the displacement fitted on the control points (output positions to displacements), on the
    whole image's grid (:data:`GRID_STEP`), then on the finer grid of each box of ``refine``."""
    h, w = out_shape
    boxes = [(dst[np.asarray(idx)], step) for idx, step in refine]
    src, dst = merged(src, dst)
    spline = Spline.fit(dst, src - dst)
    out = [Grid.evaluate(spline, (slice(0, h), slice(0, w)), GRID_STEP)]
    for points, step in boxes:
        margin = REFINE_MARGIN * (points.max(axis=0) - points.min(axis=0))
        lo = np.clip(np.floor(points.min(axis=0) - margin), 0, (w, h)).astype(int)
        hi = np.clip(np.ceil(points.max(axis=0) + margin), 0, (w, h)).astype(int)
        if (hi > lo).all():
            out.append(Grid.evaluate(spline, (slice(lo[1], hi[1]), slice(lo[0], hi[0])), step))
    return out


def strip_maps(
    src: np.ndarray, dst: np.ndarray, out_shape: tuple[int, int], refine: Sequence[tuple[np.ndarray, int]] = ()
) -> Iterator[tuple[slice, np.ndarray]]:
    """``(rows, map)`` for ``cv2.remap``, strip by strip of :data:`STRIP` output rows.

    Parameters
    ----------
    src, dst : ndarray of shape (N, 2)
        Control points in the source image and in the output, not all on one line.
    out_shape : (H, W)
    refine : sequence of (ndarray of int, int)
        Control points (their indices) whose box gets a finer grid, and its step
        (:data:`FACE_STEP`, :data:`MOUTH_STEP`); later boxes over earlier ones.

    Yields
    ------
    rows : slice
    map : ndarray of shape (rows, W, 2), float32
        Each pixel's source position; overwritten by the next strip's.
    """
    h, w = out_shape
    coarse, *fine = grids(np.asarray(src, float), np.asarray(dst, float), out_shape, refine)
    shift = np.empty((min(STRIP, h), w, 2), np.float32)
    for y0 in range(0, h, STRIP):
        rows = slice(y0, min(y0 + STRIP, h))
        n = rows.stop - y0
        shift[:n] = coarse.rows(rows.start, rows.stop)
        for g in fine:
            top, bottom = max(rows.start, g.top), min(rows.stop, g.top + g.size[0])
            if top < bottom:
                shift[top - y0 : bottom - y0, g.left : g.left + g.size[1]] = g.rows(top, bottom)
        cv2.add(shift[:n], pixel_grid(n, w), dst=shift[:n])
        # a scalar (per channel), which OpenCV 5.0's stubs do not admit beside an array (5.1's do)
        cv2.add(shift[:n], (0.0, float(y0), 0.0, 0.0), dst=shift[:n])  # type: ignore[call-overload, unused-ignore]
        yield rows, shift[:n]


@functools.lru_cache(maxsize=8)
def pixel_grid(rows: int, w: int) -> np.ndarray:
    """The ``(x, y)`` of a strip's pixels, y from the strip's top, ``(rows, w, 2)`` float32 (cached, read-only)."""
    grid = np.stack(np.meshgrid(np.arange(w, dtype=np.float32), np.arange(rows, dtype=np.float32)), axis=-1)
    grid.flags.writeable = False
    return grid


def inverse_maps(src: np.ndarray, dst: np.ndarray, out_shape: tuple[int, int], refine: Sequence[tuple[np.ndarray, int]] = ()) -> np.ndarray:
    """The spline's map from each output pixel to its source position, ``(H, W, 2)`` float32 (:func:`strip_maps`, whole)."""
    out = np.empty((*out_shape, 2), np.float32)
    for rows, strip in strip_maps(src, dst, out_shape, refine):
        out[rows] = strip
    return out


def warp(
    image: np.ndarray,
    src: np.ndarray,
    dst: np.ndarray,
    out_shape: tuple[int, int] | None = None,
    refine: Sequence[tuple[np.ndarray, int]] = (),
) -> np.ndarray:
    """Warp ``image`` by the thin-plate spline that takes control points ``src`` to ``dst``.

    Parameters
    ----------
    image : ndarray of shape (H, W, C) or (H, W)
    src, dst : ndarray of shape (N, 2)
        Control points in ``image`` and in the output.
    out_shape : (H, W), optional
        Output size; the input's by default.
    refine : sequence of (ndarray of int, int)
        Control points whose box gets a finer grid, and its step (:func:`strip_maps`).

    Returns
    -------
    ndarray
        Same dtype and channels as ``image``; where the map leaves the image, its edge is repeated.

    Examples
    --------
    >>> img = np.arange(64 * 64, dtype=np.uint8).reshape(64, 64)
    >>> pts = np.array([[0.0, 0], [63, 0], [0, 63], [63, 63], [30, 30]])
    >>> bool((warp(img, pts, pts) == img).all())
    True
    """
    out_shape = tuple(image.shape[:2] if out_shape is None else out_shape)
    out = np.empty(out_shape + image.shape[2:], image.dtype)
    for rows, strip in strip_maps(src, dst, out_shape, refine):
        # map2 None: the one map holds x and y (OpenCV 5.0's stubs refuse None there; 5.1's admit it)
        cv2.remap(image, strip, None, cv2.INTER_LINEAR, dst=out[rows], borderMode=cv2.BORDER_REPLICATE)  # type: ignore[call-overload, unused-ignore]
    return out
