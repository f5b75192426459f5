"""Vertex-tent-coordinate (VTC) transfer (Song et al. 2007): the source's expression carried to the target tent by tent.

The landmark mesh is triangulated (the target's mesh, :attr:`exprclone.imaging.piecewise.Mesh.neighbours`: the
elastic model's spring neighbours; the mouth is a hole in it, its inner lips joined through the mid-lip points
only). Vertex ``i`` and its one-ring ``N(i)`` form a *tent*, whose shape is the matrix of its edges
``E_i = [x_j - x_i for j in N(i)]`` (2 x k). The source's neutral-to-expression change of a tent is one linear map
(Eq. V1):

    Q_i = argmin_Q || Q E_i^S - E~_i^S ||^2 = I + (E~_i^S - E_i^S) E_i^S+,      E^+ = E^T (E E^T)^-1,

and the target's expression landmarks ``x~`` are those whose tents change by the same maps, in the least-squares
sense of Sumner and Popovic's deformation transfer, the target's tent maps measured as the source's are (Eq. V2):

    x~ = argmin_x  sum_i || E_i(x) E_i^T+ - Q_i ||_F^2,

``E_i(x)`` the tent's edges at ``x`` and ``E_i^T`` the target's neutral ones. ``E_i(x) E_i^T+`` is linear in ``x``,
and the two coordinates separate: each solves the normal equations (Eq. V3)

    A^T A x~_r = A^T q_r,      r in {x, y},

with one sparse ``A`` (two rows a tent, ``(A x)_(i,c) = sum_j (x_j - x_i) P_ij,c``, ``P_i = E_i^T+``) that depends on
the target's neutral face alone, so :class:`Tents` factorises ``A^T A`` once (:func:`scipy.sparse.linalg.splu`) for
every expression; ``q_r`` holds row ``r`` of each ``Q_i``. ``A^T A`` is singular by a translation only: a few
anchored vertices (the layout's rigid points) fix it.

Where this reading had to choose (the paper's 2-D equations could not be read; docs/explanation/song.rst):

- the source is first brought into the target's frame by the similarity of the paper's GI (deformation transfer
  takes meshes in one pose; a tent's map depends on the frame), its head motion removed as the other global warps
  do (:func:`exprclone.geometry.global_warp.remove_head_motion`);
- a 2-D tent has more edges than a 2 x 2 map has freedom, so each map is a least-squares fit (V1), and the target's
  tents are matched map to map (V2), as deformation transfer matches its triangles', rather than edge by edge: so
  a source cloned onto itself is its own expression (matching the edges, ``E_i(x) = Q_i E_i^T``, lost half the
  widening of a smile in that test);
- the anchors fix the translation only: their centroid moves as GI moves it, the rest of the shape is V2's.

References
----------
M. Song, Z. Dong, C. Theobalt, H. Wang, Z. Liu and H.-P. Seidel, "A generic framework for efficient 2-D and 3-D
facial expression analogy", IEEE Trans. Multimedia 9(7), 2007 (the paper's [2]). R. W. Sumner and J. Popovic,
"Deformation transfer for triangle meshes", ACM Trans. Graphics 23(3), 2004 (the paper's [8]).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Final

import numpy as np
import scipy.sparse
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

from ..landmarks import align
from ..landmarks.layout import Layout
from . import global_warp

#: added to each tent's ``E E^T`` in units of its trace, so that a tent of collinear edges has a map (the smallest
#: change); far below what moves a landmark by a measurable amount.
RIDGE: Final = 1e-9


@dataclass(frozen=True)
class Tents:
    """The vertex tents of the target's neutral landmarks, and its side of the VTC system, factorised once (:meth:`of`).

    Attributes
    ----------
    target : ndarray of shape (N, 2)
        The target's neutral landmarks.
    centre, rim : ndarray of shape (E,)
        Each tent edge's apex ``i`` and its one-ring neighbour ``j``: tent ``i`` is the edges whose ``centre`` is ``i``.
    system : scipy.sparse.csr_matrix of shape (2 N, N)
        ``A`` of Eq. (V3).
    factor : scipy.sparse.linalg.SuperLU
        ``A^T A`` with vertex 0 held (its translation), factorised. It cannot be pickled: a pickled :class:`Tents` is
        made again from its edges where it is unpickled (a prepared clone sent to another process).
    """

    target: np.ndarray
    centre: np.ndarray
    rim: np.ndarray
    system: scipy.sparse.csr_matrix
    factor: scipy.sparse.linalg.SuperLU

    @classmethod
    def of(cls, target_neutral: np.ndarray, neighbours: Sequence[np.ndarray]) -> Tents:
        """The tents of ``target_neutral`` (``(N, 2)``), vertex ``i``'s one-ring ``neighbours[i]``."""
        centre = np.repeat(np.arange(len(target_neutral)), [len(ring) for ring in neighbours])
        return cls.of_edges(target_neutral, centre, np.concatenate(neighbours).astype(int))

    @classmethod
    def of_edges(cls, target_neutral: np.ndarray, centre: np.ndarray, rim: np.ndarray) -> Tents:
        """The tents of ``target_neutral`` whose edges are ``(centre, rim)`` (:attr:`centre`, :attr:`rim`).

        Each tent's row block of ``A`` holds ``P_i = E_i^T+`` (Eq. V2): edge ``(i, j)`` adds ``P_ij`` at ``j`` and
        takes it at ``i``. A mesh whose vertices are not all joined raises ValueError (its parts would drift apart).
        """
        n = len(target_neutral)
        pseudo = inverse_rows(target_neutral, centre, rim, n)
        rows = np.concatenate([2 * centre, 2 * centre + 1] * 2)
        columns = np.concatenate([rim, rim, centre, centre])
        values = np.concatenate([pseudo[:, 0], pseudo[:, 1], -pseudo[:, 0], -pseudo[:, 1]])
        system = scipy.sparse.csr_matrix((values, (rows, columns)), shape=(2 * n, n))
        joined, _ = connected_components(scipy.sparse.coo_matrix((np.ones(len(rim)), (centre, rim)), (n, n)))
        if joined != 1:
            raise ValueError(f"the landmark mesh falls into {joined} parts")
        held = system[:, 1:]
        return cls(target_neutral, centre, rim, system, splu((held.T @ held).tocsc()))

    def __reduce__(self) -> tuple[Callable[[np.ndarray, np.ndarray, np.ndarray], Tents], tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Pickled as what it is made of (:attr:`factor` cannot be): made again where it is unpickled."""
        return Tents.of_edges, (self.target, self.centre, self.rim)

    def maps(self, neutral: np.ndarray, expression: np.ndarray) -> np.ndarray:
        """Eq. (V1): each tent's least-squares linear map from ``neutral`` to ``expression`` (``(N, 2)`` each), ``(N, 2, 2)``:
        the identity plus the fitted change, ``Q_i = I + (E~_i - E_i) E_i^+``, so that a tent whose edges do not span the
        plane keeps the identity across them."""
        n = len(neutral)
        before = neutral[self.rim] - neutral[self.centre]
        motion = expression - neutral
        change = tent_sums(self.centre, motion[self.rim] - motion[self.centre], before, n)
        spread = tent_sums(self.centre, before, before, n)
        return np.eye(2) + np.linalg.solve(spread, change.transpose(0, 2, 1)).transpose(0, 2, 1)

    def solve(self, maps: np.ndarray, anchors: Sequence[int], anchored: np.ndarray) -> np.ndarray:
        """Eqs. (V2)-(V3): the landmarks whose tents change by ``maps`` (``(N, 2, 2)``), translated so that the centroid
        of the vertices ``anchors`` is that of ``anchored`` (``(K, 2)``)."""
        wanted = maps.transpose(0, 2, 1).reshape(-1, 2)  # row (i, c) of A: column c of Q_i, one column a coordinate
        out = np.zeros((len(maps), 2))
        out[1:] = self.factor.solve(np.asarray(self.system.T @ wanted)[1:])
        return out + (np.mean(anchored, axis=0) - out[list(anchors)].mean(axis=0))


def tent_sums(centre: np.ndarray, a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    """``sum_j a_ij b_ij^T`` over each tent's edges (``(E, 2)`` each), ``(N, 2, 2)``; with ``a = b`` (``E E^T``) a ridge
    of :data:`RIDGE` times its trace is added."""
    out = np.zeros((n, 2, 2))
    np.add.at(out, centre, a[:, :, None] * b[:, None, :])
    if a is b:
        out += RIDGE * np.trace(out, axis1=1, axis2=2)[:, None, None] * np.eye(2)
    return out


def inverse_rows(points: np.ndarray, centre: np.ndarray, rim: np.ndarray, n: int) -> np.ndarray:
    """The rows of each tent's ``E^+ = E^T (E E^T)^-1`` at ``points``, one per edge: ``(E E^T)^-1 e_ij``, ``(E, 2)``."""
    edges = points[rim] - points[centre]
    spread = tent_sums(centre, edges, edges, n)
    return np.linalg.solve(spread[centre], edges[:, :, None])[:, :, 0]


def vtc_landmarks(
    source_neutral: np.ndarray, source_expression: np.ndarray, target_neutral: np.ndarray, layout: Layout, tents: Tents
) -> np.ndarray:
    """Landmarks of the target's expression by VTC transfer (Song et al.; the module's notes).

    The source's motion, its head motion removed, is brought into the target's frame by the similarity between the
    two neutral faces (GI's); each tent's change (Eq. V1) is made the target's (Eqs. V2-V3); the rigid landmarks'
    centroid (``layout.rigid``) moves as GI moves it.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (N, 2)
    layout : Layout
    tents : Tents
        The target's tents (:meth:`Tents.of`).

    Returns
    -------
    ndarray of shape (N, 2)

    Examples
    --------
    >>> from scipy.spatial import Delaunay
    >>> from exprclone.landmarks.layout import DLIB68
    >>> def tents_of(points):  # the one-rings of a Delaunay mesh
    ...     starts, rings = Delaunay(points).vertex_neighbor_vertices
    ...     return Tents.of(points, np.split(rings, starts[1:-1]))
    >>> rng = np.random.default_rng(0)
    >>> s, t = rng.uniform(0, 100, (68, 2)), rng.uniform(0, 100, (68, 2))
    >>> bool(np.allclose(vtc_landmarks(s, s, t, DLIB68, tents_of(t)), t))  # no motion: the target as it is
    True
    >>> moved = s.copy(); moved[48] += (0, 3)
    >>> t = 2 * s + 5  # a target that is the source twice as large gets the paper's similarity transfer
    >>> bool(np.allclose(vtc_landmarks(s, moved, t, DLIB68, tents_of(t)), global_warp.global_landmarks(s, moved, t, DLIB68)))
    True
    """
    motion = global_warp.remove_head_motion(source_neutral, source_expression, layout) - source_neutral
    similarity = align.fit_similarity(source_neutral, target_neutral)
    neutral = align.apply(similarity, source_neutral)
    expression = neutral + motion @ similarity[:, :2].T
    anchors = list(layout.rigid)
    anchored = target_neutral[anchors] + (expression - neutral)[anchors]  # GI at the anchors
    return tents.solve(tents.maps(neutral, expression), anchors, anchored)
