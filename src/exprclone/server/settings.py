"""How ``exprclone serve`` runs (:class:`Settings`): kept apart from the application, so that the command line reads
its defaults without loading the web framework."""

from __future__ import annotations

import os
from dataclasses import dataclass


@dataclass(frozen=True)
class Settings:
    """How the server runs.

    Attributes
    ----------
    workers : int
        Processes that clone (each loads the models once).
    queue : int
        Requests that may wait for a worker beyond those at work; more are refused (503).
    max_upload_mb : float
        The largest request body.
    max_pixels : int
        The largest photo, in pixels (checked before it is decoded).
    max_jobs : int
        Video jobs kept at once (queued, running, or done and not yet expired).
    job_ttl : float
        Seconds a finished job's result is kept.
    video_workers : int
        Processes that run video jobs (apart from the clone workers, so that a long video does not hold up clones).
    max_live : int
        Live sessions at once (:mod:`exprclone.server.routers.live`; each renders in a process of its own,
        :mod:`exprclone.server.runtime.hosts`).
    live_idle : float
        Seconds a live session may go without a frame before it is closed and its slot freed.
    max_video_seconds : float
        The longest driving video a job takes (read from its headers, and counted as it is decoded).
    max_edits : int
        Prepared clones kept at once for sliders (:mod:`exprclone.server.runtime.edits`).
    edit_ttl : float
        Seconds an edit is kept without a render.
    cors : tuple of str
        Origins allowed to call the API from other pages (none by default).
    scheduler : str or None
        A Dask scheduler's address (``tcp://HOST:8786``, or ``tls://HOST:8786`` with ``tls``): the clone, compare and
        video work runs on its cluster, whose jobs every server started on it shares
        (:mod:`exprclone.server.runtime.cluster`); ``workers`` + ``queue`` then bound the requests at work or waiting on
        the whole cluster, and ``video_workers`` is not used. None: this machine's worker processes.
    tls : tuple of str or None
        The CA certificate, this server's certificate and its private key (PEM files) to reach ``scheduler`` over TLS
        (Dask's ``Security``: the scheduler and workers started with certificates of the same CA); None: no TLS.
    worker_wait : float
        Seconds a request waits for a worker when the Dask cluster has none; then 503, saying so.
    max_requests_per_client, max_edits_per_client, max_jobs_per_client, max_live_per_client : int
        A client's share (:mod:`exprclone.server.runtime.clients`): the requests at work or waiting, edits, video jobs
        and live sessions it may hold at once; beyond, 429 with ``Retry-After`` (the others' requests are served).
    max_faces : int
        The most faces of one photo a request clones (``faces``); more chosen: 400.
    api_keys : frozenset of str
        The SHA-256 digests of the API keys clients may send (:func:`exprclone.server.runtime.clients.read_keys`); none:
        every client is named by its address.
    """

    workers: int = os.cpu_count() or 1
    queue: int = 8
    max_upload_mb: float = 20.0
    max_pixels: int = 25_000_000
    max_jobs: int = 8
    job_ttl: float = 3600.0
    video_workers: int = 1
    max_live: int = 2
    live_idle: float = 30.0
    max_video_seconds: float = 120.0
    max_edits: int = 8
    edit_ttl: float = 600.0
    cors: tuple[str, ...] = ()
    scheduler: str | None = None
    tls: tuple[str, str, str] | None = None
    worker_wait: float = 30.0
    max_requests_per_client: int = 4
    max_edits_per_client: int = 2
    max_jobs_per_client: int = 2
    max_live_per_client: int = 1
    max_faces: int = 16
    api_keys: frozenset[str] = frozenset()
