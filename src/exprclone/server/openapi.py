"""The HTTP API's own documentation: its error answers in the OpenAPI schema, and ``/docs`` and ``/redoc`` offline.

Every error the server gives is JSON ``{"error": "<field>: <problem>"}`` (:class:`ErrorAnswer`);
:func:`errors` declares, route by route, the statuses it can answer with, so that the schema
at ``/openapi.json`` is the HTTP reference. FastAPI's own 422 "validation error" answer is
taken out of the schema: the server answers a request that fails its checks with 400
(:func:`exprclone.server.app.add_error_answers`), never with that body.

The pages ``/docs`` (Swagger UI) and ``/redoc`` (ReDoc) load their scripts, styles and icon
from this server (the files of the ``fastapi-offline`` package), not from a CDN, and no font
from another host: they work with no network. ReDoc's script would show its maker's logo from
a CDN in its footer: the server's copy of the script has that address replaced by an empty
image (which ReDoc then hides), and the pages' policy refuses any other host anyway.
"""

from __future__ import annotations

import functools
import re
from importlib import resources
from pathlib import Path
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import HTMLResponse, Response
from fastapi.staticfiles import StaticFiles
from pydantic import BaseModel

#: what each error status means, in every route that can answer it.
MEANING = {
    400: "a bad parameter, a missing field, or a file that is not an image (or not a video, or not a landmark file)",
    401: "an X-API-Key this server does not know",
    404: "an unknown or expired job (or edit)",
    409: "the job is not done",
    413: "the request is larger than the server's --max-upload-mb",
    422: "a photo or video in which no face is found",
    429: "this client holds its share already (requests at work or waiting, edits or video jobs): retry after the"
    " Retry-After header's seconds",
    503: "the server cannot take the request now (its work queue is full, a worker stopped, no worker is ready, or its"
    " cluster's scheduler is lost; the error says which): retry after the Retry-After header's seconds",
}
#: where the pages' assets are served from.
ASSETS_URL = "/docs-assets"
#: ReDoc's footer logo, which its script would fetch from a CDN (:data:`REDOC_SCRIPT` has it replaced).
REDOC_LOGO = "https://cdn.redoc.ly/redoc/logo-mini.svg"
#: where the server's copy of ReDoc's script, without :data:`REDOC_LOGO`, is served.
REDOC_SCRIPT = "/docs-redoc.js"
#: the pages may load nothing from another host.
POLICY = (
    "default-src 'self'; script-src 'self' 'unsafe-inline'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:;"
    " worker-src 'self' blob:"
)


class ErrorAnswer(BaseModel):
    """The body of every error answer."""

    error: str

    model_config = {
        "json_schema_extra": {"examples": [{"error": "target_neutral: no face found (use a frontal photo, or give its landmarks)"}]}
    }


def errors(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """The ``responses=`` of a route that can answer with these error statuses."""
    return {status: {"model": ErrorAnswer, "description": MEANING[status]} for status in statuses}


def _without_validation_errors(schema: dict[str, Any]) -> dict[str, Any]:
    """The schema with FastAPI's default 422 answers (those not declared by :func:`errors`) and their models removed."""
    for path in schema.get("paths", {}).values():
        for operation in path.values():
            answer = operation.get("responses", {}).get("422", {})
            if "HTTPValidationError" in str(answer.get("content", {})):
                del operation["responses"]["422"]
    models = schema.get("components", {}).get("schemas", {})
    for name in ("HTTPValidationError", "ValidationError"):
        models.pop(name, None)
    return schema


#: a Sphinx role in a docstring (``:mod:`exprclone.data```, ``:class:`~a.B```): its target, and whether only its last name shows.
ROLE = re.compile(r":[a-z]+:`(~?)([^`]+)`")


def markdown(text: str) -> str:
    """A docstring's reStructuredText as the Markdown the schema's readers show: roles as their name in code, double
    backquotes as single.

    >>> markdown("See :mod:`exprclone.data` and :class:`~fastapi.responses.FileResponse`; ``size`` pixels.")
    'See `exprclone.data` and `FileResponse`; `size` pixels.'
    """
    named = ROLE.sub(lambda m: f"`{m[2].rsplit('.', 1)[-1] if m[1] else m[2]}`", text)
    return named.replace("``", "`")


def _in_markdown(node: Any) -> Any:
    """The schema with every description in :func:`markdown`."""
    if isinstance(node, dict):
        return {k: markdown(v) if k == "description" and isinstance(v, str) else _in_markdown(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_in_markdown(v) for v in node]
    return node


def document(app: FastAPI) -> None:
    """The schema as :mod:`exprclone.server.openapi` says, and the offline ``/docs`` and ``/redoc`` pages."""
    make_schema = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            app.openapi_schema = _in_markdown(_without_validation_errors(make_schema()))
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]
    assets = Path(str(resources.files("fastapi_offline") / "static"))
    app.mount(ASSETS_URL, StaticFiles(directory=assets), name="api-docs")
    title = app.title

    @app.get("/docs", include_in_schema=False)
    async def swagger_ui() -> HTMLResponse:
        return _own_only(
            get_swagger_ui_html(
                openapi_url="/openapi.json",
                title=f"{title}: HTTP API",
                swagger_js_url=f"{ASSETS_URL}/swagger-ui-bundle.js",
                swagger_css_url=f"{ASSETS_URL}/swagger-ui.css",
                swagger_favicon_url=f"{ASSETS_URL}/favicon.png",
            )
        )

    @functools.cache
    def redoc_script() -> bytes:  # read when first asked for (1 MB), once
        return (assets / "redoc.standalone.js").read_bytes().replace(REDOC_LOGO.encode(), b"data:,")

    @app.get(REDOC_SCRIPT, include_in_schema=False)
    async def redoc_js() -> Response:
        return Response(redoc_script(), media_type="text/javascript", headers={"Cache-Control": "public, max-age=86400"})

    @app.get("/redoc", include_in_schema=False)
    async def redoc() -> HTMLResponse:
        return _own_only(
            get_redoc_html(
                openapi_url="/openapi.json",
                title=f"{title}: HTTP API",
                redoc_js_url=REDOC_SCRIPT,
                redoc_favicon_url=f"{ASSETS_URL}/favicon.png",
                with_google_fonts=False,
            )
        )


def _own_only(page: HTMLResponse) -> HTMLResponse:
    page.headers["Content-Security-Policy"] = POLICY
    return page
