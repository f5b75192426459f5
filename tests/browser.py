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
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


@contextlib.contextmanager
def chromium(*extra_flags: str):
    """A headless Chromium page; without the browser the test is skipped (failed under EXPRCLONE_REQUIRE_ALL=1, as in CI)."""
    need(CHROMIUM, "needs Debian's Chromium (apt-get install -y chromium, as .ci/run does)")
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as profile, sync_playwright() as p:
        browser = p.chromium.launch_persistent_context(
            profile, executable_path=str(CHROMIUM), headless=True, args=FLAGS + list(extra_flags), viewport={"width": 1280, "height": 900}
        )
        try:
            yield browser.new_page() if not browser.pages else browser.pages[0]
        finally:
            browser.close()
