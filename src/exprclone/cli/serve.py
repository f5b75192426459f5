"""``exprclone serve``: the web page and the HTTP API (:mod:`exprclone.server`), until Ctrl-C.

Uvicorn serves it, bounded: at most ``--max-connections`` connections and tasks at once (more
are answered 503), idle keep-alive connections closed after ``--keep-alive`` seconds, a
WebSocket message no larger than an upload. Uvicorn has no timeout for a client that sends
its request slowly: a public deployment puts a reverse proxy in front (``deploy/nginx.conf``),
and names it with ``--forwarded-allow-ips`` so that each client is known by its own address
(no ``X-Forwarded-For`` is believed from anyone else).
"""

from __future__ import annotations

import argparse
from typing import Any

from ..cluster import connect
from ..errors import ExprCloneError
from ..server.settings import Settings
from .inputs import Interrupted

#: WebSocket messages a connection may have waiting (each at most an upload's size): the live session keeps only the newest frame.
WS_QUEUE = 4
#: serve's bounds: flag -> (type, least value, unit, help); each but uvicorn's two (:data:`UVICORN`) is a field of
#: :class:`exprclone.server.settings.Settings` (``--max-megapixels`` its ``max_pixels`` in millions) and takes its default.
BOUNDS: dict[str, tuple[type, float, str, str]] = {
    "workers": (int, 1, "", "processes that clone"),
    "queue": (int, 0, "", "requests that may wait for a worker; more are refused with 503"),
    "max-upload-mb": (float, 0.001, " MB", "largest request"),
    "max-megapixels": (float, 0.001, " megapixels", "largest photo, read from its header before it is decoded"),
    "max-connections": (int, 1, "", "connections and requests at once; more are refused with 503"),
    "keep-alive": (float, 0.001, " s", "how long an idle keep-alive connection is kept open"),
    "max-jobs": (int, 1, "", "video jobs kept at once (queued, running, or done and not yet expired); more are refused with 503"),
    "job-ttl": (float, 1, " s", "how long a finished video job's result is kept"),
    "video-workers": (int, 1, "", "processes that run video jobs"),
    "max-live": (int, 0, "", "live sessions at once, each in a process of its own; 0 turns live mode off"),
    "live-idle": (float, 1, " s", "how long a live session may go without a frame before it is closed and its slot freed"),
    "max-video-seconds": (float, 1, " s", "the longest driving video a job takes (from its headers, and counted as decoded)"),
    "max-edits": (int, 1, "", "prepared clones kept at once for the sliders; more are refused with 503"),
    "edit-ttl": (float, 1, " s", "how long a prepared clone is kept without a render"),
    "max-requests-per-client": (int, 1, "", "requests one client may have at work or waiting; more are refused with 429"),
    "max-edits-per-client": (int, 1, "", "prepared clones one client may keep; more are refused with 429"),
    "max-jobs-per-client": (int, 1, "", "video jobs one client may keep; more are refused with 429"),
    "max-live-per-client": (int, 1, "", "live sessions one client may run at once"),
    "max-faces": (int, 1, "", "faces of one photo a request may clone; more chosen are refused with 400"),
    "worker-wait": (float, 0.001, " s", "with --scheduler: how long a request waits for a worker on a cluster that has none (then 503)"),
}
#: the certificates of a Dask cluster with TLS, by flag (Dask's own flags' names): what each is.
TLS = {"tls-ca-file": "the CA's certificate", "tls-cert": "this server's certificate", "tls-key": "its private key"}
#: the defaults of uvicorn's bounds.
UVICORN = {"max-connections": 64, "keep-alive": 5.0}


def default(flag: str) -> float:
    """The default of one of :data:`BOUNDS`."""
    if flag in UVICORN:
        return UVICORN[flag]
    if flag == "max-megapixels":
        return Settings.max_pixels / 1e6
    value: float = getattr(Settings, flag.replace("-", "_"))
    return value


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    s = sub.add_parser("serve", help="serve the web page and the HTTP API")
    add_address(s)
    add_bounds(s, tuple(BOUNDS))
    s.add_argument("--cors", action="append", default=[], metavar="ORIGIN", help="let pages from ORIGIN call the API (repeatable)")
    s.add_argument(
        "--api-keys",
        metavar="FILE",
        help="API keys clients may send (X-API-Key), one a line: a client with a key has its own share, wherever it connects"
        " from; a key not in FILE is refused (401)",
    )
    s.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="do the clone, compare and video work on this Dask cluster (tcp://HOST:8786, or tls://HOST:8786 with the"
        " certificates below), sharing its jobs with the other servers on it, instead of in local processes; --workers +"
        " --queue then bound the whole cluster's requests",
    )
    for flag, what in TLS.items():
        s.add_argument(f"--{flag}", metavar="FILE", help=f"with a tls:// --scheduler: {what} (PEM; docs/howto/deploy.rst makes them)")


def add_bounds(p: argparse.ArgumentParser, flags: tuple[str, ...]) -> None:
    """The bounds of :data:`BOUNDS` named by ``flags``, each a flag with its default."""
    for flag in flags:
        kind, minimum, unit, text = BOUNDS[flag]
        shown = "the number of cores" if flag == "workers" else f"{default(flag):g}{unit}"  # not the build machine's count
        p.add_argument(f"--{flag}", type=kind, default=default(flag), help=f"{text} (default: {shown})")


def add_address(p: argparse.ArgumentParser) -> None:
    """Where a server listens (``--host`` and ``--port``), and the proxies in front of it it believes
    (``--forwarded-allow-ips``)."""
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1, this machine only)")
    p.add_argument("--port", type=port, default=8000, help="port (default: 8000)")
    p.add_argument(
        "--forwarded-allow-ips",
        metavar="ADDRESSES",
        help="the reverse proxies (comma-separated addresses or networks, e.g. 127.0.0.1) whose X-Forwarded-For names the"
        " client; by default no one's is believed, and a client is known by the address it connects from",
    )


#: the ports a server may listen on.
PORTS = (1, 65535)


def port(text: str) -> int:
    """An argparse type: a port number within :data:`PORTS` (beyond them, the socket's own error was a long traceback)."""
    low, high = PORTS
    if not text.strip().isdigit() or not low <= int(text) <= high:
        raise argparse.ArgumentTypeError(f"expected a port number from {low} to {high}, got {text!r}")
    return int(text)


def server_packages() -> None:
    """ExprCloneError unless the web server's packages are installed (FastAPI, uvicorn, ...: exprclone's own
    dependencies, missing only from an install without them, ``pip install --no-deps``)."""
    try:
        import fastapi  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as e:
        missing = f"needs the web server's packages ({e.name} is missing): pip install exprclone installs them"
        raise ExprCloneError("serve", missing) from None


def check_bounds(args: argparse.Namespace, flags: tuple[str, ...]) -> None:
    """ExprCloneError naming the first of the bounds ``flags`` given below its least value (NaN too)."""
    for flag in flags:
        _, minimum, unit, _ = BOUNDS[flag]
        value = getattr(args, flag.replace("-", "_"))
        if not value >= minimum:
            raise ExprCloneError(f"--{flag}", f"expected at least {minimum:g}{unit}, got {value:g}")


def connection_bounds(args: argparse.Namespace) -> dict[str, Any]:
    """uvicorn's bounds on connections (:data:`UVICORN`'s flags): at most so many at once, idle keep-alive closed; and
    whose ``X-Forwarded-For`` it believes (``--forwarded-allow-ips``: no one's by default, not even this machine's)."""
    proxies = args.forwarded_allow_ips
    return {
        "limit_concurrency": args.max_connections,
        "timeout_keep_alive": args.keep_alive,
        "proxy_headers": proxies is not None,
        "forwarded_allow_ips": proxies or "",
    }


def listen(app: Any, args: argparse.Namespace, said: str, **options: Any) -> None:
    """Serve ``app`` with uvicorn on ``args.host`` and ``args.port``, within the connection bounds; print ``said`` once it
    answers (its start-up done: the workers ready, the port bound), and "stopped" when it stops (after Ctrl-C,
    :class:`~exprclone.cli.inputs.Interrupted`). ExprCloneError if it cannot start (the port in use: uvicorn logs the
    reason first)."""
    import uvicorn  # (loaded when serving, not for --help)

    class Announced(uvicorn.Server):
        async def startup(self, sockets: Any = None) -> None:
            await super().startup(sockets)
            if self.started:  # (a port in use ends the start-up without it)
                print(f"exprclone: {said}", flush=True)

    config = uvicorn.Config(app, host=args.host, port=args.port, log_level="warning", **connection_bounds(args), **options)
    server = Announced(config)
    try:
        server.run()
    except SystemExit:  # (uvicorn's, when its start-up fails)
        raise ExprCloneError("serve", f"could not start on {args.host}:{args.port} (uvicorn's reason above)") from None
    except KeyboardInterrupt:  # (uvicorn raises Ctrl-C again once it has stopped)
        raise Interrupted from None
    finally:
        if server.started:
            print("exprclone: stopped", flush=True)


def tls_files(args: argparse.Namespace) -> tuple[str, str, str] | None:
    """The TLS flags' files (:data:`TLS`), all three or none; ExprCloneError naming the first missing otherwise."""
    given = [getattr(args, flag.replace("-", "_")) for flag in TLS]
    if not any(given):
        return None
    missing = [flag for flag, path in zip(TLS, given) if not path]
    if missing:
        raise ExprCloneError(f"--{missing[0]}", f"missing: give all of {', '.join('--' + f for f in TLS)}, or none")
    ca, cert, key = given
    return ca, cert, key


def run(args: argparse.Namespace) -> None:
    server_packages()
    from ..server.app import create_app  # (FastAPI, numpy and the rest: loaded when serving, not for --help)
    from ..server.runtime.clients import read_keys

    check_bounds(args, tuple(BOUNDS))
    fields = {flag.replace("-", "_"): getattr(args, flag.replace("-", "_")) for flag in BOUNDS if flag not in UVICORN}
    fields["max_pixels"] = round(fields.pop("max_megapixels") * 1e6)
    tls = tls_files(args)
    keys = read_keys(args.api_keys) if args.api_keys else frozenset()
    settings = Settings(**fields, cors=tuple(args.cors), scheduler=args.scheduler, tls=tls, api_keys=keys)
    where = f"{args.workers} workers"
    if args.scheduler:
        connect(args.scheduler, tls).close()  # one that cannot be reached is a one-line error now, not uvicorn's traceback
        where = f"the Dask cluster at {args.scheduler}"
    said = f"serving on http://{args.host}:{args.port}/ ({where}; Ctrl-C to stop)"
    listen(create_app(settings), args, said, ws_max_size=int(args.max_upload_mb * 2**20), ws_max_queue=WS_QUEUE)
