"""The tests' browser (:mod:`exprclone.testing.browser`): without Debian's Chromium a test is skipped (failed under
EXPRCLONE_REQUIRE_ALL=1, as in CI)."""

import contextlib

from conftest import need

from exprclone.testing import browser
from exprclone.testing.browser import CHROMIUM, write_y4m

__all__ = ["chromium", "chromium_pages", "write_y4m"]
REASON = "needs Debian's Chromium (apt-get install -y chromium, as .ci/run does)"


@contextlib.contextmanager
def chromium(*extra_flags: str):
    """A headless Chromium page (:func:`exprclone.testing.browser.chromium`)."""
    need(CHROMIUM, REASON)
    with browser.chromium(*extra_flags) as page:
        yield page


@contextlib.contextmanager
def chromium_pages(count: int, *extra_flags: str):
    """``count`` pages, each in a Chromium of its own (:func:`exprclone.testing.browser.chromium_pages`)."""
    need(CHROMIUM, REASON)
    with browser.chromium_pages(count, *extra_flags) as pages:
        yield pages
