"""Make a group photo of London Set people, to clone every face of (no open group photo of neutral faces is at hand).

    python tools/group_photo.py OUT.jpg [--people 039,041,043,044,045,062] [--widths 120,176,232,288,344,400]
        [--size 3000x2000] [--seed 0] [--tilts 0,10,-10,...] [--smiling] [--data ../shared/data]

Each person's London photo is scaled so that their face is as wide as asked, cut out and laid over a made background,
in two rows, the smaller faces behind (:mod:`exprclone.evaluation.groups`). Beside OUT.jpg (JPEG, quality 95) it writes
OUT.json: for each person in the order given, their id, face width, scale, offset and the 68 points of their manual
template in the group photo. People default to six London people at face widths from 120 to 400 pixels.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from exprclone.data import sets as datasets
from exprclone.evaluation.groups import make

#: the six people and face widths of the issue's group photo.
PEOPLE = "039,041,043,044,045,062"
WIDTHS = "120,176,232,288,344,400"
#: the JPEG's quality.
QUALITY = 95


def numbers(text: str) -> list[float]:
    return [float(v) for v in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", help="the photo to write (.jpg or .png); OUT.json beside it")
    parser.add_argument("--people", default=PEOPLE, help=f"London Set ids, comma-separated (default: {PEOPLE})")
    parser.add_argument("--widths", default=WIDTHS, help=f"each face's width in pixels (default: {WIDTHS})")
    parser.add_argument("--size", default="3000x2000", help="the photo's WIDTHxHEIGHT (default: 3000x2000)")
    parser.add_argument("--seed", type=int, default=0, help="the background's (default: 0)")
    parser.add_argument("--tilts", help="each head turned in the photo's plane, degrees (default: upright)")
    parser.add_argument("--smiling", action="store_true", help="their smiling photos instead of their neutral ones")
    datasets.add_argument(parser, holds="the folder holding london/")
    args = parser.parse_args()
    from exprclone.io.images import save_image

    people, widths = args.people.split(","), numbers(args.widths)
    size = tuple(int(v) for v in args.size.lower().split("x"))
    tilts = None if args.tilts is None else numbers(args.tilts)
    if len(widths) != len(people) or (tilts is not None and len(tilts) != len(people)):
        parser.error("--people, --widths and --tilts name one value per person")
    image, placed = make(Path(args.data) / "london", people, widths, (size[0], size[1]), args.seed, args.smiling, tilts)
    if args.output.lower().endswith((".jpg", ".jpeg")):
        from PIL import Image

        Image.fromarray(image).save(args.output, quality=QUALITY)
    else:
        save_image(args.output, image)
    record = [
        dict(face_id=p.face_id, width=round(p.width, 1), scale=p.scale, offset=p.offset.tolist(), landmarks=p.landmarks.round(2).tolist())
        for p in placed
    ]
    Path(args.output).with_suffix(".json").write_text(json.dumps({"size": list(size), "people": record}, indent=1))
    print(f"{args.output}: {len(placed)} people, faces {', '.join(f'{p.width:.0f}' for p in placed)} px wide")


if __name__ == "__main__":
    main()
