"""The source's neutral face and the target's, prepared once (:class:`Cloner`), and what a clone gives (:class:`CloneResult`).

A :class:`Cloner` runs the stages of Fig. 5 (:mod:`exprclone.stages`) for each source
expression: the shape stages a method needs, FI by the options' image warp, then its
detail stages (ERI, MD model, mouth interior). What each method runs is read from its
row of :data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options` of the :class:`Cloner`.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import eri, geometry, global_warp, lips, metric, mouth, mouth_fill, mouth_tone, muscle, retarget, teeth, warp
from .checks import check_face, check_lambda, check_options, options_from
from .eigenface import Eigenfaces
from .layout import DLIB68, Layout
from .methods import METHODS, SHAPES, Method, lookup
from .options import Options
from .roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from .stages import IMAGE_WARPERS, SHAPE_STAGES, Expression, RatioFaces, Rendered, Shape, ratio_image
from .transfer import Transfer


@dataclass(frozen=True)
class CloneResult:
    """A cloned expression and every intermediate worth looking at.

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The target person with the source's expression (the target photo's size).
    method : str
    landmarks : dict of str to ndarray of shape (N, 2)
        ``source_neutral``, ``source_expression``, ``target_neutral`` (the inputs),
        ``global`` (GI), ``local`` (LI), ``elastic`` (for the chosen lambda_k) and
        ``final`` (the geometry of the output, after fold-over relaxation).
    lambda_k : float or None
        The elasticity ratio used (None for methods without the elastic model).
    db_curve : metric.DBCurve or None
        DB value per candidate lambda_k, when lambda_k was chosen automatically.
    eri : ndarray of shape (H, W) or None
        The expression ratio image in the target's frame (1 where nothing changes).
    muscle_mask : ndarray of shape (H, W) or None
        The MD model's detail-importance mask M (e+md only).
    muscle_strengths : ndarray of shape (A,) or None
        ``h`` of each key muscle area (e+md only).
    mouth_mask : ndarray of shape (H, W) or None
        Weight of the source's mouth interior pasted into the opened mouth
        (:mod:`exprclone.mouth_fill`; methods with ERI), None when nothing was pasted.
    unfolded_points : int
        Control points moved to stop triangles folding over.
    options : Options
        How it was made beyond its method: the global and image warps, strength and regions.
    landmarker : str or None
        Which landmarker placed the photos' landmarks (:data:`exprclone.landmarkers.LANDMARKERS`),
        None when all were given.
    warnings : tuple of str
        What looked wrong with the inputs (:func:`exprclone.role_check.judge_roles`), also issued as ExprCloneWarnings.

    See Also
    --------
    exprclone.clone, exprclone.clone_methods : which make it.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> result = exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"))
    >>> result.method, result.image.shape, result.image.dtype.name
    ('e+md', (1350, 1350, 3), 'uint8')
    >>> sorted(result.landmarks)
    ['elastic', 'final', 'global', 'local', 'source_expression', 'source_neutral', 'target_neutral']
    >>> result.db_curve.best == result.lambda_k, result.eri.shape, result.muscle_strengths.shape
    (True, (1350, 1350), (12,))
    """

    image: np.ndarray
    method: str
    landmarks: dict[str, np.ndarray]
    lambda_k: float | None = None
    db_curve: metric.DBCurve | None = None
    eri: np.ndarray | None = None
    muscle_mask: np.ndarray | None = None
    muscle_strengths: np.ndarray | None = None
    mouth_mask: np.ndarray | None = None
    unfolded_points: int = 0
    options: Options = Options()
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()


class Cloner:
    """The source's neutral face and the target's, prepared once for many source expressions.

    Everything that depends only on the two neutral faces (the target's mesh and its
    spring neighbours, the source's neutral photo placed on that mesh) is computed here,
    so that each expression (a photo, or a frame of a driving video) costs only the
    stages of Fig. 5 that depend on it. Inputs are taken as :mod:`exprclone.checks`
    lets them through.

    Parameters
    ----------
    source_neutral, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
    source_neutral_points, target_neutral_points : ndarray of shape (N, 2)
        Their landmarks.
    eigenfaces : Eigenfaces, optional
        Basis of the DB metric; the packaged one by default.
    layout : Layout
    options : Options, optional
        How every clone it makes is made (:class:`~exprclone.options.Options`), checked
        here (:func:`exprclone.checks.check_options`); the defaults, the paper's stages
        with retargeting, if None.
    **keywords
        The same options as keywords (``strength=0.5``), instead of ``options``.

    Raises
    ------
    ExprCloneError
        An option that is not one, one given both ways, or a bad value of one (its ``subject`` the option's name).

    Examples
    --------
    >>> from exprclone import data
    >>> from exprclone.models import default_detector
    >>> detect = default_detector().detect
    >>> source, portrait, smile = data.photo("126"), data.photo("003"), data.photo("126", "smile")
    >>> cloner = Cloner(source, detect(source), portrait, detect(portrait), strength=0.5)
    >>> results = cloner.clone_methods(smile, detect(smile), ("global", "e+md"))
    >>> results["e+md"].image.shape, results["e+md"].options.strength
    ((1350, 1350, 3), 0.5)
    """

    def __init__(
        self,
        source_neutral: np.ndarray,
        source_neutral_points: np.ndarray,
        target_neutral: np.ndarray,
        target_neutral_points: np.ndarray,
        *,
        eigenfaces: Eigenfaces | None = None,
        layout: Layout = DLIB68,
        options: Options | None = None,
        **keywords: Any,
    ) -> None:
        self.layout = layout
        asked = options_from(options, keywords)
        self.options = check_options(asked, layout.n_points, target_neutral.shape, tuple(layout.regions))
        if self.options.global_landmarks is not None:
            check_face(self.options.global_landmarks, layout, "global_landmarks")
        self.image_warp = IMAGE_WARPERS[self.options.image_warp]
        self.source_image, self.target_image = source_neutral, target_neutral
        self.s_neu = lips.uncross(source_neutral_points, layout)
        self.t_neu = lips.uncross(target_neutral_points, layout)
        self.transfer = Transfer.build(self.options, self.t_neu, target_neutral.shape, layout)
        self.eigenfaces = eigenfaces
        self.mesh = warp.build_mesh(self.t_neu, target_neutral.shape, layout)
        self.neighbours = self.mesh.neighbours()
        self._source_neutral_ctrl = self.mesh.control_points(self.s_neu, geometry.fit_rigid(self.t_neu, self.s_neu, layout))

    @functools.cached_property
    def rbf_jacobians(self) -> np.ndarray:
        """The RBF map's Jacobian at each landmark, from the source's neutral face to the target's (:func:`global_warp.rbf_jacobians`)."""
        return global_warp.rbf_jacobians(self.s_neu, self.t_neu, self.layout)

    @functools.cached_property
    def db_target(self) -> tuple[np.ndarray, float]:
        """The target photo as the DB metric's candidates are warped from (:func:`exprclone.metric.target_grey`)."""
        return metric.target_grey(self.target_image, self.mesh, self.layout)

    @functools.cached_property
    def ratio_faces(self) -> RatioFaces:
        """The source's neutral photo and the target's prepared for the ERI (:class:`~exprclone.stages.RatioFaces`)."""
        return RatioFaces.prepare(self.mesh, self.source_image, self._source_neutral_ctrl, self.target_image, self.layout)

    @functools.cached_property
    def mouth_reference(self) -> mouth_tone.Reference:
        """The target photo and the source's neutral photo measured for the mouth interior's match."""
        return mouth_tone.Reference.measure(self.target_image, self.t_neu, self.layout, (self.source_image, self.s_neu))

    def pool_interior(self, frames: Sequence[np.ndarray], points: Sequence[np.ndarray]) -> None:
        """Read the source's teeth and cavity once, pooled over frames of a performance, for every paste after.

        Each frame's interior (:func:`exprclone.mouth.interior`) is taken in the target's light; the pool
        (:attr:`exprclone.mouth_tone.Reference.source_interior`) gives every later paste its colour, the same in every
        frame (:func:`exprclone.drive.prepare` reads the most open mouths of a video).

        Parameters
        ----------
        frames : sequence of ndarray of shape (H, W, 3), uint8 RGB
            Frames whose mouth is open; nothing is read without any.
        points : sequence of ndarray of shape (N, 2)
            Their landmarks.
        """
        reference, layout = self.mouth_reference, self.layout
        if not len(frames):
            return
        points = [lips.uncross(p, layout) for p in points]
        parts = [mouth.interior(f, p, layout, mouth_tone.tone_gain(f, p, reference, layout)) for f, p in zip(frames, points)]
        pixels = (np.concatenate([f[m[0]] for f, m in zip(frames, parts)]), np.concatenate([f[m[1]] for f, m in zip(frames, parts)]))
        pooled = teeth.Interior.read(pixels, float(np.median([mouth.mouth_width(p, layout) for p in points])))
        self.mouth_reference = dataclasses.replace(reference, source_interior=pooled)

    def clone_methods(
        self,
        source_expression: np.ndarray,
        source_expression_points: np.ndarray,
        methods: tuple[str, ...] = METHODS,
        lambda_k: float | str = "auto",
        *,
        mouth: bool = True,
        crop: np.ndarray | None = None,
    ) -> dict[str, CloneResult]:
        """The source expression on the target face, by each of ``methods``.

        Parameters
        ----------
        source_expression : ndarray of shape (H, W, 3), uint8 RGB
            The source person with the expression (a photo, or a frame of a video).
        source_expression_points : ndarray of shape (N, 2)
            Its landmarks.
        methods, lambda_k, mouth
            As for :func:`exprclone.clone_methods`.
        crop : ndarray of shape (S, S), optional
            Its eye-aligned crop, when the caller has made it (the role check's,
            :class:`exprclone.role_check.Photo`); made here only if the DB metric needs it.

        Returns
        -------
        dict of str to CloneResult
            One result per method.
        """
        chosen = lookup(methods)
        expression = self.expression(source_expression, source_expression_points, check_lambda(lambda_k), crop)
        shapes = self.shapes(expression, {m.shape for m in chosen})
        rendered = {kind: self.render(shapes[kind].points) for kind in {m.shape for m in chosen}}
        ratios = {kind: self.ratio(rendered[kind], expression) for kind in {m.shape for m in chosen if m.eri}}
        return {m.name: self.result(m, expression, shapes, rendered[m.shape], ratios[m.shape] if m.eri else None, mouth) for m in chosen}

    def expression(self, image: np.ndarray, points: np.ndarray, lambda_k: float | str, crop: np.ndarray | None = None) -> Expression:
        """One source expression, prepared for the shape stages: with ``retarget``, its motion cleaned and the organs
        local re-shaping aims at made the target's (:mod:`exprclone.retarget`); without, the paper's (its own points).
        ``crop`` is its eye-aligned crop if the caller has made it (:attr:`Expression.crop`)."""
        points = lips.uncross(points, self.layout)
        if not self.options.retarget:
            return Expression(image, points, lambda_k, points, points, crop)
        cleaned = retarget.clean(self.s_neu, points, self.layout)
        organs = retarget.organ_reference(self.s_neu, cleaned, self.t_neu, self.layout)
        return Expression(image, points, lambda_k, cleaned, organs, crop)

    def shapes(self, expression: Expression, wanted: set[str]) -> dict[str, Shape]:
        """The shape stages (:data:`SHAPE_STAGES`) up to the last one ``wanted``; GI and LI always."""
        shapes: dict[str, Shape] = {}
        for name in SHAPES:
            if name in wanted | {"global", "local"}:
                shapes[name] = SHAPE_STAGES[name](self, expression, shapes)
        return shapes

    def render(self, points: np.ndarray) -> Rendered:
        """FI: the target photo warped to ``points``, their motion scaled as the options ask (:mod:`exprclone.transfer`;
        inner lips made valid, fold-overs relaxed), by the options' image warp."""
        mesh = self.mesh
        control = mesh.control_points(lips.uncross(self.transfer.landmarks(points), self.layout))
        control, unfolded = warp.unfold(mesh.points, control, mesh.triangles, mesh.n_moving)
        return Rendered(self.image_warp(self.target_image, mesh.points, control, mesh), control, unfolded)

    def ratio(self, target: Rendered, expression: Expression) -> tuple[np.ndarray, tuple[slice, slice]]:
        """The ERI: both source photos warped to the geometry of FI ``target`` (Liu et al.), and the box where it is not 1."""
        placed = self.mesh.control_points(expression.points, geometry.fit_rigid(self.t_neu, expression.points, self.layout))
        # how far the source's skin moves at each control point, its head's motion removed (for shading.moved)
        aligned = global_warp.remove_head_motion(self.s_neu, expression.points, self.layout)
        shift = self.mesh.control_points(aligned, geometry.fit_rigid(self.t_neu, self.s_neu, self.layout)) - self._source_neutral_ctrl
        motion = np.linalg.norm(shift, axis=1) / geometry.interocular(self.s_neu, self.layout)
        faces = self.ratio_faces
        photo = faces.expression(expression.image, placed, self.mesh)
        ratio, box = ratio_image(self.mesh, target, faces, photo, (self._source_neutral_ctrl, placed), motion, self.layout, self.image_warp)
        return self.transfer.ratio(ratio, box), box

    def result(
        self,
        method: Method,
        expression: Expression,
        shapes: dict[str, Shape],
        rendered: Rendered,
        ratio: tuple[np.ndarray, tuple[slice, slice]] | None,
        mouth: bool,
    ) -> CloneResult:
        """One method's result: FI, then its detail stages (:meth:`details`) if it has any (then ``ratio`` is its ERI)."""
        final = rendered.control[: self.mesh.n_landmarks]
        landmarks = {SOURCE_NEUTRAL: self.s_neu, SOURCE_EXPRESSION: expression.points, TARGET_NEUTRAL: self.t_neu}
        landmarks.update({name: shapes[name].points for name in ("global", "local", method.shape)}, final=final)
        image, details = (rendered.image, {}) if ratio is None else self.details(method, expression, rendered.image, final, ratio, mouth)
        shape = shapes[method.shape]
        return CloneResult(
            image,
            method.name,
            landmarks,
            shape.lambda_k,
            shape.db_curve,
            unfolded_points=rendered.unfolded,
            options=self.options,
            **details,
        )

    def details(
        self,
        method: Method,
        expression: Expression,
        fi: np.ndarray,
        final: np.ndarray,
        ratio: tuple[np.ndarray, tuple[slice, slice]],
        mouth: bool,
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """The illumination details on FI: the ERI, weighted by the MD mask (Eqs. 9-11) for ``e+md``; then the mouth interior.

        Returns
        -------
        image : ndarray of shape (H, W, 3), uint8
        details : dict
            The :class:`CloneResult` fields they fill: ``eri``, ``muscle_mask``,
            ``muscle_strengths``, ``mouth_mask``.
        """
        ratio_map, box = ratio
        details: dict[str, Any] = {"eri": ratio_map}
        importance: np.ndarray | float = 1.0
        if method.md:
            h = muscle.strengths(self.s_neu, global_warp.remove_head_motion(self.s_neu, expression.points, self.layout), self.layout)
            centres, radii = muscle.areas(final, self.layout)
            importance = muscle.importance_mask(self.target_image.shape[:2], centres, radii, h, muscle.mask_step(radii))
            details.update(muscle_mask=importance, muscle_strengths=h)
        image = fi.copy()
        image[box] = eri.apply_details(fi[box], ratio_map[box], importance if isinstance(importance, float) else importance[box])
        if mouth:  # the photos are measured for the paste's match only when there is a paste
            image, details["mouth_mask"] = mouth_fill.fill_interior(
                image, final, expression.image, expression.points, lambda: self.mouth_reference, self.layout, self.transfer.paste
            )
        return image, details
