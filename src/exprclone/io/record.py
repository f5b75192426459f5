"""The JSON record of a clone (``--save-json``, the API's ``?format=json``): what went in and every stage's landmarks."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL

if TYPE_CHECKING:
    import numpy as np

    from ..pipeline.result import CloneResult, FaceResult


def json_number(value: float | str | None) -> float | str | None:
    """A number for JSON: infinity as the string ``"inf"`` (JSON has none); a string (``"auto"``) or None as it is."""
    if value is None or isinstance(value, str):
        return value
    return "inf" if math.isinf(value) else float(value)


def result_record(result: CloneResult, inputs: dict[str, str]) -> dict[str, Any]:
    """The record of a :class:`~exprclone.pipeline.result.CloneResult`.

    Parameters
    ----------
    result : CloneResult
    inputs : dict of str to str
        Each photo's role (``source_neutral``, ...) and what it was (a file name).

    Returns
    -------
    dict
        ``inputs``, ``method``, ``landmarker`` (which placed the photos' landmarks, null when
        all were given), ``options`` (``global_warp``: similarity, rbf, vtc or given;
        ``image_warp``, ``strength``, ``only``, ``retarget``), ``lambda_k``, ``db_curve`` (lambda_k, DB
        and its two distances of Eq. 7, to the source's expression and to GI in the eigenface basis's unit, of each
        candidate), ``muscle_strengths``, ``unfolded_points``, ``warnings`` (what looked
        wrong with the inputs, :func:`exprclone.pipeline.role_check.judge_roles`), ``landmarks`` (of each stage, to 1/1000 pixel)
        and ``faces``: for a photo of several faces, each one's ``number``, ``box``, ``region``, ``problem`` (why it was
        left as it is), ``lambda_k`` and ``landmarks`` (in the photo's pixels; those of the source's photos in theirs);
        empty for a photo of one.
    """
    curve, options = result.db_curve, result.options
    return {
        "inputs": dict(inputs),
        "method": result.method,
        "landmarker": result.landmarker,
        "options": {
            "global_warp": options.global_stage,
            "image_warp": options.image_warp,
            "strength": options.strength,
            "only": None if options.only is None else list(options.only),
            "region_strengths": options.region_strengths,
            "strength_shading": options.strength_shading,
            "retarget": options.retarget,
        },
        "lambda_k": json_number(result.lambda_k),
        "db_curve": None
        if curve is None
        else [
            {"lambda_k": json_number(lam), "db": float(db), "to_source": float(ds), "to_global": float(dg)}
            for lam, db, ds, dg in zip(curve.lambdas, curve.db, curve.to_source, curve.to_global)
        ],
        "muscle_strengths": None if result.muscle_strengths is None else [float(h) for h in result.muscle_strengths],
        "unfolded_points": result.unfolded_points,
        "warnings": list(result.warnings),
        "landmarks": _landmarks(result.landmarks),
        "faces": [_face(face) for face in result.face_results],
    }


def _landmarks(landmarks: dict[str, np.ndarray], shift: tuple[int, int] = (0, 0)) -> dict[str, list[list[float]]]:
    """Each stage's landmarks to 1/1000 pixel, those in the target's photo moved by ``shift`` (a region's corner)."""
    sources = (SOURCE_NEUTRAL, SOURCE_EXPRESSION)
    return {k: (v if k in sources else v + shift).round(3).tolist() for k, v in landmarks.items()}


def _face(face: FaceResult) -> dict[str, Any]:
    """One face of a photo of several: its number, box, region, why it was left as it is, and its clone's lambda_k and
    landmarks (in the photo's pixels; the photos of the source its own)."""
    done = face.result
    return {
        "number": face.number,
        "box": [round(v, 1) for v in face.box],
        "region": list(face.region),
        "problem": face.problem,
        "lambda_k": None if done is None else json_number(done.lambda_k),
        "landmarks": None if done is None else _landmarks(done.landmarks, face.region[:2]),
    }
