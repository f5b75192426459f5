"""Teeth and mouth cavity in white light: a prior for the pasted mouth interior, and how far to trust the driver's light.

Not in the paper: it serves the mouth interior (:mod:`exprclone.mouth.measure`), whose colour is
mapped from the source's light to the target's by the cues to the light on both faces
(:mod:`exprclone.mouth.illuminant`). Where the source's light cannot be read well (a small,
compressed video under a strong lamp: few cue pixels, clipped, or cues that disagree)
the map leaves some of that light in the mouth: on the GRID clips lit orange the pasted
interior came out olive-yellow on a white-lit portrait. Real smiles tell what a mouth
interior looks like: on the London Set (one studio, one light, taken as white) the
colour of people's teeth differs little from one person to the next
(:data:`TEETH_SPREAD`, a third of the spread of their relation to their own cheeks),
that of the cavity more (:data:`CAVITY_SPREAD`); both as read on a mouth of the
source's size (:func:`prior_colour`).

So the teeth and the cavity the source shows (:class:`Interior`) give a second estimate
of the paste's colour: each part of the prior's colour under the target's light, read
against the London studio's (:func:`white_light`). The two estimates are averaged by
their variances (:func:`pull`), in log colour (the log channels less their mean, which a
change of brightness leaves alone):

- the transfer's: that of its reading of the source's light
  (:func:`exprclone.mouth.illuminant.log_gain`: the cues' spread between people, their
  pixels' noise and number, how open the eyes are, and the cues' disagreement), plus
  the excess disagreement below;
- the prior's: the spread of the part between people.

The source's part taken back to white light by its own light's reading is compared
with the prior: the part of their squared distance that neither variance explains is
put on the source's light (a random-effects estimate, as DerSimonian and Laird's): real
teeth rarely stray beyond the measured spread, and a light read from a few compressed,
clipped pixels can. The pull toward the prior so grows continuously with the evidence
that the light was misread, and is weaker where the lights are well read (a studio
photo). The paste's pixels take the pull of the part whose brightness they have
(:func:`recolour`). Brightness is left to the transfer: the prior is of colour only.

References
----------
R. DerSimonian and N. Laird, "Meta-analysis in clinical trials", Controlled Clinical
Trials 7(3), 1986.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import illuminant

#: the London studio's light, taken as white: the mean log RGB of the skin cue and of the
#: eye whites (:class:`exprclone.mouth.illuminant.Light`) on the Set's 72 neutral photos
#: (``tools/teeth_prior.py``).
WHITE_SKIN = (5.184, 4.958, 4.842)
WHITE_SCLERA = (5.071, 4.987, 4.978)
#: the number of photos those means are taken over.
WHITE_PHOTOS = 72
#: teeth in that light: the mean log colour (log RGB less its mean) of the
#: :func:`~exprclone.mouth.illuminant.midmean` of the teeth pixels (:func:`exprclone.mouth.measure.interior`,
#: unclipped) of the London smiles that show teeth, by the width of their mouth in pixels
#: (``tools/teeth_prior.py``): shrunk to that width and saved as JPEGs (colour at half
#: resolution, as video codecs keep it), and at their own size (the last row, the median
#: width). A small, compressed mouth blends the teeth's colour with the lips': its
#: teeth read redder. Relative to the cheeks of the same smiles (the skin cue) they are
#: (-0.14, 0.03, 0.11): much less red and more blue than skin.
WIDTHS = (30.0, 45.0, 70.0, 110.0, 170.0, 200.0)
TEETH_COLOURS = (
    (0.092, -0.031, -0.060),
    (0.085, -0.025, -0.059),
    (0.078, -0.018, -0.060),
    (0.070, -0.013, -0.057),
    (0.066, -0.012, -0.054),
    (0.063, -0.012, -0.052),
)
#: between-people standard deviation of that log colour, per degree of freedom (0.019 to
#: 0.023 over the widths; of the relation to the cheeks: 0.065, three times as much).
TEETH_SPREAD = 0.021
#: the mouth's cavity (:func:`exprclone.mouth.measure.interior`) in that light, the same way:
#: dark red (tongue, gums, shadow). Smiles show little of it: at 45 px, 7 smiles show
#: enough, at 30 px none, where the 45 px row is repeated.
CAVITY_COLOURS = (
    (0.385, -0.171, -0.214),
    (0.385, -0.171, -0.214),
    (0.350, -0.175, -0.175),
    (0.330, -0.161, -0.169),
    (0.307, -0.145, -0.162),
    (0.303, -0.141, -0.162),
)
#: its spread at the photos' own size, on 35 smiles (0.053 to 0.086 over the widths, the
#: most on the 7 smiles at 45 px).
CAVITY_SPREAD = 0.058


def white_light() -> illuminant.Light:
    """The London studio's cues to the light: :data:`WHITE_SKIN` and :data:`WHITE_SCLERA`, means of :data:`WHITE_PHOTOS` people."""
    spread = np.square([illuminant.SKIN_SPREAD, illuminant.SCLERA_SPREAD])
    return illuminant.Light(np.array([WHITE_SKIN, WHITE_SCLERA]), spread / WHITE_PHOTOS)


def prior_colour(width: float, colours: tuple[tuple[float, float, float], ...] = TEETH_COLOURS) -> np.ndarray:
    """A part's log colour in white light, as read on a mouth ``width`` pixels wide.

    ``colours`` by :data:`WIDTHS`, linear in the log of the width, held beyond
    them, and less their mean (the printed values are rounded).

    Examples
    --------
    >>> np.allclose(prior_colour(45.0), TEETH_COLOURS[1], atol=1e-3), np.allclose(prior_colour(5000.0), TEETH_COLOURS[-1], atol=1e-3)
    (True, True)
    """
    at = np.log(np.clip(width, WIDTHS[0], WIDTHS[-1]))
    return illuminant.split(np.array([np.interp(at, np.log(WIDTHS), channel) for channel in np.transpose(colours)]))[1]


@dataclass(frozen=True)
class Part:
    """The colour of a part of the mouth interior (teeth, or cavity) as a source shows it, and how well it is read.

    Attributes
    ----------
    log_colour : ndarray of shape (3,)
        Log colour (:func:`exprclone.mouth.illuminant.split`) of its pixels'
        :func:`~exprclone.mouth.illuminant.midmean`.
    brightness : float
        Log brightness of that midmean.
    variance : float
        Variance of the log colour's reading per degree of freedom (its pixels' spread
        over their number).
    quartiles : tuple of float
        The first and third quartiles of its pixels' log brightness.
    """

    log_colour: np.ndarray
    brightness: float
    variance: float
    quartiles: tuple[float, float]

    @classmethod
    def read(cls, pixels: np.ndarray) -> Part | None:
        """Read pixels ``(K, 3)`` uint8 (clipped ones left out, :func:`exprclone.mouth.illuminant.read`); None when too few.

        Examples
        --------
        >>> part = Part.read(np.tile(np.array([[200, 190, 180]], np.uint8), (20, 1)))
        >>> np.exp(part.log_colour).round(3).tolist(), round(float(np.exp(part.brightness))), part.variance
        ([1.054, 1.001, 0.948], 190, 0.0)
        >>> np.exp(part.quartiles).round().tolist()
        [190.0, 190.0]
        >>> Part.read(np.full((20, 3), 255, np.uint8)) is None
        True
        """
        colour, variance = illuminant.read(pixels)
        if not np.isfinite(variance[1]):
            return None
        brightness, log_colour = illuminant.split(colour)
        shades = illuminant.split(np.log(np.maximum(pixels[pixels.max(1) < illuminant.SATURATED], 1).astype(np.float32)))[0]
        low, high = np.percentile(shades, [25, 75])
        return cls(log_colour, float(brightness), float(variance[1]), (float(low), float(high)))


@dataclass(frozen=True)
class Interior:
    """The teeth and the cavity a source shows (either None when it shows too few), on a mouth ``width`` pixels wide."""

    teeth: Part | None
    cavity: Part | None
    width: float

    @classmethod
    def read(cls, pixels: tuple[np.ndarray, np.ndarray], width: float) -> Interior:
        """Read the teeth pixels and the cavity pixels (``(K, 3)`` uint8 each, :func:`exprclone.mouth.measure.interior`)."""
        return cls(Part.read(pixels[0]), Part.read(pixels[1]), float(width))

    def priors(self, width: float) -> tuple[tuple[Part | None, np.ndarray, np.ndarray, float], ...]:
        """Each part with its prior colour (:func:`prior_colour`) on the source's mouth and on one ``width`` pixels wide, and its spread."""
        return (
            (self.teeth, prior_colour(self.width, TEETH_COLOURS), prior_colour(width, TEETH_COLOURS), TEETH_SPREAD),
            (self.cavity, prior_colour(self.width, CAVITY_COLOURS), prior_colour(width, CAVITY_COLOURS), CAVITY_SPREAD),
        )


def pull(
    part: Part, prior: np.ndarray, spread: float, target: illuminant.Light, source: illuminant.Light, aim: np.ndarray | None = None
) -> tuple[np.ndarray, float]:
    """The log colour gain that gives one part its prior colour under the target's light, and how far to pull toward it.

    The source's part is taken to white light by the reading of the source's light
    against the London studio's (:func:`white_light`, :func:`exprclone.mouth.illuminant.log_gain`,
    variance ``v``, with the part's own reading's ``r``) and compared with ``prior``:
    of their squared distance per degree of freedom ``d``, the excess
    ``e = max(0, d - (v + r + s))`` over what the three variances explain (``s``, the
    prior's: ``spread`` squared) is put on the source's light. The pull is
    ``w = (v + r + e) / (v + r + e + s)``: the transfer's variance over the sum of the
    two estimates'. The target's light is read alike in both, and does not weigh.
    The colour given is ``aim`` when given: the prior as read on the output's mouth,
    whose size is not the source's (a small, compressed source mouth reads its teeth
    redder, mixed with its lips, than the pasted teeth, enlarged, should be).

    Parameters
    ----------
    part : Part
        The source's teeth, or cavity, in the source's light.
    prior : ndarray of shape (3,)
        Its log colour in white light (:func:`prior_colour`).
    spread : float
        Its between-people standard deviation, per degree of freedom.
    target, source : illuminant.Light
        The cues on the target photo and on the source's.
    aim : ndarray of shape (3,), optional
        The log colour in white light to give the part (default ``prior``).

    Returns
    -------
    wanted : ndarray of shape (3,)
        The log colour gain that gives the part the colour ``aim`` under the target's light.
    w : float
        The pull, in [0, 1].

    Examples
    --------
    A source under an orange light whose cues say white: its teeth read orange against
    the prior, the gain wanted undoes the orange (``1 / (1, 0.8, 0.5)`` less its
    brightness), and the pull is nearly whole:

    >>> white, prior = white_light(), prior_colour(40.0)
    >>> orange = Part(illuminant.split(prior + np.log([1.0, 0.8, 0.5]))[1], 4.0, 1e-5, (4.0, 4.0))
    >>> wanted, w = pull(orange, prior, TEETH_SPREAD, white, white)
    >>> np.exp(wanted).round(2).tolist(), round(w, 3)
    ([0.74, 0.92, 1.47], 0.996)
    """
    cast_target = illuminant.split(illuminant.log_gain(target, white_light())[0])[1]
    cast_source, variance = illuminant.log_gain(source, white_light())
    in_white = part.log_colour - illuminant.split(cast_source)[1]
    known = variance + part.variance
    excess = max(0.0, float(np.square(in_white - prior).sum()) / 2 - (known + spread**2))
    w = (known + excess) / (known + excess + spread**2) if np.isfinite(known) else 1.0
    return (prior if aim is None else aim) + cast_target - part.log_colour, float(w)


def recolour(
    patch: np.ndarray, log_gain: np.ndarray, interior: Interior, target: illuminant.Light, source: illuminant.Light, width: float
) -> np.ndarray:
    """Source pixels times the transfer's gain, their colour pulled toward real teeth's and cavity's (:func:`pull`).

    A pixel as bright as the teeth or brighter is pulled as the teeth are: its colour
    gain moves by ``w`` toward the one that gives them their prior colour, and keeps
    its difference from the teeth's colour (stains, glints). One as dark as the cavity
    or darker is pulled as the cavity is, but by its own colour: it moves by ``w``
    toward the cavity's prior colour itself, since a dark pixel's own colour says little
    (on the orange-lit GRID clip lbax4n the cavity's blue is 5 of 255, and a gain that
    gave it a colour would make its noise purple). Each part is given its prior colour as
    read on the output's mouth (``width``). "As bright as the teeth" is from the teeth's
    first quartile of brightness up, "as dark as the cavity" from its third quartile
    down; between the two, the pull changes linearly with the log brightness (:func:`exprclone.mouth.illuminant.split`, which a
    light's brightness shifts alike for every pixel). With one part read, its pull
    applies to every pixel; with none, the gain alone. Brightness is the transfer's:
    the pulls are of colour only.

    Parameters
    ----------
    patch : ndarray of shape (h, w, 3), float32
        Source pixels.
    log_gain : ndarray of shape (3,)
        The transfer's log gain from the source's light to the target's.
    interior : Interior
        The source's teeth and cavity, in the source's light.
    target, source : illuminant.Light
    width : float
        The output's mouth width in pixels (:func:`exprclone.mouth.measure.mouth_width`).

    Returns
    -------
    ndarray of shape (h, w, 3), float32
    """
    colour = illuminant.split(log_gain)[1]
    brightness, own = illuminant.split(np.log(np.maximum(patch, 1.0)))
    pulls = []
    for part, prior, aim, spread in interior.priors(width):
        if part is not None:
            wanted, w = pull(part, prior, spread, target, source, aim)
            kept = 0.0 if part is interior.teeth else own - part.log_colour  # a dark pixel's own colour says little
            pulls.append((part, w * (wanted - colour - kept)))
    if not pulls:
        return patch * np.exp(log_gain).astype(np.float32)
    (top, top_pull), (bottom, bottom_pull) = pulls[0], pulls[-1]
    high, low = top.quartiles[0], bottom.quartiles[1]
    share = np.clip((brightness - low) / (high - low), 0.0, 1.0)[..., None] if high > low else 1.0
    return (patch * np.exp(log_gain + bottom_pull + share * (top_pull - bottom_pull))).astype(np.float32)
