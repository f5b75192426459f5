"""The elastic model, Eqs. (3)-(6): a balance of the global and local positions.

Every landmark ``P`` hangs on springs to its triangulation neighbours ``B_i`` (held at
their global positions, rest lengths those of the global result, stiffness ``k_N``)
and on one spring of rest length zero to its local position ``A'`` (stiffness
``k_A'``). Its final place ``P_opt`` is where the net force vanishes, searched inside
the window bounded by the global position ``A`` and ``A'`` (Eq. 5, Fig. 8).
"""

from __future__ import annotations

import numpy as np

#: candidates per side of the search window in each pass of the grid search.
GRID = 9
#: passes of the grid search; each re-centres a window of two grid steps on the best point.
PASSES = 4


def pad_neighbours(neighbours: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Pad per-point neighbour lists into an index array ``(N, K)`` and the list lengths ``(N,)``.

    Row ``i`` holds point ``i``'s neighbours in its first ``count[i]`` slots, zeros after.
    """
    count = np.array([len(n) for n in neighbours], np.int64)
    index = np.zeros((len(neighbours), max(count, default=0)), np.int64)
    for i, n in enumerate(neighbours):
        index[i, : len(n)] = n
    return index, count


def spring_force(p: np.ndarray, a: np.ndarray, b: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Force of the neighbour springs on candidate positions, in units of ``k_N`` (Eqs. 3-4).

    ``sum_i F_Bi(P)`` with ``F_Bi(P) = k_N * dl_Bi(P) * e_Bi(P)``, ``dl_Bi(P) = |P - B_i| -
    |A - B_i|`` (zero at ``P = A``) and ``e_Bi`` the unit vector from ``P`` to ``B_i``.

    Parameters
    ----------
    p : ndarray of shape (N, M, 2)
        M candidate positions for each of N points.
    a : ndarray of shape (N, 2)
        Global positions ``A``.
    b : ndarray of shape (N, K, 2)
        Neighbour positions ``B_i`` (global); point ``i`` has ``count[i]`` of them.
    count : ndarray of shape (N,)

    Returns
    -------
    ndarray of shape (N, M, 2)
    """
    # Points are visited by neighbour slot, most neighbours first, so the points that
    # have a k-th neighbour are a leading block: no work is spent on padding.
    order = np.argsort(-count, kind="stable")
    a, b, count = a[order], b[order], count[order]
    px, py = p[order, :, 0], p[order, :, 1]
    fx, fy = np.zeros(px.shape), np.zeros(px.shape)
    for k in range(b.shape[1]):
        n = int(np.count_nonzero(count > k))
        bx, by = b[:n, k, 0, None], b[:n, k, 1, None]
        rest = np.sqrt((a[:n, 0, None] - bx) ** 2 + (a[:n, 1, None] - by) ** 2)
        dx, dy = bx - px[:n], by - py[:n]  # P -> B_i
        length = np.sqrt(dx * dx + dy * dy)
        coef = (length - rest) / np.maximum(length, 1e-12)
        fx[:n] += coef * dx
        fy[:n] += coef * dy
    out = np.empty(p.shape)
    out[order, :, 0], out[order, :, 1] = fx, fy
    return out


def net_force(p: np.ndarray, a_local: np.ndarray, springs: np.ndarray, lambda_k: float | np.ndarray) -> np.ndarray:
    """Net force on candidate positions, in units of ``k_N`` (Eq. 6).

    The neighbour springs ``springs`` (:func:`spring_force`) plus the spring to ``A'``,
    ``F_A'(P) = k_A' * |P - A'| * e_A'(P) = k_A' (A' - P)``. Dividing by ``k_N`` leaves
    ``lambda_k = k_A' / k_N`` as the one parameter.

    Parameters
    ----------
    p : ndarray of shape (N, M, 2)
        M candidate positions for each of N points.
    a_local : ndarray of shape (N, 2)
        Local positions ``A'``.
    springs : ndarray of shape (N, M, 2)
        :func:`spring_force` at ``p``.
    lambda_k : float or ndarray of shape (N,)

    Returns
    -------
    ndarray of shape (N, M, 2)
    """
    lam = np.asarray(lambda_k, float).reshape(-1, 1)
    out = np.empty(p.shape)
    for d in (0, 1):  # one coordinate at a time: numpy is slow on a last axis of length 2
        out[..., d] = springs[..., d] + lam * (a_local[:, d, None] - p[..., d])
    return out


def vector_length(v: np.ndarray) -> np.ndarray:
    """Euclidean length of ``(..., 2)`` vectors (as ``np.linalg.norm(axis=-1)``, several times faster)."""
    return np.sqrt(v[..., 0] ** 2 + v[..., 1] ** 2)


def elastic_landmarks(
    global_pts: np.ndarray, local_pts: np.ndarray, neighbours: list[np.ndarray], lambda_k: float | np.ndarray, passes: int = PASSES
) -> np.ndarray:
    """``P_opt`` for every landmark, Eq. (5), by a refining grid search in the window.

    All points are solved at once (vectorised), and so are several ``lambda_k``; each
    point sees its neighbours at their global positions, as in Figs. 6-7.
    ``lambda_k = 0`` gives the global positions (the neighbour springs are at rest at
    ``A``), ``lambda_k = inf`` (``k_N = 0``) the local ones; neither is searched. The
    first pass searches the same grid for every ``lambda_k``, so its spring forces are
    computed once.

    Parameters
    ----------
    global_pts, local_pts : ndarray of shape (N, 2)
        ``A`` and ``A'`` of every landmark.
    neighbours : list of ndarray
        Triangulation neighbours of each landmark (:meth:`Mesh.neighbours`).
    lambda_k : float or ndarray of shape (L,)
        Elasticity ratio ``k_A' / k_N`` (Eq. 6), ``>= 0``.
    passes : int
        Passes of the grid search (:data:`PASSES`); fewer place the points less precisely
        (to an eighth of the window, then a quarter of that in each further pass).

    Returns
    -------
    ndarray of shape (N, 2), or (L, N, 2) for an array of ``lambda_k``
    """
    lambdas = np.atleast_1d(np.asarray(lambda_k, float))
    out = np.repeat(global_pts[None].astype(float), len(lambdas), axis=0)
    out[np.isinf(lambdas)] = local_pts  # k_N = 0: only the spring to A' is left
    searched = np.flatnonzero(np.isfinite(lambdas) & (lambdas > 0))
    points = np.flatnonzero(np.any(global_pts != local_pts, axis=1))  # where A = A' the answer is A
    if len(searched) and len(points):
        out[searched[:, None], points] = grid_search(global_pts, local_pts, neighbours, points, lambdas[searched], passes)
    return out if np.ndim(lambda_k) else out[0]


def grid_search(
    global_pts: np.ndarray,
    local_pts: np.ndarray,
    neighbours: list[np.ndarray],
    points: np.ndarray,
    lambdas: np.ndarray,
    passes: int = PASSES,
) -> np.ndarray:
    """The grid search of Eq. (5) for the landmarks ``points`` and each of ``lambdas``, ``(L, P, 2)``."""
    index, count = pad_neighbours([neighbours[i] for i in points])
    a, a_local, b = global_pts[points], local_pts[points], global_pts[index]
    lo, hi = np.minimum(a, a_local), np.maximum(a, a_local)
    steps = np.linspace(-1.0, 1.0, GRID)
    offsets = np.stack(np.meshgrid(steps, steps, indexing="ij"), -1).reshape(-1, 2)  # (M, 2)

    def grid(centre: np.ndarray, half: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        out = np.empty((len(centre), len(offsets), 2))
        for d in (0, 1):
            np.clip(centre[:, d, None] + offsets[:, d] * half[:, d, None], lo[:, d, None], hi[:, d, None], out=out[..., d])
        return out

    first = grid((lo + hi) / 2, (hi - lo) / 2, lo, hi)
    springs = spring_force(first, a, b, count)
    # From here every (lambda_k, point) is one problem.
    n_lambda, n = len(lambdas), len(points)
    a, a_local, b, count, lo, hi, first, springs = (
        np.broadcast_to(x, (n_lambda, *x.shape)).reshape(-1, *x.shape[1:]) for x in (a, a_local, b, count, lo, hi, first, springs)
    )
    lam = np.repeat(lambdas, n)
    # The window's corners A and A' are candidates of the first pass.
    best = a.copy()
    best_norm = vector_length(net_force(best[:, None], a_local, spring_force(best[:, None], a, b, count), lam))[:, 0]
    rows = np.arange(len(a))
    half = (hi - lo) / 2
    for k in range(passes):
        cand = first if k == 0 else grid(best, half, lo, hi)
        norms = vector_length(net_force(cand, a_local, springs if k == 0 else spring_force(cand, a, b, count), lam))
        j = norms.argmin(axis=1)
        better = norms[rows, j] < best_norm
        best[better] = cand[rows, j][better]
        best_norm[better] = norms[rows, j][better]
        half = half * 2 / (GRID - 1)
    return best.reshape(n_lambda, n, 2)
