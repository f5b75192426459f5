"""The greyest shadows before a change and the same clones after it: the documentation's before/after contact sheet.

    python tools/warmth_sheet.py BEFORE/pairs.csv AFTER/pairs.csv --ref REV --data ../shared/data/london -o OUT.jpg

Takes the ``count`` clones of the methods with ERI whose shadows were the least warm in ``BEFORE``'s
``exprclone evaluate`` report (:func:`exprclone.evaluation.scores.warmth`), clones each pair again with the code of
``REV`` (in a temporary git worktree) and with the working tree's, and writes one row a clone: the target's neutral
face, the clone before, the clone after, each warmth from the two reports in the captions.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from compare_reports import rows  # (which puts this tree's src/ on the path)

from exprclone.methods import TABLE

ROOT = Path(__file__).resolve().parents[1]
ERI_METHODS = {m.name for m in TABLE if m.eri}
#: the sheet's JPEG quality.
JPEG_QUALITY = 80


def render(data: Path, wanted: list[tuple[str, str, str]], out: Path) -> None:
    """Each (source, target, method) cloned with the code importable as ``exprclone``, its face crop written to ``out``."""
    import numpy as np

    from exprclone.evaluation.figures import face_box
    from exprclone.evaluation.london import Dataset
    from exprclone.evaluation.runner import clone_pair, photo
    from exprclone.io.images import save_image
    from exprclone.landmarks.backends import default_detector

    found = Dataset.open(data)
    detect = default_detector().detect
    for a, b, method in wanted:
        neutral = photo(found.path(b, False))
        points = {p: detect(photo(p)) for p in (found.path(a, False), found.path(a, True), found.path(b, False))}
        result = clone_pair(found, (a, b), (method,), points)[method]
        box = face_box(points[found.path(b, False)], neutral.shape)
        save_image(out / f"{a}-{b}-{method}.png", np.ascontiguousarray(result.image[box]))
        save_image(out / f"{b}-neutral.png", np.ascontiguousarray(neutral[box]))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--ref", required=True, help="the git commit whose code made BEFORE")
    parser.add_argument("--data", type=Path, required=True)
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--count", type=int, default=12)
    parser.add_argument("--render", help=argparse.SUPPRESS)  # internal: a JSON list to render into this folder
    args = parser.parse_args()
    if args.render:
        render(args.data, [tuple(w) for w in json.loads(Path(args.render).read_text())], Path(args.output))
        return 0
    before, after = rows(args.before), rows(args.after)
    measured = [k for k, r in before.items() if k[2] in ERI_METHODS and r.get("warmth") and after.get(k, {}).get("warmth")]
    worst = sorted(measured, key=lambda k: float(before[k]["warmth"]))[: args.count]
    with tempfile.TemporaryDirectory() as tmp:
        listed = Path(tmp) / "wanted.json"
        listed.write_text(json.dumps(worst))
        tree, folders = Path(tmp) / "tree", {"before": Path(tmp) / "before", "after": Path(tmp) / "after"}
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tree), args.ref], check=True, capture_output=True)
        try:
            for name, src in (("before", tree / "src"), ("after", ROOT / "src")):
                folders[name].mkdir()
                command = [sys.executable, __file__, args.before, args.after, "--ref", args.ref, "--data", str(args.data)]
                command += ["-o", str(folders[name]), "--render", str(listed)]
                subprocess.run(command, check=True, env=dict(os.environ, PYTHONPATH=str(src)))
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=True)
        compose(worst, before, after, folders, Path(args.output))
    return 0


def compose(worst: list, before: dict, after: dict, folders: dict[str, Path], output: Path) -> None:
    """One row a clone: [target neutral | before | after], captioned with the pair, the method and both warmths."""
    import cv2
    import numpy as np
    from PIL import Image

    from exprclone.evaluation.report import _caption
    from exprclone.io.images import load_image

    rows = []
    for a, b, method in worst:
        cells = [load_image(folders["before"] / f"{b}-neutral.png")]
        cells += [load_image(folders[name] / f"{a}-{b}-{method}.png") for name in ("before", "after")]
        cells = [cv2.resize(c, (300, 300), interpolation=cv2.INTER_AREA) for c in cells]
        _caption(cells[0], f"{a} -> {b}, {method}")
        for cell, name, report in ((cells[1], "before", before), (cells[2], "after", after)):
            _caption(cell, f"{name}: warmth {float(report[a, b, method]['warmth']):.2f}")
        rows.append(np.hstack(cells))
    if len(rows) % 2:
        rows.append(np.zeros_like(rows[0]))
    sheet = np.vstack([np.hstack(rows[k : k + 2]) for k in range(0, len(rows), 2)])
    Image.fromarray(sheet).save(output, quality=JPEG_QUALITY)  # (a page's figure: a third of save_image's bytes)


if __name__ == "__main__":
    sys.exit(main())
