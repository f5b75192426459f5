"""The sliders: time from a slider's change to its new preview on the page, against a whole clone; the same for the
expression editor's page (``/editor``).

    python benchmarks/sliders.py [--steps 40] [--repeat 7]

Starts ``exprclone serve`` and headless Chromium (tests/browser.py), clones the sample photos
(1350 pixels; the preview is 512) on the page, then drags the mouth's slider with the mouse,
``--steps`` positions back and forth, waiting at each for its preview to be on screen. Prints:

- the page's own time from each slider change (its ``input`` event) to the preview shown
  (the image decoded), median and 90th percentile, read from ``window.previewTimes``;
- over HTTP alone, in turn, ``--repeat`` times each: a preview render (512, JPEG), a full-size
  render (1350, PNG), and a whole clone of the same photos (``POST /api/clone``, the peer: what
  each change cost before the sliders), as medians, and the ratio of a preview to a clone.

Then the editor's page: the target's photo prepared (``POST /api/editor``), the smile's slider dragged the same way,
the page's times; and over HTTP an editor's preview render (the smile at a new value each time) against the same
whole clone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable

import httpx
import numpy as np

from exprclone import data as samples
from exprclone.testing.browser import chromium
from exprclone.testing.servers import Server

PHOTOS = {"source_neutral": samples.path("126"), "source_expression": samples.path("126", "smile"), "target_neutral": samples.path("003")}
RENDERED = "JSON.parse(document.querySelector('img#result').dataset.rendered || '{}')"


def on_the_page(url: str, steps: int, editor: bool = False) -> list[float]:
    """The page's milliseconds from each of ``steps`` slider changes to its preview shown: the clone page's mouth
    strength, or with ``editor`` the editor page's smile."""
    with chromium() as page:
        if editor:
            page.goto(f"{url}/editor")
            page.wait_for_selector("#control-smile")
            page.set_input_files("#photo", str(PHOTOS["target_neutral"]))
        else:
            page.goto(url)
            page.check("#source-photos")  # (the page's default is a built-in expression)
            for field, path in PHOTOS.items():
                page.set_input_files(f"input[type=file][name={field}]", str(path))
            page.click("#clone")
        page.wait_for_function(f"{RENDERED}.size === 'full'", timeout=120_000)
        slider, field = ("#control-smile", "smile") if editor else ("#strength-mouth", "strength_mouth")
        box = page.locator(slider).bounding_box()
        y, left, width = box["y"] + box["height"] / 2, box["x"], box["width"]
        page.mouse.move(left + width / 2, y)
        page.mouse.down()
        page.evaluate("window.previewTimes.length = 0")
        for k in range(steps):
            phase = (k % 20) / 20 if (k // 20) % 2 == 0 else 1 - (k % 20) / 20  # back and forth along the track
            page.mouse.move(left + 2 + (width - 4) * phase, y)
            value = page.input_value(slider)
            shown = f"r.{field} === '{value}'" if not editor or float(value) > 0 else f"r.{field} === undefined"
            page.wait_for_function(f"(r => r.size === 'preview' && {shown})({RENDERED})", timeout=60_000)
        page.mouse.up()
        times: list[float] = page.evaluate("window.previewTimes")
        return times


def in_turn(calls: dict[str, Callable[[int], httpx.Response]], repeat: int) -> dict[str, float]:
    """Median seconds of each call (given the round's number), run in turn ``repeat`` times after a round that warms up."""
    timings: dict[str, list[float]] = {name: [] for name in calls}
    for k in range(repeat + 1):
        for name, call in calls.items():
            start = time.perf_counter()
            call(k).raise_for_status()
            if k:
                timings[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in timings.items()}


def over_http(url: str, repeat: int) -> dict[str, float]:
    """Median seconds of a preview render, a full-size render and a whole clone, run in turn."""
    files = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    with httpx.Client(base_url=url, timeout=300) as client:
        made = client.post("/api/edits", files=files)
        made.raise_for_status()
        render = made.json()["render"]
        medians = in_turn(
            {
                "preview": lambda k: client.post(render, data={"strength_mouth": f"{0.5 + k / 10:g}"}),
                "full": lambda k: client.post(render, params={"preview": "false"}, data={"strength_mouth": f"{0.5 + k / 10:g}"}),
                "clone": lambda k: client.post("/api/clone", files=files),
            },
            repeat,
        )
        client.delete(render.rsplit("/", 1)[0])
    return medians


def editor_over_http(url: str, repeat: int) -> dict[str, float]:
    """Median seconds of an editor's preview render (the smile at a new value each time) and a whole clone, in turn."""
    photo = PHOTOS["target_neutral"]
    files = {field: (path.name, path.read_bytes()) for field, path in PHOTOS.items()}
    with httpx.Client(base_url=url, timeout=300) as client:
        made = client.post("/api/editor", files={"photo": (photo.name, photo.read_bytes())})
        made.raise_for_status()
        render = made.json()["render"]
        medians = in_turn(
            {
                "preview": lambda k: client.post(render, data={"smile": f"{0.3 + k / 20:g}"}),
                "clone": lambda k: client.post("/api/clone", files=files),
            },
            repeat,
        )
        client.delete(render.rsplit("/", 1)[0])
    return medians


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
        times = on_the_page(server.url, args.steps, editor=True)
        p50, p90 = np.percentile(times, [50, 90])
        print(f"the editor's page, the smile's slider to preview shown: median {p50:.0f} ms, p90 {p90:.0f} ms over {len(times)} changes")
        medians = editor_over_http(server.url, args.repeat)
        print(
            f"the editor over HTTP, in turn ({args.repeat} each): preview {1000 * medians['preview']:.0f} ms, a whole clone"
            f" {1000 * medians['clone']:.0f} ms; a preview costs {medians['preview'] / medians['clone']:.3f}x a clone"
        )
    finally:
        server.stop()


if __name__ == "__main__":
    main()
