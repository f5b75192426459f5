"""
A portrait driven by a video
============================

The sample GRID clip (a speaker saying "lay blue at x four now") drives person 003's
portrait, as in the paper's Fig. 18. :func:`exprclone.drive.prepare` tracks the clip's
landmarks, picks its most closed mouth as the neutral face and chooses lambda_k once; the
recording then renders the frames. Here, every tenth frame as a strip.
"""

import matplotlib.pyplot as plt

from exprclone import data, drive
from exprclone.drive.framing import resize_portrait
from exprclone.io.video import probe, read_frames

clip = str(data.clip())
portrait, _ = resize_portrait(data.photo("003"), None, 256)
recording = drive.prepare(portrait, None, lambda: read_frames(clip), float(probe(clip).fps), neutral_frame="closed")
print(f"neutral frame {recording.neutral_index}, lambda_k {recording.driver.lambda_k:g}")

shown = [(index, out) for index, out in enumerate(recording.frames(read_frames(clip))) if index % 10 == 5]

# %%
# The driving frames above, the portrait below.
fig, axes = plt.subplots(2, len(shown), figsize=(2 * len(shown), 4.4))
for column, (index, out) in enumerate(shown):
    axes[0, column].imshow(out.driving)
    axes[0, column].set_title(f"frame {index}")
    axes[1, column].imshow(out.image)
for ax in axes.flat:
    ax.axis("off")
fig.tight_layout()
plt.show()
