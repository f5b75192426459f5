"""Whether the server is up (``GET /api/health``), and its version."""

from __future__ import annotations

from fastapi import APIRouter

from ... import __version__
from ..answers import Health

router = APIRouter(tags=["health"])


@router.get("/api/health")
async def health() -> Health:
    """The server is up: ``{"status": "ok", "version": ...}``."""
    return Health(status="ok", version=__version__)
