"""
Scoring the methods against real smiles
=======================================

``exprclone evaluate`` clones each person's smile onto every other person and scores the
result against the target's own real smile. On the samples shipped in the package (three
people, six ordered pairs) it runs in seconds; on the full London Set it gives the
:doc:`../results/evaluation` page.
"""

import csv
import tempfile
from collections import defaultdict
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from exprclone.cli import main

out = Path(tempfile.mkdtemp()) / "report"
main(["evaluate", "--out", str(out)])

# %%
# ``pairs.csv`` has one row per pair and method: the landmark errors (in outer-eye-corner
# distances) and the identity distance to the target's neutral photo.
mouth, identity = defaultdict(list), defaultdict(list)
with open(out / "pairs.csv") as f:
    for row in csv.DictReader(f):
        if row["failed"] in ("", "False"):
            mouth[row["method"]].append(float(row["mouth"]))
            identity[row["method"]].append(float(row["identity"]))
methods = list(mouth)
fig, axes = plt.subplots(1, 2, figsize=(12, 3.6))
axes[0].barh(methods, [np.mean(mouth[m]) for m in methods])
axes[0].set_xlabel("mouth landmark error (lower is closer to the real smile)")
axes[1].barh(methods, [np.mean(identity[m]) for m in methods])
axes[1].set_xlabel("identity distance to the target (lower keeps the target)")
for ax in axes:
    ax.invert_yaxis()
fig.tight_layout()
plt.show()
