"""The E+MD pipeline (paper Fig. 5) and the other six methods of Fig. 11.

Stages: landmarks -> shape stages (global warping GI, local warping LI, the elastic
model with lambda_k by the DB metric; :data:`SHAPE_STAGES`) -> geometric warp FI ->
details (ERI, MD model, mouth interior) -> F_IMG. What each method runs is read from its
row of :data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options` of the :class:`Cloner`: which global warp gives GI
(:data:`GLOBAL_WARPS`: the paper's, Seol and Lewis's RBF transfer, or landmarks given
by any other method, which the elastic model refines as in the paper's Figs. 19-21),
which image warp gives FI (:data:`IMAGE_WARPS`), how much of the expression is
transferred (:mod:`exprclone.transfer`), and whether the source's motion is first made
the target's (:mod:`exprclone.retarget`, not in the paper; ``retarget=False`` runs the
paper's global and local stages).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import elastic, eri, geometry, global_warp, lips, local_warp, metric, muscle, retarget, tps, warp
from . import mouth as mouth_fill
from .checks import check_image, check_lambda, check_options, check_points
from .eigenface import Eigenfaces
from .landmarks import Detector
from .layout import DLIB68, Layout
from .methods import METHODS, SHAPES, Method, lookup
from .options import GIVEN, Options
from .transfer import Transfer

#: the three photos' roles, as errors name them.
ROLES = ("source_neutral", "source_expression", "target_neutral")
#: the face box the ERI is computed in: the moving control points' box grown by this many inter-ocular distances.
ERI_MARGIN = 0.5


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
        (:mod:`exprclone.mouth`; methods with ERI), None when nothing was pasted.
    unfolded_points : int
        Control points moved to stop triangles folding over.
    options : Options
        How it was made beyond its method: the global and image warps, strength and regions.
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


@functools.cache
def default_detector() -> Detector:
    """One shared lazily-loaded detector for calls that pass none."""
    return Detector()


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once."""
    return Eigenfaces.default()


def clone(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    method: str = "e+md",
    lambda_k: float | str = "auto",
    landmarks: tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None] | None = None,
    **options,
) -> CloneResult:
    """Put the source's expression on the target's face.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The three photos; they may differ in size.
    method : str
        One of :data:`METHODS`.
    lambda_k : float or "auto"
        Elasticity ratio ``k_A' / k_N`` (Eq. 6); "auto" picks it by the DB metric (Eq. 8).
    landmarks : tuple of three (N, 2) arrays or None, optional
        Known landmarks for each photo; None entries are detected.
    **options
        ``detector``, ``eigenfaces``, ``layout``, ``mouth``, and the options of
        :class:`~exprclone.options.Options` (``global_warp``, ``global_landmarks``,
        ``image_warp``, ``strength``, ``only``, ``retarget``): see :func:`clone_methods`.

    Returns
    -------
    CloneResult

    Raises
    ------
    ExprCloneError
        A bad input, its ``subject`` the photo's role (:data:`ROLES`), ``method``, ``lambda`` or the option's name.
    """
    return clone_methods(source_neutral, source_expression, target_neutral, (method,), lambda_k, landmarks, **options)[method]


def clone_methods(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    methods: tuple[str, ...] = METHODS,
    lambda_k: float | str = "auto",
    landmarks: tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None] | None = None,
    *,
    detector: Detector | None = None,
    eigenfaces: Eigenfaces | None = None,
    layout: Layout = DLIB68,
    mouth: bool = True,
    **options,
) -> dict[str, CloneResult]:
    """Several methods at once, sharing the stages they have in common (Fig. 5).

    Parameters
    ----------
    source_neutral, source_expression, target_neutral, lambda_k, landmarks
        As for :func:`clone`.
    methods : tuple of str
        Any of :data:`METHODS`.
    detector : Detector, optional
        Landmark detector for photos without given landmarks.
    eigenfaces : Eigenfaces, optional
        Basis of the DB metric; the packaged one by default.
    layout : Layout
    mouth : bool
        Fill an opened mouth with the source's mouth interior (teeth) in the methods
        with ERI (:mod:`exprclone.mouth`); False leaves the stretched lips.
    **options
        The :class:`~exprclone.options.Options` of the clone:

        - ``global_warp``: ``"similarity"`` (the paper's GI, the default) or ``"rbf"``
          (Seol and Lewis's RBF transfer, the paper's Figs. 19-20);
        - ``global_landmarks``: ``(N, 2)`` landmarks of the target's expression made by
          any other method, taken as GI (the paper's Fig. 21);
        - ``image_warp``: ``"mesh"`` (piecewise-affine, the default) or ``"tps"``
          (thin-plate spline);
        - ``strength``: from 0 (the target as it is) to 2, 1 by default;
        - ``only``: region names (``"mouth"``, ``"eyes"``, ``"brows"``) whose motion
          alone is transferred, None (the default) for the whole face;
        - ``retarget``: True (the default) makes the source's motion the target's before
          the global and local stages (:mod:`exprclone.retarget`); False runs the paper's.

    Returns
    -------
    dict of str to CloneResult
    """
    lookup(methods)
    check_lambda(lambda_k)
    images = [check_image(im, role) for im, role in zip((source_neutral, source_expression, target_neutral), ROLES)]
    given = landmarks if landmarks is not None else (None, None, None)
    detector = detector or default_detector()
    s_neu, s_exp, t_neu = (
        detector.detect(im, role) if p is None else check_points(p, im.shape, layout.n_points, role)
        for im, p, role in zip(images, given, ROLES)
    )
    cloner = Cloner(images[0], s_neu, images[2], t_neu, eigenfaces=eigenfaces, layout=layout, **options)
    return cloner.clone_methods(images[1], s_exp, methods, lambda_k, mouth=mouth)


@dataclass(frozen=True)
class Expression:
    """One source expression to clone (:meth:`Cloner.expression` makes it).

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
        ``points`` (the paper), or that motion cleaned (:func:`exprclone.retarget.clean`).
    organs : ndarray of shape (N, 2)
        What local re-shaping gives each organ the height-to-width ratio of (Eqs. 1-2):
        ``points``, the source's own organs (the paper), or the target's organs moved by
        the source (:func:`exprclone.retarget.organ_reference`).
    """

    image: np.ndarray
    points: np.ndarray
    lambda_k: float | str
    moving: np.ndarray
    organs: np.ndarray


@dataclass(frozen=True)
class Shape:
    """What a shape stage gives: landmarks, and for the elastic model the lambda_k used and the DB curve."""

    points: np.ndarray
    lambda_k: float | None = None
    db_curve: metric.DBCurve | None = None


@dataclass(frozen=True)
class Rendered:
    """The target photo warped to one shape (FI): the image, the control points it was warped to, and how many were unfolded."""

    image: np.ndarray
    control: np.ndarray
    unfolded: int


def similarity_warp(cloner: "Cloner", expression: Expression) -> np.ndarray:
    """GI of the paper: the source's motion, similarity-aligned, on the target (:func:`global_warp.global_landmarks`)."""
    return global_warp.global_landmarks(cloner.s_neu, expression.moving, cloner.t_neu, cloner.layout)


def rbf_warp(cloner: "Cloner", expression: Expression) -> np.ndarray:
    """GI of Seol and Lewis: each landmark's motion by the RBF map's Jacobian (:func:`global_warp.rbf_landmarks`)."""
    return global_warp.rbf_landmarks(cloner.s_neu, expression.moving, cloner.t_neu, cloner.layout, cloner.rbf_jacobians)


def given_warp(cloner: "Cloner", expression: Expression) -> np.ndarray:
    """GI given from outside, the result of any other method (Fig. 21)."""
    return cloner.options.global_landmarks


#: the global warps by name (:attr:`Options.global_stage`), each ``(cloner, expression) -> GI landmarks``.
GLOBAL_WARPS: dict[str, Callable[["Cloner", Expression], np.ndarray]] = {
    "similarity": similarity_warp,
    "rbf": rbf_warp,
    GIVEN: given_warp,
}


def global_stage(cloner: "Cloner", expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """GI: by the global warp of the cloner's options (:data:`GLOBAL_WARPS`)."""
    return Shape(GLOBAL_WARPS[cloner.options.global_stage](cloner, expression))


def local_stage(cloner: "Cloner", expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """LI: each organ of GI re-shaped to the expression's organs (:attr:`Expression.organs`), Eqs. (1)-(2)."""
    return Shape(local_warp.local_landmarks(shapes["global"].points, expression.organs, cloner.layout))


def elastic_stage(cloner: "Cloner", expression: Expression, shapes: dict[str, Shape]) -> Shape:
    """The elastic model's balance of GI and LI, Eqs. (3)-(6), lambda_k given or chosen by the DB metric, Eqs. (7)-(8)."""
    gl, local = shapes["global"].points, shapes["local"].points
    if expression.lambda_k != "auto":
        chosen = float(expression.lambda_k)
        return Shape(elastic.elastic_landmarks(gl, local, cloner.neighbours, chosen), chosen)
    lambdas = np.array(metric.LAMBDAS)
    candidates = list(elastic.elastic_landmarks(gl, local, cloner.neighbours, lambdas))
    eigenfaces = cloner.eigenfaces or default_eigenfaces()
    curve = metric.choose_lambda(
        cloner.target_image, cloner.mesh, candidates, lambdas, expression.image, expression.points, eigenfaces, cloner.layout
    )
    return Shape(candidates[int(np.flatnonzero(lambdas == curve.best)[0])], curve.best, curve)


#: the shape stages of :data:`exprclone.methods.SHAPES` by name, each computed from the ones before it.
SHAPE_STAGES: dict[str, Callable[["Cloner", Expression, dict[str, Shape]], Shape]] = {
    "global": global_stage,
    "local": local_stage,
    "elastic": elastic_stage,
}


def mesh_warp(image: np.ndarray, src: np.ndarray, dst: np.ndarray, mesh: warp.Mesh, out_shape: tuple[int, int] | None = None) -> np.ndarray:
    """The piecewise-affine warp over the mesh's triangles (:func:`warp.warp`), the paper's."""
    return warp.warp(image, src, dst, mesh.triangles, out_shape)


def tps_warp(image: np.ndarray, src: np.ndarray, dst: np.ndarray, mesh: warp.Mesh, out_shape: tuple[int, int] | None = None) -> np.ndarray:
    """The thin-plate spline through the mesh's control points (:func:`tps.warp`), its grid refined by :func:`tps_refine`."""
    return tps.warp(image, src, dst, out_shape, tps_refine(mesh))


def tps_refine(mesh: warp.Mesh) -> tuple[tuple[np.ndarray, int], ...]:
    """Where the TPS warp evaluates its spline on finer grids: the face (the moving control points), then the mouth."""
    return (np.arange(mesh.n_moving), tps.FACE_STEP), (mesh.mouth, tps.MOUTH_STEP)


#: the image warps by name (:attr:`Options.image_warp`), each ``(image, src, dst, mesh, out_shape) -> image``.
IMAGE_WARPS: dict[str, Callable[..., np.ndarray]] = {"mesh": mesh_warp, "tps": tps_warp}


def ratio_image(
    mesh: warp.Mesh,
    target: Rendered,
    sources: tuple[np.ndarray, np.ndarray],
    source_ctrl: list[np.ndarray],
    motion: np.ndarray,
    layout: Layout,
    image_warp: Callable[..., np.ndarray] = mesh_warp,
) -> tuple[np.ndarray, tuple[slice, slice]]:
    """The ERI of the source's two photos in the target's final geometry, warped by ``image_warp`` (:data:`IMAGE_WARPS`).

    The ratio is 1 off the face, so it is computed in the face's box only. It counts
    only where the expression moves the skin and all three photos show the same skin
    there (:func:`exprclone.eri.expression_ratio`, its ``mask`` times
    :func:`exprclone.eri.moved`, the lips exempt from the colour test).

    Parameters
    ----------
    mesh : warp.Mesh
    target : Rendered
        FI: the target photo warped to its final geometry, and that geometry's control points.
    sources : tuple of two ndarray of shape (h, w, 3), uint8 RGB
        The source's neutral and expression photos.
    source_ctrl : list of two ndarray of shape (P, 2)
        The control points in each of them.
    motion : ndarray of shape (P,)
        How far each control point moves in the source's expression (inter-ocular
        distances, head motion removed), for :func:`exprclone.eri.moved`.
    layout : Layout
    image_warp : callable

    Returns
    -------
    eri : ndarray of shape (H, W)
        In the target photo's frame.
    box : tuple of slice
        Where it may differ from 1.
    """
    dst, shape = target.control, target.image.shape
    iod = geometry.interocular(dst[: mesh.n_landmarks], layout)
    rows, cols = box = geometry.box(dst[: mesh.n_moving], shape, ERI_MARGIN * iod, closed=False)
    size = (rows.stop - rows.start, cols.stop - cols.start)
    local = dst - (cols.start, rows.start)
    # RGB, not the luma alone: the colour tells a change of material from shading
    neutral, expression = (image_warp(img, c, local, mesh, size) for img, c in zip(sources, source_ctrl))
    mask = eri.ratio_mask(size, local[: mesh.n_landmarks], local[mesh.forehead], layout)
    mask *= eri.moved(size, local, motion, mesh.triangles, iod)
    lip_region = eri.lips(size, local[: mesh.n_landmarks], layout)
    out = np.ones(shape[:2], np.float32)
    out[box] = eri.expression_ratio(neutral, expression, mask, iod, target.image[box], lip_region)
    return out, box


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
    **options
        The :class:`~exprclone.options.Options` of every clone it makes (see
        :func:`clone_methods`), checked here (:func:`exprclone.checks.check_options`).
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
        **options,
    ) -> None:
        self.layout = layout
        self.options = check_options(options, layout.n_points, target_neutral.shape, tuple(layout.regions))
        self.image_warp = IMAGE_WARPS[self.options.image_warp]
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
    def mouth_reference(self) -> mouth_fill.Reference:
        """The target photo and the source's neutral photo measured for the mouth interior's match."""
        return mouth_fill.Reference.measure(self.target_image, self.t_neu, self.layout, (self.source_image, self.s_neu))

    def clone_methods(
        self,
        source_expression: np.ndarray,
        source_expression_points: np.ndarray,
        methods: tuple[str, ...] = METHODS,
        lambda_k: float | str = "auto",
        *,
        mouth: bool = True,
    ) -> dict[str, CloneResult]:
        """The source expression on the target face, by each of ``methods`` (see :func:`clone_methods`)."""
        chosen = lookup(methods)
        expression = self.expression(source_expression, source_expression_points, check_lambda(lambda_k))
        shapes = self.shapes(expression, {m.shape for m in chosen})
        rendered = {kind: self.render(shapes[kind].points) for kind in {m.shape for m in chosen}}
        ratios = {kind: self.ratio(rendered[kind], expression) for kind in {m.shape for m in chosen if m.eri}}
        return {m.name: self.result(m, expression, shapes, rendered[m.shape], ratios.get(m.shape), mouth) for m in chosen}

    def expression(self, image: np.ndarray, points: np.ndarray, lambda_k: float | str) -> Expression:
        """One source expression, prepared for the shape stages: with ``retarget``, its motion cleaned and the organs
        local re-shaping aims at made the target's (:mod:`exprclone.retarget`); without, the paper's (its own points)."""
        points = lips.uncross(points, self.layout)
        if not self.options.retarget:
            return Expression(image, points, lambda_k, points, points)
        cleaned = retarget.clean(self.s_neu, points, self.layout)
        return Expression(image, points, lambda_k, cleaned, retarget.organ_reference(self.s_neu, cleaned, self.t_neu, self.layout))

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
        # how far the source's skin moves at each control point, its head's motion removed (for eri.moved)
        aligned = global_warp.remove_head_motion(self.s_neu, expression.points, self.layout)
        shift = self.mesh.control_points(aligned, geometry.fit_rigid(self.t_neu, self.s_neu, self.layout)) - self._source_neutral_ctrl
        motion = np.linalg.norm(shift, axis=1) / geometry.interocular(self.s_neu, self.layout)
        sources, ctrl = (self.source_image, expression.image), [self._source_neutral_ctrl, placed]
        ratio, box = ratio_image(self.mesh, target, sources, ctrl, motion, self.layout, self.image_warp)
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
        """One method's result: FI, then its detail stages (:meth:`details`) if it has any."""
        final = rendered.control[: self.mesh.n_landmarks]
        landmarks = {"source_neutral": self.s_neu, "source_expression": expression.points, "target_neutral": self.t_neu}
        landmarks.update({name: shapes[name].points for name in ("global", "local", method.shape)}, final=final)
        image, details = (rendered.image, {}) if not method.eri else self.details(method, expression, rendered.image, final, ratio, mouth)
        shape = shapes[method.shape]
        extra = dict(unfolded_points=rendered.unfolded, options=self.options)
        return CloneResult(image, method.name, landmarks, shape.lambda_k, shape.db_curve, **extra, **details)

    def details(
        self,
        method: Method,
        expression: Expression,
        fi: np.ndarray,
        final: np.ndarray,
        ratio: tuple[np.ndarray, tuple[slice, slice]],
        mouth: bool,
    ) -> tuple[np.ndarray, dict]:
        """The illumination details on FI: the ERI, weighted by the MD mask (Eqs. 9-11) for ``e+md``; then the mouth interior.

        Returns
        -------
        image : ndarray of shape (H, W, 3), uint8
        details : dict
            The :class:`CloneResult` fields they fill: ``eri``, ``muscle_mask``,
            ``muscle_strengths``, ``mouth_mask``.
        """
        ratio_map, box = ratio
        details: dict = {"eri": ratio_map}
        importance: np.ndarray | float = 1.0
        if method.md:
            h = muscle.strengths(self.s_neu, global_warp.remove_head_motion(self.s_neu, expression.points, self.layout), self.layout)
            importance = muscle.importance_mask(self.target_image.shape[:2], *muscle.areas(final, self.layout), h)
            details.update(muscle_mask=importance, muscle_strengths=h)
        image = fi.copy()
        image[box] = eri.apply_details(fi[box], ratio_map[box], importance if np.isscalar(importance) else importance[box])
        if mouth:
            reference = self.mouth_reference
            image, details["mouth_mask"] = mouth_fill.fill_interior(
                image, final, expression.image, expression.points, reference, self.layout, self.transfer.paste
            )
        return image, details
