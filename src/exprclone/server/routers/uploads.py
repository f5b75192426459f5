"""What a route reads of its request before any work: the uploads (photos, landmark files) and the options' form
fields, each checked and named by its field."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

from fastapi import Depends, File, Form, UploadFile
from fastapi import Path as InPath
from pydantic import WithJsonSchema

from ... import expressions
from ...errors import ExprCloneError, quoted
from ...io.inputs import Source
from ...methods import FIGURES
from ...options import RENDER, Driving, Framing, Options, names, spec
from ...roles import ROLES, TARGET_NEUTRAL
from .. import work
from ..forms import Asked, options_form
from ..runtime.state import Work

#: the id of a video job, an edit or an editor's photo in a path, as the schema describes it: what the server made is 32 hex digits, and
#: anything else is answered 404 (unknown), as an id it does not know.
ID_LENGTH = {"minLength": 32, "maxLength": 32}
JobId = Annotated[str, InPath(description="the job's id, as POST /api/video answered it", json_schema_extra=ID_LENGTH)]
EditId = Annotated[str, InPath(description="the edit's id, as POST /api/edits answered it", json_schema_extra=ID_LENGTH)]
EditorId = Annotated[str, InPath(description="the photo's id, as POST /api/editor answered it", json_schema_extra=ID_LENGTH)]
#: the landmark files of a clone, by form field: each photo's role (the form field of the photo) and ``_landmarks``.
LANDMARK_FIELDS = tuple(f"{role}_landmarks" for role in ROLES)
#: what the landmark files may be (their client file name's extension is the only part of it used).
LANDMARK_EXTENSIONS = (".json", ".tem")

#: an optional file's schema: a file, not "a file or null" (a form cannot say null; clients would send the text).
MaybeFile = Annotated[UploadFile | None, WithJsonSchema({"type": "string", "contentMediaType": "application/octet-stream"})]
Photo = Annotated[UploadFile, File(description="a photo (JPEG, PNG, ...)")]
SourcePhoto = Annotated[MaybeFile, File(description="a photo of the source person (JPEG, PNG, ...); not with expression")]
Landmarks = Annotated[MaybeFile, File(description='its landmarks: .json ([[x, y], ...] or {"landmarks": ...}) or a .tem template')]
GlobalLandmarks = Annotated[MaybeFile, File(description=spec(Options, "global_landmarks").help)]
#: the clone's options of each route, as form fields (:func:`exprclone.server.forms.options_form`).
CloneOptions = Annotated[Asked, Depends(options_form(Options))]
CompareOptions = Annotated[Asked, Depends(options_form(Options, tuple(n for n in names(Options) if n != "method")))]
VideoOptions = Annotated[Asked, Depends(options_form(Options, tuple(n for n in names(Options) if n not in ("global_landmarks", "faces"))))]
DrivingForm = Annotated[Asked, Depends(options_form(Driving))]
FramingForm = Annotated[Asked, Depends(options_form(Framing))]
LandmarkerForm = Annotated[Asked, Depends(options_form(Options, ("landmarker",)))]
RenderOptions = Annotated[Asked, Depends(options_form(Options, RENDER))]


async def read_optional(upload: UploadFile | None, field: str, extensions: tuple[str, ...] = ()) -> Source | None:
    """An upload's content, None when it was not sent (no part, or an empty one without a file name); for a landmark
    file, its kind from the extension the client gave it (nothing else of a client's file name is used)."""
    if upload is None:
        return None
    content = await upload.read()
    if not content:
        if upload.filename:
            raise ExprCloneError(field, "the file is empty")
        return None
    extension = Path(upload.filename or "").suffix.lower()
    if extensions and extension not in extensions:
        raise ExprCloneError(field, f"a landmark file must be {' or '.join(extensions)}, got {extension or 'no extension'!r}")
    return Source(field, content, extension)


async def read_upload(upload: UploadFile | None, field: str) -> Source:
    """An upload that must be sent (:func:`read_optional`), or ExprCloneError: ``missing``."""
    found = await read_optional(upload, field)
    if found is None:
        raise ExprCloneError(field, "missing")
    return found


async def clone_request(server: Work, uploads: dict[str, Any], asked: Asked, figure: str = FIGURES[0]) -> work.CloneRequest:
    """The checked request: the options checked (by the form), three photos (or the target's and a built-in
    ``expression``, :func:`source_roles`) and any landmark files read."""
    if figure not in FIGURES:
        raise ExprCloneError("figure", f"must be {' or '.join(FIGURES)}, got {quoted(figure)}")
    expression = uploads["expression"]
    roles = source_roles(uploads, expression)
    sn, se = [await read_upload(uploads[role], role) if role in roles else None for role in ROLES[:2]]
    tn = await read_upload(uploads[TARGET_NEUTRAL], TARGET_NEUTRAL)
    marks = [
        await read_optional(uploads[f"{role}_landmarks"], f"{role}_landmarks", LANDMARK_EXTENSIONS) if role in roles else None
        for role in ROLES
    ]
    given = await read_optional(uploads["global_landmarks"], "global_landmarks", LANDMARK_EXTENSIONS)
    photos, marked = (sn, se, tn), (marks[0], marks[1], marks[2])
    settings = server.settings
    return work.CloneRequest(photos, marked, asked.options, settings.max_pixels, given, figure, asked.given, expression, settings.max_faces)


def source_roles(uploads: dict[str, UploadFile | None], expression: str | None) -> tuple[str, ...]:
    """The photos a request must send: all three, or with a built-in ``expression`` (a name of
    :func:`exprclone.expressions.names`) the target's alone (ExprCloneError if the source's photos or landmarks come too)."""
    if expression is None:
        return ROLES
    if expression not in expressions.names():
        raise ExprCloneError(
            "expression", f"unknown expression {expression!r}; the built-in expressions are: {', '.join(expressions.names())}"
        )
    sent = [f for f in ROLES[:2] + LANDMARK_FIELDS[:2] if (upload := uploads[f]) is not None and (upload.filename or upload.size)]
    if sent:
        raise ExprCloneError(sent[0], "not with an expression: a built-in expression takes the place of the source's photos")
    return (TARGET_NEUTRAL,)


async def clone_uploads(
    target_neutral: Photo,
    source_neutral: SourcePhoto = None,
    source_expression: SourcePhoto = None,
    expression: Annotated[
        str | None,
        Form(
            description="a built-in expression (GET /api/expressions) instead of source_neutral and source_expression",
            json_schema_extra={"enum": list(expressions.names())},
        ),
    ] = None,
    source_neutral_landmarks: Landmarks = None,
    source_expression_landmarks: Landmarks = None,
    target_neutral_landmarks: Landmarks = None,
    global_landmarks: GlobalLandmarks = None,
) -> dict[str, Any]:
    """The inputs of ``/api/clone``, ``/api/edits`` and ``/api/compare`` by field name: three photos (or the target's and
    a built-in ``expression``), their optional landmark files, the given GI."""
    uploads: dict[str, Any] = dict(zip(ROLES, (source_neutral, source_expression, target_neutral)))
    uploads.update(zip(LANDMARK_FIELDS, (source_neutral_landmarks, source_expression_landmarks, target_neutral_landmarks)))
    uploads.update(global_landmarks=global_landmarks, expression=expression)
    return uploads


Uploads = Annotated[dict[str, Any], Depends(clone_uploads)]
