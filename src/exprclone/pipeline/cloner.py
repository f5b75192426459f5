"""A clone prepared once and rendered many times: :class:`Cloner` (two neutral faces and the options), :class:`Prepared`
(one source expression on them), and what a render gives (:class:`CloneResult`).

The stages of Fig. 5 fall in two parts. What a source expression costs once is
:meth:`Cloner.prepare`: the expression made ready (:func:`exprclone.pipeline.stages.expression`),
the shape stages its methods need (GI, LI, the elastic model with the lambda search of the
DB metric) and the expression photo as the ERI takes it. What a render costs is
:meth:`Prepared.render`: FI by the options' image warp, then each method's detail stages
(the ERI in FI's geometry, the MD model, the mouth interior). What each method runs is read
from its row of :data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options` of the :class:`Cloner`.
"""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..details import eri, muscle
from ..details.mesh_image import RATIOS
from ..details.stage import ExpressionPhoto, Ratio
from ..errors import ExprCloneError
from ..geometry import db_metric
from ..geometry.weights import Transfer
from ..imaging import piecewise
from ..imaging.warpers import IMAGE_WARPERS, ImageWarper
from ..landmarks import lips
from ..methods import Method, lookup
from ..mouth import paste
from ..options import RENDER, Options
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from . import stages
from .checks import check_for_target
from .faces import Faces
from .stages import Expression, Shape


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
        (:mod:`exprclone.mouth.paste`; methods with ERI), None when nothing was pasted.
    unfolded_points : int
        Control points moved to stop triangles folding over.
    options : Options
        How it was made: its options (:class:`~exprclone.options.Options`), ``method`` its own.
    landmarker : str or None
        Which landmarker placed the photos' landmarks (:data:`exprclone.landmarks.backends.LANDMARKERS`),
        None when all were given.
    warnings : tuple of str
        What looked wrong with the inputs (:func:`exprclone.pipeline.role_check.judge_roles`), also issued as ExprCloneWarnings.
    face_results : tuple of FaceResult
        For a target photo of several faces (:mod:`exprclone.pipeline.group`), each face found, in reading order: its
        own clone in its region, or why it was left as it is. ``image`` is then the whole photo; the fields of one
        clone (``landmarks``, ``lambda_k``, the masks...) are each face's, and empty or None here. Empty for a photo
        of one face.

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
    db_curve: db_metric.DBCurve | None = None
    eri: np.ndarray | None = None
    muscle_mask: np.ndarray | None = None
    muscle_strengths: np.ndarray | None = None
    mouth_mask: np.ndarray | None = None
    unfolded_points: int = 0
    options: Options = Options()
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()
    face_results: tuple[FaceResult, ...] = ()


@dataclass(frozen=True)
class FaceResult:
    """One face of a target photo of several (:attr:`CloneResult.face_results`).

    Attributes
    ----------
    number : int
        Its number in reading order, from 1 (as ``exprclone faces`` lists them).
    box : tuple of float
        Its box ``(left, top, right, bottom)`` in the photo.
    region : tuple of int
        ``(x0, y0, x1, y1)``: the part of the photo its clone was made on, the target photo of ``result``.
    result : CloneResult or None
        Its clone, in its region's pixels (add ``(x0, y0)`` to its landmarks for the photo's); None when it was left as
        it is.
    problem : str
        Why it was left as it is (not chosen, too small...); empty when it was cloned.
    """

    number: int
    box: tuple[float, float, float, float]
    region: tuple[int, int, int, int]
    result: CloneResult | None
    problem: str = ""


class Cloner:
    """The source's neutral face and the target's, prepared once (:class:`~exprclone.pipeline.faces.Faces`), with the
    options of every clone made between them.

    Each source expression (a photo, or a frame of a driving video) then costs only the
    stages of Fig. 5 that depend on it: :meth:`prepare` once, :meth:`Prepared.render` for each
    image made of it. Inputs are taken as :mod:`exprclone.pipeline.checks` lets them through.

    Parameters
    ----------
    source_neutral, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
    source_neutral_points, target_neutral_points : ndarray of shape (N, 2)
        Their landmarks.
    options : Options, optional
        How every clone it makes is made (:class:`~exprclone.options.Options`), checked
        here against the target photo (:func:`exprclone.pipeline.checks.check_for_target`); the
        defaults, the paper's stages with retargeting, if None.
    **keywords
        Options as keywords (``strength=0.5``), changing ``options``.

    Attributes
    ----------
    faces : Faces
        The two neutral faces, prepared.
    options : Options
        The options, checked.

    Raises
    ------
    ExprCloneError
        An option that is not one, one given both ways, or a bad value of one (its ``subject`` the option's name).

    Examples
    --------
    >>> from exprclone import data
    >>> from exprclone.landmarks.backends import default_detector
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
        options: Options | None = None,
        **keywords: Any,
    ) -> None:
        self.options = check_for_target(Options.of(options, keywords), target_neutral.shape)
        layout = self.options.landmarks_layout
        self.faces = Faces(source_neutral, source_neutral_points, target_neutral, target_neutral_points, layout)
        self.transfer = self._transfer(self.options)

    @property
    def image_warp(self) -> ImageWarper:
        """How the target's photo follows its landmarks: the options' ``image_warp``."""
        return IMAGE_WARPERS[self.options.image_warp]

    def changed(self, options: Options | None = None, **changes: Any) -> Cloner:
        """The same prepared faces with other ``options``, or its own changed by keywords (``changed(lambda_k=0.5)``):
        nothing of the faces is made again.

        Raises
        ------
        ExprCloneError
            A bad option, or another ``layout`` (the faces were prepared for theirs).
        """
        options = check_for_target(Options.of(options or self.options, changes), self.faces.target_image.shape)
        if options.landmarks_layout is not self.faces.layout:
            raise ExprCloneError("layout", "the faces were prepared with another layout: make a new Cloner")
        other = copy.copy(self)
        other.options, other.transfer = options, self.weights(options)
        return other

    def weights(self, options: Options) -> Transfer:
        """How much of the expression ``options`` transfer, and where (:class:`~exprclone.geometry.weights.Transfer`):
        the cloner's own when their strengths are its options'."""
        if (options.region_strengths, options.strength_shading) == (self.options.region_strengths, self.options.strength_shading):
            return self.transfer
        return self._transfer(options)

    def _transfer(self, options: Options) -> Transfer:
        faces = self.faces
        return Transfer.build(options.region_strengths, options.strength_shading, faces.t_neu, faces.target_image.shape, faces.layout)

    def prepare(
        self,
        source_expression: np.ndarray,
        source_expression_points: np.ndarray,
        methods: tuple[str, ...] | None = None,
        *,
        crop: np.ndarray | None = None,
    ) -> Prepared:
        """One source expression prepared for ``methods``: what every render of it shares.

        Parameters
        ----------
        source_expression : ndarray of shape (H, W, 3), uint8 RGB
            The source person with the expression (a photo, or a frame of a video).
        source_expression_points : ndarray of shape (N, 2)
            Its landmarks.
        methods : tuple of str, optional
            Any of :data:`~exprclone.methods.METHODS`, sharing the stages they have in common; the options'
            ``method`` alone by default.
        crop : ndarray of shape (S, S), optional
            Its eye-aligned crop, when the caller has made it (the role check's,
            :class:`exprclone.pipeline.role_check.Photo`); made here only if the DB metric needs it.

        Returns
        -------
        Prepared
        """
        chosen = lookup(methods or (self.options.method,))
        options = self.options
        expression = stages.expression(self.faces, source_expression, source_expression_points, options.lambda_k, options.retarget, crop)
        shapes = stages.shapes(self.faces, options, expression, chosen)
        ratio = any(m.ratio for m in chosen)
        photo = self.faces.expression_photo(expression.image, expression.points, expression.still) if ratio else None
        return Prepared(self, chosen, expression, shapes, photo)

    def clone_methods(
        self,
        source_expression: np.ndarray,
        source_expression_points: np.ndarray,
        methods: tuple[str, ...] | None = None,
        *,
        crop: np.ndarray | None = None,
    ) -> dict[str, CloneResult]:
        """The source expression on the target face, by each of ``methods``: :meth:`prepare`, then :meth:`Prepared.render`.

        Returns
        -------
        dict of str to CloneResult
            One result per method.
        """
        return self.prepare(source_expression, source_expression_points, methods, crop=crop).render()

    def fi(self, points: np.ndarray, transfer: Transfer) -> Rendered:
        """FI: the target photo warped to ``points``, their motion scaled by ``transfer`` (:mod:`exprclone.geometry.weights`;
        inner lips made valid, fold-overs relaxed but for the landmarks held by a strength of 0), by the options' image warp."""
        faces = self.faces
        mesh = faces.mesh
        moved = transfer.landmarks(points)
        valid = lips.uncross(moved, faces.layout)
        held = None if transfer.motion is None else np.flatnonzero(transfer.motion == 0)  # a region at strength 0 stays put
        if held is not None:
            valid[held] = moved[held]  # (uncross judges the lips in the face's axes, which the other regions turn)
        control, unfolded = piecewise.unfold(mesh.points, mesh.control_points(valid), mesh.triangles, mesh.n_moving, held)
        return Rendered(self.image_warp(faces.target_image, mesh.points, control, mesh), control, unfolded)

    def ratio(self, target: Rendered, photo: ExpressionPhoto, transfer: Transfer, kind: str = "eri") -> Ratio:
        """The ERI and its tint: both source photos warped to the geometry of FI ``target`` (Liu et al.), or the mesh
        image made of them (Song et al.: ``kind``, :data:`exprclone.details.mesh_image.RATIOS`), scaled by ``transfer``."""
        faces = self.faces
        shape = faces.target_image.shape
        made = RATIOS[kind](
            faces.mesh, target.control, shape, faces.ratio_faces, faces.source_neutral_ctrl, photo, faces.layout, self.image_warp
        )
        return Ratio(transfer.ratio(made.eri, made.box), transfer.tint(made.tint, made.box), made.box)

    def result(
        self,
        method: Method,
        expression: Expression,
        shapes: dict[str, Shape],
        rendered: Rendered,
        ratio: Ratio | None,
        options: Options,
        transfer: Transfer,
    ) -> CloneResult:
        """One method's result: FI, then its detail stages (:meth:`details`) if it has any (then ``ratio`` is its ERI)."""
        faces = self.faces
        final = rendered.control[: faces.mesh.n_landmarks]
        landmarks = {SOURCE_NEUTRAL: faces.s_neu, SOURCE_EXPRESSION: expression.points, TARGET_NEUTRAL: faces.t_neu}
        landmarks.update({name: shapes[method.key(name)].points for name in ("global", "local", method.shape)}, final=final)
        if ratio is None:
            image, details = rendered.image, dict[str, Any]()
        else:
            image, details = self.details(method, expression, rendered.image, final, ratio, options.mouth, transfer)
        shape = shapes[method.stage]
        return CloneResult(
            image,
            method.name,
            landmarks,
            shape.lambda_k,
            shape.db_curve,
            unfolded_points=rendered.unfolded,
            options=options.ran_by(method),
            **details,
        )

    def details(
        self,
        method: Method,
        expression: Expression,
        fi: np.ndarray,
        final: np.ndarray,
        ratio: Ratio,
        mouth: bool,
        transfer: Transfer,
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """The illumination details on FI: the ERI, weighted by the MD mask (Eqs. 9-11) for ``e+md``; then the mouth interior.

        Returns
        -------
        image : ndarray of shape (H, W, 3), uint8
        details : dict
            The :class:`CloneResult` fields they fill: ``eri``, ``muscle_mask``,
            ``muscle_strengths``, ``mouth_mask``.
        """
        faces, layout = self.faces, self.faces.layout
        ratio_map, box = ratio.eri, ratio.box
        details: dict[str, Any] = {"eri": ratio_map}
        importance: np.ndarray | float = 1.0
        if method.md:
            h = muscle.strengths(faces.s_neu, expression.still, layout)
            centres, radii = muscle.areas(final, layout)
            importance = muscle.importance_mask(faces.target_image.shape[:2], centres, radii, h, muscle.mask_step(radii))
            details.update(muscle_mask=importance, muscle_strengths=h)
        image = fi.copy()
        image[box] = eri.apply_details(
            fi[box], ratio_map[box], importance if isinstance(importance, float) else importance[box], ratio.tint
        )
        if mouth:  # the photos are measured for the paste's match only when there is a paste
            image, details["mouth_mask"] = paste.fill_interior(
                image, final, expression.image, expression.points, lambda: faces.mouth_reference, layout, transfer.paste
            )
        return image, details


@dataclass(frozen=True)
class Rendered:
    """The target photo warped to one shape (FI): the image, the control points it was warped to, and how many were unfolded."""

    image: np.ndarray
    control: np.ndarray
    unfolded: int


@dataclass(frozen=True)
class Prepared:
    """One source expression prepared on a :class:`Cloner`'s faces (:meth:`Cloner.prepare`): rendered as often as asked.

    Attributes
    ----------
    cloner : Cloner
    methods : tuple of Method
        The methods it was prepared for.
    expression : Expression
        The source expression, ready for the shape stages.
    shapes : dict of str to Shape
        The shape stages its methods need (GI, LI and, for the elastic model, lambda_k and the DB curve).
    photo : ExpressionPhoto or None
        The expression photo as the ERI takes it; None when no method has the ERI.
    landmarker : str or None
        Which landmarker placed the photos' landmarks, for the results (:func:`exprclone.prepare` sets it).
    warnings : tuple of str
        What looked wrong with the photos, for the results (:func:`exprclone.prepare` sets it).
    """

    cloner: Cloner
    methods: tuple[Method, ...]
    expression: Expression
    shapes: dict[str, Shape]
    photo: ExpressionPhoto | None
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()

    @property
    def target_size(self) -> tuple[int, int]:
        """The target photo's ``(height, width)``."""
        height, width = self.cloner.faces.target_image.shape[:2]
        return height, width

    @property
    def lambda_k(self) -> float | None:
        """The elasticity ratio of its first method's shape (None for a method without the elastic model)."""
        return self.shapes[self.methods[0].stage].lambda_k

    def render(self, **changes: Any) -> dict[str, CloneResult]:
        """Each method's image, with the cloner's options or others of their cheap part (:data:`RENDER`: the strengths,
        ``only``, ``mouth``): FI for each shape, the ERI in its geometry, then the detail stages (:meth:`Cloner.result`).

        Raises
        ------
        ExprCloneError
            A bad value, or an option that is not of the cheap part (the expression must be prepared again).
        """
        costly = sorted(set(changes) - set(RENDER))
        if costly:
            raise ExprCloneError(costly[0], f"not changed by a render (only {', '.join(RENDER)} are): prepare the clone again")
        cloner = self.cloner
        options = Options.of(cloner.options, changes)
        transfer = cloner.weights(options)
        kinds = {m.stage for m in self.methods}
        rendered = {kind: cloner.fi(self.shapes[kind].points, transfer) for kind in kinds}
        ratios: dict[tuple[str, str | None], Ratio] = {}
        if self.photo is not None:
            made = {(m.stage, m.ratio) for m in self.methods if m.ratio is not None}
            ratios = {(stage, kind): cloner.ratio(rendered[stage], self.photo, transfer, kind) for stage, kind in made}
        results = {
            m.name: cloner.result(m, self.expression, self.shapes, rendered[m.stage], ratios.get((m.stage, m.ratio)), options, transfer)
            for m in self.methods
        }
        if self.landmarker is None and not self.warnings:
            return results
        return {name: dataclasses.replace(r, landmarker=self.landmarker, warnings=self.warnings) for name, r in results.items()}
