"""A clone's inputs gathered from where a surface gets them: the one place files and uploads become a
:class:`~exprclone.pipeline.request.Request`.

The command line names files, the server receives their bytes, a batch's manifest names files
whose landmarks it has placed: each describes every input as a :class:`Source`, and
:func:`gather` reads them (photos decoded within ``max_pixels``, landmark files read for their
photo's size, a built-in expression's photos and landmarks loaded, the given GI read) into
the request the door checks and prepares (:mod:`exprclone.pipeline.request`).

A process that sees the same photos again (the server's workers) keeps what was found of them
(:class:`Seen`): a photo sent again with another expression is neither decoded nor looked at again,
and the role check's look at it (:meth:`exprclone.pipeline.request.Photo.seen`) is kept with it.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ExprCloneError
from ..expressions import load
from ..landmarks.backends import name_of
from ..options import Options
from ..pipeline import request as door
from ..pipeline.request import Photo, Request
from ..roles import ROLES, SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from .images import load_image
from .landmarks import parse_landmarks, read_landmarks

#: photos whose landmarks a process remembers (:class:`Seen`).
SEEN = 256


@dataclass(frozen=True)
class Source:
    """Where one input comes from: a file, or bytes sent (an upload).

    Attributes
    ----------
    name : str
        What names it in errors and records: the file's path, or the form field it came in.
    content : bytes or None
        What was sent; None: the file at ``name`` is read.
    extension : str
        A landmark file's kind (``.json`` or ``.tem``) when it is sent: the only part of a client's file name used.
    points : ndarray of shape (N, 2) or None
        A photo's landmarks when the surface has placed them (a batch's first pass).
    """

    name: str
    content: bytes | None = None
    extension: str = ""
    points: np.ndarray | None = dataclasses.field(default=None, repr=False)

    def image(self, max_pixels: int | None = None) -> np.ndarray:
        """The photo, ``(H, W, 3)`` uint8 RGB, refused beyond ``max_pixels`` before it is decoded."""
        return load_image(self.name if self.content is None else self.content, name=self.name, max_pixels=max_pixels)

    def landmarks(self, shape: tuple[int, ...]) -> np.ndarray:
        """The landmarks of a landmark file, for a photo of ``shape``."""
        if self.content is None:
            return read_landmarks(self.name, shape)
        return parse_landmarks(self.content.decode("utf-8-sig", errors="replace"), self.extension, shape, name=self.name)


class Seen:
    """The photos a process has seen, by their bytes and the landmarker: each kept as the door placed it (its landmarks,
    its faces), with what the role check took of it; the last :data:`SEEN` of them."""

    def __init__(self) -> None:
        self._photos: OrderedDict[tuple[str, str, str], Photo] = OrderedDict()

    @staticmethod
    def key(source: Source, every: bool, landmarker: str) -> tuple[str, str, str] | None:
        """A sent photo's key (its bytes' SHA-256, whether every face was looked for, the landmarker); None for a file."""
        if source.content is None:
            return None
        return hashlib.sha256(source.content).hexdigest(), str(every), landmarker

    def get(self, key: tuple[str, str, str] | None, name: str) -> Photo | None:
        if key is None or key not in self._photos:
            return None
        self._photos.move_to_end(key)
        return dataclasses.replace(self._photos[key], name=name)

    def keep(self, key: tuple[str, str, str] | None, photo: Photo) -> None:
        if key is not None:
            self._photos[key] = photo
            if len(self._photos) > SEEN:
                self._photos.popitem(last=False)


def gather(
    photos: Sequence[Source | None],
    landmarks: Sequence[Source | None] = (None, None, None),
    options: Options | None = None,
    *,
    expression: str | None = None,
    global_landmarks: Source | None = None,
    max_pixels: int | None = None,
    seen: Seen | None = None,
    check_roles: bool | None = None,
) -> Request:
    """The request of the three photos (:data:`~exprclone.roles.ROLES`; with a built-in ``expression``, the target's
    alone and None for the others), their landmark files (None: placed by the options' landmarker), the options and
    the given GI's file, read.

    With ``seen``, the landmarks of photos sent as bytes are placed here (:func:`placed`), remembered there for the
    next time they are sent. ``check_roles`` as for :meth:`~exprclone.pipeline.request.Request.of`: by default the
    roles are checked unless every photo's landmarks are given, or the source is a built-in expression (the check
    judges the source's two photos, and a built-in pair is shipped as it was made).

    Raises
    ------
    ExprCloneError
        An input that cannot be read, or a photo missing, named as its :class:`Source` names it.
    """
    asked = options or Options()
    read = [None if p is None else photo(p, role, asked, f, max_pixels, seen) for p, f, role in zip(photos, landmarks, ROLES)]
    given = [p is None or f is not None or p.points is not None for p, f in zip(photos, landmarks)]  # (None: the expression's)
    if expression is not None:
        chosen = load(expression)
        read[0] = Photo(chosen.neutral.image, SOURCE_NEUTRAL, chosen.neutral.points)
        read[1] = Photo(chosen.expression.image, SOURCE_EXPRESSION, chosen.expression.points)
    missing = [role for role, p in zip(ROLES, read) if p is None]
    if missing:
        raise ExprCloneError(missing[0], "missing")
    sn, se, tn = read
    assert sn is not None and se is not None and tn is not None
    if global_landmarks is not None:
        asked = dataclasses.replace(asked, global_landmarks=global_landmarks.landmarks(tn.image.shape))
    vouched = expression is not None or all(given)  # (the role check judges the source's pair: a built-in one is shipped)
    return Request(sn, se, tn, asked, not vouched if check_roles is None else check_roles)


def photo(
    source: Source,
    role: str,
    options: Options,
    marks: Source | None = None,
    max_pixels: int | None = None,
    seen: Seen | None = None,
) -> Photo:
    """One photo of a request, named ``role`` in errors: with its landmark file's landmarks (``marks``), or the source's,
    else placed and remembered (:func:`placed`, with ``seen``), else for the door to place."""
    if marks is None and source.points is None and seen is not None:
        return placed(source, options, seen, max_pixels, every=role == TARGET_NEUTRAL, name=role)
    image = source.image(max_pixels)
    points = marks.landmarks(image.shape) if marks is not None else source.points
    return door.photo(image, points, role, options.landmarks_layout)


def placed(
    source: Source, options: Options, seen: Seen, max_pixels: int | None = None, *, every: bool = False, name: str | None = None
) -> Photo:
    """A photo sent as bytes, its face's landmarks placed by the options' landmarker (with ``every``, its every face:
    :func:`exprclone.pipeline.request.place`), or remembered from the last time it was sent (``seen``); named ``name``
    in errors (the source's name by default)."""
    key, name = Seen.key(source, every, name_of(options.landmarker)), name or source.name
    photo = seen.get(key, name)
    if photo is None:
        image = door.photo(source.image(max_pixels), None, name, options.landmarks_layout)
        photo = door.place(image, options, every=every)
        seen.keep(key, photo)
    return photo
