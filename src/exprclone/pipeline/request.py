"""The front door: one :class:`Request` (the photos, what is known of them, the options), checked once, from which every
surface gets its prepared clone.

Every surface builds the same request: :func:`exprclone.clone` from arrays, the command line,
the server and a batch from files or uploads (:mod:`exprclone.io.inputs`), a driven video
and live mode from a portrait and the frames of a performance. The door then

1. checks it (:meth:`Request.of`: the photos' pixels, given landmarks, the options);
2. places what is not known (:func:`located`: landmarks by the options' landmarker, every
   face of the target photo);
3. checks the roles (:func:`judge_roles`: the source's two photos one person's, its neutral
   one the less expressive), once per photo: what the check takes of a photo is kept with
   it (:meth:`Photo.seen`). A caller who vouches for the roles skips it: by default, one who
   gives every photo's landmarks (the landmarks say the caller has looked at the photos), a
   batch's manifest or a video's frames;
4. makes the two neutral faces (:func:`pair`: the :class:`~exprclone.pipeline.cloner.Cloner`,
   made here and nowhere else) and prepares the expression on them (:func:`prepare`), or each
   face of a target photo of several (:mod:`exprclone.pipeline.group`).

A prepared clone then renders as often as asked (:meth:`~exprclone.pipeline.cloner.Prepared.render`).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ExprCloneError, ExprCloneWarning, NoFaceError
from ..landmarks.backends import name_of, resolve
from ..landmarks.layout import Layout
from ..methods import lookup
from ..options import Options
from ..roles import ROLES, SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from . import group, role_check
from .checks import check_face, check_image, check_points
from .cloner import Cloner, Prepared

#: given landmarks for the three photos (None entries are placed by the landmarker).
Landmarks = tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None]


@dataclass(frozen=True, eq=False)
class Photo:
    """One photo of a request and what is known of it.

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    name : str
        What names it in errors: its role (:data:`~exprclone.roles.ROLES`), or a file the caller read it from.
    points : ndarray of shape (N, 2) or None
        Its face's landmarks, given or placed; None until placed.
    found : tuple of Found or None
        Every face found in it (a target photo), None until looked for.
    """

    image: np.ndarray = field(repr=False)
    name: str
    points: np.ndarray | None = field(default=None, repr=False)
    found: tuple[group.Found, ...] | None = field(default=None, repr=False)
    _seen: dict[int, role_check.Face] = field(default_factory=dict, repr=False)

    def seen(self, layout: Layout) -> role_check.Face:
        """What the role check takes of it (its crop, and its descriptor on first use), made once and kept with it."""
        if id(layout) not in self._seen:
            assert self.points is not None, "placed first (located)"
            self._seen[id(layout)] = role_check.Face.of(self.image, self.points, layout)
        return self._seen[id(layout)]

    def placed(self, points: np.ndarray) -> Photo:
        """The same photo with its landmarks placed."""
        return dataclasses.replace(self, points=points, _seen={})

    def looked(self, found: tuple[group.Found, ...]) -> Photo:
        """The same photo with its faces found."""
        return dataclasses.replace(self, found=found)


@dataclass(frozen=True)
class Request:
    """What a clone needs: the source's two photos (or, for a performance, its neutral face alone), the target's, the
    options, and whether the roles are checked.

    Made by :meth:`of` (arrays) or :func:`exprclone.io.inputs.gather` (files, uploads, built-in expressions): checked
    as it is made.

    Attributes
    ----------
    source_neutral, target : Photo
    source_expression : Photo or None
        None for a performance, whose frames come one by one (:func:`pair`).
    options : Options
    check_roles : bool
        Whether the door checks the photos' roles (:func:`judge_roles`).
    """

    source_neutral: Photo
    source_expression: Photo | None
    target: Photo
    options: Options = Options()
    check_roles: bool = True

    @classmethod
    def of(
        cls,
        source_neutral: np.ndarray,
        source_expression: np.ndarray | None,
        target_neutral: np.ndarray,
        *,
        landmarks: Landmarks | None = None,
        options: Options | None = None,
        target_faces: Sequence[group.Found] | None = None,
        check_roles: bool | None = None,
        **keywords: Any,
    ) -> Request:
        """A request of arrays, checked: the photos ``(H, W, 3)`` uint8 RGB, given landmarks a face inside their photo,
        the options (``options`` changed by ``keywords``); ExprCloneError about the first bad input, its ``subject`` the
        photo's role or the option's name.

        ``check_roles`` None checks them unless every photo's landmarks are given (the caller vouches for them).
        """
        asked = Options.of(options, keywords)
        given = landmarks if landmarks is not None else (None, None, None)
        layout = asked.landmarks_layout
        sn, tn = photo(source_neutral, given[0], ROLES[0], layout), photo(target_neutral, given[2], TARGET_NEUTRAL, layout)
        se = None if source_expression is None else photo(source_expression, given[1], SOURCE_EXPRESSION, layout)
        if target_faces is not None:
            tn = tn.looked(tuple(target_faces))
        vouched = all(p is None or p.points is not None for p in (sn, se, tn))
        return cls(sn, se, tn, asked, not vouched if check_roles is None else check_roles)

    @property
    def photos(self) -> tuple[Photo, ...]:
        """Its photos, in the order of :data:`~exprclone.roles.ROLES` (without the expression of a performance)."""
        return tuple(p for p in (self.source_neutral, self.source_expression, self.target) if p is not None)


def photo(image: np.ndarray, points: np.ndarray | None, name: str, layout: Layout) -> Photo:
    """A photo checked, with its landmarks if given (checked: a face inside it); ExprCloneError about ``name``."""
    image = check_image(image, name)
    if points is not None:
        points = check_face(check_points(points, image.shape, layout.n_points, name), layout, name)
    return Photo(image, name, points)


def place(photo: Photo, options: Options, every: bool = False) -> Photo:
    """The photo with its face's landmarks placed by the options' landmarker (its largest face), or with ``every`` face
    found (a target photo: :func:`exprclone.pipeline.group.find`); as it is if they are known. A photo in which no face
    is found says so, or, under :data:`~exprclone.pipeline.group.MIN_ACROSS` pixels on a side, that it is too small
    (:class:`~exprclone.errors.NoFaceError` either way)."""
    detector, layout = resolve(options.landmarker), options.landmarks_layout
    if photo.points is not None or (every and photo.found is not None):
        return photo
    try:
        if every:
            return photo.looked(group.find(photo.image, detector, photo.name, layout))
        return photo.placed(detector.detect(photo.image, photo.name))
    except NoFaceError:
        height, width = photo.image.shape[:2]
        if min(height, width) < group.MIN_ACROSS:
            problem = f"too small to find a face in ({width}x{height} pixels; at least {group.MIN_ACROSS} on each side needed)"
            raise NoFaceError(photo.name, problem) from None
        raise


def located(request: Request) -> tuple[Request, str | None]:
    """The request with every photo's landmarks placed by its options' landmarker (the target's every face, unless its
    landmarks are given: :func:`place`); and the landmarker's name, None when every landmark was given."""
    options = request.options
    sn, se = (None if p is None else place(p, options) for p in (request.source_neutral, request.source_expression))
    target = place(request.target, options, every=True)
    if target.points is not None:
        group.check_count(options.faces, 1)
    placed = name_of(options.landmarker) if any(p.points is None for p in request.photos) else None
    assert sn is not None
    return dataclasses.replace(request, source_neutral=sn, source_expression=se, target=target), placed


def judge_roles(request: Request) -> tuple[str, ...]:
    """What looks wrong with the request's photos (:func:`exprclone.pipeline.role_check.judge_roles`), none when its
    roles are vouched for; its photos' landmarks placed (:func:`located`)."""
    se = request.source_expression
    if not request.check_roles or se is None:
        return ()
    layout = request.options.landmarks_layout
    return tuple(role_check.judge_roles(request.source_neutral.seen(layout), se.seen(layout), layout, request.target.seen(layout)))


#: why two of the photos being the same one is worth a word: the pair's roles, the one named second first.
SAME_PHOTO = {
    (SOURCE_NEUTRAL, SOURCE_EXPRESSION): "so there is no expression to clone",
    (SOURCE_NEUTRAL, TARGET_NEUTRAL): "so the source's expression goes back onto its own face",
    (SOURCE_EXPRESSION, TARGET_NEUTRAL): "so the target already wears the expression",
}


def same_photos(request: Request) -> tuple[str, ...]:
    """A warning for each two of the request's photos that are the same one (the same pixels: one file given twice),
    naming the second after the first, with what it makes of the clone."""
    photos = [p for p in (request.source_neutral, request.source_expression, request.target) if p is not None]
    said = []
    for k, later in enumerate(photos):
        first = next((p for p in photos[:k] if same_pixels(p.image, later.image)), None)
        if first is not None:
            why = SAME_PHOTO.get((first.name, later.name), "")
            said.append(f"{later.name}: the same photo as {first.name}{', ' + why if why else ''}; is one of them the wrong file?")
    return tuple(said)


#: :func:`same_pixels` compares every this many rows of two photos before the whole.
SAMPLED_ROWS = 16


def same_pixels(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two photos have the same pixels: told apart by a few rows of each first (two photos seldom share them), then
    compared whole.

    Examples
    --------
    >>> a = np.zeros((64, 64, 3), np.uint8)
    >>> b = a.copy()
    >>> b[63, 63, 2] = 1
    >>> same_pixels(a, a.copy()), same_pixels(a, b), same_pixels(a, a[:32])
    (True, False, False)
    """
    return a.shape == b.shape and np.array_equal(a[::SAMPLED_ROWS], b[::SAMPLED_ROWS]) and np.array_equal(a, b)


def pair(request: Request) -> Cloner:
    """The source's neutral face and the target's prepared with the request's options, for many expressions on them
    (a performance's frames, a batch's rows): the one place a :class:`~exprclone.pipeline.cloner.Cloner` is made. The
    landmarks not known are placed (:func:`place`; the target photo's largest face).

    Examples
    --------
    >>> from exprclone import data
    >>> cloner = pair(Request.of(data.photo("126"), None, data.photo("003"), strength=0.5))
    >>> cloner.options.strength, cloner.faces.t_neu.shape
    (0.5, (68, 2))
    """
    sn, tn = (place(p, request.options) for p in (request.source_neutral, request.target))
    assert sn.points is not None and tn.points is not None
    return Cloner(sn.image, sn.points, tn.image, tn.points, request.options)


def prepare(request: Request, methods: tuple[str, ...] | None = None, *, cloner: Cloner | None = None) -> Prepared | group.Group:
    """The request's clone prepared for ``methods`` (the options' ``method`` by default): its landmarks placed, its
    roles checked, the two neutral faces and the expression prepared; a target photo of several faces face by face,
    each chosen face on its own region (:mod:`exprclone.pipeline.group`). What looked wrong is issued as
    :class:`~exprclone.errors.ExprCloneWarning` s and kept in the results.

    ``cloner``: the request's two neutral faces when they have been prepared (:func:`pair`), for many expressions on
    them (a batch's rows): only the expression is prepared, with the cloner's options."""
    if methods is not None:
        lookup(methods)
    if request.source_expression is None:
        raise ExprCloneError(SOURCE_EXPRESSION, "missing: a clone needs the source's expression")
    request, placed = located(request)
    target = request.target
    if target.points is None:
        assert target.found is not None
        chosen = group.choose(target.found, request.options.faces)
        if len(target.found) > 1:
            return _prepare_group(request, chosen, methods, placed)
        request = dataclasses.replace(request, target=target.placed(target.found[0].points))
    return _prepare_one(request, methods, placed, cloner)


def _prepare_one(
    request: Request, methods: tuple[str, ...] | None, placed: str | None, cloner: Cloner | None = None, stacklevel: int = 4
) -> Prepared:
    """One face's clone prepared (:func:`prepare`), on ``cloner``'s faces if they are prepared; what looked wrong with the photos
    issued as warnings (``stacklevel`` as :func:`warnings.warn`'s, from here)."""
    said = same_photos(request) or judge_roles(request)  # (the roles of one photo given twice say nothing more)
    for message in said:
        warnings.warn(message, ExprCloneWarning, stacklevel=stacklevel)
    se = request.source_expression
    assert se is not None and se.points is not None
    prepared = (cloner or pair(request)).prepare(se.image, se.points, methods)
    return dataclasses.replace(prepared, landmarker=placed, warnings=said)


def _prepare_group(request: Request, chosen: tuple[group.Found, ...], methods: tuple[str, ...] | None, placed: str | None) -> group.Group:
    """Several faces' clones prepared (:func:`prepare`), each chosen face's on its region (:mod:`exprclone.pipeline.group`);
    a face that cannot be cloned left as it is, with a warning naming it."""
    options, found = request.options, request.target.found
    assert found is not None
    if options.global_landmarks is not None:
        raise ExprCloneError("global_landmarks", f"one face's, and {TARGET_NEUTRAL} shows {len(found)}: give its landmarks too")
    target, layout = request.target.image, options.landmarks_layout
    said: list[str] = [f"{TARGET_NEUTRAL}: face {f.number}: {f.problem}; left as it is" for f in chosen if f.problem]
    taken = {f.number for f in chosen}
    left = {f.number: f.problem or "not chosen" for f in found if f.problem or f.number not in taken}
    cloned = []
    for face in (f for f in chosen if not f.problem):
        x0, y0, x1, y1 = box = group.region(face.points, target.shape)
        try:
            crop = photo(np.ascontiguousarray(target[y0:y1, x0:x1]), face.points - (x0, y0), TARGET_NEUTRAL, layout)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                one = _prepare_one(dataclasses.replace(request, target=crop), methods, placed)
        except ExprCloneError as e:
            if e.subject != TARGET_NEUTRAL:  # an option's or a source photo's: every face's
                raise
            said.append(f"{TARGET_NEUTRAL}: face {face.number}: {e.problem}; left as it is")
            left[face.number] = e.problem
            continue
        said += [str(w.message) for w in caught if str(w.message) not in said]
        cloned.append((face, box, one))
    for message in said:
        warnings.warn(message, ExprCloneWarning, stacklevel=3)
    weights = group.weights(found, [f for f, _, _ in cloned], [r for _, r, _ in cloned], target.shape)
    chosen_methods = lookup(methods or (options.method,))
    return group.Group(target, found, chosen_methods, options, tuple(cloned), tuple(weights), left, placed, tuple(said))
