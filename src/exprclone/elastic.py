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
    """Pad per-point neighbour lists into an index array and a validity mask, ``(N, K)``."""
    k = max(len(n) for n in neighbours)
    index = np.zeros((len(neighbours), k), np.int64)
    mask = np.zeros((len(neighbours), k), bool)
    for i, n in enumerate(neighbours):
        index[i, : len(n)] = n
        mask[i, : len(n)] = True
    return index, mask


def net_force(
    p: np.ndarray, a: np.ndarray, a_local: np.ndarray, b: np.ndarray, mask: np.ndarray, lambda_k: float | np.ndarray
) -> np.ndarray:
    """Net spring force on candidate positions, in units of ``k_N`` (Eqs. 3, 4, 6).

    ``F_Bi(P) = k_N * dl_Bi(P) * e_Bi(P)`` with ``dl_Bi(P) = |P - B_i| - |A - B_i|`` (zero
    at ``P = A``) and ``e_Bi`` the unit vector from ``P`` to ``B_i``;
    ``F_A'(P) = k_A' * |P - A'| * e_A'(P) = k_A' (A' - P)``. Dividing by ``k_N`` leaves
    ``lambda_k = k_A' / k_N`` (Eq. 6) as the one parameter.

    Parameters
    ----------
    p : ndarray of shape (N, M, 2)
        M candidate positions for each of N points.
    a, a_local : ndarray of shape (N, 2)
        Global positions ``A`` and local positions ``A'``.
    b : ndarray of shape (N, K, 2)
        Neighbour positions ``B_i`` (global).
    mask : ndarray of shape (N, K)
        Which neighbour slots are real.
    lambda_k : float or ndarray of shape (N,)

    Returns
    -------
    ndarray of shape (N, M, 2)
    """
    rest = np.sqrt(((a[:, None, :] - b) ** 2).sum(-1))[:, None, :]  # (N, 1, K)
    dx = b[None, :, :, 0].transpose(1, 0, 2) - p[:, :, 0, None]  # (N, M, K): P -> B_i
    dy = b[None, :, :, 1].transpose(1, 0, 2) - p[:, :, 1, None]
    length = np.sqrt(dx * dx + dy * dy)
    coef = (length - rest) * mask[:, None, :] / np.maximum(length, 1e-12)
    lam = np.asarray(lambda_k, float).reshape(-1, 1)
    fx = (coef * dx).sum(-1) + lam * (a_local[:, None, 0] - p[:, :, 0])
    fy = (coef * dy).sum(-1) + lam * (a_local[:, None, 1] - p[:, :, 1])
    return np.stack([fx, fy], -1)


def elastic_landmarks(
    global_pts: np.ndarray, local_pts: np.ndarray, neighbours: list[np.ndarray], lambda_k: float | np.ndarray
) -> np.ndarray:
    """``P_opt`` for every landmark, Eq. (5), by a refining grid search in the window.

    All points are solved at once (vectorised), and so are several ``lambda_k``; each
    point sees its neighbours at their global positions, as in Figs. 6-7.
    ``lambda_k = 0`` gives the global positions, ``lambda_k = inf`` (``k_N = 0``) the
    local ones.

    Parameters
    ----------
    global_pts, local_pts : ndarray of shape (N, 2)
        ``A`` and ``A'`` of every landmark.
    neighbours : list of ndarray
        Triangulation neighbours of each landmark (:meth:`Mesh.neighbours`).
    lambda_k : float or ndarray of shape (L,)
        Elasticity ratio ``k_A' / k_N`` (Eq. 6), ``>= 0``.

    Returns
    -------
    ndarray of shape (N, 2), or (L, N, 2) for an array of ``lambda_k``
    """
    lambdas = np.atleast_1d(np.asarray(lambda_k, float))
    n_lambda, n = len(lambdas), len(global_pts)
    index, mask = pad_neighbours(neighbours)
    # every (lambda_k, point) is one problem; where A = A' the answer is A
    a, a_local = np.tile(global_pts, (n_lambda, 1)), np.tile(local_pts, (n_lambda, 1))
    solve = np.flatnonzero(np.any(a != a_local, axis=1))
    a_s, a_local_s = a[solve], a_local[solve]
    b, mask = np.tile(global_pts[index], (n_lambda, 1, 1))[solve], np.tile(mask, (n_lambda, 1))[solve]
    lam = np.repeat(np.where(np.isinf(lambdas), 0.0, lambdas), n)[solve]
    lo, hi = np.minimum(a_s, a_local_s), np.maximum(a_s, a_local_s)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    steps = np.linspace(-1.0, 1.0, GRID)
    offsets = np.stack(np.meshgrid(steps, steps, indexing="ij"), -1).reshape(-1, 2)  # (M, 2)
    # The window's corners A and A' are candidates of the first pass.
    best = a_s.copy()
    best_norm = np.linalg.norm(net_force(best[:, None], a_s, a_local_s, b, mask, lam)[:, 0], axis=-1)
    rows = np.arange(len(a_s))
    for _ in range(PASSES):
        cand = np.clip(centre[:, None, :] + offsets[None] * half[:, None, :], lo[:, None], hi[:, None])
        norms = np.linalg.norm(net_force(cand, a_s, a_local_s, b, mask, lam), axis=-1)
        k = norms.argmin(axis=1)
        better = norms[rows, k] < best_norm
        best[better] = cand[rows, k][better]
        best_norm[better] = norms[rows, k][better]
        centre, half = best, half * 2 / (GRID - 1)
    a[solve] = best
    best = a
    out = best.reshape(n_lambda, n, 2)
    out[np.isinf(lambdas)] = local_pts  # k_N = 0: only the spring to A' is left
    return out if np.ndim(lambda_k) else out[0]
