"""The Face Research Lab 189-point template (WebMorph / Psychomorph) mapped to the 68-point layout.

The London Set ships a manual 189-point template for each neutral photo (points 0 and 1
are the pupils). Each of dlib's 68 points is a fixed template point or a fixed convex
combination of two neighbouring ones, fitted by ``tools/derive_frl_map.py``: for every
dlib index, the template point (or pair and weight) whose position has the smallest
median distance to dlib's detection over the 72 neutral photos, in inter-pupil
distances. Measured there: median 0.021, 90th percentile 0.054 for the inner face
(brows, eyes, nose, lips, points 17-67); the jaw contour (0-16), which dlib and the
template sample differently, median 0.056, 90th percentile 0.13; the nose tip (30),
0.10, as dlib places it lower than the template. The templates show closed mouths, on
which the upper and lower inner lips coincide, so the fit cannot tell them apart: the
inner-lip rows hold for closed mouths only.
"""

from __future__ import annotations

import numpy as np

#: for each of the 68 points: ((template index, weight), ...), weights summing to 1.
FRL189_TO_DLIB68 = (
    ((109, 0.9), (164, 0.1)),  # 0
    ((110, 0.45), (185, 0.55)),  # 1
    ((186, 0.7), (111, 0.3)),  # 2
    ((111, 0.45), (125, 0.55)),  # 3
    ((126, 0.5), (125, 0.5)),  # 4
    ((126, 0.5), (127, 0.5)),  # 5
    ((145, 0.55), (176, 0.45)),  # 6
    ((128, 0.9), (183, 0.1)),  # 7
    ((129, 1.0),),  # 8
    ((130, 0.75), (129, 0.25)),  # 9
    ((131, 0.55), (130, 0.45)),  # 10
    ((131, 0.5), (132, 0.5)),  # 11
    ((132, 0.75), (133, 0.25)),  # 12
    ((133, 0.55), (114, 0.45)),  # 13
    ((188, 0.8), (114, 0.2)),  # 14
    ((113, 0.75), (167, 0.25)),  # 15
    ((112, 1.0),),  # 16
    ((71, 0.9), (134, 0.1)),  # 17
    ((72, 0.75), (73, 0.25)),  # 18
    ((73, 0.6), (74, 0.4)),  # 19
    ((74, 0.75), (75, 0.25)),  # 20
    ((75, 1.0),),  # 21
    ((78, 1.0),),  # 22
    ((79, 0.6), (78, 0.4)),  # 23
    ((80, 0.65), (79, 0.35)),  # 24
    ((81, 0.8), (80, 0.2)),  # 25
    ((82, 0.9), (144, 0.1)),  # 26
    ((50, 0.55), (56, 0.45)),  # 27
    ((52, 0.55), (57, 0.45)),  # 28
    ((53, 0.5), (59, 0.5)),  # 29
    ((54, 0.7), (180, 0.3)),  # 30
    ((64, 0.65), (65, 0.35)),  # 31
    ((64, 0.4), (180, 0.6)),  # 32
    ((181, 0.55), (170, 0.45)),  # 33
    ((172, 0.7), (182, 0.3)),  # 34
    ((69, 0.6), (70, 0.4)),  # 35
    ((18, 0.85), (28, 0.15)),  # 36
    ((3, 1.0),),  # 37
    ((9, 1.0),),  # 38
    ((22, 0.8), (30, 0.2)),  # 39
    ((30, 0.55), (6, 0.45)),  # 40
    ((28, 0.65), (6, 0.35)),  # 41
    ((23, 0.85), (31, 0.15)),  # 42
    ((11, 1.0),),  # 43
    ((17, 1.0),),  # 44
    ((27, 0.8), (33, 0.2)),  # 45
    ((33, 0.65), (14, 0.35)),  # 46
    ((31, 0.65), (14, 0.35)),  # 47
    ((87, 1.0),),  # 48
    ((88, 0.75), (94, 0.25)),  # 49
    ((89, 0.9), (90, 0.1)),  # 50
    ((90, 0.8), (96, 0.2)),  # 51
    ((91, 0.85), (90, 0.15)),  # 52
    ((92, 0.9), (97, 0.1)),  # 53
    ((93, 1.0),),  # 54
    ((93, 0.35), (107, 0.65)),  # 55
    ((107, 0.7), (106, 0.3)),  # 56
    ((106, 1.0),),  # 57
    ((105, 0.75), (106, 0.25)),  # 58
    ((104, 0.7), (105, 0.3)),  # 59
    ((87, 0.6), (99, 0.4)),  # 60
    ((95, 0.9), (96, 0.1)),  # 61
    ((101, 1.0),),  # 62
    ((102, 0.8), (101, 0.2)),  # 63
    ((93, 0.6), (98, 0.4)),  # 64
    ((102, 0.8), (101, 0.2)),  # 65
    ((106, 0.1), (101, 0.9)),  # 66
    ((100, 0.85), (96, 0.15)),  # 67
)


def frl_to_68(points189: np.ndarray) -> np.ndarray:
    """The 68 dlib-layout landmarks of a 189-point template, ``(189, 2)`` -> ``(68, 2)``."""
    points189 = np.asarray(points189, float)
    return np.array([sum(w * points189[j] for j, w in row) for row in FRL189_TO_DLIB68])
