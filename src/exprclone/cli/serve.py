"""``exprclone serve``: the web page and the HTTP API (:mod:`exprclone.server`), until Ctrl-C.

Uvicorn serves it, bounded: at most ``--max-connections`` connections and tasks at once (more
are answered 503), idle keep-alive connections closed after ``--keep-alive`` seconds, a
WebSocket message no larger than an upload. Uvicorn has no timeout for a client that sends
its request slowly: a public deployment puts a reverse proxy in front (``deploy/nginx.conf``).
"""

from __future__ import annotations

import argparse
import os

from ..errors import ExprCloneError

#: WebSocket messages a connection may have waiting (each at most an upload's size): the live session keeps only the newest frame.
WS_QUEUE = 4


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    s = sub.add_parser("serve", help="serve the web page and the HTTP API")
    add_address(s)
    s.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="processes that clone (default: the number of cores)")
    s.add_argument("--queue", type=int, default=8, help="requests that may wait for a worker; more are refused with 503 (default: 8)")
    s.add_argument("--max-upload-mb", type=float, default=20.0, help="largest request, in MB (default: 20)")
    s.add_argument(
        "--max-connections", type=int, default=64, help="connections and requests at once; more are refused with 503 (default: 64)"
    )
    s.add_argument("--keep-alive", type=float, default=5.0, help="seconds an idle keep-alive connection is kept open (default: 5)")
    s.add_argument("--cors", action="append", default=[], metavar="ORIGIN", help="let pages from ORIGIN call the API (repeatable)")


def add_address(p: argparse.ArgumentParser) -> None:
    """Where a server listens: ``--host`` and ``--port``."""
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1, this machine only)")
    p.add_argument("--port", type=int, default=8000, help="port (default: 8000)")


def run(args: argparse.Namespace) -> None:
    import uvicorn

    from ..server.app import Settings, create_app

    if args.workers < 1:
        raise ExprCloneError("--workers", f"expected at least 1, got {args.workers}")
    if args.queue < 0:
        raise ExprCloneError("--queue", f"expected 0 or more, got {args.queue}")
    if args.max_upload_mb <= 0:
        raise ExprCloneError("--max-upload-mb", f"expected a positive size, got {args.max_upload_mb:g}")
    if args.max_connections < 1:
        raise ExprCloneError("--max-connections", f"expected at least 1, got {args.max_connections}")
    if not args.keep_alive > 0:
        raise ExprCloneError("--keep-alive", f"expected a positive number of seconds, got {args.keep_alive:g}")
    settings = Settings(workers=args.workers, queue=args.queue, max_upload_mb=args.max_upload_mb, cors=tuple(args.cors))
    print(f"exprclone: serving on http://{args.host}:{args.port}/ ({args.workers} workers; Ctrl-C to stop)", flush=True)
    uvicorn.run(
        create_app(settings),
        host=args.host,
        port=args.port,
        log_level="warning",
        limit_concurrency=args.max_connections,
        timeout_keep_alive=args.keep_alive,
        ws_max_size=int(args.max_upload_mb * 2**20),
        ws_max_queue=WS_QUEUE,
    )
    print("exprclone: stopped", flush=True)
