"""What the HTTP API answers, typed: a pydantic model for each JSON answer (FastAPI checks each answer against it, and
the OpenAPI schema at ``/openapi.json`` shows it), and the answers that are files (an image, a video).

The models of the options' answer (``GET /api/options``) are in :mod:`exprclone.server.described`; every error is an
:class:`~exprclone.server.openapi.ErrorAnswer`.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel

from .. import __version__
from .openapi import errors


class Health(BaseModel):
    """The server is up, and its version."""

    status: Literal["ok"]
    version: str

    model_config = {"json_schema_extra": {"examples": [{"status": "ok", "version": __version__}]}}


class Ready(BaseModel):
    """The server can serve a request now, and its version."""

    status: Literal["ready"]
    version: str

    model_config = {"json_schema_extra": {"examples": [{"status": "ready", "version": __version__}]}}


class ExpressionListed(BaseModel):
    """A built-in expression: its name (the ``expression`` field of ``/api/clone``) and what it is."""

    name: str
    description: str


class Expressions(BaseModel):
    """The built-in expressions."""

    expressions: list[ExpressionListed]


class LandmarksFound(BaseModel):
    """A photo's size and the landmarks of its face, ``[[x, y], ...]`` in its pixels (68 points)."""

    width: int
    height: int
    landmarks: list[list[float]]


class FaceFound(BaseModel):
    """A face of a photo: its number in reading order (the ``faces`` field's), its box, and why it cannot be cloned."""

    number: int
    box: list[float]
    problem: str


class FacesFound(BaseModel):
    """The photo's size and every face of it, in reading order."""

    width: int
    height: int
    faces: list[FaceFound]


class EditorMade(BaseModel):
    """A photo prepared for the expression editor (``POST /api/editor``): its id, where to render it, its sizes, and
    how long it is kept without a render."""

    id: str
    render: str
    width: int
    height: int
    preview_width: int
    preview_height: int
    expires_after: float


class EditMade(EditorMade):
    """A prepared clone (``POST /api/edits``): its id, where to render it, its sizes, lambda_k and the photos' warnings."""

    lambda_k: float | str | None
    warnings: list[str]


class JobMade(BaseModel):
    """A video job started: its id, where to follow its state, and where its result will be."""

    id: str
    status: str
    result: str


class VideoMade(BaseModel):
    """What a done job's worker says of its video: the frames written, the lambda_k used (``"inf"`` for infinity), the
    neutral frame's number (None with a neutral photo) and the frames in which no face was found."""

    frames: int
    lambda_k: float | str | None
    neutral_frame: int | None
    frames_without_face: int


class JobState(BaseModel):
    """A video job's state: queued, running, done or failed; its progress from 0 to 1; its error once failed, and once
    done what its worker said of the video."""

    id: str
    state: Literal["queued", "running", "done", "failed"]
    progress: float
    error: str | None
    info: VideoMade | None


#: the clone's answer by ``format``: the file extension it is encoded as (:func:`exprclone.io.images.encode_image`: PNG at
#: zlib level 1, JPEG and WebP at quality 95) and its media type; ``json`` is the record with the PNG in it.
ANSWERS = {
    "png": (".png", "image/png"),
    "jpeg": (".jpg", "image/jpeg"),
    "webp": (".webp", "image/webp"),
    "json": (".png", "application/json"),
}
#: the compare sheet's answer by ``format``: its file extension and media type.
SHEETS = {name: ANSWERS[name] for name in ("png", "jpeg", "webp")}
#: a video job's result, as a download names it.
MP4 = "exprclone.mp4"


def image_answers(description: str, *statuses: int) -> dict[int | str, dict[str, Any]]:
    """A route's answers when it answers an image (PNG, JPEG or WebP) described so, or an error of ``statuses``."""
    return {200: {"content": {"image/png": {}, "image/jpeg": {}, "image/webp": {}}, "description": description}, **errors(*statuses)}
