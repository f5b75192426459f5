"""The distance-based (DB) metric, Eqs. (7)-(8), which picks the elasticity ratio.

``DB(lambda_k) = exp(|E(lambda_k) - E_source_exp| / u) + omega_db exp(|E(lambda_k) - E_target_gl| / u)``

with ``omega_db = 1`` and one ``lambda_k`` for the whole face, as in the paper. How each part is read (this reading was
written down before any choice of lambda_k was measured on it, and nothing in it was tuned to the rate of
``lambda_k > 0`` it gives):

- ``E``, the features (:mod:`exprclone.geometry.eigenface`): eigenface coefficients (Turk and Pentland) of the face's
  organs, the patches of the brows, eyes, nose and mouth of a grey crop aligned on the eye centres with 128 pixels
  between them. There, the organs' changes between GI and LI (0.013-0.08 inter-ocular distances) are 2-10 pixels;
  in the 64-pixel crops of before (25.6 pixels between the eyes) they were a fraction of one. The basis is trained as
  the paper trains it, on several expressions of one person: of each person of the training set (the London Set's
  neutral face and smile), each person's mean removed, so that its axes span expression, not identity.
- ``|.|``, the Euclidean distance between feature vectors in face space, as Turk and Pentland measure it (not whitened:
  no axis weighted up), in one unit ``u``: the root-mean-square distance between two photos of one training person
  (:attr:`exprclone.geometry.eigenface.Eigenfaces.unit`; for the London Set's basis, a person's smile from their own
  neutral face). The paper takes exponentials of distances whose unit it does not give, and the unit decides the
  answer (tiny distances make ``exp`` linear, and then, the triangle inequality says, ``lambda_k = 0`` always wins;
  large ones let the first term swamp the second). The paper's features come from several expressions of one person,
  so the one scale they carry is how far that person's expressions move the face: a distance of 1 is one expression
  of one person away from another. The basis's own spread, stated once, not a constant chosen by its effect.
- ``I_target_exp(lambda_k)``, the candidates, scored as the synthesized image, not as geometry alone: E+MD's image at
  GI's landmarks (the target photo warped, its ERI weighted by the MD mask, the source's mouth interior pasted) carried
  to each candidate's landmarks by the piecewise-affine map of the target's mesh from GI's control points to the
  candidate's. The target photo's part of it is the candidate's own warp exactly (two affine maps of one triangle
  are one); its shading and mouth move with the triangles they lie in. It is made at full strength with the mouth
  pasted, whatever a render asks, so that lambda_k is the same for every strength (a render changes strengths without
  preparing again). ``E_target_gl`` is the candidate at ``lambda_k = 0``, GI's image itself.
"""

from __future__ import annotations

from collections.abc import Sequence
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
#: two place each point to a 64th of its window (the window from A to A' is at most a tenth of an inter-ocular distance,
#: 13 pixels of the features' crop: a 64th is a fifth of one); the lambda_k chosen is then solved in full.
CANDIDATE_PASSES = 2


@dataclass(frozen=True)
class DBCurve:
    """The DB metric over the candidate grid.

    Attributes
    ----------
    lambdas, db : ndarray of shape (L,)
    to_source, to_global : ndarray of shape (L,)
        The two distances of Eq. (7), in the basis's unit (:attr:`~exprclone.geometry.eigenface.Eigenfaces.unit`):
        its terms are ``exp(to_source)`` and ``omega_db exp(to_global)``.
    best : float
        ``lambda_k_opt`` of Eq. (8).
    """

    lambdas: np.ndarray
    db: np.ndarray
    to_source: np.ndarray
    to_global: np.ndarray
    best: float


def db_metric(
    e_candidates: np.ndarray, e_source_exp: np.ndarray, e_target_gl: np.ndarray, unit: float, omega_db: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. (7) for each candidate feature vector, distances in ``unit`` (the basis's: see the module's notes).

    Parameters
    ----------
    e_candidates : ndarray of shape (L, K)
        Eigenface features of the candidates ``I_target_exp(lambda_k)``.
    e_source_exp, e_target_gl : ndarray of shape (K,)
    unit : float
    omega_db : float

    Returns
    -------
    db, to_source, to_global : ndarray of shape (L,)
        DB and its two distances in ``unit``.
    """
    to_source = np.linalg.norm(e_candidates - e_source_exp, axis=1) / unit
    to_global = np.linalg.norm(e_candidates - e_target_gl, axis=1) / unit
    return np.exp(to_source) + omega_db * np.exp(to_global), to_source, to_global


@dataclass(frozen=True)
class Synthesized:
    """The clone's image at GI's landmarks as the candidates are carried from it (:meth:`of`).

    Attributes
    ----------
    grey : ndarray of shape (h, w)
        The image in grey, shrunk near the features' scale (:func:`exprclone.geometry.eigenface.downscaled`).
    control : ndarray of shape (P, 2)
        The mesh's control points it was warped to, on ``grey``.
    """

    grey: np.ndarray
    control: np.ndarray

    @classmethod
    def of(cls, image: np.ndarray, control: np.ndarray, layout: Layout, n_landmarks: int) -> Synthesized:
        """``image`` (``(H, W, 3)`` uint8 RGB), warped to the mesh's ``control`` points (landmarks first)."""
        transform = eigenface.crop_transform(control[:n_landmarks], layout, eigenface.FEATURE_SIZE)
        grey, scale = eigenface.downscaled(image, transform)
        return cls(grey, control * scale)


def carried_crops(synthesized: Synthesized, mesh: piecewise.Mesh, candidates: Sequence[np.ndarray], layout: Layout) -> np.ndarray:
    """The features' crops of the candidates, ``(L, S, S)``: ``synthesized`` carried from its control points to each
    candidate's by the mesh's piecewise-affine map, in the crop its own eyes set
    (:func:`exprclone.geometry.eigenface.crop_transform`).

    Each candidate labels its crop's pixels by triangle; the triangles' maps of all candidates are solved in one batch
    (:func:`exprclone.imaging.piecewise.affines`), each as it would be alone.
    """
    size = eigenface.FEATURE_SIZE
    labellings = []
    for landmarks in candidates:
        dst = mesh.control_points(lips.uncross(landmarks, layout))
        dst, _ = piecewise.unfold(mesh.points, dst, mesh.triangles, mesh.n_moving)
        t = eigenface.crop_transform(landmarks, layout, size)
        labellings.append(piecewise.Labelling.of(align.apply(t, dst), mesh.triangles, (size, size)))
    carried = piecewise.affines(labellings, synthesized.control)
    return np.asarray([piecewise.sample(synthesized.grey, pa) for pa in carried], np.float32)


def choose_lambda(
    synthesized: Synthesized,
    mesh: piecewise.Mesh,
    candidates: list[np.ndarray],
    lambdas: np.ndarray,
    source_crop: np.ndarray,
    basis: Eigenfaces,
    layout: Layout,
) -> DBCurve:
    """Eq. (8): the candidate ``lambda_k`` of smallest DB.

    ``candidates[i]`` are the elastic landmarks for ``lambdas[i]``; ``lambdas[0]`` must be 0, whose candidate is GI,
    ``I_target_gl``. ``synthesized`` is the clone's image at GI (:class:`Synthesized`), carried to each candidate
    (:func:`carried_crops`); ``source_crop`` the source's expression photo in the features' crop
    (:func:`exprclone.geometry.eigenface.crop` at :data:`~exprclone.geometry.eigenface.FEATURE_SIZE`).
    """
    if lambdas[0] != 0:
        raise ValueError("the first candidate lambda_k must be 0 (the global warping result)")
    e = basis.features(carried_crops(synthesized, mesh, candidates, layout))
    e_src = basis.features(source_crop[None])[0]
    db, to_source, to_global = db_metric(e, e_src, e[0], basis.unit)
    return DBCurve(np.asarray(lambdas, float), db, to_source, to_global, float(lambdas[int(np.argmin(db))]))
