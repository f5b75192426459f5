"""Real servers for the tests, the tools and the benchmarks: ``exprclone serve`` started on a free port of 127.0.0.1,
stopped by its own PID; nginx in front of them with the configuration shipped in the repository's ``deploy/``."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import httpx

from ..errors import ExprCloneError

#: seconds a server may take to start (it loads the models in each worker first).
START_TIMEOUT = 90
NGINX = Path("/usr/sbin/nginx")
#: the nginx configuration shipped, for one server or several (its upstreams list each).
NGINX_CONFIG = Path(__file__).resolve().parents[3] / "deploy" / "nginx.conf"


def interruptible() -> None:
    """In a child before it runs: Ctrl-C (SIGINT) as a user's terminal gives it. A test run started in the background
    of a non-interactive shell ignores SIGINT, and a Python started so would ignore it too (no KeyboardInterrupt)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    """``exprclone serve ARGS`` (or another ``command``) in a process of its own, with ``env`` added to its environment;
    ``url`` once it answers ``/api/health``.

    Its output goes to temporary files, not pipes: a pipe nobody reads while the server
    runs fills up (64 KB of log), and the server then stops at its next line.
    """

    def __init__(self, *args: str, command: tuple[str, ...] = ("serve",), env: dict[str, str] | None = None) -> None:
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        line = [sys.executable, "-m", "exprclone", *command, "--port", str(self.port), *args]
        self.output = tempfile.TemporaryFile("w+"), tempfile.TemporaryFile("w+")
        self.said: list[str] = []  # its output, once stopped
        environment = None if env is None else {**os.environ, **env}
        self.process = subprocess.Popen(
            line, stdout=self.output[0], stderr=self.output[1], text=True, env=environment, preexec_fn=interruptible
        )
        deadline = time.time() + START_TIMEOUT
        while time.time() < deadline and self.process.poll() is None:
            try:
                if httpx.get(f"{self.url}/api/health", timeout=1).status_code == 200:
                    return
            except httpx.TransportError:
                time.sleep(0.2)
        self.stop()
        raise RuntimeError(f"the server did not start: {self.stop()[1]}")

    def stop(self) -> tuple[str, str]:
        """Ctrl-C (SIGINT) to the server's own PID, as a user would stop it; its output (stdout, stderr)."""
        if self.process.poll() is None:
            os.kill(self.process.pid, signal.SIGINT)
        try:
            self.process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        if not self.said:  # (once: the files are closed after)
            for file in self.output:
                file.seek(0)
                self.said.append(file.read())
                file.close()
        return self.said[0], self.said[1]


@contextlib.contextmanager
def nginx(folder: Path, ports: list[int]) -> Iterator[str]:
    """nginx on a free port of 127.0.0.1 with ``deploy/nginx.conf`` as shipped, in front of the servers on ``ports`` of
    127.0.0.1 (each listed in its upstreams), its files in ``folder``: its URL, until the block ends."""
    if not NGINX.exists():
        raise ExprCloneError(str(NGINX), "not found: needs nginx (Debian's package nginx; .ci/run installs it)")
    port = free_port()
    servers = " ".join(f"server 127.0.0.1:{p};" for p in ports)
    site = NGINX_CONFIG.read_text().replace("server 127.0.0.1:8000;", servers)
    (folder / "exprclone.conf").write_text(site.replace("listen 80;", f"listen 127.0.0.1:{port};"))
    temporary = " ".join(f"{kind}_temp_path {folder / kind};" for kind in ("client_body", "proxy", "fastcgi", "uwsgi", "scgi"))
    (folder / "nginx.conf").write_text(
        ("user root;\n" if os.geteuid() == 0 else "")
        + f"daemon off; worker_processes 1; pid {folder / 'nginx.pid'}; error_log {folder / 'error.log'};\n"
        + f"events {{ worker_connections 256; }}\nhttp {{ access_log off; {temporary} include {folder / 'exprclone.conf'}; }}\n"
    )
    process = subprocess.Popen([str(NGINX), "-p", str(folder), "-e", str(folder / "error.log"), "-c", str(folder / "nginx.conf")])
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(100):
            try:
                if httpx.get(f"{url}/api/health", timeout=2).status_code == 200:
                    break
            except httpx.TransportError:
                time.sleep(0.1)
        yield url
    finally:
        os.kill(process.pid, signal.SIGQUIT)
        process.wait(timeout=30)
