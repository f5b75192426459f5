"""The panels of a comparison sheet (:mod:`exprclone.evaluation.figures`): pictures with their captions above them,
cells of text, difference images, the DB curve's plot, laid out on a grid.

Words are drawn in Pillow's own scalable font (:func:`font`) at sizes that read at the sheet's own size: a caption's
:data:`FONT` pixels are about a fifteenth of a picture's side. Every panel is :data:`CELL` wide and :data:`HEIGHT`
tall (its caption's band, then its picture), so that the rows of a sheet line up.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import cv2
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ..geometry.db_metric import DBCurve
from ..imaging import raster

#: a picture's side, in pixels.
CELL = 320
#: the caption's band above a picture: a line of caption and two of notes.
BAND = 72
#: a panel's height.
HEIGHT = BAND + CELL
#: the font's sizes, in pixels: captions and titles, notes and the words of a text panel.
FONT, SMALL = 20, 17
#: colours: words, notes that warn (equal panels), the chosen lambda_k.
INK, NOTE, CHOSEN = (0, 0, 0), (190, 0, 0), (220, 0, 0)


@functools.cache
def font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """Pillow's own scalable font at ``size`` pixels (nothing to ship, nothing to find on the machine)."""
    return ImageFont.load_default(size=size)


def wrapped(text: str, width: int, size: int) -> list[str]:
    """``text`` broken into lines no wider than ``width`` pixels in :func:`font` of ``size``."""
    lines: list[str] = []
    for word in text.split():
        if lines and font(size).getlength(f"{lines[-1]} {word}") <= width:
            lines[-1] += f" {word}"
        else:
            lines.append(word)
    return lines


def write(draw: ImageDraw.ImageDraw, xy: tuple[int, int], lines: Sequence[tuple[str, tuple[int, int, int], int]], width: int) -> int:
    """Each ``(text, colour, size)`` wrapped to ``width`` from ``xy`` down; the height written."""
    x, y = xy
    top = y
    for text, colour, size in lines:
        for line in wrapped(text, width, size):
            draw.text((x, y), line, fill=colour, font=font(size))
            y += round(size * 1.25)
    return y - top


def panel(picture: np.ndarray | None, caption: str, note: str = "", inside: str = "") -> np.ndarray:
    """A panel: ``picture`` (any size; white if None) scaled to :data:`CELL`, under its ``caption`` and a ``note`` in red;
    ``inside`` written over the picture's middle in grey (what a black difference image means)."""
    out = np.full((HEIGHT, CELL, 3), 255, np.uint8)
    if picture is not None:
        out[BAND:] = cv2.resize(picture, (CELL, CELL), interpolation=cv2.INTER_AREA)
    image = Image.fromarray(out)
    draw = ImageDraw.Draw(image)
    write(draw, (6, 4), [(caption, INK, FONT), (note, NOTE, SMALL)] if note else [(caption, INK, FONT)], CELL - 12)
    if inside:
        write(draw, (16, BAND + CELL // 2 - 2 * FONT), [(inside, (200, 200, 200), FONT)], CELL - 32)
    return np.asarray(image)


def words(title: str, lines: Sequence[str | tuple[str, tuple[int, int, int]]]) -> np.ndarray:
    """A panel of text: ``title`` in the caption's band, then each line (or ``(line, colour)``), wrapped."""
    image = Image.fromarray(panel(None, title))
    said = [(line, INK, SMALL) if isinstance(line, str) else (line[0], line[1], SMALL) for line in lines]
    write(ImageDraw.Draw(image), (6, BAND + 4), said, CELL - 12)
    return np.asarray(image)


def difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Absolute luminance difference of two RGB images, normalised to 0-255 ("normalizing the values to the range
    0~255", Sec. IV), as RGB; black where they are equal."""
    d = np.abs(raster.luma(a).astype(np.float32) - raster.luma(b))
    d = (255 * d / max(float(d.max()), 1e-6)).astype(np.uint8)
    return cv2.cvtColor(d, cv2.COLOR_GRAY2RGB)


def db_plot(curve: DBCurve | None) -> np.ndarray:
    """The DB metric over the candidate lambda_k (evenly spaced), the chosen one in red; a blank panel without a curve."""
    if curve is None:
        return panel(None, "")
    image = Image.fromarray(panel(None, f"DB (Eq. 7) over lambda_k; chosen {curve.best:g}"))
    draw = ImageDraw.Draw(image)
    left, right, top, bottom = 52, CELL - 16, BAND + 24, HEIGHT - 66
    lo, hi = float(curve.db.min()), float(curve.db.max())
    xs = np.linspace(left, right, len(curve.db))
    ys = bottom - (curve.db - lo) / max(hi - lo, 1e-9) * (bottom - top)
    draw.line([(left, top), (left, bottom), (right, bottom)], fill=INK, width=1)
    draw.line(list(zip(xs.tolist(), ys.tolist())), fill=(40, 40, 200), width=3)
    small = font(SMALL - 3)
    for k, (x, lam) in enumerate(zip(xs, curve.lambdas)):
        draw.text((x, bottom + 4 + (SMALL - 2) * (k % 2)), "inf" if np.isinf(lam) else f"{lam:g}", fill=INK, font=small, anchor="ma")
    k = int(np.flatnonzero(curve.lambdas == curve.best)[0])
    draw.ellipse((xs[k] - 7, ys[k] - 7, xs[k] + 7, ys[k] + 7), fill=CHOSEN)
    for value, y in ((hi, top), (lo, bottom)):
        draw.text((left - 4, y), f"{value:.2f}", fill=INK, font=small, anchor="rm")
    draw.text((CELL // 2, HEIGHT - 8), "candidates of Eq. 8, evenly spaced", fill=INK, font=small, anchor="ms")
    return np.asarray(image)


def grid(rows: Sequence[Sequence[np.ndarray]], title: str = "") -> np.ndarray:
    """Rows of panels as one RGB image, each row's panels side by side, shorter rows padded with white; ``title`` in a
    band above them all."""
    width = max(len(row) for row in rows) * CELL
    stacked = [np.hstack([*row, np.full((HEIGHT, width - len(row) * CELL, 3), 255, np.uint8)]) for row in rows]
    if not title:
        return np.vstack(stacked)
    band = Image.fromarray(np.full((BAND, width, 3), 255, np.uint8))
    write(ImageDraw.Draw(band), (8, 6), [(title, INK, FONT + 4)], width - 16)
    return np.vstack([np.asarray(band), *stacked])
