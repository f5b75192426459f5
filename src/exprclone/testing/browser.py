"""A real browser for the tests, the tools and the benchmarks: Debian's Chromium, headless, driven by Playwright (whose
own browser download cannot work here)."""

from __future__ import annotations

import contextlib
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import av

from ..errors import ExprCloneError

if TYPE_CHECKING:
    from playwright.sync_api import Page

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
def chromium(*extra_flags: str) -> Iterator[Page]:
    """A headless Chromium page; without the browser, ExprCloneError."""
    with chromium_pages(1, *extra_flags) as pages:
        yield pages[0]


@contextlib.contextmanager
def chromium_pages(count: int, *extra_flags: str) -> Iterator[list[Page]]:
    """``count`` pages, each in a headless Chromium of its own (each in the foreground: none is throttled)."""
    if not CHROMIUM.exists():
        raise ExprCloneError(str(CHROMIUM), "not found: needs Debian's Chromium (apt-get install -y chromium, as .ci/run does)")
    from playwright.sync_api import sync_playwright  # (Playwright: a test dependency, loaded when a browser starts)

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


def write_y4m(clip: str | Path, path: str | Path) -> None:
    """The clip as a Y4M file, which Chromium plays as a fake camera (in a loop)."""
    with av.open(str(clip)) as container, open(path, "wb") as out:
        stream = container.streams.video[0]
        w, h = stream.codec_context.width, stream.codec_context.height
        out.write(f"YUV4MPEG2 W{w} H{h} F25:1 Ip A1:1 C420jpeg\n".encode())
        for frame in container.decode(stream):
            out.write(b"FRAME\n" + frame.to_ndarray(format="yuv420p").tobytes())
