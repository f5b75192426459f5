"""Edits: a clone prepared once (``POST /api/edits``), rendered again with other strengths as a user drags a slider
(``POST /api/edits/{id}/render``), forgotten when asked (``DELETE``) or when unused (:mod:`exprclone.server.runtime.edits`)."""

from __future__ import annotations

import base64
from typing import Annotated

from fastapi import APIRouter, Query
from fastapi.responses import JSONResponse, Response

from ...io.record import json_number
from .. import work
from ..answers import ANSWERS, EditMade, image_answers
from ..openapi import errors
from ..runtime.edits import PREVIEW, Edit
from ..runtime.state import Server
from .uploads import CloneOptions, RenderOptions, Uploads, clone_request

router = APIRouter(tags=["edits"])


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


@router.post("/api/edits/{edit_id}/render", responses=image_answers("the result at the size asked", 400, 404, 413, 422, 503))
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
