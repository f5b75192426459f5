"""
Regions only
============

``only`` transfers the motion of the named regions alone (``mouth``, ``eyes``, ``brows``):
the others keep the target's own. The weight falls smoothly between regions, and the jaw
and nose follow the nearest region named.
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import face_box
from exprclone.landmarks.backends import default_detector

source_neutral, source_smile, target_neutral = data.photo("003"), data.photo("003", "smile"), data.photo("126")
box = face_box(default_detector().detect(target_neutral), target_neutral.shape)
fig, axes = plt.subplots(1, 4, figsize=(12, 3.4))
axes[0].imshow(target_neutral[box])
axes[0].set_title("target as it is")
for ax, only in zip(axes[1:], (("mouth",), ("eyes", "brows"), ("mouth", "eyes", "brows"))):
    result = exprclone.clone(source_neutral, source_smile, target_neutral, only=only)
    ax.imshow(result.image[box])
    ax.set_title("only " + " + ".join(only))
for ax in axes:
    ax.axis("off")
fig.tight_layout()
plt.show()
