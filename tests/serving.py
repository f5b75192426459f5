"""The tests' servers (:mod:`exprclone.testing.servers`): without nginx its test is skipped (failed under
EXPRCLONE_REQUIRE_ALL=1, as in CI)."""

import contextlib

from conftest import need

from exprclone.testing import servers
from exprclone.testing.servers import NGINX, Server, free_port, interruptible

__all__ = ["Server", "free_port", "interruptible", "nginx"]


@contextlib.contextmanager
def nginx(folder, ports):
    """nginx in front of the servers on ``ports`` (:func:`exprclone.testing.servers.nginx`)."""
    need(NGINX, "needs nginx (Debian's package nginx; .ci/run installs it)")
    with servers.nginx(folder, ports) as url:
        yield url
