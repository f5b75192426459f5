"""The E+MD pipeline (paper Fig. 5) and the other six methods of Fig. 11.

Stages: landmarks -> global warping GI -> local warping LI -> elastic model (lambda_k
by the DB metric) -> geometric warp FI -> ERI -> MD model -> F_IMG.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import cv2
import numpy as np

from . import elastic, eri, geometry, global_warp, lips, local_warp, metric, muscle, warp
from . import mouth as mouth_fill
from .eigenface import Eigenfaces
from .errors import ExprCloneError
from .landmark_files import check_points
from .landmarks import Detector
from .layout import DLIB68, Layout
from .methods import METHODS


@dataclass
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


@functools.cache
def default_detector() -> Detector:
    """One shared lazily-loaded detector for calls that pass none."""
    return Detector()


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once."""
    return Eigenfaces.default()


def check_image(image: np.ndarray, name: str) -> np.ndarray:
    """An (H, W, 3) uint8 RGB image, or ExprCloneError naming it."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ExprCloneError(f"{name}: expected an (H, W, 3) uint8 RGB image, got shape {image.shape} dtype {image.dtype}")
    return image


def check_request(methods: tuple[str, ...], lambda_k: float | str) -> None:
    """ExprCloneError unless every method is known and lambda_k is "auto" or a number >= 0."""
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise ExprCloneError(f"unknown method {unknown[0]!r}; choose one of: {', '.join(METHODS)}")
    if lambda_k != "auto" and not (isinstance(lambda_k, (int, float)) and lambda_k >= 0):
        raise ExprCloneError(f"lambda_k must be 'auto' or a number >= 0, got {lambda_k!r}")


def padded_box(points: np.ndarray, iod: float, shape: tuple[int, ...]) -> tuple[int, int, int, int]:
    """``(x0, y0, x1, y1)``: the points' bounding box grown by half an inter-ocular distance, inside the image."""
    lo = np.floor(points.min(0) - 0.5 * iod).astype(int)
    hi = np.ceil(points.max(0) + 0.5 * iod).astype(int)
    return max(lo[0], 0), max(lo[1], 0), min(hi[0], shape[1]), min(hi[1], shape[0])


def ratio_image(
    mesh: warp.Mesh,
    dst: np.ndarray,
    sources: tuple[np.ndarray, np.ndarray],
    source_ctrl: list[np.ndarray],
    shape: tuple[int, ...],
    layout: Layout,
) -> tuple[np.ndarray, tuple[slice, slice]]:
    """The ERI of the source's two photos in the target's final geometry ``dst``.

    The ratio is 1 off the face, so it is computed in the face's box only.

    Returns
    -------
    eri : ndarray of shape (H, W)
        In the target photo's frame.
    box : tuple of slice
        Where it may differ from 1.
    """
    final = dst[: mesh.n_landmarks]
    iod = geometry.interocular(final, layout)
    x0, y0, x1, y1 = padded_box(dst[: mesh.n_moving], iod, shape)
    local = dst - (x0, y0)
    # the ratio needs the luma only: one channel to warp instead of three
    lumas = (cv2.cvtColor(img, cv2.COLOR_RGB2GRAY) for img in sources)
    neutral, expression = (warp.warp(img, c, local, mesh.triangles, (y1 - y0, x1 - x0)) for img, c in zip(lumas, source_ctrl))
    mask = eri.ratio_mask((y1 - y0, x1 - x0), local[: mesh.n_landmarks], local[mesh.forehead], layout)
    out = np.ones(shape[:2], np.float32)
    out[y0:y1, x0:x1] = eri.expression_ratio(neutral, expression, mask, iod)
    return out, (slice(y0, y1), slice(x0, x1))


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
        ``detector``, ``eigenfaces``, ``layout``, ``names``, ``mouth``: see :func:`clone_methods`.

    Returns
    -------
    CloneResult
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
    names: tuple[str, str, str] = ("source_neutral", "source_expression", "target_neutral"),
    mouth: bool = True,
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
    names : tuple of str
        How to name the three photos in error messages (their file paths).
    mouth : bool
        Fill an opened mouth with the source's mouth interior (teeth) in the methods
        with ERI (:mod:`exprclone.mouth`); False leaves the stretched lips.

    Returns
    -------
    dict of str to CloneResult
    """
    check_request(methods, lambda_k)
    images = [check_image(im, n) for im, n in zip((source_neutral, source_expression, target_neutral), names)]
    given = landmarks if landmarks is not None else (None, None, None)
    detector = detector or default_detector()
    s_neu, s_exp, t_neu = (
        detector.detect(im, n) if p is None else check_points(p, im.shape, layout.n_points, n) for im, p, n in zip(images, given, names)
    )
    cloner = Cloner(images[0], s_neu, images[2], t_neu, eigenfaces=eigenfaces, layout=layout)
    return cloner.clone_methods(images[1], s_exp, methods, lambda_k, mouth=mouth)


class Cloner:
    """The source's neutral face and the target's, prepared once for many source expressions.

    Everything that depends only on the two neutral faces (the target's mesh and its
    spring neighbours, the source's neutral photo placed on that mesh) is computed here,
    so that each expression (a photo, or a frame of a driving video) costs only the
    stages of Fig. 5 that depend on it.

    Parameters
    ----------
    source_neutral, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
    source_neutral_points, target_neutral_points : ndarray of shape (N, 2)
        Their landmarks.
    eigenfaces : Eigenfaces, optional
        Basis of the DB metric; the packaged one by default.
    layout : Layout
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
    ) -> None:
        self.layout = layout
        self.source_image, self.target_image = source_neutral, target_neutral
        self.s_neu = lips.uncross(source_neutral_points, layout)
        self.t_neu = lips.uncross(target_neutral_points, layout)
        self.eigenfaces = eigenfaces
        self.mesh = warp.build_mesh(self.t_neu, target_neutral.shape, layout)
        self.neighbours = self.mesh.neighbours()
        rigid = list(layout.rigid)
        self._source_neutral_ctrl = self.mesh.control_points(self.s_neu, geometry.fit_similarity(self.t_neu[rigid], self.s_neu[rigid]))

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
        check_request(methods, lambda_k)
        layout, mesh, tgt_img = self.layout, self.mesh, self.target_image
        s_neu, t_neu, s_exp = self.s_neu, self.t_neu, lips.uncross(source_expression_points, layout)

        gl = global_warp.global_landmarks(s_neu, s_exp, t_neu, layout)
        lo = local_warp.local_landmarks(gl, s_exp, layout)
        stages = {"source_neutral": s_neu, "source_expression": s_exp, "target_neutral": t_neu, "global": gl, "local": lo}
        kinds = {m: "elastic" if m == "e+md" else m.split("+")[0] for m in methods}
        chosen, curve = None, None
        if "elastic" in kinds.values():
            if lambda_k == "auto":
                lambdas = np.array(metric.LAMBDAS)
                candidates = list(elastic.elastic_landmarks(gl, lo, self.neighbours, lambdas))
                eigenfaces = self.eigenfaces or default_eigenfaces()
                curve = metric.choose_lambda(tgt_img, mesh, candidates, lambdas, source_expression, s_exp, eigenfaces, layout)
                chosen = curve.best
                stages["elastic"] = candidates[int(np.flatnonzero(lambdas == chosen)[0])]
            else:
                chosen = float(lambda_k)
                stages["elastic"] = elastic.elastic_landmarks(gl, lo, self.neighbours, chosen)

        # FI: the target photo warped to each geometry in use
        geometry_of, fi = {}, {}
        for kind in set(kinds.values()):
            dst, n_fixed = warp.unfold(mesh.points, mesh.control_points(lips.uncross(stages[kind], layout)), mesh.triangles, mesh.n_moving)
            geometry_of[kind] = (dst, n_fixed)
            fi[kind] = warp.warp(tgt_img, mesh.points, dst, mesh.triangles)

        # ERI: both source photos warped to the target's final geometry (Liu et al.)
        rigid = list(layout.rigid)
        source_ctrl = [
            self._source_neutral_ctrl,
            mesh.control_points(s_exp, geometry.fit_similarity(t_neu[rigid], s_exp[rigid])),
        ]
        sources = (self.source_image, source_expression)
        ratios, boxes = {}, {}
        for kind in {kinds[m] for m in methods if m.endswith("+eri") or m == "e+md"}:
            ratios[kind], boxes[kind] = ratio_image(mesh, geometry_of[kind][0], sources, source_ctrl, tgt_img.shape, layout)

        def with_details(kind: str, importance: np.ndarray | float = 1.0) -> np.ndarray:
            """Eq. (9) applied in the face box, where the ERI differs from 1."""
            box = boxes[kind]
            out = fi[kind].copy()
            out[box] = eri.apply_details(fi[kind][box], ratios[kind][box], importance if np.isscalar(importance) else importance[box])
            return out

        results = {}
        for m in methods:
            kind = kinds[m]
            dst, n_fixed = geometry_of[kind]
            lm = dict(stages, final=dst[: mesh.n_landmarks])
            if kind != "elastic":
                lm.pop("elastic", None)
            r = CloneResult(
                fi[kind], m, lm, chosen if kind == "elastic" else None, curve if kind == "elastic" else None, unfolded_points=n_fixed
            )
            if m == "e+md":
                centres, radii = muscle.areas(lm["final"], layout)
                r.muscle_strengths = muscle.strengths(s_neu, global_warp.remove_head_motion(s_neu, s_exp, layout), layout)
                r.muscle_mask = muscle.importance_mask(tgt_img.shape[:2], centres, radii, r.muscle_strengths)
                r.eri, r.image = ratios[kind], with_details(kind, r.muscle_mask)
            elif m.endswith("+eri"):
                r.eri, r.image = ratios[kind], with_details(kind)
            if mouth and r.eri is not None:
                r.image, r.mouth_mask = mouth_fill.fill_interior(
                    r.image, lm["final"], source_expression, s_exp, self.mouth_reference, layout
                )
            results[m] = r
        return results
