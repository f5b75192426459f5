"""
A first clone
=============

Person 126's smile, cloned onto person 003 with E+MD: the three photos in, the result out.
:func:`exprclone.clone` finds the landmarks, chooses the elasticity ratio by the DB metric
and returns the image with every intermediate stage.
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import face_box

source_neutral, source_smile = data.photo("126"), data.photo("126", "smile")
target_neutral = data.photo("003")

result = exprclone.clone(source_neutral, source_smile, target_neutral, method="e+md")
print(f"lambda_k chosen by the DB metric: {result.lambda_k:g}")

# %%
# Show the faces, each cropped around its landmarks.
panels = [
    ("source, neutral", source_neutral, result.landmarks["source_neutral"]),
    ("source, smiling", source_smile, result.landmarks["source_expression"]),
    ("target, neutral", target_neutral, result.landmarks["target_neutral"]),
    ("target, cloned smile", result.image, result.landmarks["final"]),
]
fig, axes = plt.subplots(1, 4, figsize=(12, 3.4))
for ax, (title, image, points) in zip(axes, panels):
    ax.imshow(image[face_box(points, image.shape)])
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
plt.show()
