"""Edits: a clone prepared once (``POST /api/edits``), rendered again with other strengths as a user drags a slider
(``POST /api/edits/{id}/render``), forgotten when asked (``DELETE``) or when unused (:mod:`exprclone.server.runtime.edits`)."""

from __future__ import annotations

import base64
from typing import Annotated

from fastapi import APIRouter, Query, Request
from fastapi.responses import JSONResponse, Response

from ...errors import ExprCloneError
from ...io.record import json_number
from ...options import RENDER, Options, key, offered
from .. import work
from ..answers import ANSWERS, EditMade, image_answers
from ..openapi import errors
from ..runtime.clients import Client
from ..runtime.edits import PREVIEW, Edit
from ..runtime.state import Server
from .uploads import CloneOptions, EditId, RenderOptions, Uploads, clone_request

router = APIRouter(tags=["edits"])

#: the form fields of the options fixed when a clone is prepared: a render refuses them (400), rather than ignore them.
PREPARED = tuple(key(Options, name) for name in offered(Options, "form") if name not in RENDER)


@router.post("/api/edits", status_code=201, responses=errors(400, 401, 413, 422, 429, 503))
async def make_edit(server: Server, client: Client, uploads: Uploads, asked: CloneOptions) -> EditMade:
    """Prepare a clone to render again and again with other strengths (sliders): the inputs and options of
    ``/api/clone``; then ``POST /api/edits/{id}/render``. Kept until ``expires_after`` seconds pass without a render
    (or ``DELETE /api/edits/{id}``); a server keeps a bounded number (503 with ``Retry-After`` beyond), and a client
    its share of them (429)."""
    request = await clone_request(server, uploads, asked)
    full, preview, inputs, placed = await server.run(client, work.prepare_edit, request, PREVIEW)
    edit_id = server.edits.add(Edit(full, preview, inputs, placed, client))
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


@router.post("/api/edits/{edit_id}/render", responses=image_answers("the result at the size asked", 400, 401, 404, 413, 422, 429, 503))
async def render_edit(
    server: Server,
    client: Client,
    http: Request,
    edit_id: EditId,
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
    others were fixed when it was prepared, and a render that sends one is refused, 400): tens of milliseconds for a
    preview. At the default strengths, the image of ``/api/clone`` on the same inputs, bit for bit."""
    fixed = [name for name in (await http.form()).keys() if name in PREPARED]
    if fixed:
        raise ExprCloneError(fixed[0], "was fixed when the clone was prepared: prepare it again (POST /api/edits) to change it")
    edit = server.edits.get(edit_id)
    format = format or ("jpeg" if preview else "png")
    extension, media_type = ANSWERS[format]
    changes = {name: getattr(asked.options, name) for name in asked.given}
    encoded, record = await server.render(client, edit.answer, preview, changes, extension, format == "json")
    if record is not None:
        return JSONResponse({**record, "png": base64.b64encode(encoded).decode()})
    return Response(encoded, media_type=media_type)


@router.delete("/api/edits/{edit_id}", status_code=204, responses=errors(404))
async def delete_edit(server: Server, edit_id: EditId) -> Response:
    """Forget a prepared clone (its memory is freed at once rather than when it expires)."""
    server.edits.delete(edit_id)
    return Response(status_code=204)
