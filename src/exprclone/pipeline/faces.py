"""The source's neutral face and the target's, prepared once for every expression cloned between them (:class:`Faces`).

Everything here depends on the two neutral faces alone, not on a source expression nor on
a clone's options: the target's mesh and its spring neighbours, the source's neutral photo
placed on that mesh, and, each made on first use, what the RBF and VTC transfers, the
ERI and the mouth interior take of the two photos. A clone of a photo, each frame of a
video and each render of a slider are then the stages of Fig. 5 that depend on the
expression (:mod:`exprclone.pipeline.cloner`).
"""

from __future__ import annotations

import copy
import dataclasses
import functools
from collections.abc import Sequence

import numpy as np

from ..details.stage import ExpressionPhoto, RatioFaces
from ..geometry import global_warp, vtc
from ..imaging import piecewise
from ..landmarks import align, lips
from ..landmarks.layout import Layout
from ..mouth import measure, paste, teeth, tone


class Faces:
    """The two neutral faces of a clone, prepared once (see the module's notes).

    Parameters
    ----------
    source_neutral, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
    source_neutral_points, target_neutral_points : ndarray of shape (N, 2)
        Their landmarks, checked (:mod:`exprclone.pipeline.checks`); the inner lips are made valid here.
    layout : Layout

    Attributes
    ----------
    s_neu, t_neu : ndarray of shape (N, 2)
        The two neutral faces' landmarks, their inner lips made valid (:func:`exprclone.landmarks.lips.uncross`).
    mesh : piecewise.Mesh
        The target's mesh (:func:`exprclone.imaging.piecewise.build_mesh`), whose control points every warp moves.
    neighbours : ndarray
        The mesh's spring neighbours (the elastic model's, Eqs. 3-6).
    source_neutral_ctrl : ndarray of shape (P, 2)
        The mesh's control points placed on the source's neutral photo.
    """

    def __init__(
        self,
        source_neutral: np.ndarray,
        source_neutral_points: np.ndarray,
        target_neutral: np.ndarray,
        target_neutral_points: np.ndarray,
        layout: Layout,
    ) -> None:
        self.layout = layout
        self.source_image, self.target_image = source_neutral, target_neutral
        self.s_neu = lips.uncross(source_neutral_points, layout)
        self.t_neu = lips.uncross(target_neutral_points, layout)
        self.mesh = piecewise.build_mesh(self.t_neu, target_neutral.shape, layout)
        self.neighbours = self.mesh.neighbours()
        self.source_neutral_ctrl = self.mesh.control_points(self.s_neu, align.fit_rigid(self.t_neu, self.s_neu, layout))

    @functools.cached_property
    def rbf_jacobians(self) -> np.ndarray:
        """The RBF map's Jacobian at each landmark, from the source's neutral face to the target's
        (:func:`exprclone.geometry.global_warp.rbf_jacobians`)."""
        return global_warp.rbf_jacobians(self.s_neu, self.t_neu, self.layout)

    @functools.cached_property
    def tents(self) -> vtc.Tents:
        """The target's vertex tents over the mesh's landmarks, their least-squares system factorised once, for the VTC
        transfer (:class:`exprclone.geometry.vtc.Tents`)."""
        return vtc.Tents.of(self.t_neu, self.neighbours)

    @functools.cached_property
    def ratio_faces(self) -> RatioFaces:
        """The source's neutral photo and the target's prepared for the ERI (:class:`~exprclone.details.stage.RatioFaces`)."""
        return RatioFaces.of(self.mesh, self.source_image, self.source_neutral_ctrl, self.target_image, self.layout)

    @functools.cached_property
    def mouth_reference(self) -> tone.Reference:
        """The target photo and the source's neutral photo measured for the mouth interior's match."""
        return tone.Reference.measure(self.target_image, self.t_neu, self.layout, (self.source_image, self.s_neu))

    def expression_photo(self, image: np.ndarray, points: np.ndarray, still: np.ndarray) -> ExpressionPhoto:
        """A source expression photo with its landmarks ``points`` (``still``: the head's motion removed) as the ERI takes
        it (:meth:`RatioFaces.expression`)."""
        mesh, layout = self.mesh, self.layout
        placed = mesh.control_points(points, align.fit_rigid(self.t_neu, points, layout))
        motion = ExpressionPhoto.motion_of(still, self.s_neu, self.t_neu, self.source_neutral_ctrl, mesh, layout)
        return self.ratio_faces.expression(image, placed, motion, mesh)

    def pooled(self, frames: Sequence[np.ndarray], points: Sequence[np.ndarray]) -> Faces:
        """The same faces with the source's teeth and cavity, and its camera's grain, read once, pooled over frames of a
        performance, for every paste after (these faces are left as they are).

        Each frame's interior (:func:`exprclone.mouth.measure.interior`) is taken in the target's light; the pool
        (:attr:`exprclone.mouth.tone.Reference.source_interior`) gives every later paste its colour, the same in every
        frame (:func:`exprclone.drive.prepare` reads the most open mouths of a video). The grain a paste needs
        (:func:`exprclone.mouth.paste.grain`, at the target's scale) is the median of the frames'
        (:attr:`exprclone.mouth.tone.Reference.source_grain`): one camera's, the same in every frame.

        Parameters
        ----------
        frames : sequence of ndarray of shape (H, W, 3), uint8 RGB
            Frames whose mouth is open; nothing is read without any.
        points : sequence of ndarray of shape (N, 2)
            Their landmarks.

        Returns
        -------
        Faces
            A copy whose :attr:`mouth_reference` holds the pool (the rest shared with these faces).
        """
        if not len(frames):
            return self
        reference, layout = self.mouth_reference, self.layout
        points = [lips.uncross(p, layout) for p in points]
        parts = [measure.interior(f, p, layout, tone.tone_gain(f, p, reference, layout)) for f, p in zip(frames, points)]
        pixels = (np.concatenate([f[m[0]] for f, m in zip(frames, parts)]), np.concatenate([f[m[1]] for f, m in zip(frames, parts)]))
        pooled = teeth.Interior.read(pixels, float(np.median([measure.mouth_width(p, layout) for p in points])))
        iod = align.interocular(self.t_neu, layout)
        grains = [paste.grain(f, p, reference, iod / align.interocular(p, layout)) for f, p in zip(frames, points)]
        pooled_grain = (float(np.median([g[0] for g in grains])), np.median([g[1] for g in grains], axis=0))
        other = copy.copy(self)
        other.mouth_reference = dataclasses.replace(reference, source_interior=pooled, source_grain=pooled_grain)
        return other
