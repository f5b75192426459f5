"""Clones: the source's expression on the target (``POST /api/clone``), the paper's comparison sheets
(``POST /api/compare``), and what the page shows of a photo before: its landmarks and its faces."""

from __future__ import annotations

import base64
from typing import Annotated, Any

from fastapi import APIRouter, Form, Query
from fastapi.responses import JSONResponse, Response

from ...methods import FIGURES
from .. import work
from ..answers import ANSWERS, SHEETS, FacesFound, LandmarksFound, image_answers
from ..openapi import errors
from ..runtime.clients import Client
from ..runtime.state import Server
from .uploads import CloneOptions, CompareOptions, LandmarkerForm, Photo, Uploads, clone_request, read_upload

router = APIRouter(tags=["clone"])


@router.post("/api/landmarks", responses=errors(400, 401, 413, 422, 429, 503))
async def landmarks(server: Server, client: Client, photo: Photo, asked: LandmarkerForm) -> LandmarksFound:
    """The landmarks detected on a photo: ``{"width", "height", "landmarks": [[x, y], ...]}`` (68 points)."""
    upload = await read_upload(photo, "photo")
    found: dict[str, Any] = await server.run(client, work.landmarks, upload, server.settings.max_pixels, asked.options.landmarker)
    return LandmarksFound(**found)


@router.post("/api/faces", responses=errors(400, 401, 413, 422, 429, 503))
async def faces(server: Server, client: Client, photo: Photo, asked: LandmarkerForm) -> FacesFound:
    """Every face of a photo, numbered in reading order as the ``faces`` field of ``/api/clone`` chooses them: ``box``
    ``[left, top, right, bottom]`` in its pixels, ``problem`` why it would be left as it is (empty when it can be
    cloned)."""
    upload = await read_upload(photo, "photo")
    found: dict[str, Any] = await server.run(client, work.faces, upload, server.settings.max_pixels, asked.options.landmarker)
    return FacesFound(**found)


@router.post("/api/clone", responses=image_answers("the result, at the target photo's size", 400, 401, 413, 422, 429, 503))
async def clone(
    server: Server,
    client: Client,
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
    encoded, record = await server.run(client, work.clone, request, extension)
    if format == "json":
        return JSONResponse({**record, "png": base64.b64encode(encoded).decode()})
    return Response(encoded, media_type=media_type)


@router.post("/api/compare", responses=image_answers("the sheet of Figs. 11-13", 400, 401, 413, 422, 429, 503))
async def compare(
    server: Server,
    client: Client,
    uploads: Uploads,
    asked: CompareOptions,
    figure: Annotated[
        str,
        Form(
            description="11: Figs. 11-13 by the paper's stages, the DB curve and its terms, and this project's default below them"
            " unless retarget is false; 16: E+MD beside Song et al.'s method; 17: the elastic model and E+MD on"
            " Song et al.'s global warp; 19: the elastic model on the RBF result (Figs. 19-21)",
            json_schema_extra={"enum": list(FIGURES)},
        ),
    ] = FIGURES[0],
    format: Annotated[str, Query(pattern=f"^({'|'.join(SHEETS)})$", description="png (default), jpeg or webp")] = "png",
) -> Response:
    """Every method of Fig. 11 by the paper's stages, the difference images of Figs. 12-13, the DB curve and its terms,
    and (with ``retarget``, the default) the seven as this project makes them by default below, as one sheet (PNG,
    JPEG or WebP: ``?format=``); or Figs. 16-17 (``figure=16``, ``17``: E+MD beside Song et al.'s method), or Figs. 19-21 (``figure=19``:
    the elastic model on the RBF transfer's result, or on ``global_landmarks``)."""
    request = await clone_request(server, uploads, asked, figure)
    extension, media_type = SHEETS[format]
    sheet = await server.run(client, work.compare, request, extension)
    return Response(sheet, media_type=media_type)
