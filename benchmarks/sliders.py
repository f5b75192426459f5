"""The sliders: time from a slider's change to its new preview on the page, against a whole clone.

    python benchmarks/sliders.py [--steps 40] [--repeat 7]

Starts ``exprclone serve`` and headless Chromium (tests/browser.py), clones the sample photos
(1350 pixels; the preview is 512) on the page, then drags the mouth's slider with the mouse,
``--steps`` positions back and forth, waiting at each for its preview to be on screen. Prints:

- the page's own time from each slider change (its ``input`` event) to the preview shown
  (the image decoded), median and 90th percentile, read from ``window.previewTimes``;
- over HTTP alone, in turn, ``--repeat`` times each: a preview render (512, JPEG), a full-size
  render (1350, PNG), and a whole clone of the same photos (``POST /api/clone``, the peer: what
  each change cost before the sliders), as medians, and the ratio of a preview to a clone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import httpx
import numpy as np

from exprclone import data as samples
from exprclone.testing.browser import chromium
from exprclone.testing.servers import Server

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}
RENDERED = "JSON.parse(document.querySelector('img#result').dataset.rendered || '{}')"


def on_the_page(url: str, steps: int) -> list[float]:
    """The page's milliseconds from each of ``steps`` slider changes to its preview shown."""
    with chromium() as page:
        page.goto(url)
        page.check("#source-photos")  # (the page's default is a built-in expression)
        for field, path in PHOTOS.items():
            page.set_input_files(f"input[type=file][name={field}]", str(path))
        page.click("#clone")
        page.wait_for_function(f"{RENDERED}.size === 'full'", timeout=120_000)
        box = page.locator("#strength-mouth").bounding_box()
        y, left, width = box["y"] + box["height"] / 2, box["x"], box["width"]
        page.mouse.move(left + width / 2, y)
        page.mouse.down()
        page.evaluate("window.previewTimes.length = 0")
        for k in range(steps):
            phase = (k % 20) / 20 if (k // 20) % 2 == 0 else 1 - (k % 20) / 20  # back and forth along the track
            page.mouse.move(left + 2 + (width - 4) * phase, y)
            value = page.input_value("#strength-mouth")
            page.wait_for_function(f"(r => r.size === 'preview' && r.strength_mouth === '{value}')({RENDERED})", timeout=60_000)
        page.mouse.up()
        times: list[float] = page.evaluate("window.previewTimes")
        return times


def over_http(url: str, repeat: int) -> dict[str, float]:
    """Median seconds of a preview render, a full-size render and a whole clone, run in turn."""
    files = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    timings: dict[str, list[float]] = {"preview": [], "full": [], "clone": []}
    with httpx.Client(base_url=url, timeout=300) as client:
        made = client.post("/api/edits", files=files)
        made.raise_for_status()
        render = made.json()["render"]
        for k in range(repeat + 1):  # the first round warms up
            for name, call in (
                ("preview", lambda: client.post(render, data={"strength_mouth": f"{0.5 + k / 10:g}"})),
                ("full", lambda: client.post(render, params={"preview": "false"}, data={"strength_mouth": f"{0.5 + k / 10:g}"})),
                ("clone", lambda: client.post("/api/clone", files=files)),
            ):
                start = time.perf_counter()
                call().raise_for_status()
                if k:
                    timings[name].append(time.perf_counter() - start)
        client.delete(render.rsplit("/", 1)[0])
    return {name: statistics.median(values) for name, values in timings.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    server = Server("--workers", "1")
    print(f"exprclone sliders benchmark: {os.cpu_count()} cores, e+md, the sample photos (target 1350 px, preview 512 px)")
    try:
        times = on_the_page(server.url, args.steps)
        p50, p90 = np.percentile(times, [50, 90])
        print(f"the page, slider change to preview shown: median {p50:.0f} ms, p90 {p90:.0f} ms over {len(times)} changes")
        medians = over_http(server.url, args.repeat)
        print(
            f"over HTTP, in turn ({args.repeat} each): preview {1000 * medians['preview']:.0f} ms, full size"
            f" {1000 * medians['full']:.0f} ms, a whole clone {1000 * medians['clone']:.0f} ms;"
            f" a preview costs {medians['preview'] / medians['clone']:.3f}x a clone"
        )
    finally:
        server.stop()


if __name__ == "__main__":
    main()
