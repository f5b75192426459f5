"""The state of a running ``exprclone serve`` (:class:`Work`): where its work runs, its queue, edits and live sessions.

Kept below the application and its routes (:mod:`exprclone.server.app`, :mod:`exprclone.server.routers`), which reach
it through the FastAPI dependency :data:`Server`.
"""

from __future__ import annotations

import asyncio
from collections import Counter
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

from fastapi import Depends
from starlette.requests import HTTPConnection

from ..settings import Settings
from .edits import Edit, Editing, Edits
from .hosts import Hosts
from .limits import Gate
from .processes import Processes

if TYPE_CHECKING:
    from .cluster import Cluster

T = TypeVar("T")


class Work:
    """The server's state: where its clone and video work runs (:attr:`backend`), the work queue's gate, the edits, the
    expression editor's photos and the live sessions.

    Attributes
    ----------
    backend : Processes or Cluster
        The server's own worker processes (:class:`~exprclone.server.runtime.processes.Processes`), or with
        ``settings.scheduler`` a Dask cluster (:class:`~exprclone.server.runtime.cluster.Cluster`).
    """

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self.gate = Gate(settings.workers + settings.queue, settings.workers, settings.max_requests_per_client)
        self.backend: Processes | Cluster
        if settings.scheduler is None:
            self.backend = Processes(settings, self.gate)
        else:
            from .cluster import Cluster  # (Dask, an extra, is loaded only by a server that uses it)

            self.backend = Cluster(settings, self.gate)
        self.edits: Edits[Edit] = Edits(settings.max_edits, settings.edit_ttl, settings.max_edits_per_client)
        self.editors: Edits[Editing] = Edits(settings.max_edits, settings.edit_ttl, settings.max_edits_per_client)  # the editor's photos
        self.renders = ThreadPoolExecutor(settings.workers, thread_name_prefix="render")  # edits render in this process
        self.live_sessions: Counter[str] = Counter()  # by client
        self.live_hosts = Hosts(settings.max_live)

    async def start(self) -> None:
        """Start the workers now (each loads the models as it starts), or connect to the cluster."""
        await self.backend.start()

    async def run(self, client: str, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` in a clone worker, past the gate as ``client``'s request (a full gate, or a worker that
        stops: 503; the client's share of it: 429)."""
        return await self.backend.run(client, function, *args)

    async def render(self, client: str, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` on a render thread of this process (an edit's render, which holds its prepared clone), past
        the gate as ``client``'s request."""
        with self.gate.entered(client):
            return await asyncio.get_running_loop().run_in_executor(self.renders, function, *args)

    async def problems(self) -> list[str]:
        """Why the server cannot serve a request now (none when it can): its workers' or its cluster's."""
        return await self.backend.problems()

    async def close(self) -> None:
        """Stop the workers (or leave the cluster) and the live hosts. The requests have been answered by then (uvicorn
        waits for them)."""
        await self.backend.close()
        self.live_hosts.close()
        self.renders.shutdown(wait=False, cancel_futures=True)


def the_server(connection: HTTPConnection) -> Work:
    """The server's state (:class:`Work`, made when it starts), for a route or a WebSocket: a FastAPI dependency."""
    work: Work = connection.app.state.work
    return work


#: a route's parameter for the server's state (:func:`the_server`).
Server = Annotated[Work, Depends(the_server)]
