"""The expression editor over HTTP: its controls (``GET /api/editor/controls``), a photo prepared once
(``POST /api/editor``), rendered with the controls' values as a user drags their sliders
(``POST /api/editor/{id}/render``), forgotten when asked (``DELETE``) or when unused
(:class:`exprclone.server.runtime.edits.Editing`). Apart from ``/api/edits``, whose sliders are a clone's strengths."""

from __future__ import annotations

import inspect
from collections.abc import Awaitable, Callable
from typing import Annotated, Any

from fastapi import APIRouter, Depends, Form, Query
from fastapi.responses import Response
from pydantic import BaseModel

from ...errors import naming
from ...expressions.controls import CONTROLS
from ...expressions.editor import SHADING
from ...methods import FIGURES
from ...options import EDIT, Options
from ...roles import TARGET_NEUTRAL
from .. import work
from ..answers import ANSWERS, EditorMade, image_answers
from ..forms import Asked, options_form
from ..openapi import errors
from ..runtime.clients import Client
from ..runtime.edits import PREVIEW, Editing
from ..runtime.state import Server
from .uploads import LANDMARK_EXTENSIONS, EditorId, Landmarks, Photo, read_optional, read_upload

router = APIRouter(tags=["editor"])

#: the options an edit takes, as form fields.
EditorOptions = Annotated[Asked, Depends(options_form(Options, EDIT))]


class ControlListed(BaseModel):
    """A control: its name (its form field), what it does, whether it was learnt from real faces or built from the
    face's anatomy and from what, the region it moves, and the blendshape scores it raises."""

    name: str
    sentence: str
    made: str
    source: str
    region: str
    scores: list[str]


class EditorControls(BaseModel):
    """The editor's controls, each from 0 (the face as it is) to 1."""

    controls: list[ControlListed]


def values_form() -> Callable[..., Awaitable[dict[str, float]]]:
    """A FastAPI dependency reading each control's value from a form field of its name (0 to 1; absent: 0)."""
    parameters = [
        inspect.Parameter(
            c.name,
            inspect.Parameter.KEYWORD_ONLY,
            default=None,
            annotation=Annotated[float | None, Form(ge=0, le=1, description=f"{c.sentence}: 0 (as it is) to 1")],
        )
        for c in CONTROLS
    ]

    async def read(**fields: Any) -> dict[str, float]:
        return {name: float(value) for name, value in fields.items() if value is not None}

    read.__signature__ = inspect.Signature(parameters, return_annotation=dict[str, float])  # type: ignore[attr-defined]
    return read


Values = Annotated[dict[str, float], Depends(values_form())]


@router.get("/api/editor/controls")
async def controls() -> EditorControls:
    """The editor's controls (``exprclone edit --list``): the form fields of ``POST /api/editor/{id}/render``."""
    listed = [ControlListed(**{**c.__dict__, "scores": list(c.scores)}) for c in CONTROLS]
    return EditorControls(controls=listed)


@router.post("/api/editor", status_code=201, responses=errors(400, 401, 413, 422, 429, 503))
async def make_editor(server: Server, client: Client, photo: Photo, asked: EditorOptions, landmarks: Landmarks = None) -> EditorMade:
    """Prepare a photo for the expression editor (its largest face, unless its landmarks are given); then
    ``POST /api/editor/{id}/render`` with the controls' values. Kept until ``expires_after`` seconds pass without a
    render (or ``DELETE /api/editor/{id}``); a server keeps a bounded number (503 with ``Retry-After`` beyond), and a
    client its share of them (429), as the edits of ``/api/edits``."""
    sent = await read_upload(photo, "photo")
    marks = await read_optional(landmarks, "landmarks", LANDMARK_EXTENSIONS)
    request = work.CloneRequest(
        (None, None, sent), (None, None, marks), asked.options, server.settings.max_pixels, None, FIGURES[0], asked.given, SHADING
    )
    with naming({TARGET_NEUTRAL: "photo"}):
        full, preview = await server.run(client, work.prepare_editor, request, PREVIEW)
    editor_id = server.editors.add(Editing(full, preview, client))
    (height, width), (preview_height, preview_width) = (e.cloner.faces.target_image.shape[:2] for e in (full, preview))
    return EditorMade(
        id=editor_id,
        render=f"/api/editor/{editor_id}/render",
        width=width,
        height=height,
        preview_width=preview_width,
        preview_height=preview_height,
        expires_after=server.settings.edit_ttl,
    )


@router.post("/api/editor/{editor_id}/render", responses=image_answers("the photo edited, at the size asked", 400, 401, 404, 413, 429, 503))
async def render_editor(
    server: Server,
    client: Client,
    editor_id: EditorId,
    values: Values,
    preview: Annotated[bool, Query(description=f"true: the preview, its longest side {PREVIEW} pixels; false: the photo's size")] = True,
    format: Annotated[
        str | None,
        Query(pattern="^(png|jpeg|webp)$", description="by default jpeg for a preview, png at full size"),
    ] = None,
) -> Response:
    """The photo with the controls at the values given (those not given at 0): tens of milliseconds for a preview."""
    editing = server.editors.get(editor_id)
    extension, media_type = ANSWERS[format or ("jpeg" if preview else "png")]
    encoded = await server.render(client, editing.answer, preview, values, extension)
    return Response(encoded, media_type=media_type)


@router.delete("/api/editor/{editor_id}", status_code=204, responses=errors(404))
async def delete_editor(server: Server, editor_id: EditorId) -> Response:
    """Forget a photo prepared for the editor."""
    server.editors.delete(editor_id)
    return Response(status_code=204)
