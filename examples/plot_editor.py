"""
The expression editor: one photo, named controls
================================================

:func:`exprclone.edit` changes one photo's expression by named controls, each from 0 (the face
as it is) to 1: the ``smile`` learnt from the London Set's smiles, ``mouth_open``, ``pucker`` and
``eyes_closed`` learnt from the GRID clips' frames, the others built from the face's anatomy
(:doc:`../explanation/editor`). The same controls are ``exprclone edit --set NAME=VALUE``, the
form fields of ``POST /api/editor/{id}/render`` and the sliders of the page at ``/editor``.
"""

import matplotlib.pyplot as plt

from exprclone import data
from exprclone.evaluation.figures import face_box
from exprclone.expressions.controls import CONTROLS
from exprclone.expressions.editor import Editor, request

photo = data.photo("001")

# %%
# The photo is prepared once (:class:`~exprclone.expressions.editor.Editor`: its landmarks, the two
# neutral faces of the clone that renders it); each set of values then costs a render. A row per
# control, at 0, 0.5 and 1.
editor = Editor.of(request(photo))
values = (0.0, 0.5, 1.0)
box = face_box(editor.neutral, photo.shape)
fig, axes = plt.subplots(len(values), len(CONTROLS), figsize=(15, 5.6))
for column, control in zip(axes.T, CONTROLS):
    for ax, value in zip(column, values):
        ax.imshow(editor.render({control.name: value}).image[box])
        ax.set_title(f"{control.name} {value:g}", fontsize=8)
        ax.axis("off")
fig.tight_layout()
plt.show()
