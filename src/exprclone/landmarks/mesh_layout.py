"""MediaPipe's 468-point face mesh as data: its contours, and the table that gives dlib's 68 points from it.

The method runs on the 68-point layout (:data:`exprclone.landmarks.layout.DLIB68`); the mesh
landmarker (:mod:`exprclone.landmarks.facemesh`) hands it 68 points made from its 468 by
:data:`MESH_TO_68`: each of the 68 is one mesh point, or a fixed convex combination
of two or three. The contours name the mesh points along each feature (MediaPipe's
``face_mesh_connections``), subject's right first (on the image's left).
"""

from __future__ import annotations

import numpy as np

from .layout import weight_matrix

#: the mesh's points.
MESH_POINTS = 468
#: the outer eye corners (subject's right, left): the mesh's horizontal axis.
MESH_EYE_CORNERS = (33, 263)
#: the face's outline, from the forehead's top round the subject's left cheek, the chin and back.
FACE_OVAL = (
    *(10, 338, 297, 332, 284, 251, 389, 356, 454, 323, 361, 288, 397, 365, 379, 378, 400, 377),
    *(152, 148, 176, 149, 150, 136, 172, 58, 132, 93, 234, 127, 162, 21, 54, 103, 67, 109),
)
#: the brows, outer end to inner end (the subject's right, then left), lower and upper edge.
BROWS = ((46, 53, 52, 65, 55, 70, 63, 105, 66, 107), (276, 283, 282, 295, 285, 300, 293, 334, 296, 336))
#: each eye's upper and lower lid, from its outer corner to its inner one (the subject's right, then left).
EYE_LIDS = (
    ((33, 246, 161, 160, 159, 158, 157, 173, 133), (33, 7, 163, 144, 145, 153, 154, 155, 133)),
    ((263, 466, 388, 387, 386, 385, 384, 398, 362), (263, 249, 390, 373, 374, 380, 381, 382, 362)),
)
#: the nose: the bridge down the midline to the tip and the columella, then the base and the wings.
NOSE = (168, 6, 197, 195, 5, 4, 1, 19, 94, 2, 98, 97, 326, 327, 64, 48, 115, 220, 45, 275, 440, 344, 278, 294, 60, 99, 240, 290, 328, 460)
#: the outer lips' upper and lower contours, right mouth corner (61) to left (291).
OUTER_LIPS = ((61, 185, 40, 39, 37, 0, 267, 269, 270, 409, 291), (61, 146, 91, 181, 84, 17, 314, 405, 321, 375, 291))
#: the inner lips' upper and lower contours, right inner corner (78) to left (308).
INNER_LIPS = ((78, 191, 80, 81, 82, 13, 312, 311, 310, 415, 308), (78, 95, 88, 178, 87, 14, 317, 402, 318, 324, 308))


#: for each of dlib's 68 points: ((mesh index, weight), ...), weights summing to 1. Derived by
#: ``tools/derive_mesh_map.py`` (its notes say how) on 48 of the London Set's 72 people; on the 24
#: held out, the 68 points are 0.031 outer-eye distances from the manual templates on average
#: (dlib: 0.029; :mod:`exprclone.evaluation.accuracy`).
MESH_TO_68 = (
    ((127, 0.785), (162, 0.215)),  # 0
    ((234, 1.0),),  # 1
    ((93, 1.0),),  # 2
    ((58, 0.406), (132, 0.594)),  # 3
    ((172, 0.536), (58, 0.464)),  # 4
    ((150, 0.123), (136, 0.877)),  # 5
    ((149, 0.697), (150, 0.303)),  # 6
    ((148, 0.215), (176, 0.785)),  # 7
    ((152, 1.0),),  # 8
    ((400, 0.547), (377, 0.453)),  # 9
    ((379, 0.357), (378, 0.643)),  # 10
    ((365, 1.0),),  # 11
    ((288, 0.485), (397, 0.515)),  # 12
    ((361, 0.567), (288, 0.433)),  # 13
    ((323, 0.709), (361, 0.291)),  # 14
    ((454, 1.0),),  # 15
    ((389, 0.21), (356, 0.79)),  # 16
    ((70, 1.0),),  # 17
    ((70, 0.248), (63, 0.752)),  # 18
    ((105, 0.792), (66, 0.208)),  # 19
    ((66, 0.757), (107, 0.243)),  # 20
    ((107, 1.0),),  # 21
    ((336, 1.0),),  # 22
    ((296, 0.671), (336, 0.329)),  # 23
    ((334, 0.681), (296, 0.319)),  # 24
    ((293, 1.0),),  # 25
    ((300, 1.0),),  # 26
    ((168, 1.0),),  # 27
    ((4, 0.31), (6, 0.69)),  # 28
    ((4, 0.492), (197, 0.508)),  # 29
    ((5, 0.649), (19, 0.351)),  # 30
    ((64, 0.48), (99, 0.52)),  # 31
    ((2, 0.223), (97, 0.777)),  # 32
    ((1, 0.187), (2, 0.813)),  # 33
    ((2, 0.172), (326, 0.828)),  # 34
    ((294, 0.487), (328, 0.513)),  # 35
    ((33, 1.0),),  # 36
    ((160, 0.683), (159, 0.317)),  # 37
    ((158, 0.813), (157, 0.187)),  # 38
    ((133, 1.0),),  # 39
    ((153, 1.0),),  # 40
    ((144, 1.0),),  # 41
    ((362, 1.0),),  # 42
    ((385, 0.63), (384, 0.37)),  # 43
    ((387, 0.467), (386, 0.533)),  # 44
    ((263, 1.0),),  # 45
    ((373, 0.683), (374, 0.317)),  # 46
    ((380, 0.855), (381, 0.145)),  # 47
    ((61, 1.0),),  # 48
    ((40, 0.271), (39, 0.729)),  # 49
    ((37, 1.0),),  # 50
    ((0, 1.0),),  # 51
    ((267, 1.0),),  # 52
    ((269, 0.613), (270, 0.387)),  # 53
    ((291, 1.0),),  # 54
    ((405, 0.626), (321, 0.374)),  # 55
    ((314, 1.0),),  # 56
    ((17, 1.0),),  # 57
    ((84, 1.0),),  # 58
    ((91, 0.431), (181, 0.569)),  # 59
    ((78, 1.0),),  # 60
    ((81, 0.473), (82, 0.527)),  # 61
    ((13, 1.0),),  # 62
    ((312, 0.807), (311, 0.193)),  # 63
    ((308, 1.0),),  # 64
    ((317, 1.0),),  # 65
    ((14, 1.0),),  # 66
    ((178, 0.416), (87, 0.584)),  # 67
)


_WEIGHTS = weight_matrix(MESH_TO_68, MESH_POINTS)


def to_68(mesh: np.ndarray) -> np.ndarray:
    """The 68 points of :data:`exprclone.landmarks.layout.DLIB68` from the mesh's 468 (:data:`MESH_TO_68`).

    Parameters
    ----------
    mesh : ndarray of shape (468, 2)

    Returns
    -------
    ndarray of shape (68, 2), float64

    Examples
    --------
    >>> points = to_68(np.tile(np.arange(468.0)[:, None], 2))
    >>> points.shape, points[8].tolist(), points[36].tolist()
    ((68, 2), [152.0, 152.0], [33.0, 33.0])
    """
    return _WEIGHTS @ mesh
