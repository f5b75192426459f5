"""
Expression strength
===================

``strength`` scales what is transferred: the landmark motion, the expression ratio image
(as ``ERI ** strength``) and the mouth interior. 0 gives the target photo exactly, 1 the
whole expression, 2 an exaggerated one. The same option is ``--strength`` on the command
line and a form field of the HTTP API.
"""

import matplotlib.pyplot as plt

from exprclone import Cloner, data
from exprclone.evaluation.figures import face_box
from exprclone.landmarks.backends import default_detector

source_neutral, source_smile, target_neutral = data.photo("126"), data.photo("126", "smile"), data.photo("001")
detector = default_detector()
points = [detector.detect(image) for image in (source_neutral, source_smile, target_neutral)]

# %%
# One :class:`~exprclone.Cloner` per strength: the options belong to the prepared
# pair of faces.
strengths = (0.0, 0.5, 1.0, 1.5, 2.0)
box = face_box(points[2], target_neutral.shape)
fig, axes = plt.subplots(1, len(strengths), figsize=(14, 3.2))
for ax, strength in zip(axes, strengths):
    cloner = Cloner(source_neutral, points[0], target_neutral, points[2], strength=strength)
    result = cloner.clone_methods(source_smile, points[1], ("e+md",))["e+md"]
    ax.imshow(result.image[box])
    ax.set_title(f"strength {strength:g}")
    ax.axis("off")
fig.tight_layout()
plt.show()
