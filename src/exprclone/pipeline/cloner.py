"""A clone prepared once and rendered many times: :class:`Cloner` (two neutral faces and the options) and
:class:`Prepared` (one source expression on them).

The stages of Fig. 5 fall in two parts. What a source expression costs once is
:meth:`Cloner.prepare`: the expression made ready (:func:`exprclone.pipeline.stages.expression`),
the shape stages its methods need (GI, LI, the elastic model with the lambda search of the
DB metric) and the expression photo as the ERI takes it. What an image costs is
:meth:`Prepared.render`: the stages of :mod:`exprclone.pipeline.render` over the data the
prepared clone holds. What each method runs is read from its row of
:data:`exprclone.methods.TABLE`; how its stages run, from the :class:`~exprclone.options.Options`.
A Cloner is made at the door (:mod:`exprclone.pipeline.request`), from the photos of a request.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..details.stage import ExpressionPhoto
from ..errors import ExprCloneError
from ..geometry.weights import Transfer
from ..methods import Method, lookup
from ..mouth import paste
from ..options import RENDER, Options
from . import render, stages
from .checks import check_for_target
from .faces import Faces
from .result import CloneResult
from .stages import Shape, SourceExpression


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
        self.transfer = render.transfer(self.faces, self.options)

    def changed(self, options: Options | None = None, *, faces: Faces | None = None, **changes: Any) -> Cloner:
        """The same prepared faces (or ``faces``, the same two faces measured further: :meth:`Faces.pooled`) with other
        ``options``, or its own changed by keywords (``changed(lambda_k=0.5)``): nothing of the faces is made again.

        Raises
        ------
        ExprCloneError
            A bad option, or another ``layout`` (the faces were prepared for theirs).
        """
        options = check_for_target(Options.of(options or self.options, changes), self.faces.target_image.shape)
        if options.landmarks_layout != self.faces.layout:  # (equal, not the same object: faces made in another process)
            raise ExprCloneError("layout", "the faces were prepared with another layout: make a new Cloner")
        other = object.__new__(Cloner)
        other.options, other.faces = options, faces or self.faces
        other.transfer = self.transfer if _same_strengths(options, self.options) else render.transfer(other.faces, options)
        return other

    def prepare(
        self, source_expression: np.ndarray, source_expression_points: np.ndarray, methods: tuple[str, ...] | None = None
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

        Returns
        -------
        Prepared
        """
        chosen = lookup(methods or (self.options.method,))
        faces, options = self.faces, self.options
        expression = stages.expression(faces, source_expression, source_expression_points, options)
        shaded = any(m.ratio for m in chosen)
        # the ERI's photo on another core, beside the shape stages and then the mouth's measures (the faces' own, made once)
        with concurrent.futures.ThreadPoolExecutor(1) as beside:
            photo = beside.submit(faces.expression_photo, expression.image, expression.points, expression.still) if shaded else None
            synthesis = render.synthesis(faces, expression, options.image_warp, None if photo is None else photo.result)
            shapes = stages.method_shapes(faces, options, expression, chosen, synthesis)
            if shaded and options.mouth and paste.open_share(expression.points, faces.layout) > 0:
                _ = faces.mouth_reference  # measured on this core meanwhile, once for every render's paste
            return Prepared(faces, options, self.transfer, chosen, expression, shapes, None if photo is None else photo.result())

    def choose_lambda(self, frames: Sequence[np.ndarray], points: Sequence[np.ndarray]) -> float:
        """One lambda_k for several expressions on these faces (the frames of a performance): the median of the DB
        metric's choices (Eq. 8) on each, ``frames[i]`` with its landmarks ``points[i]``."""
        options = dataclasses.replace(self.options, lambda_k="auto")
        chosen = []
        for frame, p in zip(frames, points):
            expression = stages.expression(self.faces, frame, p, options)
            synthesis = render.synthesis(self.faces, expression, options.image_warp)
            chosen.append(stages.shapes(self.faces, options, expression, {"elastic"}, synthesis)["elastic"].lambda_k)
        return float(np.median(np.array(chosen, float)))

    def clone_methods(
        self, source_expression: np.ndarray, source_expression_points: np.ndarray, methods: tuple[str, ...] | None = None
    ) -> dict[str, CloneResult]:
        """The source expression on the target face, by each of ``methods``: :meth:`prepare`, then :meth:`Prepared.render`.

        Returns
        -------
        dict of str to CloneResult
            One result per method.
        """
        return self.prepare(source_expression, source_expression_points, methods).render()


def _same_strengths(a: Options, b: Options) -> bool:
    """Whether two options transfer the same share of the expression everywhere (one :class:`Transfer` serves both)."""
    return (a.region_strengths, a.strength_shading) == (b.region_strengths, b.strength_shading)


@dataclass(frozen=True)
class Prepared:
    """One source expression prepared on a :class:`Cloner`'s faces (:meth:`Cloner.prepare`): rendered as often as asked.

    Attributes
    ----------
    faces : Faces
        The two neutral faces it was prepared on.
    options : Options
        The options it was prepared with.
    transfer : Transfer
        How much of the expression those options transfer, and where.
    methods : tuple of Method
        The methods it was prepared for.
    expression : SourceExpression
        The source expression, ready for the shape stages.
    shapes : dict of str to Shape
        The shape stages its methods need (GI, LI and, for the elastic model, lambda_k and the DB curve), each by
        :meth:`exprclone.methods.Method.key` (a method's own global warp's as ``stage@warp``).
    photo : ExpressionPhoto or None
        The expression photo as the ERI (or the mesh image) takes it; None when no method has either.
    landmarker : str or None
        Which landmarker placed the photos' landmarks, for the results (the door sets it: :mod:`exprclone.pipeline.request`).
    warnings : tuple of str
        What looked wrong with the photos, for the results (the door sets it).
    """

    faces: Faces
    options: Options
    transfer: Transfer
    methods: tuple[Method, ...]
    expression: SourceExpression
    shapes: dict[str, Shape]
    photo: ExpressionPhoto | None
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()

    @property
    def target_size(self) -> tuple[int, int]:
        """The target photo's ``(height, width)``."""
        height, width = self.faces.target_image.shape[:2]
        return height, width

    @property
    def lambda_k(self) -> float | None:
        """The elasticity ratio of its first method's shape (None for a method without the elastic model)."""
        return self.shapes[self.methods[0].stage].lambda_k

    def render(self, **changes: Any) -> dict[str, CloneResult]:
        """Each method's image, with the options it was prepared with or others of their cheap part (:data:`RENDER`: the
        strengths, ``only``, ``mouth``): the stages of :func:`exprclone.pipeline.render.render`.

        Raises
        ------
        ExprCloneError
            A bad value, or an option that is not of the cheap part (the expression must be prepared again).
        """
        costly = sorted(set(changes) - set(RENDER))
        if costly:
            raise ExprCloneError(costly[0], f"not changed by a render (only {', '.join(RENDER)} are): prepare the clone again")
        options = Options.of(self.options, changes)
        transfer = self.transfer if _same_strengths(options, self.options) else render.transfer(self.faces, options)
        results = render.render(self.faces, self.methods, self.expression, self.shapes, self.photo, options, transfer)
        if self.landmarker is None and not self.warnings:
            return results
        return {name: dataclasses.replace(r, landmarker=self.landmarker, warnings=self.warnings) for name, r in results.items()}
