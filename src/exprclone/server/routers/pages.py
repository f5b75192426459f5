"""The pages: the clone page (``/``), the live page (``/live``) and the expression editor's (``/editor``), files of the
package's ``static`` folder, which the application also serves at ``/static`` (their scripts and style)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from fastapi import APIRouter
from fastapi.responses import FileResponse

router = APIRouter()

#: the pages' folder.
STATIC = Path(str(resources.files("exprclone.server") / "static"))


@router.get("/", include_in_schema=False)
async def page() -> FileResponse:
    return FileResponse(STATIC / "index.html")


@router.get("/live", include_in_schema=False)
async def live_page() -> FileResponse:
    return FileResponse(STATIC / "live.html")


@router.get("/editor", include_in_schema=False)
async def editor_page() -> FileResponse:
    return FileResponse(STATIC / "editor.html")
