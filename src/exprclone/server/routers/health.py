"""Whether the server is up and its version (``GET /api/health``, the same as ``/api/health/live``), and whether it can
serve a request now (``GET /api/health/ready``), for a load balancer's or an orchestrator's probes.

Liveness says the process answers: restart it if it does not. Readiness says its work can run: a clone worker ready
(on this machine), or on a Dask cluster the scheduler reached and a worker there; else 503 with what is missing, and
a balancer sends the requests to another replica meanwhile. Neither does any work.
"""

from __future__ import annotations

from fastapi import APIRouter

from ... import __version__
from ..answers import Health, Ready
from ..openapi import errors
from ..runtime.limits import Busy
from ..runtime.state import Server

router = APIRouter(tags=["health"])


@router.get("/api/health")
async def health() -> Health:
    """The server is up: ``{"status": "ok", "version": ...}`` (its liveness, as ``/api/health/live``)."""
    return Health(status="ok", version=__version__)


@router.get("/api/health/live")
async def liveness() -> Health:
    """The server's process answers: ``{"status": "ok", "version": ...}``."""
    return Health(status="ok", version=__version__)


@router.get("/api/health/ready", responses=errors(503))
async def readiness(server: Server) -> Ready:
    """The server can serve a request now: ``{"status": "ready", "version": ...}``; else 503 saying what is missing (no
    worker ready, a worker pool starting again, the cluster's scheduler lost, no worker on the cluster)."""
    problems = await server.problems()
    if problems:
        raise Busy(f"not ready: {'; '.join(problems)}")
    return Ready(status="ready", version=__version__)
