"""
The elastic model on another global warp (Figs. 19-21)
======================================================

The paper's last claim: the elastic model improves the result of any global warping
method. Here the global warp is the radial-basis-function transfer of Seol and Lewis
(``global_warp="rbf"``); the elastic model then balances it with local re-shaping, with
lambda_k chosen by the DB metric. Geometry only, as in the paper's figures.
"""

import matplotlib.pyplot as plt

import exprclone
from exprclone import data
from exprclone.evaluation.figures import difference, face_box

source_neutral, source_smile, target_neutral = data.photo("001"), data.photo("001", "smile"), data.photo("126")
methods = ("global", "elastic")
similarity = exprclone.clone_methods(source_neutral, source_smile, target_neutral, methods)
rbf = exprclone.clone_methods(source_neutral, source_smile, target_neutral, methods, global_warp="rbf")
print(f"lambda_k on the similarity GI: {similarity['elastic'].lambda_k:g}, on the RBF GI: {rbf['elastic'].lambda_k:g}")

# %%
# The similarity transfer (the paper's GI), the RBF transfer, the elastic model on the RBF
# result, and where the last two differ.
box = face_box(rbf["global"].landmarks["target_neutral"], target_neutral.shape)
panels = [
    ("GI: similarity", similarity["global"].image),
    ("GI: RBF", rbf["global"].image),
    (f"elastic on RBF (lambda_k {rbf['elastic'].lambda_k:g})", rbf["elastic"].image),
    ("difference", difference(rbf["elastic"].image, rbf["global"].image)),
]
fig, axes = plt.subplots(1, 4, figsize=(12, 3.4))
for ax, (title, image) in zip(axes, panels):
    ax.imshow(image[box])
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
plt.show()
