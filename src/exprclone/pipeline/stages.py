"""The shape stages of Fig. 5 (GI, LI, the elastic model) as a table of functions over the prepared faces.

A source expression is first made ready for them (:func:`expression`): with ``retarget``, its
motion cleaned and the organs local re-shaping aims at made the target's. Each shape stage
(:data:`SHAPE_STAGES`) then computes its landmarks from the ones before it (:func:`shapes`): the
global stage by the global warp the options name (:data:`GLOBAL_WARPERS`, keyed by
:attr:`exprclone.options.Options.global_warp`) unless they give GI, or by a method's own (Song et al.'s
VTC: :func:`method_shapes`); the elastic stage with lambda_k given or chosen by the DB metric. What a user may
choose is :mod:`exprclone.options`'.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..geometry import db_metric, eigenface, elastic, global_warp, local_warp, vtc
from ..geometry.eigenface import default_eigenfaces
from ..geometry.expression_shape import default_model
from ..landmarks import align, lips
from ..methods import SHAPES, Method
from ..options import Options
from .faces import Faces

#: LI this close to GI (pixels) is GI: the elastic model has nothing to balance, and the DB metric nothing to choose.
SAME = 1e-6

#: the image a clone synthesizes at some landmarks, and the mesh's control points it was warped to: E+MD's, the whole
#: expression (:func:`exprclone.pipeline.render.synthesized`), which the DB metric's candidates are carried from.
Synthesis = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class SourceExpression:
    """One source expression to clone (:func:`expression` makes it).

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
        Its photo.
    points : ndarray of shape (N, 2)
        Its landmarks in the photo, the lips made valid.
    lambda_k : float or str
        The lambda_k asked for.
    moving : ndarray of shape (N, 2)
        The landmarks whose motion from the source's neutral ones the global warps carry:
        ``points`` (the paper), or the motion the target's own face makes of it, carried back to the source's frame
        (:meth:`exprclone.geometry.expression_shape.ExpressionShape.transfer`).
    organs : ndarray of shape (N, 2)
        What local re-shaping gives each organ the height-to-width ratio of (Eqs. 1-2):
        ``points``, the source's own organs (the paper), or the target's own face so moved (then LI is GI: the
        elastic model has nothing to balance).
    still : ndarray of shape (N, 2)
        ``points`` with the head's motion removed, in the neutral photo's frame
        (:func:`exprclone.geometry.global_warp.remove_head_motion`): what the ERI's gate and the MD model measure.
    """

    image: np.ndarray
    points: np.ndarray
    lambda_k: float | str
    moving: np.ndarray
    organs: np.ndarray
    still: np.ndarray


@dataclass(frozen=True)
class Shape:
    """What a shape stage gives: landmarks, and for the elastic model the lambda_k used and the DB curve."""

    points: np.ndarray
    lambda_k: float | None = None
    db_curve: db_metric.DBCurve | None = None


def similarity_warp(faces: Faces, expression: SourceExpression) -> np.ndarray:
    """GI of the paper: the source's motion, similarity-aligned, on the target (:func:`exprclone.geometry.global_warp.global_landmarks`)."""
    return global_warp.global_landmarks(faces.s_neu, expression.moving, faces.t_neu, faces.layout)


def rbf_warp(faces: Faces, expression: SourceExpression) -> np.ndarray:
    """GI of Seol and Lewis: each landmark's motion by the RBF map's Jacobian (:func:`exprclone.geometry.global_warp.rbf_landmarks`)."""
    return global_warp.rbf_landmarks(faces.s_neu, expression.moving, faces.t_neu, faces.layout, faces.rbf_jacobians)


def vtc_warp(faces: Faces, expression: SourceExpression) -> np.ndarray:
    """GI of Song et al.: each vertex tent's change made the target's (:func:`exprclone.geometry.vtc.vtc_landmarks`)."""
    return vtc.vtc_landmarks(faces.s_neu, expression.moving, faces.t_neu, faces.layout, faces.tents)


#: the global warps by name (:data:`exprclone.options.GLOBAL_WARPS`), each ``(faces, expression) -> GI landmarks``.
GLOBAL_WARPERS: dict[str, Callable[[Faces, SourceExpression], np.ndarray]] = {
    "similarity": similarity_warp,
    "rbf": rbf_warp,
    "vtc": vtc_warp,
}


def global_stage(faces: Faces, options: Options, expression: SourceExpression, shapes: dict[str, Shape], synthesis: Synthesis) -> Shape:
    """GI: given from outside, the result of any other method (Fig. 21), else by the global warp of the options
    (:data:`GLOBAL_WARPERS`)."""
    given = options.global_landmarks
    return Shape(given if given is not None else GLOBAL_WARPERS[options.global_warp](faces, expression))


def local_stage(faces: Faces, options: Options, expression: SourceExpression, shapes: dict[str, Shape], synthesis: Synthesis) -> Shape:
    """LI: each organ of GI re-shaped to the expression's organs (:attr:`SourceExpression.organs`), Eqs. (1)-(2)."""
    return Shape(local_warp.local_landmarks(shapes["global"].points, expression.organs, faces.layout))


def elastic_stage(faces: Faces, options: Options, expression: SourceExpression, shapes: dict[str, Shape], synthesis: Synthesis) -> Shape:
    """The elastic model's balance of GI and LI, Eqs. (3)-(6), lambda_k given or chosen by the DB metric, Eqs. (7)-(8):
    its candidates the image ``synthesis`` makes at GI carried to each (:func:`exprclone.geometry.db_metric.choose_lambda`)."""
    gl, local = shapes["global"].points, shapes["local"].points
    if expression.lambda_k == "auto" and np.abs(local - gl).max() < SAME:  # every lambda_k gives GI: nothing to choose
        return Shape(gl, 0.0)
    if expression.lambda_k != "auto":
        chosen = float(expression.lambda_k)
        return Shape(elastic.elastic_landmarks(gl, local, faces.neighbours, chosen), chosen)
    lambdas = np.array(db_metric.LAMBDAS)
    # the candidates need no finer search than the features' pixels (db_metric.CANDIDATE_PASSES)
    candidates = list(elastic.elastic_landmarks(gl, local, faces.neighbours, lambdas, db_metric.CANDIDATE_PASSES))
    layout = faces.layout
    at_gl = db_metric.Synthesized.of(*synthesis(gl), layout, faces.mesh.n_landmarks)
    crop = eigenface.crop(expression.image, expression.points, layout, eigenface.FEATURE_SIZE)
    curve = db_metric.choose_lambda(at_gl, faces.mesh, candidates, lambdas, crop, options.eigenfaces or default_eigenfaces(), layout)
    return Shape(elastic.elastic_landmarks(gl, local, faces.neighbours, curve.best), curve.best, curve)


#: the shape stages of :data:`exprclone.methods.SHAPES` by name, each computed from the ones before it.
SHAPE_STAGES: dict[str, Callable[[Faces, Options, SourceExpression, dict[str, Shape], Synthesis], Shape]] = {
    "global": global_stage,
    "local": local_stage,
    "elastic": elastic_stage,
}


def expression(
    faces: Faces,
    image: np.ndarray,
    points: np.ndarray,
    options: Options,
) -> SourceExpression:
    """One source expression, prepared for the shape stages: with the options' ``retarget``, its motion made as the
    target's own face makes it (:meth:`exprclone.geometry.expression_shape.ExpressionShape.transfer`, by the options'
    ``expression_shape`` or the model shipped), carried by the global warps and aimed at by local re-shaping; without,
    the paper's (its own points)."""
    layout = faces.layout
    points = lips.uncross(points, layout)
    still = global_warp.remove_head_motion(faces.s_neu, points, layout)
    if not options.retarget:
        return SourceExpression(image, points, options.lambda_k, points, points, still)
    model = options.expression_shape or default_model()
    motion = model.transfer(faces.s_neu, still - faces.s_neu, faces.t_neu, layout)
    linear = align.fit_similarity(faces.s_neu, faces.t_neu)[:, :2]  # how the global warp carries a motion to the target
    # the motion in the source's frame that the global warp carries there (with no head motion of its own to remove)
    moving = global_warp.remove_head_motion(faces.s_neu, faces.s_neu + motion @ np.linalg.inv(linear).T, layout)
    return SourceExpression(image, points, options.lambda_k, moving, faces.t_neu + (moving - faces.s_neu) @ linear.T, still)


def shapes(faces: Faces, options: Options, expression: SourceExpression, wanted: set[str], synthesis: Synthesis) -> dict[str, Shape]:
    """The shape stages (:data:`SHAPE_STAGES`) up to the last one ``wanted``; GI and LI always. ``synthesis`` makes the
    image the DB metric's candidates are carried from (:data:`Synthesis`), if it runs."""
    done: dict[str, Shape] = {}
    for name in SHAPES:
        if name in wanted | {"global", "local"}:
            done[name] = SHAPE_STAGES[name](faces, options, expression, done, synthesis)
    return done


def method_shapes(
    faces: Faces, options: Options, expression: SourceExpression, methods: tuple[Method, ...], synthesis: Synthesis
) -> dict[str, Shape]:
    """The shape stages ``methods`` need (:func:`shapes`), each kept by :meth:`exprclone.methods.Method.key`: on the
    options' global warp, and on each method's own (:attr:`~exprclone.methods.Method.warp`, which replaces the options'
    global stage)."""
    done: dict[str, Shape] = {}
    for warp in dict.fromkeys(m.warp for m in methods):
        own = [m for m in methods if m.warp == warp]
        chosen = options if warp is None else dataclasses.replace(options, global_warp=warp, global_landmarks=None)
        made = shapes(faces, chosen, expression, {m.shape for m in own}, synthesis)
        done.update({own[0].key(name): shape for name, shape in made.items()})
    return done
