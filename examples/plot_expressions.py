"""
Sad, surprised and angry sources
================================

Every built-in expression is a source pair, a neutral face and the expression, that a clone
carries onto one photo (:mod:`exprclone.expressions`). Beside the smiles, ``surprise``, ``sad``
and ``angry`` are made by the expression editor's controls on the London Set's average neutral
face (:doc:`../explanation/editor`); here each is cloned by E+MD onto the sample people. These
sources are geometry alone (the editor warps one photo), so what reaches the targets is the
motion, the brows, lids and mouth, and no folds of their own.
"""

import matplotlib.pyplot as plt

import exprclone.expressions as expressions
from exprclone import data
from exprclone.evaluation.figures import face_box

targets = {name: data.photo(name) for name in ("001", "003", "126")}
shown = ("surprise", "sad", "angry")

# %%
# A row per expression: its source's neutral face and expression, then its clone onto each
# target.
fig, axes = plt.subplots(len(shown), 2 + len(targets), figsize=(12, 7.8))
for row, name in zip(axes, shown):
    source = expressions.load(name)
    cells = [
        (source.neutral.image, source.neutral.points, f"{name}: source at rest"),
        (source.expression.image, source.expression.points, name),
    ]
    for target, photo in targets.items():
        result = expressions.clone(photo, name)
        cells.append((result.image, result.landmarks["final"], f"onto {target}"))
    for ax, (image, points, title) in zip(row, cells):
        ax.imshow(image[face_box(points, image.shape)])
        ax.set_title(title, fontsize=9)
        ax.axis("off")
fig.tight_layout()
plt.show()
