"""A Dask cluster as exprclone uses it (``batch --scheduler``, ``serve --scheduler``): a client of its scheduler, and a
worker's memory.

Both commands connect here (:func:`connect`, or :func:`connect_async` from an event loop),
so that Dask missing, or a scheduler that cannot be reached, is the same one-line error
naming ``--scheduler`` everywhere. A cluster whose scheduler and workers were started with TLS
certificates (Dask's ``--tls-ca-file``, ``--tls-cert``, ``--tls-key``) is reached with the
client's own (:func:`security`): it refuses a client without a certificate of its CA.

A clone at 1350 pixels allocates and frees buffers of 22 MB (a float image). glibc's
malloc keeps such buffers in its heap after the first few are freed, unless a
``MALLOC_TRIM_THRESHOLD_`` is set, which freezes its thresholds: every buffer is then
mapped and unmapped again, page by page. Dask's nanny sets it (65536) in every worker
it starts, and a batch ran at 64% of the local pool's speed there (4.4 against 7.0
pairs a second, ``benchmarks/batch.py``). A worker therefore sets the thresholds where
glibc's own adjustment would take them (:func:`keep_buffers`) before its first clone.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os
from collections.abc import Iterator
from types import ModuleType
from typing import Any

from .errors import ExprCloneError

#: seconds to wait for a Dask scheduler.
CONNECT_TIMEOUT = 10
#: glibc's ``mallopt`` parameters (malloc.h) and the largest mmap threshold it accepts on 64-bit
#: systems (its adaptive threshold's ceiling): buffers up to 32 MB stay in the heap.
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD, BUFFER_BYTES = -1, -3, 32 * 1024 * 1024


@contextlib.contextmanager
def _reaching(scheduler: str) -> Iterator[ModuleType]:
    """Dask's ``distributed``, for a block that connects to ``scheduler``: its failure to, an ExprCloneError."""
    try:
        import distributed  # (Dask: an extra)
    except ImportError:
        raise ExprCloneError("--scheduler", "needs Dask: pip install 'exprclone[dask]'") from None
    try:
        yield distributed
    except (OSError, ValueError) as e:
        raise ExprCloneError("--scheduler", f"cannot reach a Dask scheduler at {scheduler} ({e})") from None


def security(scheduler: str, tls: tuple[str, str, str] | None) -> Any:
    """Dask's ``Security`` for a client of ``scheduler`` with ``tls``, the CA's certificate, the client's certificate and
    its key (PEM files; encryption required), or None without; ExprCloneError for a file missing, or a ``tls`` without
    a ``tls://`` address (or the reverse)."""
    if tls is None:
        if scheduler.startswith("tls://"):
            flags = "--tls-ca-file, --tls-cert, --tls-key"
            raise ExprCloneError("--scheduler", f"{scheduler} is a TLS address: give the certificates ({flags})")
        return None
    if not scheduler.startswith("tls://"):
        raise ExprCloneError("--scheduler", f"with certificates, the scheduler's address is tls://HOST:PORT, got {scheduler}")
    for flag, path in zip(("--tls-ca-file", "--tls-cert", "--tls-key"), tls):
        if not os.path.isfile(path):
            raise ExprCloneError(flag, f"{path}: no such file")
    from distributed.security import Security  # (Dask: an extra, checked by _reaching first)

    ca, cert, key = tls
    return Security(tls_ca_file=ca, tls_client_cert=cert, tls_client_key=key, require_encryption=True)


def connect(scheduler: str, tls: tuple[str, str, str] | None = None) -> Any:
    """A ``distributed.Client`` connected to the scheduler at ``scheduler`` (``tcp://HOST:8786``, or ``tls://HOST:8786``
    with ``tls``: :func:`security`), or ExprCloneError."""
    with _reaching(scheduler) as distributed:
        return distributed.Client(scheduler, timeout=CONNECT_TIMEOUT, security=security(scheduler, tls))


async def connect_async(scheduler: str, tls: tuple[str, str, str] | None = None, timeout: float = CONNECT_TIMEOUT) -> Any:
    """:func:`connect`'s client for the running event loop (``asynchronous=True``: its calls are awaited), which fetches
    results from the workers directly, not through the scheduler (a server's are images and videos); given up after
    ``timeout`` seconds."""
    with _reaching(scheduler) as distributed:
        return await distributed.Client(
            scheduler, timeout=timeout, asynchronous=True, direct_to_workers=True, security=security(scheduler, tls)
        )


@functools.cache
def keep_buffers() -> None:
    """Let glibc's malloc keep freed image buffers for the next clone (see the module's notes); nothing elsewhere."""
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:
        return
    libc.mallopt(M_MMAP_THRESHOLD, BUFFER_BYTES)
    libc.mallopt(M_TRIM_THRESHOLD, 2 * BUFFER_BYTES)
