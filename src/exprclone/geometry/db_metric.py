"""The distance-based (DB) metric, Eqs. (7)-(8), which picks the elasticity ratio.

``DB(lambda_k) = exp(|E(lambda_k) - E_source_exp| / s) + omega_db exp(|E(lambda_k) - E_target_gl| / s)``

with ``E`` the eigenface features (:mod:`exprclone.geometry.eigenface`) and ``omega_db = 1`` as
in the paper. The paper takes exponentials of raw distances, whose unit is arbitrary,
and the unit decides the answer: with tiny distances ``exp`` is linear and Eq. (8)
always keeps the global result, with large ones the first term swamps the second and
it always takes the local result. We measure distances in the unit of the training
faces: features are whitened (Mahalanobis distance in face space) and divided by
``s = sqrt(2 K)``, the expected distance between two training faces, so a distance of
1 is "as far apart as two typical faces". Exponents stay near [0, 3]: no overflow, no
flattening, and the answer does not depend on how the basis was scaled.

The candidate images ``I_target_exp(lambda_k)`` are the geometric (elastic) results,
rendered straight into the 64-pixel crop frame from a shrunk copy of the target photo
(a full-size warp per candidate would be wasted on a 64-pixel feature).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..imaging import piecewise
from ..landmarks import align, lips
from ..landmarks.layout import Layout
from . import eigenface
from .eigenface import Eigenfaces

#: candidate elasticity ratios lambda_k = k_A' / k_N searched by Eq. (8).
LAMBDAS = (0.0, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, np.inf)
#: passes of the elastic model's grid search (:data:`exprclone.geometry.elastic.PASSES`) for the candidates the metric compares:
#: two place each point to a 64th of its window, a small part of a pixel of the 64-pixel crops; the lambda_k chosen
#: is then solved in full.
CANDIDATE_PASSES = 2


@dataclass(frozen=True)
class DBCurve:
    """The DB metric over the candidate grid.

    Attributes
    ----------
    lambdas, db : ndarray of shape (L,)
    to_source, to_global : ndarray of shape (L,)
        The two scaled distances of Eq. (7).
    best : float
        ``lambda_k_opt`` of Eq. (8).
    """

    lambdas: np.ndarray
    db: np.ndarray
    to_source: np.ndarray
    to_global: np.ndarray
    best: float


def db_metric(
    e_candidates: np.ndarray, e_source_exp: np.ndarray, e_target_gl: np.ndarray, omega_db: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. (7) for each candidate feature vector, distances in units of ``sqrt(2 K)``.

    Parameters
    ----------
    e_candidates : ndarray of shape (L, K)
        Whitened eigenface features of the candidates ``I_target_exp(lambda_k)``.
    e_source_exp, e_target_gl : ndarray of shape (K,)
    omega_db : float

    Returns
    -------
    db, to_source, to_global : ndarray of shape (L,)
        DB and its two scaled distances.
    """
    scale = np.sqrt(2.0 * e_candidates.shape[1])
    to_source = np.linalg.norm(e_candidates - e_source_exp, axis=1) / scale
    to_global = np.linalg.norm(e_candidates - e_target_gl, axis=1) / scale
    return np.exp(to_source) + omega_db * np.exp(to_global), to_source, to_global


def target_grey(target_neutral: np.ndarray, mesh: piecewise.Mesh, layout: Layout) -> tuple[np.ndarray, float]:
    """The target photo in grey, shrunk near the crops' scale, and its scale (:func:`exprclone.geometry.eigenface.downscaled`):
    what every candidate's crop is warped from, the same for every expression cloned onto it."""
    return eigenface.downscaled(target_neutral, eigenface.crop_transform(mesh.points[: mesh.n_landmarks], layout))


def render_crops(target: tuple[np.ndarray, float], mesh: piecewise.Mesh, candidates: list[np.ndarray], layout: Layout) -> np.ndarray:
    """Aligned crops of the target photo (its :func:`target_grey`) warped to each candidate landmark set, ``(L, S, S)``.

    Each candidate labels its crop's pixels by triangle; the triangles' maps of all candidates are solved in one batch
    (:func:`exprclone.imaging.piecewise.affines`), each as it would be alone.
    """
    size = eigenface.CROP_SIZE
    grey, scale = target
    labellings = []
    for landmarks in candidates:
        dst = mesh.control_points(lips.uncross(landmarks, layout))
        dst, _ = piecewise.unfold(mesh.points, dst, mesh.triangles, mesh.n_moving)
        t = eigenface.crop_transform(landmarks, layout)
        labellings.append(piecewise.Labelling.of(align.apply(t, dst), mesh.triangles, (size, size)))
    return np.asarray([piecewise.sample(grey, pa) for pa in piecewise.affines(labellings, mesh.points * scale)], np.float32)


def choose_lambda(
    target: tuple[np.ndarray, float],
    mesh: piecewise.Mesh,
    candidates: list[np.ndarray],
    lambdas: np.ndarray,
    source_crop: np.ndarray,
    basis: Eigenfaces,
    layout: Layout,
) -> DBCurve:
    """Eq. (8): the candidate ``lambda_k`` of smallest DB.

    ``candidates[i]`` are the elastic landmarks for ``lambdas[i]``; ``lambdas[0]`` must
    be 0, whose candidate is the global result ``I_target_gl``. ``target`` is the target
    photo as :func:`target_grey` gives it (a :class:`~exprclone.Cloner` keeps it);
    ``source_crop`` the source's expression photo as :func:`exprclone.geometry.eigenface.crop` gives it.
    """
    if lambdas[0] != 0:
        raise ValueError("the first candidate lambda_k must be 0 (the global warping result)")
    e = basis.features(render_crops(target, mesh, candidates, layout))
    e_src = basis.features(source_crop[None])[0]
    db, to_source, to_global = db_metric(e, e_src, e[0])
    return DBCurve(np.asarray(lambdas, float), db, to_source, to_global, float(lambdas[int(np.argmin(db))]))
