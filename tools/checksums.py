"""Checksums of exprclone's outputs, to show that a refactor changes no pixel.

    python tools/checksums.py record OUT.json [--ref REV] [--pairs 20] [--data ../shared/data]
    python tools/checksums.py compare BEFORE.json AFTER.json

``record`` clones the smile of 20 ordered London pairs (seed 0) by every method and
drives a 256-pixel portrait with one GRID clip, and writes the SHA-256 of every output
image, of every decoded video frame, and the chosen lambda_k. With ``--ref`` it runs the
code of that commit (checked out in a temporary git worktree) instead of the working
tree's. ``compare`` lists what differs and exits 1 if anything does.

Only the public API (``exprclone.clone_methods``) and the ``exprclone video`` command are
used, and photos are read with Pillow, so the tool works on both sides of a refactor.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from exprclone.data import sets as datasets

ROOT = Path(__file__).resolve().parents[1]


def sha(array) -> str:
    import numpy as np

    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()[:16]


def record(pairs: int, data: Path) -> dict:
    """Checksums of the stills and of one video, with the code importable as ``exprclone``."""
    import av
    import numpy as np
    from PIL import Image

    import exprclone

    london = data / "london"
    ids = sorted(p.name[:3] for p in (london / "neutral_front").glob("*_03.jpg"))
    every = [(a, b) for a in ids for b in ids if a != b]
    chosen = [every[i] for i in sorted(np.random.default_rng(0).choice(len(every), pairs, replace=False))]
    photo = lambda face, smile: np.array(  # noqa: E731
        Image.open(london / ("smiling_front" if smile else "neutral_front") / f"{face}_{'08' if smile else '03'}.jpg").convert("RGB")
    )
    out = {}
    for a, b in chosen:
        results = exprclone.clone_methods(photo(a, False), photo(a, True), photo(b, False))
        for method, r in results.items():
            out[f"{a}->{b} {method}"] = f"{sha(r.image)} lambda_k={r.lambda_k}"
        print(f"{a} -> {b}", file=sys.stderr)
    with tempfile.TemporaryDirectory() as tmp:
        video = Path(tmp) / "driven.mp4"
        command = [sys.executable, "-m", "exprclone", "video", str(london / "neutral_front" / "003_03.jpg")]
        command += [str(data / "grid" / "lbax4n.mpg"), "-o", str(video), "--size", "256", "--neutral-frame", "closed"]
        subprocess.run(command, check=True, capture_output=True)
        with av.open(str(video)) as container:
            for i, frame in enumerate(container.decode(video=0)):
                out[f"video frame {i}"] = sha(frame.to_ndarray(format="rgb24"))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("record")
    r.add_argument("output")
    r.add_argument("--ref", help="a git commit to run instead of the working tree")
    r.add_argument("--pairs", type=int, default=20)
    datasets.add_argument(r)
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    args = parser.parse_args()
    if args.command == "compare":
        before, after = (json.loads(Path(p).read_text()) for p in (args.before, args.after))
        differ = [k for k in before.keys() | after.keys() if before.get(k) != after.get(k)]
        for k in sorted(differ):
            print(f"{k}: {before.get(k)} -> {after.get(k)}")
        print(f"{len(before)} outputs before, {len(after)} after, {len(differ)} differ")
        return 1 if differ else 0
    if args.ref:
        with tempfile.TemporaryDirectory() as tmp:
            tree = Path(tmp) / "tree"
            subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tree), args.ref], check=True, capture_output=True)
            try:
                env = dict(os.environ, PYTHONPATH=str(tree / "src"))
                command = [sys.executable, __file__, "record", os.path.abspath(args.output), "--pairs", str(args.pairs)]
                subprocess.run(command + ["--data", str(args.data)], check=True, env=env)
            finally:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=True)
        return 0
    Path(args.output).write_text(json.dumps(record(args.pairs, args.data), indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
