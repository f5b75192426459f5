"""The JSON record of a clone (``--save-json``, the API's ``?format=json``): what went in and every stage's landmarks."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..pipeline.cloner import CloneResult


def json_number(value: float | str | None) -> float | str | None:
    """A number for JSON: infinity as the string ``"inf"`` (JSON has none); a string (``"auto"``) or None as it is."""
    if value is None or isinstance(value, str):
        return value
    return "inf" if math.isinf(value) else float(value)


def result_record(result: CloneResult, inputs: dict[str, str]) -> dict[str, Any]:
    """The record of a :class:`~exprclone.pipeline.cloner.CloneResult`.

    Parameters
    ----------
    result : CloneResult
    inputs : dict of str to str
        Each photo's role (``source_neutral``, ...) and what it was (a file name).

    Returns
    -------
    dict
        ``inputs``, ``method``, ``landmarker`` (which placed the photos' landmarks, null when
        all were given), ``options`` (``global_warp``: similarity, rbf or given;
        ``image_warp``, ``strength``, ``only``, ``retarget``), ``lambda_k``, ``db_curve`` (lambda_k and
        DB of each candidate), ``muscle_strengths``, ``unfolded_points``, ``warnings`` (what looked
        wrong with the inputs, :func:`exprclone.pipeline.role_check.judge_roles`) and ``landmarks`` (of each stage, to 1/1000 pixel).
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
        else [{"lambda_k": json_number(lam), "db": float(db)} for lam, db in zip(curve.lambdas, curve.db)],
        "muscle_strengths": None if result.muscle_strengths is None else [float(h) for h in result.muscle_strengths],
        "unfolded_points": result.unfolded_points,
        "warnings": list(result.warnings),
        "landmarks": {k: v.round(3).tolist() for k, v in result.landmarks.items()},
    }
