"""The web application of ``exprclone serve``: settings, the worker pools, error answers, the page.

Models are loaded once per worker process at start-up (FastAPI's lifespan), CPU work
runs in those processes, never on the event loop, and every error a user can cause is
answered as JSON ``{"error": "<field: problem>"}`` with a 4xx status: 400 for a file
that is not an image or a bad parameter, 401 for an unknown API key, 413 for an upload over
the limit, 422 for a photo or video without a face, 429 (with ``Retry-After``) when a client
holds its share, 503 (with ``Retry-After``) when the work queue is full or no worker can take it.
"""

from __future__ import annotations

import contextlib
import logging
import warnings
from collections.abc import AsyncIterator

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.middleware.cors import CORSMiddleware
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles
from PIL.Image import DecompressionBombWarning
from starlette.exceptions import HTTPException

from .. import __version__
from ..errors import ExprCloneError, NoFaceError
from .openapi import document
from .routers import ROUTERS
from .routers.pages import STATIC
from .runtime.clients import UnknownKey
from .runtime.jobs import JobNotDone, NoSuchJob
from .runtime.limits import Busy, TooMany, UploadLimit
from .runtime.state import Work
from .settings import Settings

log = logging.getLogger("exprclone.server")


def _error(status: int, message: str, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status, headers=headers)


def _shown(part: object, longest: int = 40) -> str:
    """A part of a field's location (a client's JSON key may hold anything) as short text on one line."""
    text = str(part).encode("unicode_escape").decode("ascii")
    return text if len(text) <= longest else f"{text[: longest - 3]}..."


def _validation_message(error: RequestValidationError) -> str:
    """One line naming the first field that failed FastAPI's checks, and why."""
    first = error.errors()[0]
    where = [_shown(part) for part in first.get("loc", ()) if part not in ("body", "query", "path")]
    return f"{'.'.join(where) or 'request'}: {'missing' if first.get('type') == 'missing' else first.get('msg', 'invalid')}"


def add_error_answers(app: FastAPI, statuses: dict[type[Exception], int] | None = None) -> None:
    """Every error as JSON ``{"error": ...}``; nothing a user sends gives a traceback.

    ``statuses``: more exception types, each answered with its own status.
    """
    for kind, status in (statuses or {}).items():
        app.add_exception_handler(kind, lambda request, e, status=status: _error(status, str(e)))
    app.add_exception_handler(NoFaceError, lambda request, e: _error(422, str(e)))
    app.add_exception_handler(UnknownKey, lambda request, e: _error(401, str(e)))
    app.add_exception_handler(ExprCloneError, lambda request, e: _error(400, str(e)))
    app.add_exception_handler(RequestValidationError, lambda request, e: _error(400, _validation_message(e)))
    app.add_exception_handler(Busy, lambda request, e: _error(503, str(e), {"Retry-After": str(e.retry_after)}))
    app.add_exception_handler(TooMany, lambda request, e: _error(429, str(e), {"Retry-After": str(e.retry_after)}))
    app.add_exception_handler(NoSuchJob, lambda request, e: _error(404, str(e)))
    app.add_exception_handler(JobNotDone, lambda request, e: _error(409, str(e)))
    app.add_exception_handler(HTTPException, lambda request, e: _error(e.status_code, str(e.detail), e.headers))

    async def internal(request: Request, e: Exception) -> JSONResponse:
        log.exception("internal error on %s", request.url.path)
        return _error(500, "internal error")

    app.add_exception_handler(Exception, internal)


def create_app(settings: Settings | None = None) -> FastAPI:
    """The application; its workers start (and load the models) when it starts serving."""
    settings = settings or Settings()
    # the photos' sizes are checked against settings.max_pixels before decoding: Pillow's own alarm is only noise in the log
    warnings.filterwarnings("ignore", category=DecompressionBombWarning)

    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        app.state.work = Work(settings)
        await app.state.work.start()
        try:
            yield
        finally:
            await app.state.work.close()

    description = (__doc__ or "").split("\n\n")[1]
    app = FastAPI(title="exprclone", version=__version__, lifespan=lifespan, description=description, docs_url=None, redoc_url=None)
    add_error_answers(app)
    document(app)
    for router in ROUTERS:
        app.include_router(router)
    app.mount("/static", StaticFiles(directory=STATIC), name="static")
    if settings.cors:
        app.add_middleware(CORSMiddleware, allow_origins=list(settings.cors), allow_methods=["GET", "POST"])
    app.add_middleware(UploadLimit, max_bytes=int(settings.max_upload_mb * 2**20))
    return app
