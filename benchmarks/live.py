"""Live mode in the browser test's setting: frames per second, latency and dropped frames, one session and two at once.

    python benchmarks/live.py [--seconds 20] [--method e+md]

Starts ``exprclone serve`` and headless Chromium (tests/browser.py) with the sample GRID
clip as a fake camera (looped), opens ``/live`` with the sample portrait, and watches
each session's WebSocket for ``--seconds`` after its first answer (the first 2 seconds,
while the neutral face is captured, are left out). Per session at 256 and 512 pixels:

- frames per second delivered (answers received), and the page's own readout;
- latency from a frame sent to its answer received (p50, p95), and the page's median
  from sent to shown (drawn on the canvas);
- the share of frames sent that were dropped (the server kept a newer one).
"""

from __future__ import annotations

import argparse
import os
import struct
import tempfile
import time
from pathlib import Path

import numpy as np

from exprclone import data as samples
from exprclone.testing.browser import (
    chromium_pages,
    write_y4m,
)
from exprclone.testing.servers import Server

SETTLE = 2.0


class Watched:
    """One page's WebSocket traffic: when each frame was sent, when each answer came."""

    def __init__(self, page) -> None:
        self.sent: dict[int, float] = {}
        self.answered: list[tuple[float, int]] = []
        page.on("websocket", self.watch)

    def watch(self, ws) -> None:
        def sent(payload):
            if isinstance(payload, bytes):
                self.sent[struct.unpack(">I", payload[:4])[0]] = time.perf_counter()

        def received(payload):
            if isinstance(payload, bytes):
                self.answered.append((time.perf_counter(), struct.unpack(">I", payload[:4])[0]))

        ws.on("framesent", sent)
        ws.on("framereceived", received)

    def report(self, seconds: float) -> str:
        if not self.answered:
            return "no frame answered"
        start = self.answered[0][0] + SETTLE
        end = start + seconds
        answered = [(t, n) for t, n in self.answered if start <= t < end]
        numbers = [n for _, n in answered]
        latency = [1000 * (t - self.sent[n]) for t, n in answered if n in self.sent]
        sent = [n for n, t in self.sent.items() if start <= t < end and n <= max(numbers)]
        dropped = 1 - len(set(sent) & set(numbers)) / max(len(sent), 1)
        p50, p95 = np.percentile(latency, [50, 95])
        return f"{len(answered) / seconds:5.1f} fps, latency p50 {p50:4.0f} ms p95 {p95:4.0f} ms, dropped {100 * dropped:4.1f}%"


def run(url: str, flags: tuple[str, ...], size: str, sessions: int, args) -> list[str]:
    """``sessions`` pages at once, each in a browser of its own (a page in the background would be throttled)."""
    with chromium_pages(sessions, *flags) as pages:
        watched = [Watched(page) for page in pages]
        for page in pages:
            page.goto(f"{url}/live")
            page.set_input_files("input[type=file][name=portrait]", str(samples.path("001")))
            page.select_option("#size", size)
            page.select_option("#method", args.method)
        for page in pages:
            page.click("#start")
        pages[0].wait_for_timeout(1000 * (args.seconds + SETTLE + 2))
        readouts = [(page.text_content("#fps"), page.text_content("#latency"), page.text_content("#error")) for page in pages]
        for page in pages:
            if page.is_enabled("#stop"):  # a session the server ended has stopped already: its error is reported
                page.click("#stop")
    return [
        f"{w.report(args.seconds)} (the page says {fps} fps, {latency} ms to shown{'; ' + error if error else ''})"
        for w, (fps, latency, error) in zip(watched, readouts)
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--method", default="e+md")
    args = parser.parse_args()
    camera = Path(tempfile.mkdtemp()) / "grid.y4m"
    write_y4m(samples.clip(), camera)
    server = Server("--workers", "1", "--max-live-per-client", "2")  # (the sessions at once are one client's)
    flags = ("--use-fake-ui-for-media-stream", "--use-fake-device-for-media-stream", f"--use-file-for-fake-video-capture={camera}")
    print(f"exprclone live benchmark: {os.cpu_count()} cores, {args.method}, the sample GRID clip as the camera, {args.seconds:g} s a run")
    try:
        for size in ("256", "512"):
            for sessions in (1, 2):
                print(f"{size} px, {sessions} session(s) at once: " + "; ".join(run(server.url, flags, size, sessions, args)))
    finally:
        server.stop()


if __name__ == "__main__":
    main()
