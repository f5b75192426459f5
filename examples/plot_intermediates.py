"""
Inside a clone: the ERI, the muscle mask and the mouth
======================================================

A :class:`~exprclone.CloneResult` keeps what each stage made: the landmarks of every
stage, the expression ratio image (ERI), the muscle-distribution model's importance mask
``M`` (Eqs. 10-11) and where the source's mouth interior was pasted.
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import face_box

result = exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"))
box = face_box(result.landmarks["final"], result.image.shape)

# %%
# The landmarks of the shape stages: global warping (GI), local re-shaping (LI) and the
# elastic model's balance of the two, on the result.
fig, ax = plt.subplots(figsize=(5, 5))
ax.imshow(result.image[box])
for stage, colour in (("global", "tab:blue"), ("local", "tab:orange"), ("elastic", "tab:green")):
    points = result.landmarks[stage] - [box[1].start, box[0].start]
    ax.plot(*points.T, ".", color=colour, label=stage, markersize=4)
ax.legend()
ax.axis("off")
plt.show()

# %%
# The ERI (grey at 1: darker where the expression shades the skin, lighter where it
# brightens it), the importance mask M, and the mouth interior's mask.
fig, axes = plt.subplots(1, 3, figsize=(12, 4))
axes[0].imshow(result.eri[box], cmap="gray", vmin=0.7, vmax=1.3)
axes[0].set_title("ERI")
axes[1].imshow(result.muscle_mask[box], cmap="magma")
axes[1].set_title("muscle mask M")
axes[2].imshow(result.mouth_mask[box], cmap="gray")
axes[2].set_title("mouth interior")
for ax in axes:
    ax.axis("off")
fig.tight_layout()
plt.show()
