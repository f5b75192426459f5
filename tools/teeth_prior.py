"""Measure the constants of ``exprclone.mouth.teeth`` on the London Set: the studio's light, and teeth in it.

    python tools/teeth_prior.py [--data ../shared/data] [--widths 30 45 70 110 170]

Prints, from the 72 neutral photos, the mean log RGB of the two cues to the light
(``WHITE_SKIN``, ``WHITE_SCLERA``: :class:`exprclone.mouth.illuminant.Light`), and, from the
smiles that show teeth (``exprclone.mouth.measure.interior``: at least :data:`TEETH_SHOWN`
squared mouth widths), the mean and the between-people spread (per degree of freedom)
of the log colour of their teeth and of their mouth's cavity (``exprclone.mouth.teeth.Part.read``): at the photo's own
size, and with the smile shrunk until its mouth is ``--widths`` pixels wide and saved
as a JPEG of quality :data:`QUALITY` (with its colour at half resolution, as video
codecs keep it): small, compressed mouths blend the teeth's colour with the lips' and
the gums' (``TEETH_COLOURS``, ``CAVITY_COLOURS``). The last row is the photos' own size, at the median
width of their mouths; the relation of the teeth to the cheeks of the same smiles (the
skin cue) is printed for comparison.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cv2
import numpy as np

from exprclone.data import sets as datasets
from exprclone.io.images import load_image
from exprclone.landmarks import lips
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import illuminant, measure, teeth

ROOT = Path(__file__).resolve().parents[1]
#: a smile shows teeth from this area, in squared mouth widths (as ``exprclone.evaluation``'s).
TEETH_SHOWN = 0.004
#: JPEG quality of the shrunk smiles.
QUALITY = 75
#: the mouth widths (pixels) the smiles are shrunk to.
WIDTHS = (30, 45, 70, 110, 170)


def shrunk(image: np.ndarray, points: np.ndarray, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The photo scaled by ``scale`` (area-averaged) and saved as a JPEG of :data:`QUALITY`, and its landmarks."""
    small = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    _, data = cv2.imencode(".jpg", cv2.cvtColor(small, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, QUALITY])
    return cv2.cvtColor(cv2.imdecode(data, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB), points * scale


def part_colours(image: np.ndarray, points: np.ndarray) -> list[np.ndarray | None]:
    """The log colour of the teeth and of the cavity a photo shows (``teeth.Part.read``), None where too few."""
    parts = [teeth.Part.read(image[mask]) for mask in measure.interior(image, points, DLIB68)]
    return [None if part is None else part.log_colour for part in parts]


def spread(colours: list[np.ndarray]) -> str:
    """Mean log colour and between-people spread per degree of freedom, as text."""
    c = np.array(colours)
    return f"{np.round(c.mean(0), 3).tolist()}, spread {np.sqrt(c.var(0).sum() / 2):.3f}, {len(c)} smiles"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--widths", type=int, nargs="*", default=list(WIDTHS))
    args = parser.parse_args()
    london, detector = args.data / "london", default_detector()
    cues = []
    for path in sorted((london / "neutral_front").glob("*_03.jpg")):
        image = load_image(path)
        cues.append(illuminant.Light.measure(image, detector.detect(image), DLIB68).log_colour)
    skin, sclera = np.array(cues).mean(0)
    print(f"WHITE_SKIN = {tuple(np.round(skin, 3).tolist())}\nWHITE_SCLERA = {tuple(np.round(sclera, 3).tolist())}  # {len(cues)} photos")
    rows: dict[int, list[list[np.ndarray]]] = {w: [[], []] for w in [*args.widths, 0]}
    relations, widths = [], []
    for path in sorted((london / "smiling_front").glob("*_08.jpg")):
        image = load_image(path)
        points = lips.uncross(detector.detect(image), DLIB68)
        width = measure.mouth_width(points, DLIB68)
        if measure.interior(image, points, DLIB68)[0].sum() < TEETH_SHOWN * width**2:
            continue
        widths.append(width)
        for w in rows:
            for row, colour in zip(rows[w], part_colours(*(shrunk(image, points, w / width) if w else (image, points)))):
                if colour is not None:
                    row.append(colour)
        if (own := part_colours(image, points)[0]) is not None:
            relations.append(own - illuminant.split(illuminant.read(illuminant.skin_pixels(image, points, DLIB68))[0])[1])
    for w, (teeth_rows, cavity_rows) in rows.items():
        name = f"{w} px" if w else f"{np.median(widths):.0f} px (the photos' own)"
        print(f"mouth {name}: teeth {spread(teeth_rows)}; cavity {spread(cavity_rows)}")
    print(f"teeth relative to the cheeks: {spread(relations)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
