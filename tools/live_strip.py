"""A strip of live frames for the README: the fake camera (a GRID clip) and the portrait answering it.

    python tools/live_strip.py [-o docs/_static/live.jpg] [--frames 6]

Starts ``exprclone serve`` and headless Chromium with the sample clip as its camera
(tests/browser.py), opens ``/live`` with the sample portrait at 256 pixels, watches the
WebSocket for 8 seconds, and lays out the camera frames whose mouths are most open
(after the neutral face is captured) above the frames the server answered them with.
"""

import argparse
import struct
import tempfile
from pathlib import Path

import cv2
import numpy as np
from PIL import Image

from exprclone import data as samples
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth.measure import opening
from exprclone.server.session import decode_jpeg
from exprclone.testing.browser import (
    chromium,
    write_y4m,
)
from exprclone.testing.servers import Server

SIZE = 256


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default=str(Path(__file__).resolve().parents[1] / "docs" / "live.jpg"))
    parser.add_argument("--frames", type=int, default=6)
    args = parser.parse_args()
    camera = Path(tempfile.mkdtemp()) / "grid.y4m"
    write_y4m(samples.clip(), camera)
    sent, answers = {}, []

    def watch(ws):
        ws.on("framesent", lambda p: isinstance(p, bytes) and sent.__setitem__(struct.unpack(">I", p[:4])[0], p[4:]))
        ws.on("framereceived", lambda p: isinstance(p, bytes) and answers.append((struct.unpack(">I", p[:4])[0], p[4:])))

    server = Server("--workers", "1")
    flags = ("--use-fake-ui-for-media-stream", "--use-fake-device-for-media-stream", f"--use-file-for-fake-video-capture={camera}")
    try:
        with chromium(*flags) as page:
            page.on("websocket", watch)
            page.goto(f"{server.url}/live")
            page.set_input_files("input[type=file][name=portrait]", str(samples.path("001")))
            page.select_option("#size", str(SIZE))
            page.click("#start")
            page.wait_for_timeout(8000)
            page.click("#stop")
    finally:
        server.stop()
    detector = default_detector()
    scored = []
    for number, jpeg in answers[len(answers) // 4 :]:  # after the neutral face is captured
        frame = decode_jpeg(sent[number])
        boxes = detector.faces(frame)
        if boxes:
            scored.append((opening(detector.fit(frame, boxes[0]), DLIB68), number, frame, decode_jpeg(jpeg)))
    chosen = sorted(sorted(scored, key=lambda s: -s[0])[: args.frames], key=lambda s: s[1])

    def square(frame):  # the middle of a frame, as high as it is wide, at SIZE
        h, w = frame.shape[:2]
        side = min(h, w)
        middle = frame[(h - side) // 2 : (h + side) // 2, (w - side) // 2 : (w + side) // 2]
        return cv2.resize(middle, (SIZE, SIZE), interpolation=cv2.INTER_AREA)

    strip = np.vstack([np.hstack([square(frame) for _, _, frame, _ in chosen]), np.hstack([square(out) for *_, out in chosen])])
    Image.fromarray(strip).save(args.output, quality=85)
    print(f"{args.output}: {len(chosen)} frames of {len(answers)} answered, camera above, portrait below")


if __name__ == "__main__":
    main()
