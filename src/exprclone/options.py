"""Every option a user can choose, declared once: each a field with its default, its check and its help.

Three values hold them: :class:`Options`, a clone's (its method, lambda_k, warps, strength...);
:class:`Driving`, how a video drives a portrait (its neutral frame, smoothing, head motion);
:class:`Framing`, how a driven video is framed (its size, the driving video beside it). Pure
data, like :mod:`exprclone.methods`: the command line builds its arguments from it
without loading numpy. A value is checked when it is made (a bad value raises
:class:`~exprclone.ExprCloneError` naming the option), so a value that exists is a valid one;
what can only be checked against the photos (``global_landmarks`` inside the target photo) is
checked by the :class:`~exprclone.Cloner`.

Each field's :class:`Spec` says how the option is given outside Python, and every surface turns
its own input into a value through one adapter made from those specs: keywords in Python
(:meth:`Options.of`, :func:`changed`), the words of a command line
(:func:`exprclone.cli.inputs.add_options`), the fields of an HTTP form
(:func:`exprclone.server.forms.options_form`), texts such as a manifest's cells
(:func:`from_text`) and JSON such as a live session's messages (:func:`from_json`). A new
option is one field here, and its use.

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
- ``retarget`` (not in the paper; on by default): the source's motion is cleaned of the
  landmark fitter's scatter and of its lopsided part before any global warp, and local
  re-shaping aims at the target's own organs moved by the source instead of the source's
  organs (:mod:`exprclone.geometry.retarget`). ``retarget=False`` runs the paper's global and local
  stages as they are.
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
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

from .errors import ExprCloneError, quoted
from .landmarks.backends import DEFAULT, LANDMARKERS, Landmarker
from .methods import BY_NAME, METHODS, Method

if TYPE_CHECKING:
    import numpy as np

    from .geometry.eigenface import Eigenfaces
    from .landmarks.layout import Layout

#: the global warps (``global_warp``); the first is the default, the paper's.
GLOBAL_WARPS = ("similarity", "rbf", "vtc")
#: the global stage's name when GI is given (``global_landmarks``).
GIVEN = "given"
#: the image warps (``image_warp``); the first is the default, the paper's.
IMAGE_WARPS = ("mesh", "tps")
#: the regions ``only`` may name (:attr:`exprclone.landmarks.layout.Layout.regions` of the 68-point layout).
REGIONS = ("mouth", "eyes", "brows")
#: the strengths allowed: 0 leaves the target as it is, 1 is the whole expression, 2 twice its motion.
STRENGTH_RANGE = (0.0, 2.0)
#: where an option may be offered outside Python: the command line, an HTTP form, a JSON message (live), a manifest's cell.
SURFACES = frozenset({"cli", "form", "json", "manifest"})


@dataclass(frozen=True)
class Spec:
    """How one option is given outside Python, and how it is checked.

    Attributes
    ----------
    help : str
        What it does, for the command line's help, the HTTP API's documentation and the docs.
    check : callable
        ``check(value, name)``: the value as the option holds it, or ExprCloneError about ``name``.
    parse : callable or None
        ``parse(text)``: the value a text gives (a command line's word, a form field, a manifest's cell);
        None when the text is the value.
    kind : type
        What a form or a JSON message gives: ``str``, ``bool``, ``int`` or ``float``; text for ``str``,
        which ``parse`` reads.
    also : tuple of type
        Other JSON types a message may give it as (its value itself: ``"lambda": 0.5``, ``"only": ["mouth"]``).
    choices : tuple of str or None
        The values allowed, when they are a list of names.
    key : str or None
        Its name in forms, JSON and manifests when it is not the field's (``lambda``).
    flag : str or None
        Its command line flag when it is not ``--`` and the key with dashes (``--no-mouth``).
    metavar : str or None
        What the command line's help shows for its value.
    file : bool
        Given outside Python as a file (landmarks, an eigenface basis), which the surface reads.
    surfaces : frozenset of str
        Where it is offered (:data:`SURFACES`); nowhere but in Python when empty.
    schema : dict
        What a form field's value meets beyond its kind, in JSON Schema's words (``pattern``, ``minimum``...), for
        an HTTP API's schema; the check still decides.
    """

    help: str
    check: Callable[[Any, str], Any]
    parse: Callable[[str], Any] | None = None
    kind: type = str
    also: tuple[type, ...] = ()
    choices: tuple[str, ...] | None = None
    key: str | None = None
    flag: str | None = None
    metavar: str | None = None
    file: bool = False
    surfaces: frozenset[str] = SURFACES
    schema: Mapping[str, Any] = dataclasses.field(default_factory=dict)


def option(default: Any, spec: Spec) -> Any:
    """A field of :class:`Options`: its default, and its :class:`Spec` in the field's metadata."""
    return dataclasses.field(default=default, metadata={"spec": spec})


def _one_of(choices: tuple[str, ...]) -> Callable[[Any, str], str]:
    def check(value: Any, name: str) -> str:
        if value not in choices:
            raise ExprCloneError(name, f"unknown {name.replace('_', ' ')} {quoted(value)}; choose one of: {', '.join(choices)}")
        return str(value)

    return check


def check_boolean(value: Any, name: str) -> bool:
    if type(value).__name__ not in ("bool", "bool_"):  # numpy's bool_ too
        raise ExprCloneError(name, f"must be True or False, got {quoted(value)}")
    return bool(value)


def _number(text: str) -> float:
    """A number, as a text gives it."""
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"expected a number, got {quoted(text)}") from None


def parse_boolean(text: str) -> bool:
    """``true``/``false`` (``1``/``0``, ``yes``/``no``), as forms and manifests write them."""
    words = {"true": True, "1": True, "yes": True, "false": False, "0": False, "no": False}
    if text.strip().lower() not in words:
        raise ValueError(f"expected true or false, got {quoted(text)}")
    return words[text.strip().lower()]


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


def _strength(value: Any, name: str) -> float:
    low, high = STRENGTH_RANGE
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise ExprCloneError(name, f"must be a number from {low:g} to {high:g}, got {quoted(value)}")
    return float(value)


def _region_strength(value: Any, name: str) -> float | None:
    return None if value is None else _strength(value, name)


def _strength_spec(help: str, check: Callable[[Any, str], Any] = _strength) -> Spec:
    """The spec of a strength (``strength``, a region's, the shading's): a number within :data:`STRENGTH_RANGE`."""
    schema = {"minimum": STRENGTH_RANGE[0], "maximum": STRENGTH_RANGE[1]}
    return Spec(help, check, _number, float, also=(int,), metavar="S", schema=schema)


def _region_spec(region: str) -> Spec:
    """The spec of a region's own strength (``strength_mouth``...): None follows ``strength``."""
    return _strength_spec(
        f"the strength of the {region} alone (motion and shading), from 0 (the target's own {region}) to 2; by default the strength",
        _region_strength,
    )


def check_regions(only: Any, name: str = "only", regions: tuple[str, ...] = REGIONS) -> tuple[str, ...] | None:
    """``only`` as a tuple of known region names without repeats (a comma-separated string is split), or None for all
    (also when it names every region: the whole face)."""
    if only is None:
        return None
    names = tuple(n.strip() for n in only.split(",")) if isinstance(only, str) else tuple(only)
    bad = [n for n in names if n not in regions]
    if not names or bad:
        raise ExprCloneError(name, f"unknown region {quoted(bad[0] if bad else '')}; choose from: {', '.join(regions)}")
    return None if set(names) == set(regions) else tuple(dict.fromkeys(names))


def _landmarker(value: Any, name: str) -> str | Landmarker:
    if isinstance(value, str):
        return _one_of(LANDMARKERS)(value, name)
    if not callable(getattr(value, "detect", None)):
        raise ExprCloneError(name, f"must be one of {', '.join(LANDMARKERS)} or an object with detect(), got {quoted(value)}")
    return value


def _given(value: Any, name: str) -> Any:
    """Anything: checked where it is used (``global_landmarks`` against the target photo, ``eigenfaces`` and ``layout``
    by their types)."""
    return value


#: the words ``faces`` may be besides face numbers: every face of the photo, or its largest.
FACE_WORDS = ("all", "largest")


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


class Chosen:
    """What :class:`Options`, :class:`Driving` and :class:`Framing` share: fields made by :func:`option`, each checked by
    its spec as the value is made, the value made from keywords, texts or JSON, and shown by what differs from the
    defaults."""

    def __post_init__(self) -> None:
        checked(self)

    @classmethod
    def of(cls: type[C], base: C | None = None, keywords: Mapping[str, Any] | None = None) -> C:
        """The value of a Python call: ``base`` (the defaults if None), changed by the options given as keywords
        (:func:`changed`: an ExprCloneError about a keyword that is not an option, or a bad value)."""
        return changed(cls, base, keywords or {})

    @classmethod
    def from_text(cls: type[C], given: Mapping[str, str], base: C | None = None) -> C:
        """The value a mapping of texts gives (a manifest's cells, a form's fields: :func:`from_text`)."""
        return from_text(cls, given, base)

    @classmethod
    def from_json(cls: type[C], given: Mapping[str, Any], base: C | None = None) -> C:
        """The value a JSON object gives (a live session's messages: :func:`from_json`)."""
        return from_json(cls, given, base)

    def __repr__(self) -> str:
        return shown(self)


C = TypeVar("C", bound=Chosen)


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
        Make the source's motion the target's before the global and local stages
        (:mod:`exprclone.geometry.retarget`); False: the paper's stages.
    eigenfaces : Eigenfaces or None
        The DB metric's basis; None for the packaged one.
    faces : str or tuple of int
        Which faces of a target photo of several are cloned, each in its own region
        (:mod:`exprclone.pipeline.group`): ``"all"``, ``"largest"``, or their numbers from 1 in reading order.
    layout : Layout or None
        The landmarks' layout; None for dlib's 68 points (:data:`~exprclone.landmarks.layout.DLIB68`).

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
        "e+md", Spec("the method: one of the paper's Fig. 11, or song, Song et al.'s (Figs. 16-17)", _one_of(METHODS), choices=METHODS)
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
        ),
    )
    mouth: bool = option(
        True,
        Spec(
            "paste the source's mouth interior (teeth) into an opened mouth; false leaves the stretched lips",
            check_boolean,
            parse_boolean,
            bool,
            flag="--no-mouth",
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
        ),
    )
    global_warp: str = option(
        GLOBAL_WARPS[0],
        Spec(
            "how the source's motion reaches the target (GI): similarity, the paper's; rbf, by the local Jacobian of a"
            " radial-basis-function map between the two neutral faces (Seol and Lewis; Figs. 19-20); or vtc, each vertex"
            " tent of the landmark mesh changed as the source's (Song et al.; Fig. 17)",
            _one_of(GLOBAL_WARPS),
            choices=GLOBAL_WARPS,
        ),
    )
    global_landmarks: np.ndarray | None = option(
        None,
        Spec(
            "the target's expression landmarks from any other method (.json or .tem), taken as GI and refined (Fig. 21)",
            _given,
            metavar="FILE",
            file=True,
            surfaces=frozenset({"cli", "form"}),
        ),
    )
    image_warp: str = option(
        IMAGE_WARPS[0],
        Spec(
            "how the photo follows its landmarks: mesh, piecewise-affine (the paper's), or tps, a smooth thin-plate spline",
            _one_of(IMAGE_WARPS),
            choices=IMAGE_WARPS,
        ),
    )
    strength: float = option(
        1.0, _strength_spec("how much of the expression to transfer: 0 leaves the target as it is, 1 all of it, up to 2")
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
    strength_mouth: float | None = option(None, _region_spec("mouth"))
    strength_eyes: float | None = option(None, _region_spec("eyes"))
    strength_brows: float | None = option(None, _region_spec("brows"))
    strength_shading: float = option(
        1.0,
        _strength_spec(
            "how much of the expression's shading (the ERI's folds and shadows, methods with ERI) goes with its motion: 0"
            " the motion alone, 1 as much as the motion, up to 2"
        ),
    )
    retarget: bool = option(
        True,
        Spec(
            "make the source's motion the target's: cleaned, each organ keeping the target's own shape; false runs the"
            " paper's global and local stages, the source's motion as it is and its own organ shapes",
            check_boolean,
            parse_boolean,
            bool,
            flag="--no-retarget",
        ),
    )
    eigenfaces: Eigenfaces | None = option(
        None,
        Spec(
            "eigenface basis for the DB metric: a .npz, or a folder of face photos to train one on",
            _given,
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
    layout: Layout | None = option(None, Spec("the landmarks' layout", _given, surfaces=frozenset()))

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
        from .landmarks.layout import DLIB68

        return self.layout if self.layout is not None else DLIB68


def _neutral_frame(value: Any, name: str) -> int | str:
    if value in ("closed", "first") or (isinstance(value, int) and not isinstance(value, bool) and value >= 0):
        return value
    raise ExprCloneError(name, f"must be closed, first or a frame number >= 0, got {quoted(value)}")


def _frame_text(text: str) -> int | str:
    """``closed``, ``first`` or a frame number, as a text gives it."""
    if text in ("closed", "first"):
        return text
    if not text.isdigit():
        raise ValueError(f"expected closed, first or a frame number >= 0, got {quoted(text)}")
    return int(text)


@dataclass(frozen=True, repr=False)
class Driving(Chosen):
    """How a performance drives the portrait, beyond the clone's options (:func:`exprclone.drive.prepare`).

    Examples
    --------
    >>> Driving().neutral_frame, Driving.from_text({"neutral_frame": "12"}).neutral_frame
    ('closed', 12)
    """

    neutral_frame: int | str = option(
        "closed",
        Spec(
            "the frame (from 0) with the source's neutral face; closed: the one whose mouth is most closed (expression"
            " motion is measured from it, so parted lips there would make every closing a negative opening); first: the"
            " first frame with a face",
            _neutral_frame,
            _frame_text,
            also=(int,),
            metavar="N|closed|first",
            schema={"pattern": "^(closed|first|[0-9]+)$"},
        ),
    )
    lambda_per_frame: bool = option(
        False,
        Spec(
            "choose lambda_k by the DB metric on every frame (slower)",
            check_boolean,
            parse_boolean,
            bool,
            surfaces=frozenset({"cli", "form"}),
        ),
    )
    smooth: bool = option(
        True,
        Spec(
            "smooth the landmarks over time; false uses the raw per-frame fits",
            check_boolean,
            parse_boolean,
            bool,
            flag="--no-smooth",
            surfaces=frozenset({"cli", "form"}),
        ),
    )
    head_motion: bool = option(
        False,
        Spec(
            "carry the source's head motion over (a similarity of the whole frame)",
            check_boolean,
            parse_boolean,
            bool,
            surfaces=frozenset({"cli", "form"}),
        ),
    )


#: the sizes a video may be asked for: the portrait's longest side, pixels.
SIZE_RANGE = (16, 4096)


def _size(value: Any, name: str) -> int | None:
    low, high = SIZE_RANGE
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high):
        raise ExprCloneError(name, f"must be from {low} to {high} pixels, or full (the portrait's own size), got {quoted(value)}")
    return value


def _size_text(text: str) -> int | None:
    """A size in pixels, or ``full``: the portrait's own."""
    if text == "full":
        return None
    if not text.isdigit():
        raise ValueError(f"expected a number of pixels or full, got {quoted(text)}")
    return int(text)


@dataclass(frozen=True, repr=False)
class Framing(Chosen):
    """How a driven video is framed (:mod:`exprclone.drive.framing`): the portrait's size, the driving video beside it.

    Examples
    --------
    >>> Framing().size, Framing.from_text({"size": "full", "side_by_side": "true"})
    (512, Framing(size=None, side_by_side=True))
    """

    size: int | None = option(
        512,
        Spec(
            "the portrait's longest side in the output, pixels (full: its own size)",
            _size,
            _size_text,
            int,
            metavar="PIXELS",
            schema={"minimum": SIZE_RANGE[0], "maximum": SIZE_RANGE[1]},
            surfaces=frozenset({"cli", "form", "json"}),
        ),
    )
    side_by_side: bool = option(
        False,
        Spec("the driving video beside the result", check_boolean, parse_boolean, bool, surfaces=frozenset({"cli", "form"})),
    )


T = TypeVar("T")


def checked(value: Any) -> None:
    """Check every field of an options value made of :func:`option` fields, in place (its ``__post_init__``)."""
    for f in dataclasses.fields(value):
        object.__setattr__(value, f.name, spec(type(value), f.name).check(getattr(value, f.name), key(type(value), f.name)))


def names(cls: type) -> tuple[str, ...]:
    """The options of ``cls`` (:class:`Options` or another value made of :func:`option` fields), in their order."""
    return tuple(f.name for f in dataclasses.fields(cls))


def spec(cls: type, name: str) -> Spec:
    """The :class:`Spec` of the option ``name`` of ``cls``."""
    found: Spec = {f.name: f for f in dataclasses.fields(cls)}[name].metadata["spec"]
    return found


def key(cls: type, name: str) -> str:
    """The option's name in forms, JSON and manifests (``lambda`` for ``lambda_k``)."""
    return spec(cls, name).key or name


def offered(cls: type, surface: str, chosen: tuple[str, ...] | None = None) -> tuple[str, ...]:
    """The options of ``cls`` that ``surface`` (of :data:`SURFACES`) offers, of ``chosen`` (all by default), in order."""
    return tuple(n for n in (chosen or names(cls)) if surface in spec(cls, n).surfaces)


def changed(cls: type[T], base: T | None, changes: Mapping[str, Any]) -> T:
    """``base`` (the defaults if None) with ``changes`` by option name, checked; ExprCloneError about a name that is not
    an option of ``cls``, or a bad value."""
    unknown = sorted(set(changes) - set(names(cls)))
    if unknown:
        raise ExprCloneError(unknown[0], f"not an option; choose from {', '.join(names(cls))}")
    start = base if base is not None else cls()
    return dataclasses.replace(start, **changes) if changes else start  # type: ignore[type-var]


def from_text(cls: type[T], given: Mapping[str, str], base: T | None = None) -> T:
    """The options of ``cls`` a mapping of texts gives by key (a manifest's cells, a form's fields), each read by its
    :attr:`Spec.parse`; empty texts and keys that are not options are left out, the others as in ``base``."""
    changes = {}
    for name in names(cls):
        text = given.get(key(cls, name))
        if text is None or text == "":
            continue
        parse = spec(cls, name).parse
        try:
            changes[name] = text if parse is None else parse(text)
        except ExprCloneError:
            raise
        except ValueError as e:
            raise ExprCloneError(key(cls, name), str(e)) from None
    return changed(cls, base, changes)


def from_json(cls: type[T], given: Mapping[str, Any], base: T | None = None) -> T:
    """The options of ``cls`` a JSON object gives by key (a live session's messages): a text option may come as text
    or as its value (``"lambda": 0.5``, ``"only": ["mouth"]``); keys that are not options offered to JSON are left out,
    the others as in ``base``."""
    changes = {}
    for name in offered(cls, "json"):
        value = given.get(key(cls, name))
        if value is None:
            continue
        parse = spec(cls, name).parse
        kinds = (spec(cls, name).kind, *spec(cls, name).also)
        if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds):
            raise ExprCloneError(key(cls, name), f"must be {expected(kinds)}, got {quoted(value)}")
        if isinstance(value, str) and parse is not None:
            value = parse(value)
        changes[name] = tuple(value) if isinstance(value, list) else value
    return changed(cls, base, changes)


#: how a JSON type is named in errors.
JSON_NAMES = {str: "a string", bool: "true or false", int: "an integer", float: "a number", list: "a list"}


def expected(kinds: tuple[type, ...]) -> str:
    """What JSON values of ``kinds`` are, for an error: ``a string or a list``."""
    return " or ".join(dict.fromkeys(JSON_NAMES[float if k is int and float in kinds else k] for k in kinds))


def json_kinds(cls: type) -> dict[str, tuple[type, ...]]:
    """The JSON types each option of ``cls`` offered to JSON may come as, by key."""
    return {key(cls, n): (spec(cls, n).kind, *spec(cls, n).also) for n in offered(cls, "json")}


def shown(value: Any) -> str:
    """An options value as its type and the options that are not the defaults: ``Options(method='global', strength=0.5)``."""
    default = type(value)()
    differ = [f"{n}={getattr(value, n)!r}" for n in names(type(value)) if not _same(getattr(value, n), getattr(default, n))]
    return f"{type(value).__name__}({', '.join(differ)})"


def _same(a: Any, b: Any) -> bool:
    return a is b or (type(a) is type(b) and not hasattr(a, "shape") and a == b)


#: the options a prepared clone renders again with (:meth:`exprclone.pipeline.cloner.Prepared.render`): the cheap part.
RENDER = ("mouth", "strength", "only", "strength_mouth", "strength_eyes", "strength_brows", "strength_shading")
