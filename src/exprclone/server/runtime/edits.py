"""Edits: a clone prepared once on the server and rendered again with other strengths as a user drags a slider; and
a photo prepared once for the expression editor, rendered again with other controls' values (:class:`Editing`).

``POST /api/edits`` prepares the clone (:func:`exprclone.prepare`: the landmarks, the
expression, the lambda search, the ERI's inputs) in a clone worker, twice: at the target
photo's size and at a preview size (its longest side :data:`PREVIEW`, with the landmarks
and lambda_k of the first, so that both show the same clone). The web process keeps both
(:class:`Edit`), and ``POST /api/edits/{id}/render`` renders one of them with the cheap
options (:data:`exprclone.options.RENDER`: the strengths, ``only``, ``mouth``) on a thread
of its own: tens of milliseconds at the preview's size, against seconds for a clone.

Bounds: at most ``Settings.max_edits`` edits are kept (another is refused with 503 and
``Retry-After``), and ``Settings.max_edits_per_client`` of one client (then 429: one client
renewing its edits cannot keep the others out), each until ``Settings.edit_ttl`` seconds pass
without a render, or its ``DELETE``; ids are random (128 bits), as the video jobs' are.
"""

from __future__ import annotations

import dataclasses
import math
import secrets
import threading
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, Protocol, TypeVar

from ...errors import quoted
from ...io.images import encode_image
from ...io.record import result_record
from .jobs import JOB_ID, NoSuchJob
from .limits import Busy, share

if TYPE_CHECKING:
    from ...expressions.editor import Editor
    from ...pipeline.cloner import Prepared
    from ...pipeline.group import Group
    from ...pipeline.result import CloneResult

#: the preview's longest side, pixels.
PREVIEW = 512


class NoSuchEdit(NoSuchJob):
    """An edit id that is malformed, unknown or expired: answered 404."""


@dataclass
class Edit:
    """One prepared clone: at the target's size and at the preview's, its method, and what its record says of its inputs.

    Attributes
    ----------
    full, preview : Prepared or Group
        The clone prepared at the target photo's size, and at the preview's (the same object when the photo is no larger,
        or shows several faces).
    inputs : dict of str to str
        What each photo was, for the record (:func:`exprclone.server.work.inputs_of`).
    landmarker : str or None
        Which landmarker placed landmarks, for the record.
    client : str
        Whose it is (:mod:`exprclone.server.runtime.clients`).
    used : float
        When it was made or last rendered (``time.time()``).
    """

    full: Prepared | Group
    preview: Prepared | Group
    inputs: dict[str, str]
    landmarker: str | None
    client: str = ""
    used: float = field(default_factory=time.time)

    def render(self, preview: bool, changes: dict[str, Any]) -> CloneResult:
        """Its method's result, the preview or at the target's size, with ``changes`` to its options (of the cheap part)."""
        prepared = self.preview if preview else self.full
        (result,) = prepared.render(**changes).values()
        return result

    def answer(self, preview: bool, changes: dict[str, Any], extension: str, record: bool) -> tuple[bytes, dict[str, Any] | None]:
        """:meth:`render`, encoded as a file of ``extension`` (:func:`exprclone.io.images.encode_image`), and if asked its
        JSON record (:func:`exprclone.io.record.result_record`), as ``POST /api/clone`` gives them."""
        result = self.render(preview, changes)
        said = result_record(dataclasses.replace(result, landmarker=self.landmarker), self.inputs) if record else None
        return encode_image(result.image, extension), said


@dataclass
class Editing:
    """One photo prepared for the expression editor (``POST /api/editor``): at the photo's size and at the preview's.

    Attributes
    ----------
    full, preview : Editor
        The photo's editor (:class:`exprclone.expressions.editor.Editor`) at its size, and at the preview's (the same
        object when the photo is no larger).
    client : str
        Whose it is (:mod:`exprclone.server.runtime.clients`).
    used : float
        When it was made or last rendered (``time.time()``).
    """

    full: Editor
    preview: Editor
    client: str = ""
    used: float = field(default_factory=time.time)

    def answer(self, preview: bool, values: dict[str, float], extension: str) -> bytes:
        """The photo with the controls at ``values``, the preview or at its size, encoded as a file of ``extension``."""
        return encode_image((self.preview if preview else self.full).render(values).image, extension)


class Kept(Protocol):
    """What the server keeps for a client to render again: whose it is, and when it was last used."""

    client: str
    used: float


K = TypeVar("K", bound=Kept)


class Edits(Generic[K]):
    """The server's edits (or the editor's photos): at most ``limit`` kept, and ``per_client`` of one client, each until
    ``ttl`` seconds pass without a render."""

    def __init__(self, limit: int, ttl: float, per_client: int | None = None) -> None:
        self.limit, self.ttl, self.per_client = limit, ttl, per_client or limit
        self._edits: dict[str, K] = {}
        self._lock = threading.Lock()  # renders look edits up from threads

    def add(self, edit: K) -> str:
        """Keep ``edit``; its id. :class:`Busy` when ``limit`` are kept already, :class:`~exprclone.server.runtime.limits.TooMany`
        when ``per_client`` of its client's are. ``Retry-After``: when the least recently used may expire (if it is not
        rendered again)."""
        with self._lock:
            now = time.time()
            self._expire(now)
            own = [e.used for e in self._edits.values() if e.client == edit.client]
            if len(self._edits) >= self.limit:
                wait = max(1, math.ceil(min(e.used for e in self._edits.values()) + self.ttl - now))
                raise Busy(f"{self.limit} edits are kept; try again in {wait} s (when the least recently used expires)", wait)
            if len(own) >= self.per_client:
                wait = max(1, math.ceil(min(own) + self.ttl - now))
                raise share(self.per_client, "edits", wait, "its least recently used expires, or it deletes one")
            edit_id = secrets.token_hex(16)
            self._edits[edit_id] = edit
            return edit_id

    def get(self, edit_id: str) -> K:
        """The edit, its time to live started again; :class:`NoSuchEdit` if there is none by that id."""
        with self._lock:
            self._expire(time.time())
            if not JOB_ID.fullmatch(edit_id) or edit_id not in self._edits:
                raise NoSuchEdit(f"no edit {quoted(edit_id)} (unknown, deleted, or expired after {self.ttl:g} s unused)")
            edit = self._edits[edit_id]
            edit.used = time.time()
            return edit

    def delete(self, edit_id: str) -> None:
        """Forget the edit (:class:`NoSuchEdit` if there is none)."""
        self.get(edit_id)
        with self._lock:
            self._edits.pop(edit_id, None)

    def _expire(self, now: float) -> None:
        for edit_id, edit in list(self._edits.items()):
            if now - edit.used > self.ttl:
                del self._edits[edit_id]
