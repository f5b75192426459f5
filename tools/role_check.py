"""How well :mod:`exprclone.pipeline.role_check` tells photos given in the wrong roles, on the London Set (72 people).

For every person: the right order (their neutral photo, then their smile), the swapped order (the smile as
the neutral), and mismatched people (their neutral with each of the next ``--others`` people's smiles). It
prints how often each is flagged, over all people and over each half (even and odd places in the set's
order): the bounds in the module were read off the even half (its right-order pairs' 99th percentile), so
the odd half's rates are measured on people the bounds never saw. The mean neutral face is also taken
without the person judged (leave-one-out), as printed.

    PYTHONPATH=src python tools/role_check.py [--data ../shared/data/london] [--write-template]

``--write-template`` first writes ``src/exprclone/data/neutral_face.json`` (:data:`exprclone.pipeline.role_check.NEUTRAL_FACE`),
the mean of the 72 neutral faces' detected landmarks.
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from exprclone.io.images import load_image  # noqa: E402
from exprclone.landmarks import align  # noqa: E402
from exprclone.landmarks.backends import default_detector  # noqa: E402
from exprclone.landmarks.layout import DLIB68  # noqa: E402
from exprclone.pipeline import role_check  # noqa: E402

TEMPLATE = Path(__file__).resolve().parents[1] / "src" / "exprclone" / "data" / "neutral_face.json"


def load(data: Path) -> tuple[list[str], dict[str, role_check.Photo]]:
    """Every person's neutral (``ID_n``) and smiling (``ID_s``) photo with its detected landmarks."""
    people = sorted(p.stem[:3] for p in (data / "neutral_front").glob("*_03.jpg"))
    if not people:
        raise SystemExit(f"no London Set photos in {data}/neutral_front (give --data)")
    photos = {}
    for i in people:
        for kind, path in (("n", data / "neutral_front" / f"{i}_03.jpg"), ("s", data / "smiling_front" / f"{i}_08.jpg")):
            image = load_image(path)
            photos[f"{i}_{kind}"] = role_check.Photo.of(image, default_detector().detect(image, str(path)), DLIB68)
    return people, photos


def mean_face(shapes: list[np.ndarray]) -> np.ndarray:
    """The mean of faces, each rigidly aligned on the mean (twice), outer eye corners at (0, 0) and (1, 0)."""
    units = [s / align.interocular(s, DLIB68) for s in shapes]
    mean = units[0]
    for _ in range(3):
        mean = np.mean([align.apply(align.fit_rigid(u, mean, DLIB68), u) for u in units], axis=0)
        i, j = DLIB68.eye_corners
        mean = align.apply(align.fit_similarity(mean[[i, j]], np.array([[0.0, 0.0], [1.0, 0.0]])), mean)
    return mean


def judged(people: list[str], photos: dict, others: int) -> dict[str, list[tuple[int, bool]]]:
    """For each kind of pair, (the person's place, whether it was flagged) of each pair; and the even half's bounds."""
    out = {"right order": [], "swapped": [], "mismatched": []}
    surplus = []  # how much more expressive each one's neutral photo looks than their smile
    for k, i in enumerate(people):
        role_check.NEUTRAL_FACE = mean_face([photos[f"{j}_n"].points for j in people if j != i])  # leave-one-out
        surplus.append(
            role_check.expressiveness(photos[f"{i}_n"].points, DLIB68) - role_check.expressiveness(photos[f"{i}_s"].points, DLIB68)
        )
        out["right order"].append((k, bool(role_check.judge_roles(photos[f"{i}_n"], photos[f"{i}_s"], DLIB68))))
        out["swapped"].append((k, bool(role_check.judge_roles(photos[f"{i}_s"], photos[f"{i}_n"], DLIB68))))
        for j in (people[(k + d) % len(people)] for d in range(1, others + 1)):
            out["mismatched"].append((k, bool(role_check.judge_roles(photos[f"{i}_n"], photos[f"{j}_s"], DLIB68))))
    print(f"expressiveness of the neutral photo over the smile, even half: largest {max(surplus[::2]):.4f}")
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data" / "london")
    parser.add_argument("--others", type=int, default=5, help="mismatched people per person (default: 5)")
    parser.add_argument("--write-template", action="store_true", help="write the mean neutral face first")
    args = parser.parse_args()
    people, photos = load(args.data)
    if args.write_template:
        mean = mean_face([photos[f"{i}_n"].points for i in people])
        TEMPLATE.write_text(json.dumps({"people": len(people), "landmarks": np.round(mean, 5).tolist()}) + "\n")
        print(f"wrote {TEMPLATE}")
    own = np.array([role_check.identity_distance(photos[f"{i}_n"], photos[f"{i}_s"], DLIB68) for i in people])
    print(f"identity distance of one person's two photos, even half: 99th percentile {np.percentile(own[::2], 99):.3f}")
    print(f"(MAX_IDENTITY = {role_check.MAX_IDENTITY}, MIN_SWAP = {role_check.MIN_SWAP})")
    for kind, rows in judged(people, photos, args.others).items():
        flags = np.array([f for _, f in rows])
        halves = [np.array([f for k, f in rows if k % 2 == h]) for h in (0, 1)]
        print(
            f"{kind:12s} flagged {flags.sum():3d} of {len(flags):3d} ({flags.mean():.1%});"
            f" even half {halves[0].mean():.1%}, odd half {halves[1].mean():.1%}"
        )


if __name__ == "__main__":
    main()
