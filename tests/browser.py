"""A real browser for the tests: Debian's Chromium, headless, driven by Playwright (whose own browser download cannot work here)."""

import contextlib
import tempfile
from pathlib import Path

from conftest import need

#: where Debian's chromium package puts the browser.
CHROMIUM = Path("/usr/lib/chromium/chromium")
#: flags for a headless Chromium as root on a machine with no network beyond loopback.
FLAGS = [
    "--no-sandbox",
    "--disable-dev-shm-usage",  # a container's /dev/shm may be too small for Chromium
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    # a page in the background keeps its timers and frames (the benchmark runs two sessions at once)
    "--disable-background-timer-throttling",
    "--disable-renderer-backgrounding",
    "--disable-backgrounding-occluded-windows",
]


@contextlib.contextmanager
def chromium(*extra_flags: str):
    """A headless Chromium page; without the browser the test is skipped (failed under EXPRCLONE_REQUIRE_ALL=1, as in CI)."""
    with chromium_pages(1, *extra_flags) as pages:
        yield pages[0]


@contextlib.contextmanager
def chromium_pages(count: int, *extra_flags: str):
    """``count`` pages, each in a headless Chromium of its own (each in the foreground: none is throttled)."""
    need(CHROMIUM, "needs Debian's Chromium (apt-get install -y chromium, as .ci/run does)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p, contextlib.ExitStack() as stack:
        pages = []
        for _ in range(count):
            profile = stack.enter_context(tempfile.TemporaryDirectory())
            browser = p.chromium.launch_persistent_context(
                profile,
                executable_path=str(CHROMIUM),
                headless=True,
                args=FLAGS + list(extra_flags),
                viewport={"width": 1280, "height": 900},
            )
            stack.callback(browser.close)
            pages.append(browser.pages[0] if browser.pages else browser.new_page())
        yield pages
