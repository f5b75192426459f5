"""A screenshot of the web page after a clone of the sample photos, taken with the browser tests' tooling.

    python tools/page_screenshot.py [-o docs/_static/page.jpg]

Starts ``exprclone serve``, opens the page in headless Chromium (tests/browser.py), clicks
"Try the sample photos", clones, and saves the page.
"""

import argparse
import io
from pathlib import Path

from PIL import Image

from exprclone.testing.browser import chromium
from exprclone.testing.servers import Server

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("-o", "--output", default=str(Path(__file__).resolve().parents[1] / "docs" / "page.jpg"))
args = parser.parse_args()
server = Server("--workers", "1")
try:
    with chromium() as page:
        page.goto(server.url)
        page.check("#source-photos")  # the expression of the sample's source, from its two photos
        page.click("#samples")
        page.wait_for_function("document.querySelector('[data-field=target_neutral] img').naturalWidth > 0")
        page.wait_for_timeout(1500)  # the landmarks of the three photos
        page.click("#clone")
        page.wait_for_function("document.querySelector('img#result').naturalWidth > 0", timeout=60_000)
        shot = page.screenshot(full_page=True, clip={"x": 0, "y": 0, "width": 1280, "height": 1700})
finally:
    server.stop()
image = Image.open(io.BytesIO(shot)).convert("RGB")
image.resize((image.width * 3 // 4, image.height * 3 // 4), Image.LANCZOS).save(args.output, quality=82)
print(f"{args.output}: {image.width}x{image.height} page, saved at 3/4")
