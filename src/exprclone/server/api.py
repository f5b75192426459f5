"""The HTTP API and the page: ``/api/...`` routes, each a thin layer over :mod:`exprclone.server.work`."""

from __future__ import annotations

import base64
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, File, Form, Query, UploadFile
from fastapi.responses import FileResponse, JSONResponse, Response
from pydantic import BaseModel, WithJsonSchema

from .. import __version__, expressions
from .. import data as samples
from ..errors import ExprCloneError, quoted
from ..io.inputs import Source
from ..io.record import json_number
from ..io.video import Limits
from ..methods import FIGURES
from ..options import RENDER, Driving, Framing, Options, names, spec
from ..roles import ROLES, SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL
from . import work
from .edits import PREVIEW, Edit
from .forms import Asked, options_form
from .openapi import errors
from .state import Server

router = APIRouter()

#: the landmark files of a clone, by form field: each photo's role (the form field of the photo) and ``_landmarks``.
LANDMARK_FIELDS = tuple(f"{role}_landmarks" for role in ROLES)
#: the samples the page's "try the sample photos" fetches, by name.
SAMPLES: dict[str, Callable[[], Path]] = {
    SOURCE_NEUTRAL: lambda: samples.path(samples.SOURCE),
    SOURCE_EXPRESSION: lambda: samples.path(samples.SOURCE, "smile"),
    TARGET_NEUTRAL: lambda: samples.path(samples.TARGET),
    "portrait": lambda: samples.path(samples.TARGET),
    "driving_video": samples.clip,
}
#: a video job's result, as a download names it.
MP4 = "exprclone.mp4"
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


async def clone_request(server: Server, uploads: dict[str, Any], asked: Asked, figure: str = FIGURES[0]) -> work.CloneRequest:
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
    return work.CloneRequest(photos, marked, asked.options, server.settings.max_pixels, given, figure, asked.given, expression)


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


@router.get("/", include_in_schema=False)
async def page() -> FileResponse:
    return FileResponse(Path(str(resources.files(__package__) / "static" / "index.html")))


@router.get("/live", include_in_schema=False)
async def live_page() -> FileResponse:
    return FileResponse(Path(str(resources.files(__package__) / "static" / "live.html")))


class Health(BaseModel):
    """The server is up, and its version."""

    status: Literal["ok"]
    version: str

    model_config = {"json_schema_extra": {"examples": [{"status": "ok", "version": __version__}]}}


@router.get("/api/health")
async def health() -> Health:
    """The server is up: ``{"status": "ok", "version": ...}``."""
    return Health(status="ok", version=__version__)


@router.get("/api/samples/{name}", responses=errors(400))
async def sample(name: str) -> FileResponse:
    """A sample shipped in the package (:mod:`exprclone.data`): ``source_neutral``, ``source_expression``,
    ``target_neutral``, ``portrait`` or ``driving_video``."""
    if name not in SAMPLES:
        raise ExprCloneError("sample", f"no sample {name!r}; choose one of {', '.join(SAMPLES)}")
    path = SAMPLES[name]()
    return FileResponse(path, filename=path.name)


@router.get("/api/expressions")
async def expression_names() -> dict[str, list[dict[str, str]]]:
    """The built-in expressions, for the ``expression`` field of ``/api/clone`` and ``/api/compare``:
    ``{"expressions": [{"name", "description"}, ...]}``."""
    return {"expressions": [{"name": name, "description": expressions.load(name).description} for name in expressions.names()]}


@router.post("/api/landmarks", responses=errors(400, 413, 422, 503))
async def landmarks(server: Server, photo: Photo, asked: LandmarkerForm) -> dict[str, Any]:
    """The landmarks detected on a photo: ``{"width", "height", "landmarks": [[x, y], ...]}`` (68 points)."""
    upload = await read_upload(photo, "photo")
    found: dict[str, Any] = await server.run(work.landmarks, upload, server.settings.max_pixels, asked.options.landmarker)
    return found


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


@router.post("/api/faces", responses=errors(400, 413, 422, 503))
async def faces(server: Server, photo: Photo, asked: LandmarkerForm) -> FacesFound:
    """Every face of a photo, numbered in reading order as the ``faces`` field of ``/api/clone`` chooses them: ``box``
    ``[left, top, right, bottom]`` in its pixels, ``problem`` why it would be left as it is (empty when it can be
    cloned)."""
    upload = await read_upload(photo, "photo")
    found: dict[str, Any] = await server.run(work.faces, upload, server.settings.max_pixels, asked.options.landmarker)
    return FacesFound(**found)


async def clone_uploads(
    target_neutral: Photo,
    source_neutral: SourcePhoto = None,
    source_expression: SourcePhoto = None,
    expression: Annotated[
        str | None, Form(description="a built-in expression (GET /api/expressions) instead of source_neutral and source_expression")
    ] = None,
    source_neutral_landmarks: Landmarks = None,
    source_expression_landmarks: Landmarks = None,
    target_neutral_landmarks: Landmarks = None,
    global_landmarks: GlobalLandmarks = None,
) -> dict[str, Any]:
    """The inputs of ``/api/clone`` and ``/api/compare`` by field name: three photos (or the target's and a built-in
    ``expression``), their optional landmark files, the given GI."""
    uploads: dict[str, Any] = dict(zip(ROLES, (source_neutral, source_expression, target_neutral)))
    uploads.update(zip(LANDMARK_FIELDS, (source_neutral_landmarks, source_expression_landmarks, target_neutral_landmarks)))
    uploads.update(global_landmarks=global_landmarks, expression=expression)
    return uploads


Uploads = Annotated[dict[str, Any], Depends(clone_uploads)]


#: the clone's answer by ``format``: the file extension it is encoded as (:func:`exprclone.io.images.encode_image`: PNG at zlib
#: level 1, JPEG and WebP at quality 95) and its media type; ``json`` is the record with the PNG in it.
ANSWERS = {
    "png": (".png", "image/png"),
    "jpeg": (".jpg", "image/jpeg"),
    "webp": (".webp", "image/webp"),
    "json": (".png", "application/json"),
}


def image_answers(description: str, *statuses: int) -> dict[int | str, dict[str, Any]]:
    """A route's answers when it answers an image (PNG, JPEG or WebP) described so, or an error of ``statuses``."""
    return {200: {"content": {"image/png": {}, "image/jpeg": {}, "image/webp": {}}, "description": description}, **errors(*statuses)}


@router.post(
    "/api/clone",
    responses=image_answers("the result, at the target photo's size", 400, 413, 422, 503),
)
async def clone(
    server: Server,
    uploads: Uploads,
    asked: CloneOptions,
    format: Annotated[
        str,
        Query(
            pattern=f"^({'|'.join(ANSWERS)})$",
            description="png (default, lossless), jpeg or webp (quality 95: about a fifth and a seventh of the PNG's bytes;"
            " JPEG the fastest to encode), or json: the record with the PNG as base64",
        ),
    ] = "png",
) -> Response:
    """The source's expression on the target: PNG, JPEG or WebP (``?format=``), or with ``?format=json`` the JSON record of
    ``--save-json`` plus ``png`` (base64).

    The options are those of ``exprclone clone``, by the same names (``lambda`` for ``--lambda``)."""
    request = await clone_request(server, uploads, asked)
    extension, media_type = ANSWERS[format]
    encoded, record = await server.run(work.clone, request, extension)
    if format == "json":
        return JSONResponse({**record, "png": base64.b64encode(encoded).decode()})
    return Response(encoded, media_type=media_type)


class EditMade(BaseModel):
    """A prepared clone (``POST /api/edits``): its id, where to render it, its sizes, lambda_k and the photos' warnings."""

    id: str
    render: str
    width: int
    height: int
    preview_width: int
    preview_height: int
    lambda_k: float | str | None
    expires_after: float
    warnings: list[str]


@router.post("/api/edits", status_code=201, responses=errors(400, 413, 422, 503))
async def make_edit(server: Server, uploads: Uploads, asked: CloneOptions) -> EditMade:
    """Prepare a clone to render again and again with other strengths (sliders): the inputs and options of
    ``/api/clone``; then ``POST /api/edits/{id}/render``. Kept until ``expires_after`` seconds pass without a render
    (or ``DELETE /api/edits/{id}``); a server keeps a bounded number (503 with ``Retry-After`` beyond)."""
    request = await clone_request(server, uploads, asked)
    full, preview, inputs, placed = await server.run(work.prepare_edit, request, PREVIEW)
    edit_id = server.edits.add(Edit(full, preview, inputs, placed))
    (height, width), (preview_height, preview_width) = full.target_size, preview.target_size
    return EditMade(
        id=edit_id,
        render=f"/api/edits/{edit_id}/render",
        width=width,
        height=height,
        preview_width=preview_width,
        preview_height=preview_height,
        lambda_k=json_number(full.lambda_k),
        expires_after=server.settings.edit_ttl,
        warnings=list(full.warnings),
    )


@router.post(
    "/api/edits/{edit_id}/render",
    responses=image_answers("the result at the size asked", 400, 404, 413, 422, 503),
)
async def render_edit(
    server: Server,
    edit_id: str,
    asked: RenderOptions,
    preview: Annotated[
        bool, Query(description=f"true: the preview, its longest side {PREVIEW} pixels; false: the target photo's size")
    ] = True,
    format: Annotated[
        str | None,
        Query(pattern=f"^({'|'.join(ANSWERS)})$", description="as /api/clone's; by default jpeg for a preview, png at full size"),
    ] = None,
) -> Response:
    """The prepared clone rendered with its options changed by the fields given (the strengths, ``only``, ``mouth``: the
    others were fixed when it was prepared): tens of milliseconds for a preview. At the default strengths, the image of
    ``/api/clone`` on the same inputs, bit for bit."""
    edit = server.edits.get(edit_id)
    format = format or ("jpeg" if preview else "png")
    extension, media_type = ANSWERS[format]
    changes = {name: getattr(asked.options, name) for name in asked.given}
    encoded, record = await server.render(edit.answer, preview, changes, extension, format == "json")
    if record is not None:
        return JSONResponse({**record, "png": base64.b64encode(encoded).decode()})
    return Response(encoded, media_type=media_type)


@router.delete("/api/edits/{edit_id}", status_code=204, responses=errors(404))
async def delete_edit(server: Server, edit_id: str) -> Response:
    """Forget a prepared clone (its memory is freed at once rather than when it expires)."""
    server.edits.delete(edit_id)
    return Response(status_code=204)


#: the compare sheet's answer by ``format``: its file extension and media type.
SHEETS = {name: ANSWERS[name] for name in ("png", "jpeg", "webp")}


@router.post(
    "/api/compare",
    responses=image_answers("the sheet of Figs. 11-13", 400, 413, 422, 503),
)
async def compare(
    server: Server,
    uploads: Uploads,
    asked: CompareOptions,
    figure: Annotated[
        str,
        Form(
            description="11: Figs. 11-13 and the DB curve; 19: the elastic model on the RBF result (Figs. 19-21)",
            json_schema_extra={"enum": list(FIGURES)},
        ),
    ] = FIGURES[0],
    format: Annotated[str, Query(pattern=f"^({'|'.join(SHEETS)})$", description="png (default), jpeg or webp")] = "png",
) -> Response:
    """Every method of Fig. 11, the difference images of Figs. 12-13 and the DB curve, as one sheet (PNG, JPEG or WebP:
    ``?format=``); or Figs. 19-21 (``figure=19``: the elastic model on the RBF transfer's result, or on
    ``global_landmarks``)."""
    request = await clone_request(server, uploads, asked, figure)
    extension, media_type = SHEETS[format]
    sheet = await server.run(work.compare, request, extension)
    return Response(sheet, media_type=media_type)


@router.post("/api/video", status_code=202, responses=errors(400, 413, 422, 503))
async def video(
    server: Server,
    portrait: Photo,
    driving_video: Annotated[UploadFile, File(description="a video of the source person (any format FFmpeg reads)")],
    asked: VideoOptions,
    driving: DrivingForm,
    framing: FramingForm,
) -> dict[str, str]:
    """Start a video job: ``202 {"id", "status", "result"}``; follow it at ``/api/jobs/{id}``.

    The options are those of ``exprclone video``, by the same names (``lambda`` for ``--lambda``)."""
    options = asked.options
    photo = await read_upload(portrait, "portrait")
    # a portrait without a face fails now, not in the job
    await server.run(work.landmarks, photo, server.settings.max_pixels, options.landmarker)
    limits = Limits(server.settings.max_pixels, server.settings.max_video_seconds)  # its frames bounded as photos are
    request = work.VideoRequest(photo, options, driving.options, framing.options, limits)
    job_id = await server.backend.submit_video(request, driving_video.file)
    return {"id": job_id, "status": f"/api/jobs/{job_id}", "result": f"/api/jobs/{job_id}/result"}


@router.get("/api/jobs/{job_id}", responses=errors(404))
async def job_state(server: Server, job_id: str) -> dict[str, Any]:
    """A job's ``state`` (queued, running, done, failed), ``progress`` (0 to 1), ``error`` and, once done, ``info``."""
    return await server.backend.video_state(job_id)


@router.get("/api/jobs/{job_id}/result", responses={200: {"content": {"video/mp4": {}}}, **errors(404, 409)})
async def job_result(server: Server, job_id: str) -> Response:
    """The job's MP4 once it is done; 409 with ``{"error"}`` before."""
    state = await server.backend.video_state(job_id)
    if state["state"] != "done":
        return JSONResponse(
            {"error": f"job {job_id}: {state['state']}" + (f" ({state['error']})" if state["error"] else "")}, status_code=409
        )
    result = await server.backend.video_result(job_id)
    if isinstance(result, Path):
        return FileResponse(result, media_type="video/mp4", filename=MP4)
    return Response(result, media_type="video/mp4", headers={"Content-Disposition": f'attachment; filename="{MP4}"'})
