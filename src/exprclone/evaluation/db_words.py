"""The elasticity ratio and the DB metric's choice of it, in words, for the comparison sheet (:mod:`.figures`).

:func:`lambda_words`: what lambda_k does, how far LI lies from GI, and who chose the value. :func:`terms_words`: the
two terms of Eq. (7) at lambda_k = 0 (GI), at the value chosen and at LI, and why that one won: along the way from GI
to LI the second term rises from 1 as ``exp(d_GI)`` while the first falls from ``exp(d_source(0))`` as the candidate
nears the source; a first step towards LI lowers DB only when LI lies towards the source at a cosine above
``exp(-d_source(0))`` (the cosine read from the chord: ``(d_source(0) - d_source(LI)) / d_GI(LI)``).
"""

from __future__ import annotations

import numpy as np

from ..landmarks import align
from ..pipeline.result import CloneResult
from ..roles import TARGET_NEUTRAL


def lambda_words(result: CloneResult) -> list[str]:
    """What lambda_k does in the elastic model's ``result``, how far apart GI and LI are, and how its value came."""
    lm = result.landmarks
    shift = float(np.linalg.norm(lm["local"] - lm["global"], axis=1).max())
    iod = align.interocular(lm[TARGET_NEUTRAL], result.options.landmarks_layout) if result.options is not None else 1.0
    said = [
        "lambda_k = k_A' / k_N (Eq. 6) weighs LI against GI in (c), (f), (g): 0 keeps GI, inf gives LI.",
        f"LI moves a landmark up to {shift / iod:.3f} eye distances ({shift:.1f} px) from GI.",
    ]
    if result.db_curve is not None:
        return [*said, f"The DB metric (Eqs. 7-8) chose {result.db_curve.best:g} of {len(result.db_curve.lambdas)} candidates."]
    if shift == 0:
        return [*said, "Nothing to balance: every lambda_k gives GI, and none is chosen."]
    return [*said, f"Given: {result.lambda_k:g}."]


def terms_words(result: CloneResult) -> list[str | tuple[str, tuple[int, int, int]]]:
    """Eq. (7)'s two terms at lambda_k = 0, at the value chosen and at LI, and why the chosen one won."""
    curve = result.db_curve
    if curve is None:
        return ["No DB curve: lambda_k was given, or LI is GI."]
    best = int(np.flatnonzero(curve.lambdas == curve.best)[0])
    said: list[str | tuple[str, tuple[int, int, int]]] = [
        "DB = e^ds + e^dg (Eq. 7): ds to the source's expression, dg to GI, in units of one person's smile from their own neutral face."
    ]
    for k, name in sorted({0: "0 (GI)", best: f"{curve.best:g}, chosen", len(curve.lambdas) - 1: "inf (LI)"}.items()):
        ds, dg = curve.to_source[k], curve.to_global[k]
        line = f"lambda_k {name}: e^{ds:.2f} + e^{dg:.2f} = {np.exp(ds):.2f} + {np.exp(dg):.2f} = {curve.db[k]:.2f}"
        said.append((line, (220, 0, 0)) if k == best else line)
    ds0, ds_li, dg_li = curve.to_source[0], curve.to_source[-1], curve.to_global[-1]
    if best == 0:
        cos = (ds0 - ds_li) / max(dg_li, 1e-12)
        why = f"LI lies at cosine {cos:.2f} towards the source; a step from GI lowers DB only above e^-{ds0:.2f} = {np.exp(-ds0):.2f}."
        return [*said, why]
    gain, cost = np.exp(ds0) - np.exp(curve.to_source[best]), np.exp(curve.to_global[best]) - 1
    return [*said, f"The first term falls by {gain:.2f} from GI, the second rises by {cost:.2f}: less in all."]
