"""The inner-lip polygon kept valid.

Landmark fitters often put the inner lips of a closed mouth crossed over each other
(the lower inner lip a pixel above the upper one), and now and then an inner lip
outside the outer one. Either folds the mesh over and makes the mouth opening a
self-intersecting polygon, or one that spills over the lips, so every landmark set is
made valid first (:func:`uncross`).
"""

from __future__ import annotations

import numpy as np

from . import align
from .layout import Layout

#: how far outside a polygon (pixels) a point may be and still count as on its edge.
TOLERANCE = 1e-6
#: how near (pixels) to the farthest place its edges allow an inner-lip point is put back (:func:`inside_outer_lips`).
PRECISION = 1e-3


def uncross(landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks whose lips are stacked in order and whose inner lips lie inside the outer ones.

    First, in the face's own frame (so a tilted head works), for each column
    ``(upper outer, upper inner, lower inner, lower outer)`` of ``layout.lip_columns``:
    an inner lip point above its outer lip (or below, for the lower lip) is moved onto
    it, and a crossed inner pair moves to its midpoint: the mouth is closed there.
    Then what still lies outside the outer lips (an inner mouth corner beside the outer
    one, an edge cutting across the Cupid's bow) is pulled in by :func:`inside_outer_lips`.
    Valid lips are left as they are; the outer lips never move.

    Parameters
    ----------
    landmarks : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)
    """
    out = np.array(landmarks, float)
    down = align.face_axes(out, layout)[1]
    for upper_outer, upper, lower, lower_outer in layout.lip_columns:
        for inner, outer, sign in ((upper, upper_outer, 1), (lower, lower_outer, -1)):
            depth = sign * (out[inner] - out[outer]) @ down  # how far inside the outer lip
            if depth < 0:
                out[inner] -= sign * depth * down
        if (out[lower] - out[upper]) @ down < 0:
            out[[upper, lower]] = (out[upper] + out[lower]) / 2
    return inside_outer_lips(out, layout)


def inside_outer_lips(landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks whose inner-lip polygon lies inside the outer-lip polygon (edges included).

    When an inner-lip point lies outside the outer lips, or an inner edge leaves them,
    the inner points are taken to the centre of the outer lips (the mean of their
    points) and put back one at a time, each as far along the way back to where it was
    as its two edges allow (by bisection, to :data:`PRECISION`): first the points that were inside, then the
    others. A point is only ever placed where both its edges, to neighbours placed or
    still at the centre, lie inside; a point at the centre has edges inside, so this
    always succeeds whenever the centre is inside the outer lips (any real mouth). The
    points that could go back all the way do: only what was outside moves, and only as
    far as needed.

    Parameters
    ----------
    landmarks : ndarray of shape (N, 2)
    layout : Layout

    Returns
    -------
    ndarray of shape (N, 2)
        The same values when the inner lips were already inside.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> t = np.linspace(0, 2 * np.pi, 13)[:-1]
    >>> lm = np.zeros((68, 2))
    >>> lm[48:60] = np.c_[-50 * np.cos(t), -20 * np.sin(t)]  # outer lips: an ellipse
    >>> lm[60:68] = 0.5 * lm[48:60][[0, 2, 3, 4, 6, 8, 9, 10]]  # inner lips inside it
    >>> lm[60] = [-70, 0]  # but one inner mouth corner outside
    >>> fixed = inside_outer_lips(lm, DLIB68)
    >>> bool(np.allclose(fixed[60], [-50, 0])), bool(np.array_equal(fixed[61:], lm[61:]))
    (True, True)
    """
    out = np.array(landmarks, float)
    outer = out[list(layout.mouth_outer)]
    ring = list(layout.mouth_inner)
    n = len(ring)
    if clearly_inside(out[ring], outer) or all(segment_inside(out[ring[k]], out[ring[(k + 1) % n]], outer) for k in range(n)):
        return out
    centre = outer.mean(0)
    goal = out[ring].copy()
    was_inside = inside(goal, outer)
    out[ring] = centre
    for k in sorted(range(n), key=lambda k: not was_inside[k]):
        edges = (out[ring[k - 1]], out[ring[(k + 1) % n]])

        def at(s: float) -> np.ndarray:
            return goal[k] if s == 1 else centre + s * (goal[k] - centre)

        def fits(s: float) -> bool:
            return all(segment_inside(at(s), q, outer) for q in edges)

        lo, hi = (1.0, 1.0) if fits(1.0) else (0.0, 1.0)
        reach = float(np.linalg.norm(goal[k] - centre))
        while (hi - lo) * reach > PRECISION:
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        out[ring[k]] = at(lo)
    return out


def inside(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Which points lie inside a closed polygon or on its edges (within :data:`TOLERANCE`).

    Parameters
    ----------
    points : ndarray of shape (K, 2)
    polygon : ndarray of shape (M, 2)
        Its vertices in order.

    Returns
    -------
    ndarray of shape (K,), bool
    """
    p = np.atleast_2d(points)[:, None, :]
    c, d = polygon, _following(polygon)
    e = d - c
    # even-odd rule: count the edges crossed by a ray to the right
    spans = (c[:, 1] > p[..., 1]) != (d[:, 1] > p[..., 1])
    x = c[:, 0] + (p[..., 1] - c[:, 1]) * e[:, 0] / np.where(e[:, 1] == 0, 1.0, e[:, 1])
    result: np.ndarray = (spans & (p[..., 0] < x)).sum(1) % 2 == 1
    outside = ~result  # only these may still be on an edge
    if outside.any():
        q = p[outside]
        t = np.clip(((q - c) * e).sum(-1) / np.maximum((e * e).sum(-1), 1e-300), 0.0, 1.0)
        result[outside] = (np.linalg.norm(q - (c + t[..., None] * e), axis=-1) <= TOLERANCE).any(1)
    return result


def clearly_inside(ring: np.ndarray, polygon: np.ndarray) -> bool:
    """A quick test, sufficient but not necessary, that a closed ring lies inside a polygon.

    True when every vertex of the ring is inside and no edge of the ring meets or touches
    an edge of the polygon (a path that starts inside and never meets the boundary stays
    inside); anything touching is left to the exact :func:`segment_inside`.

    Parameters
    ----------
    ring, polygon : ndarray of shape (K, 2) and (M, 2)
        Vertices in order.

    Returns
    -------
    bool
    """
    if not inside(ring, polygon).all():
        return False
    a0, a1 = ring[:, None], _following(ring)[:, None]
    b0, b1 = polygon[None], _following(polygon)[None]
    meet = (_cross(a1 - a0, b0 - a0) * _cross(a1 - a0, b1 - a0) <= 0) & (_cross(b1 - b0, a0 - b0) * _cross(b1 - b0, a1 - b0) <= 0)
    return not meet.any()


def segment_inside(a: np.ndarray, b: np.ndarray, polygon: np.ndarray) -> bool:
    """Whether the whole segment ``a``-``b`` lies inside a closed polygon (edges included).

    Exact: the segment is cut where it meets the polygon's edges; between two cuts it is
    all inside or all outside, so its ends and the middles of the pieces decide.
    """
    r = b - a
    rr = r @ r
    if rr == 0:
        return bool(inside(a, polygon)[0])
    c, d = polygon, _following(polygon)
    e, q = d - c, c - a
    denom = _cross(r, e)
    crossing = np.abs(denom) > 1e-12 * np.sqrt(rr * (e * e).sum(1))
    with np.errstate(divide="ignore", invalid="ignore"):
        t, u = _cross(q, e) / denom, _cross(q, r) / denom
    cuts = t[crossing & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)]
    # parallel edges may overlap the segment: cut at their ends too
    ends = np.concatenate([q[~crossing], (d - a)[~crossing]]) @ r / rr
    ts = np.unique(np.clip(np.concatenate([[0.0, 1.0], cuts, ends]), 0.0, 1.0))
    ts = np.concatenate([ts, (ts[1:] + ts[:-1]) / 2])
    return bool(inside(a + ts[:, None] * r, polygon).all())


def _following(polygon: np.ndarray) -> np.ndarray:
    """Each vertex's next one around a closed polygon: ``np.roll(polygon, -1, axis=0)``, five times as fast."""
    return np.concatenate([polygon[1:], polygon[:1]])


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z-component of the cross product of 2-d vectors (broadcast over leading axes)."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
