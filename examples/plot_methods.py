"""
The seven methods of the paper's Fig. 11
========================================

:func:`exprclone.clone_methods` runs every method of the paper's Fig. 11 on the same three
photos, computing the stages they share once: the geometry alone (global warping, local
re-shaping, the elastic model), then each with the expression ratio image, and E+MD. The figure is
the paper's, so it is drawn by the paper's stages: ``retarget=False`` (this project's default
re-expresses the source's smile in the target's own shape, which makes local re-shaping equal to
global warping and leaves the elastic model nothing to balance).
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import face_box

source_neutral, source_smile = data.photo("126"), data.photo("126", "smile")
target_neutral = data.photo("001")
paper = exprclone.Options(retarget=False)
results = exprclone.clone_methods(source_neutral, source_smile, target_neutral, options=paper)

# %%
# Every result cropped alike, around the target's face, and the source's smile last (the
# paper's panel h).
box = face_box(results["e+md"].landmarks["target_neutral"], target_neutral.shape)
fig, axes = plt.subplots(2, 4, figsize=(12, 6.6))
for ax, (name, result) in zip(axes.flat, results.items()):
    ax.imshow(result.image[box])
    ax.set_title(name)
    ax.axis("off")
axes.flat[-1].imshow(source_smile[face_box(results["e+md"].landmarks["source_expression"], source_smile.shape)])
axes.flat[-1].set_title("source smile")
axes.flat[-1].axis("off")
fig.tight_layout()
plt.show()

# %%
# The DB metric of Eq. (7) over the candidate elasticity ratios; Eq. (8) picks its minimum.
curve = results["e+md"].db_curve
fig, ax = plt.subplots(figsize=(6, 3))
ax.plot(range(len(curve.lambdas)), curve.db, "o-")
ax.set_xticks(range(len(curve.lambdas)), [f"{v:g}" for v in curve.lambdas])
ax.axvline(list(curve.lambdas).index(curve.best), color="tab:red", label=f"chosen: {curve.best:g}")
ax.set_xlabel("lambda_k")
ax.set_ylabel("DB")
ax.legend()
fig.tight_layout()
plt.show()
