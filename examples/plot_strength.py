"""
Expression strength, whole and per region
=========================================

``strength`` scales what is transferred: the landmark motion, the expression ratio image
(as ``ERI ** strength``) and the mouth interior. 0 gives the target photo exactly, 1 the
whole expression, 2 an exaggerated one. Each region has a strength of its own
(``strength_mouth``, ``strength_eyes``, ``strength_brows``; by default the whole one's), and
``strength_shading`` scales the folds and shadows alone. The same options are
``--strength-mouth`` and so on on the command line, form fields of the HTTP API, and the
sliders of the web page.
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import face_box
from exprclone.landmarks.backends import default_detector

source_neutral, source_smile, target_neutral = data.photo("126"), data.photo("126", "smile"), data.photo("001")
detector = default_detector()
points = [detector.detect(image) for image in (source_neutral, source_smile, target_neutral)]

# %%
# The clone is prepared once (:func:`exprclone.prepare`: the landmarks, the expression, the
# lambda search, the ERI's inputs), then rendered with each strength: a fraction of a clone's
# time each. A row per option, the others at their defaults.
prepared = exprclone.prepare(source_neutral, source_smile, target_neutral, landmarks=tuple(points))
rows = ("strength", "strength_mouth", "strength_eyes", "strength_brows", "strength_shading")
strengths = (0.0, 0.5, 1.0, 1.5, 2.0)
box = face_box(points[2], target_neutral.shape)
fig, axes = plt.subplots(len(rows), len(strengths), figsize=(12, 12.5))
for row, option in zip(axes, rows):
    for ax, strength in zip(row, strengths):
        result = prepared.render(**{option: strength})["e+md"]
        ax.imshow(result.image[box])
        ax.set_title(f"{option} {strength:g}", fontsize=9)
        ax.axis("off")
fig.tight_layout()
plt.show()
