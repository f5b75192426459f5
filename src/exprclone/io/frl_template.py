"""The Face Research Lab 189-point template (WebMorph / Psychomorph) mapped to dlib's 68 points.

The London Set ships a manual 189-point template for each neutral photo (points 0 and 1 are
the pupils). :data:`FRL189_TO_DLIB68` gives, for each of dlib's 68 points (iBUG 300-W layout),
either one template point or a fixed convex combination of two template points.

Derived by ``PYTHONPATH=src python tools/derive_frl_map.py`` from the 72 neutral photos: for
each dlib index, among the template points of the same feature (jaw contour, upper brow
edge, eyelid contour, nose base, lip contours) and the convex combinations of two
neighbours on that contour (weight fitted by least squares), the one with the smallest
median distance to dlib's detection, in inter-pupil distances; a single point is kept
unless a pair lowers the median by 0.01. Eye and mouth corners, the subnasale and the chin
are pinned to the template point with the same anatomical definition. The template has no
midline nose-bridge points, so dlib's 27-30 (bridge and tip) are midpoints of the left and
right nose-side points; the eyelids use the lid contours, never the iris outline.

Measured error over all 68 points and 72 faces: median 0.028, 90th percentile 0.081
inter-pupil distances (inner face 17-67: 0.024 / 0.056; jaw 0-16: 0.057 / 0.134). The jaw
maps worst (points 4, 5, 11 and 12 have a 90th percentile of 0.14-0.18), because dlib and
the template trace the lower face outline differently. The templates show closed mouths,
so the inner-lip rows (60-67) are fitted where the upper and lower inner lips coincide.
"""

from __future__ import annotations

import numpy as np

from ..errors import ExprCloneError
from ..landmarks.layout import weight_matrix

#: for each of the 68 points: ((template index, weight), ...), weights summing to 1.
FRL189_TO_DLIB68 = (
    ((109, 1.0),),  # 0
    ((185, 0.32), (110, 0.68)),  # 1
    ((186, 1.0),),  # 2
    ((111, 0.45), (125, 0.55)),  # 3
    ((125, 0.46), (126, 0.54)),  # 4
    ((126, 0.49), (127, 0.51)),  # 5
    ((127, 0.69), (128, 0.31)),  # 6
    ((128, 1.0),),  # 7
    ((129, 1.0),),  # 8
    ((129, 0.24), (130, 0.76)),  # 9
    ((130, 0.44), (131, 0.56)),  # 10
    ((131, 0.65), (132, 0.35)),  # 11
    ((132, 0.67), (133, 0.33)),  # 12
    ((133, 0.62), (114, 0.38)),  # 13
    ((114, 0.29), (188, 0.71)),  # 14
    ((113, 0.72), (187, 0.28)),  # 15
    ((112, 1.0),),  # 16
    ((71, 1.0),),  # 17
    ((72, 1.0),),  # 18
    ((73, 0.59), (74, 0.41)),  # 19
    ((74, 0.66), (75, 0.34)),  # 20
    ((75, 1.0),),  # 21
    ((78, 1.0),),  # 22
    ((78, 0.34), (79, 0.66)),  # 23
    ((79, 0.39), (80, 0.61)),  # 24
    ((80, 0.16), (81, 0.84)),  # 25
    ((82, 1.0),),  # 26
    ((50, 0.52), (56, 0.48)),  # 27
    ((52, 0.54), (58, 0.46)),  # 28
    ((53, 0.52), (59, 0.48)),  # 29
    ((54, 0.5), (60, 0.5)),  # 30
    ((64, 0.62), (65, 0.38)),  # 31
    ((170, 1.0),),  # 32
    ((55, 1.0),),  # 33
    ((172, 1.0),),  # 34
    ((70, 0.38), (69, 0.62)),  # 35
    ((18, 1.0),),  # 36
    ((19, 0.65), (20, 0.35)),  # 37
    ((20, 0.37), (21, 0.63)),  # 38
    ((22, 1.0),),  # 39
    ((30, 0.57), (29, 0.43)),  # 40
    ((29, 0.31), (28, 0.69)),  # 41
    ((23, 1.0),),  # 42
    ((24, 0.68), (25, 0.32)),  # 43
    ((25, 0.39), (26, 0.61)),  # 44
    ((27, 1.0),),  # 45
    ((33, 0.63), (32, 0.37)),  # 46
    ((32, 0.34), (31, 0.66)),  # 47
    ((87, 1.0),),  # 48
    ((88, 1.0),),  # 49
    ((89, 1.0),),  # 50
    ((90, 1.0),),  # 51
    ((91, 1.0),),  # 52
    ((92, 1.0),),  # 53
    ((93, 1.0),),  # 54
    ((108, 0.64), (107, 0.36)),  # 55
    ((107, 0.63), (106, 0.37)),  # 56
    ((106, 1.0),),  # 57
    ((106, 0.24), (105, 0.76)),  # 58
    ((105, 0.25), (104, 0.75)),  # 59
    ((87, 0.56), (94, 0.44)),  # 60
    ((95, 1.0),),  # 61
    ((96, 1.0),),  # 62
    ((96, 0.21), (97, 0.79)),  # 63
    ((98, 0.47), (93, 0.53)),  # 64
    ((102, 0.79), (101, 0.21)),  # 65
    ((101, 1.0),),  # 66
    ((100, 1.0),),  # 67
)


_WEIGHTS = weight_matrix(FRL189_TO_DLIB68, 189)


def frl_to_68(points189: np.ndarray) -> np.ndarray:
    """The 68 dlib-layout landmarks of a Face Research Lab template.

    Parameters
    ----------
    points189 : ndarray of shape (189, 2)
        Template points (x, y), in template order.

    Returns
    -------
    ndarray of shape (68, 2), float64

    Raises
    ------
    ExprCloneError
        If ``points189`` is not of shape (189, 2).
    """
    points189 = np.asarray(points189, dtype=np.float64)
    if points189.shape != (189, 2):
        raise ExprCloneError("template", f"expected points of shape (189, 2), got {points189.shape}")
    return _WEIGHTS @ points189
