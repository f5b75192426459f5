"""The options of a clone (:class:`Options`): every choice a user makes beyond the three photos, each a field with its
default, its check and its words (:mod:`exprclone.options.specs`).

The options (beyond the method of Fig. 11 and its lambda_k):

- ``global_warp``: which global warping gives GI, the shape every other stage starts
  from. ``similarity`` is the paper's (Liu et al.: the source's motion rotated and
  scaled into the target by one similarity); ``rbf`` carries each landmark's motion by
  the local Jacobian of a radial-basis-function map between the two neutral faces (Seol
  and Lewis, the paper's Figs. 19-20; :func:`exprclone.geometry.global_warp.rbf_landmarks`); ``vtc`` makes each
  vertex tent of the landmark mesh change as the source's does (Song et al.'s vertex-tent-coordinate transfer, on
  which the paper's Fig. 17 puts its elastic model; :func:`exprclone.geometry.vtc.vtc_landmarks`).
- ``global_landmarks``: GI given from outside, the result of any other method, which the
  elastic model then refines (the paper's Fig. 21).
- ``image_warp``: how the photo follows its landmarks: ``mesh``, the piecewise-affine
  warp over the Delaunay mesh (the paper's), or ``tps``, a thin-plate spline
  (Bookstein), smooth across the mesh's triangle edges (:mod:`exprclone.imaging.tps`).
- ``strength``, ``only``, the regions' own strengths (``strength_mouth``, ``strength_eyes``,
  ``strength_brows``) and ``strength_shading`` (not in the paper): how much of the expression
  is transferred, and where (:mod:`exprclone.geometry.weights`).
- ``retarget`` (not in the paper; on by default): the source's expression made as the target's
  own face makes it, learnt from real faces (:mod:`exprclone.geometry.expression_shape`), before
  any global warp, and local re-shaping aimed at it: the target smiles its own smile.
  ``retarget=False`` runs the paper's stages exactly: GI carries the source's motion, LI gives each
  organ the source's organ's height-to-width ratio, the elastic model balances the two.
- ``mouth``, ``landmarker``, ``eigenfaces``, ``layout``: the mouth interior, what places the
  landmarks, the DB metric's basis and the landmarks' layout.
- ``faces``: which faces of a target photo of several take the expression (all by default), each
  cloned in its own region (:mod:`exprclone.pipeline.group`).

The strengths, ``only`` and ``mouth`` are the cheap part (:data:`RENDER`): a prepared clone renders
again with other values of them (:meth:`exprclone.pipeline.cloner.Prepared.render`).

>>> Options().global_stage, Options(global_warp="rbf").global_stage
('similarity', 'rbf')
>>> Options(only="mouth").only
('mouth',)
>>> Options.from_text({"method": "global", "lambda": "0.5"}).lambda_k
0.5
>>> Options(strength=3)
Traceback (most recent call last):
...
exprclone.errors.ExprCloneError: strength: must be a number from 0 to 2, got 3
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..errors import ExprCloneError, quoted
from ..landmarks.backends import DEFAULT, LANDMARKERS, Landmarker
from ..methods import BY_NAME, METHODS, TABLE, Method
from .specs import Choice, Chosen, Page, Spec, given, one_of, option, switch
from .strengths import REGIONS, check_regions, region_spec, strength_spec

if TYPE_CHECKING:
    import numpy as np

    from ..geometry.eigenface import Eigenfaces
    from ..geometry.expression_shape import ExpressionShape
    from ..landmarks.layout import Layout

#: the global warps (``global_warp``); the first is the default, the paper's.
GLOBAL_WARPS = ("similarity", "rbf", "vtc")
#: the global stage's name when GI is given (``global_landmarks``).
GIVEN = "given"
#: the image warps (``image_warp``); the first is the default, the paper's.
IMAGE_WARPS = ("mesh", "tps")
#: the words ``faces`` may be besides face numbers: every face of the photo, or its largest.
FACE_WORDS = ("all", "largest")


def check_lambda(value: Any, name: str = "lambda") -> float | str:
    """``"auto"`` or a number >= 0 (``inf`` allowed: the local result), or ExprCloneError about ``name``."""
    if value != "auto" and (isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0):
        raise ExprCloneError(name, f"must be 'auto' or a number >= 0, got {quoted(value)}")
    return value


def parse_lambda(text: str) -> float | str:
    """lambda_k as a text gives it: ``"auto"`` or a number (:func:`check_lambda` checks it).

    >>> parse_lambda("auto"), parse_lambda("0.5"), parse_lambda("inf")
    ('auto', 0.5, inf)
    """
    if text == "auto":
        return text
    try:
        return float(text)
    except ValueError:
        raise ExprCloneError("lambda", f"must be 'auto' or a number >= 0, got {quoted(text)}") from None


def lambdas() -> tuple[Choice, ...]:
    """The values of lambda_k a page offers: ``auto``, then the candidates the DB metric searches
    (:data:`exprclone.geometry.db_metric.LAMBDAS`)."""
    from ..geometry.db_metric import LAMBDAS  # (numpy: the command line reads the options without it)

    searched = tuple(Choice(f"{lam:g}", "∞" if lam == float("inf") else f"{lam:g}") for lam in LAMBDAS)
    return (Choice("auto", "auto: chosen for these faces", "The program tries each value and keeps the most natural face."), *searched)


def _landmarker(value: Any, name: str) -> str | Landmarker:
    if isinstance(value, str):
        return one_of(LANDMARKERS)(value, name)
    if not callable(getattr(value, "detect", None)):
        raise ExprCloneError(name, f"must be one of {', '.join(LANDMARKERS)} or an object with detect(), got {quoted(value)}")
    return value


def check_faces(value: Any, name: str = "faces") -> str | tuple[int, ...]:
    """``all``, ``largest``, or face numbers from 1 (a comma-separated string is split), sorted without repeats; or
    ExprCloneError about ``name``.

    >>> check_faces("3,1"), check_faces([2]), check_faces(2), check_faces("largest")
    ((1, 3), (2,), (2,), 'largest')
    """
    if value in FACE_WORDS:
        return str(value)
    words = value.split(",") if isinstance(value, str) else [value] if isinstance(value, int) else value
    try:
        numbers = [int(w) if isinstance(w, str) and w.strip().isdigit() else w for w in words]
    except TypeError:
        numbers = []
    chosen = [n for n in numbers if isinstance(n, int) and not isinstance(n, bool) and n >= 1]
    if not numbers or len(chosen) < len(numbers):
        raise ExprCloneError(name, f"must be all, largest or face numbers from 1 (1,3: as exprclone faces lists them), got {quoted(value)}")
    return tuple(sorted(set(chosen)))


#: the landmarkers in a person's words (:data:`~exprclone.landmarks.backends.LANDMARKERS`; one not here is shown by its name).
LANDMARKER_WORDS = {
    "dlib": Choice("dlib", "dlib (its model: non-commercial use only)", "dlib's 68-point model, which may not be used commercially."),
    "mesh": Choice("mesh", "MediaPipe face mesh (Apache-2.0)", "Google's face mesh, free for any use."),
}


@dataclass(frozen=True, eq=False, repr=False)
class Options(Chosen):
    """The options of a clone: every choice a user makes beyond the three photos (see the module's notes).

    Made with keywords (``Options(strength=0.5)``) and checked as it is made; each surface makes it
    from its own input by the adapters of this module. ``dataclasses.replace`` checks again.

    Attributes
    ----------
    method : str
        One of :data:`~exprclone.methods.METHODS`.
    lambda_k : float or "auto"
        The elasticity ratio of Eq. (6); "auto" chooses it by the DB metric (Eq. 8).
    mouth : bool
        Paste the source's mouth interior into an opened mouth (methods with ERI).
    landmarker : str or Landmarker
        What places the landmarks of photos without given ones (:data:`~exprclone.landmarks.backends.LANDMARKERS`).
    global_warp : str
        One of :data:`GLOBAL_WARPS`.
    global_landmarks : ndarray of shape (N, 2) or None
        GI given from outside, in the target photo; replaces ``global_warp``.
    image_warp : str
        One of :data:`IMAGE_WARPS`.
    strength : float
        Within :data:`STRENGTH_RANGE`.
    only : tuple of str or None
        Regions (:data:`REGIONS`) whose motion alone is transferred; None for all.
    strength_mouth, strength_eyes, strength_brows : float or None
        A region's own strength (:attr:`region_strengths`); None: ``strength``.
    strength_shading : float
        A factor on the details' strength (the ERI's exponent), within :data:`STRENGTH_RANGE`.
    retarget : bool
        Make the source's expression the target's own before the global and local stages
        (:mod:`exprclone.geometry.expression_shape`); False: the paper's stages.
    eigenfaces : Eigenfaces or None
        The DB metric's basis; None for the packaged one.
    faces : str or tuple of int
        Which faces of a target photo of several are cloned, each in its own region
        (:mod:`exprclone.pipeline.group`): ``"all"``, ``"largest"``, or their numbers from 1 in reading order.
    layout : Layout or None
        The landmarks' layout; None for dlib's 68 points (:data:`~exprclone.landmarks.layout.DLIB68`).
    expression_shape : ExpressionShape or None
        How a face's neutral shape makes the expression (:mod:`exprclone.geometry.expression_shape`), for
        ``retarget``; None for the model shipped. ``exprclone evaluate --held-out`` gives models learnt without the
        people it clones.

    See Also
    --------
    exprclone.clone : whose result keeps its options (``result.options``).

    Examples
    --------
    >>> Options(strength=0.5, only=("mouth",)).only
    ('mouth',)
    >>> Options(method="e+md", global_warp="rbf").global_stage
    'rbf'
    >>> Options(method="x")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: method: unknown method 'x'; choose one of: global, local, elastic, ..., song
    """

    method: str = option(
        "e+md",
        Spec(
            "the method: one of the paper's Fig. 11, or song, Song et al.'s (Figs. 16-17)",
            one_of(METHODS),
            choices=METHODS,
            page=Page(
                "Method",
                "Which way carries the expression over: the paper's seven, (g) its own, or Song et al.'s, which it is compared with.",
                "method",
                choices=tuple(Choice(m.name, f"({m.panel}) {m.title}" if m.panel else m.title, m.sentence, m.panel or None) for m in TABLE),
            ),
        ),
    )
    lambda_k: float | str = option(
        "auto",
        Spec(
            "the elasticity ratio k_A'/k_N of Eq. (6): auto, chosen by the DB metric (Eq. 8; for a video, the median of"
            " its choices on the 5 most expressive frames), or a number >= 0",
            check_lambda,
            parse_lambda,
            also=(int, float),
            key="lambda",
            metavar="auto|FLOAT",
            schema={"pattern": r"^(auto|inf|[0-9]+(\.[0-9]*)?|\.[0-9]+)$"},
            page=Page(
                "Balance λk",
                "How far the face holds each feature's own new shape against the motion of the whole face: 0 the whole"
                " face's motion alone, ∞ each feature's shape alone.",
                "method",
                choices=lambdas,
            ),
        ),
    )
    mouth: bool = option(
        True,
        switch(
            "paste the source's mouth interior (teeth) into an opened mouth; false leaves the stretched lips",
            "paste no mouth interior: an opened mouth shows the target's lips stretched apart, no teeth",
            flag="--no-mouth",
            page=Page("teeth in an opened mouth", "Where the mouth opens, the source person's teeth show in it."),
        ),
    )
    landmarker: str | Landmarker = option(
        DEFAULT,
        Spec(
            "which landmarker places (and in a video tracks) the landmarks of photos without given ones: dlib, whose"
            " model's licence excludes commercial use, or mesh, MediaPipe's face mesh (Apache-2.0)",
            _landmarker,
            choices=LANDMARKERS,
            surfaces=frozenset({"cli", "form", "json"}),
            page=Page(
                "Landmarks",
                "Which program finds the points of each face (eyes, brows, nose, mouth, jaw).",
                "method",
                choices=tuple(LANDMARKER_WORDS.get(name, Choice(name, name)) for name in LANDMARKERS),
            ),
        ),
    )
    global_warp: str = option(
        GLOBAL_WARPS[0],
        Spec(
            "how the source's motion reaches the target (GI): similarity, the paper's; rbf, by the local Jacobian of a"
            " radial-basis-function map between the two neutral faces (Seol and Lewis; Figs. 19-20); or vtc, each vertex"
            " tent of the landmark mesh changed as the source's (Song et al.; Fig. 17)",
            one_of(GLOBAL_WARPS),
            choices=GLOBAL_WARPS,
            page=Page(
                "Global warp",
                "How the source's motion is fitted to the target's face: as one turn and scaling of the whole face,"
                " bent to the differences between the two faces, or each small patch of it changed as the source's.",
                "transfer",
                (
                    Choice(GLOBAL_WARPS[0], "similarity (Liu et al., the paper's)", "The whole face's motion, turned and scaled as one."),
                    Choice(GLOBAL_WARPS[1], "RBF (Seol and Lewis)", "The motion bent to follow how the two faces differ."),
                    Choice(GLOBAL_WARPS[2], "VTC (Song et al.)", "Each small patch of the face bends as the source's did."),
                ),
                unset=f"default: {GLOBAL_WARPS[0]} (RBF for Figs. 19-21)",
            ),
        ),
    )
    global_landmarks: np.ndarray | None = option(
        None,
        Spec(
            "the target's expression landmarks from any other method (.json or .tem), taken as GI and refined (Fig. 21)",
            given,
            metavar="FILE",
            file=True,
            surfaces=frozenset({"cli", "form"}),
        ),
    )
    image_warp: str = option(
        IMAGE_WARPS[0],
        Spec(
            "how the photo follows its landmarks: mesh, piecewise-affine (the paper's), or tps, a smooth thin-plate spline",
            one_of(IMAGE_WARPS),
            choices=IMAGE_WARPS,
            page=Page(
                "Image warp",
                "How the photo's pixels follow the face's moved points.",
                "transfer",
                (
                    Choice(IMAGE_WARPS[0], "piecewise-affine mesh", "In small flat triangles, each stretched on its own."),
                    Choice(IMAGE_WARPS[1], "thin-plate spline", "Bent smoothly, with no creases along the triangles' edges."),
                ),
            ),
        ),
    )
    strength: float = option(
        1.0,
        strength_spec(
            "how much of the expression to transfer: 0 leaves the target as it is, 1 all of it, up to 2",
            Page("Whole expression", "How much of the expression: 0 the target's own face, 1 all of it, 2 twice.", "strengths", step=0.1),
        ),
    )
    only: tuple[str, ...] | None = option(
        None,
        Spec(
            f"transfer the motion of these regions only (comma-separated: {','.join(REGIONS)}), the others held where they are"
            " (unless given a strength of their own)",
            check_regions,
            also=(list,),
            metavar="REGIONS",
            schema={"pattern": f"^({'|'.join(REGIONS)})(,({'|'.join(REGIONS)}))*$"},
        ),
    )
    strength_mouth: float | None = option(None, region_spec("mouth"))
    strength_eyes: float | None = option(None, region_spec("eyes"))
    strength_brows: float | None = option(None, region_spec("brows"))
    strength_shading: float = option(
        1.0,
        strength_spec(
            "how much of the expression's shading (the ERI's folds and shadows, methods with ERI) goes with its motion: 0"
            " the motion alone, 1 as much as the motion, up to 2",
            Page("Shading (folds and shadows)", "How much of the expression's folds and shadows come with it.", "strengths", step=0.1),
        ),
    )
    retarget: bool = option(
        True,
        switch(
            "this project's addition, not in the paper (on by default): the source's expression made as the target's own"
            " face makes it, learnt from real faces; off (false): the paper's stages exactly (GI carries the source's"
            " motion, LI gives each organ the source organ's height-to-width ratio, the elastic model balances them with"
            " lambda_k chosen by the DB metric)",
            "the paper's stages exactly, without this project's retargeting: GI carries the source's motion as it is, LI"
            " gives each organ the source organ's height-to-width ratio, and the elastic model balances the two (lambda_k"
            " by the DB metric)",
            flag="--no-retarget",
            page=Page(
                "the target's own smile (this project's; unchecked: the paper's stages)",
                "The source's expression made as the target's own face makes it, learnt from real faces (not in the paper);"
                " unchecked, the paper's stages carry the source's motion and its organs' shapes.",
                "transfer",
            ),
        ),
    )
    eigenfaces: Eigenfaces | None = option(
        None,
        Spec(
            "eigenface basis for the DB metric: a .npz, or a folder of photos of one person's expressions to train one on (as"
            " the paper does)",
            given,
            metavar="PATH",
            file=True,
            surfaces=frozenset({"cli"}),
        ),
    )
    faces: str | tuple[int, ...] = option(
        FACE_WORDS[0],
        Spec(
            "which faces of a photo of several take the expression: all, largest, or their numbers (comma-separated, in"
            " reading order as exprclone faces lists them); each is cloned in its own region, the others left as they are",
            check_faces,
            also=(list,),
            metavar="all|largest|N,N",
            schema={"pattern": r"^(all|largest|[0-9]+(,[0-9]+)*)$"},
            surfaces=frozenset({"cli", "form", "manifest"}),
        ),
    )
    layout: Layout | None = option(None, Spec("the landmarks' layout", given, surfaces=frozenset()))
    expression_shape: ExpressionShape | None = option(
        None, Spec("how a face's neutral shape makes the expression, for retarget (the model shipped if None)", given, surfaces=frozenset())
    )

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.global_landmarks is not None and self.global_warp != GLOBAL_WARPS[0]:
            raise ExprCloneError("global_landmarks", f"given landmarks replace the global warp; drop global_warp={self.global_warp!r}")
        own = BY_NAME[self.method].warp  # a method with a global warp of its own (Song et al.'s) takes no other GI
        said = f"method {self.method} warps by its own global warp, {own}"
        if own is not None and self.global_landmarks is not None:
            raise ExprCloneError("global_landmarks", f"{said}; drop the given landmarks")
        if own is not None and self.global_warp not in (GLOBAL_WARPS[0], own):
            raise ExprCloneError("global_warp", f"{said}; drop global_warp={self.global_warp!r}")

    @property
    def global_stage(self) -> str:
        """The global warp that gives GI: :data:`GIVEN` when its landmarks are given, else ``global_warp``."""
        return GIVEN if self.global_landmarks is not None else self.global_warp

    def ran_by(self, method: Method) -> Options:
        """These options as ``method`` ran with them (a result's): its name, and its own global warp, if it has one
        (:attr:`exprclone.methods.Method.warp`), in place of the global stage's; the same value when nothing changes.

        >>> Options(global_warp="rbf").ran_by(BY_NAME["song"])
        Options(method='song', global_warp='vtc')
        """
        changes: dict[str, Any] = {} if self.method == method.name else {"method": method.name}
        if method.warp is not None and self.global_stage != method.warp:
            changes.update(global_warp=method.warp, global_landmarks=None)
        return dataclasses.replace(self, **changes) if changes else self

    @property
    def region_strengths(self) -> dict[str, float]:
        """Each region's strength (:data:`REGIONS`): its own if given, else ``strength``, or 0 for a region that ``only``
        leaves out (``only`` is a shorthand for those zeros).

        >>> Options(strength=0.8, strength_mouth=1.3, strength_eyes=0).region_strengths
        {'mouth': 1.3, 'eyes': 0.0, 'brows': 0.8}
        >>> Options(only="mouth").region_strengths, Options(only="mouth", strength_eyes=0.5).region_strengths
        ({'mouth': 1.0, 'eyes': 0.0, 'brows': 0.0}, {'mouth': 1.0, 'eyes': 0.5, 'brows': 0.0})
        """
        own = {r: getattr(self, f"strength_{r}") for r in REGIONS}
        return {r: s if s is not None else self.strength if self.only is None or r in self.only else 0.0 for r, s in own.items()}

    @property
    def landmarks_layout(self) -> Layout:
        """:attr:`layout`, or dlib's 68 points when it is None."""
        from ..landmarks.layout import DLIB68  # (numpy: the command line reads the options without it)

        return self.layout if self.layout is not None else DLIB68


#: the options a prepared clone renders again with (:meth:`exprclone.pipeline.cloner.Prepared.render`): the cheap part.
RENDER = ("mouth", "strength", "only", "strength_mouth", "strength_eyes", "strength_brows", "strength_shading")
#: the options an expression edit takes from a user (:mod:`exprclone.expressions.editor`: its method, lambda_k and GI are its own).
EDIT = ("landmarker", "image_warp", "mouth", "strength_shading")
