"""The blendshape judge: how close a result's expression is to the one asked for, region by region.

Every judge of ``exprclone evaluate`` but this one is a smile judge. This one reads the 52
blendshape scores of MediaPipe's Face Landmarker (:mod:`exprclone.landmarks.blendshapes`) on
the result, on the source's expression photo and, where there is one, on the target's real
expression, and says:

* **the distance to the source's expression**: the Euclidean distance between the result's
  scores and the source expression photo's, over each region's names
  (:data:`exprclone.landmarks.blendshapes.REGIONS`: mouth, eyes, brows) and over all of them
  (the gaze left out); the total's square is the sum of the regions' squares. Two people's
  faces differ at rest too: the target's neutral photo (``no change``) and its real smile
  (``real``) give the floor and the spread of real faces on the same scale;
* **the distance to the target's real expression**, the same way;
* **the change against the source's**: the same distance between the result's change from the
  target's neutral photo and the source's change from its own (expression minus neutral, score by
  score). People's faces at rest score apart (on the London Set two people's neutral photos lie
  0.75 apart in total, as far as a smile is from its own neutral face, 0.97: ``mouthShrugLower``,
  ``mouthPucker`` and the brows differ most), and a clone that keeps the target's face keeps that
  difference: this distance leaves it out, and measures the motion alone;
* **the rise kept**: of the :data:`RISE_TOP` scores the source raises most from its neutral
  photo to its expression, how much the result raises them from the target's neutral photo,
  as a share of the source's rise (sum over those scores of result minus target neutral, over
  the sum of source expression minus source neutral): 1 where the clone moves the face as the
  source moved its own, 0 where it does not move it.

Distances are in score units (each score runs from 0 to 1). The blendshape model reads the
landmarks the mesh places, not the pixels: it sees the shape of an expression, and its shading
only where that moves a landmark.
"""

from __future__ import annotations

import numpy as np

from ..landmarks.blendshapes import EXPRESSION, REGIONS, indices

#: the source's most raised scores the rise kept is measured on (issue 57's "four expression scores each source raises most").
RISE_TOP = 4
#: a source whose top scores rise by less than this in all (a face that barely moves) has no rise to keep: NaN.
MIN_RISE = 0.1
#: the judge's columns in ``pairs.csv``: the distances to the source's expression and to the target's real one, and of
#: the result's change to the source's, per region and in total; and the rise kept.
COLUMNS = (
    *(f"to_source_{region}" for region in REGIONS),
    "to_source",
    *(f"to_real_{region}" for region in REGIONS),
    "to_real",
    *(f"change_{region}" for region in REGIONS),
    "change",
    "rise_kept",
)
#: each region's names' places among the 52 scores, and every region's ("total").
PLACES = {**{region: indices(names) for region, names in REGIONS.items()}, "total": indices(EXPRESSION)}


def distances(a: np.ndarray, b: np.ndarray) -> dict[str, float]:
    """The Euclidean distance between two faces' scores ``(52,)`` over each region's names and over all (``total``).

    >>> from exprclone.landmarks.blendshapes import NAMES
    >>> a, b = np.zeros(52), np.zeros(52)
    >>> b[NAMES.index("jawOpen")], b[NAMES.index("browInnerUp")] = 0.3, 0.4
    >>> {k: round(v, 3) for k, v in distances(a, b).items()}
    {'mouth': 0.3, 'eyes': 0.0, 'brows': 0.4, 'total': 0.5}
    """
    return {region: float(np.linalg.norm(a[places] - b[places])) for region, places in PLACES.items()}


def rise_kept(source_neutral: np.ndarray, source_expression: np.ndarray, target_neutral: np.ndarray, result: np.ndarray) -> float:
    """How much of the source's rise the result makes on the target: over the :data:`RISE_TOP` expression scores the
    source raises most, the sum of ``result - target_neutral`` over the sum of ``source_expression - source_neutral``;
    NaN when the source's sum is under :data:`MIN_RISE`.

    >>> from exprclone.landmarks.blendshapes import NAMES
    >>> rest, smile = np.zeros(52), np.zeros(52)
    >>> smile[NAMES.index("mouthSmileLeft")] = smile[NAMES.index("mouthSmileRight")] = 0.6
    >>> rise_kept(rest, smile, rest, smile / 2), rise_kept(rest, smile, rest, rest)
    (0.5, 0.0)
    """
    places = np.array(PLACES["total"])
    rise = source_expression[places] - source_neutral[places]
    top = places[np.argsort(-rise, kind="stable")[:RISE_TOP]]
    asked = float(np.sum(source_expression[top] - source_neutral[top]))
    return float(np.sum(result[top] - target_neutral[top]) / asked) if asked >= MIN_RISE else float("nan")


#: a person's neutral and expression scores, each None where no face was found.
Faces = tuple[np.ndarray | None, np.ndarray | None]


def judged(result: np.ndarray | None, source: Faces, target: Faces) -> dict[str, float | str]:
    """The judge's :data:`COLUMNS` for one result's scores: ``source`` and ``target`` are each person's neutral and
    expression scores (the target's expression is its real one); ``""`` where a face was not scored (no face found)."""
    out: dict[str, float | str] = dict.fromkeys(COLUMNS, "")
    if result is None:
        return out
    for name, other in (("to_source", source[1]), ("to_real", target[1])):
        if other is not None:
            out.update(_columns(name, distances(result, other)))
    (source_neutral, source_expression), target_neutral = source, target[0]
    if source_neutral is not None and source_expression is not None and target_neutral is not None:
        out.update(_columns("change", distances(result - target_neutral, source_expression - source_neutral)))
        kept = rise_kept(source_neutral, source_expression, target_neutral, result)
        out["rise_kept"] = "" if np.isnan(kept) else round(kept, 4)
    return out


def _columns(name: str, found: dict[str, float]) -> dict[str, float | str]:
    """:func:`distances`' output as the columns ``NAME_mouth``, ``NAME_eyes``, ``NAME_brows`` and ``NAME`` (the total)."""
    return {**{f"{name}_{region}": round(found[region], 4) for region in REGIONS}, name: round(found["total"], 4)}
