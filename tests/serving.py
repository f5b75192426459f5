"""The tests' servers (:mod:`exprclone.testing.servers`): without nginx its test is skipped (failed under
EXPRCLONE_REQUIRE_ALL=1, as in CI)."""

import contextlib
import io

import httpx
import numpy as np
from conftest import need
from PIL import Image

from exprclone.testing import servers
from exprclone.testing.servers import NGINX, Server, free_port, interruptible

__all__ = ["Server", "client", "free_port", "interruptible", "nginx", "pixels"]


@contextlib.contextmanager
def nginx(folder, ports):
    """nginx in front of the servers on ``ports`` (:func:`exprclone.testing.servers.nginx`)."""
    need(NGINX, "needs nginx (Debian's package nginx; .ci/run installs it)")
    with servers.nginx(folder, ports) as url:
        yield url


@contextlib.contextmanager
def client(*args: str):
    """An HTTP client of a real server started with ``args`` (``exprclone serve``'s), stopped after."""
    running = Server(*args)
    try:
        with httpx.Client(base_url=running.url, timeout=120) as c:
            yield c
    finally:
        running.stop()


def pixels(answer: httpx.Response) -> np.ndarray:
    """An answer's image, RGB; the answer must be a success."""
    assert answer.status_code == 200, answer.text
    return np.asarray(Image.open(io.BytesIO(answer.content)).convert("RGB"))
