"""How well :mod:`exprclone.pipeline.role_check` tells photos given in the wrong boxes, on the London Set (72 people).

For every person i, with j the next person in the set's order as the target (and as the other person): the right
order (i's neutral, i's smile, j's neutral), every other order of those three photos, and two people as the source
(i's neutral with each of the next ``--others`` people's smiles). It prints how often each is flagged, and for the
orders that swap the target's photo with one of the source's, how often the warning names those two boxes. The
mean neutral face and the smile's direction are learnt without the person judged (leave-one-out), so every rate
is measured on a person they never saw; the bounds of the module are fixed numbers (the descriptors' is dlib's),
and the rates are printed for each half of the set (even and odd places) too.

    PYTHONPATH=src python tools/role_check.py [--data ../shared/data/london] [--write-template]

``--write-template`` first writes ``src/exprclone/data/neutral_face.json``: the mean of the 72 neutral faces'
detected landmarks (:data:`exprclone.pipeline.role_check.NEUTRAL_FACE`) and the smile's direction learnt on all of
them (:data:`~exprclone.pipeline.role_check.SMILE`).
"""

import argparse
import json
from pathlib import Path

import numpy as np

from exprclone.data import sets as datasets
from exprclone.io.images import load_image
from exprclone.landmarks import align
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline import role_check

TEMPLATE = Path(__file__).resolve().parents[1] / "src" / "exprclone" / "data" / "neutral_face.json"
#: the ridge regression's weight on the smile direction's norm (the even half's leave-one-out errors are fewest at it).
RIDGE = 0.03
#: the orders of (i's neutral, i's smile, j's neutral) judged, as the three boxes take them, and the boxes a warning
#: should name as swapped (None: any warning will do).
ORDERS = {
    "right order": ((0, 1, 2), None),
    "source's two swapped": ((1, 0, 2), None),
    "target in source_neutral's box": ((2, 1, 0), "source_neutral and target_neutral swapped"),
    "target in source_expression's box": ((0, 2, 1), "source_expression and target_neutral swapped"),
    "all three turned (target first)": ((2, 0, 1), None),
    "all three turned (smile first)": ((1, 2, 0), None),
}


def load(data: Path) -> tuple[list[str], dict[str, role_check.Face]]:
    """Every person's neutral (``ID_n``) and smiling (``ID_s``) photo with its detected landmarks."""
    people = sorted(p.stem[:3] for p in (data / "neutral_front").glob("*_03.jpg"))
    if not people:
        raise SystemExit(f"no London Set photos in {data}/neutral_front (give --data)")
    photos = {}
    for i in people:
        for kind, path in (("n", data / "neutral_front" / f"{i}_03.jpg"), ("s", data / "smiling_front" / f"{i}_08.jpg")):
            image = load_image(path)
            photos[f"{i}_{kind}"] = role_check.Face.of(image, default_detector().detect(image, str(path)), DLIB68)
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


def learn(people: list[str], photos: dict[str, role_check.Face]) -> tuple[np.ndarray, np.ndarray]:
    """The mean neutral face of ``people`` and the direction their smiles move the moving landmarks from it: ``w``
    minimising ``sum (1 - w d)^2 + RIDGE |w|^2`` over each person's motion ``d`` (smile minus neutral)."""
    role_check.NEUTRAL_FACE = mean_face([photos[f"{i}_n"].points for i in people])
    moved = {key: role_check.moving(photos[key].points, DLIB68).ravel() for i in people for key in (f"{i}_n", f"{i}_s")}
    motion = np.array([moved[f"{i}_s"] - moved[f"{i}_n"] for i in people])
    direction = np.linalg.solve(motion.T @ motion + RIDGE * np.eye(motion.shape[1]), motion.sum(0))
    return role_check.NEUTRAL_FACE, direction


def judged(people: list[str], photos: dict[str, role_check.Face], others: int) -> dict[str, list[tuple[int, bool, bool]]]:
    """For each kind of mistake, (the person's place, whether it was flagged, whether the warning named the right boxes)."""
    out: dict[str, list[tuple[int, bool, bool]]] = {kind: [] for kind in [*ORDERS, "two people"]}
    for k, i in enumerate(people):
        role_check.NEUTRAL_FACE, role_check.SMILE = learn([j for j in people if j != i], photos)  # leave-one-out
        j = people[(k + 1) % len(people)]
        three = (photos[f"{i}_n"], photos[f"{i}_s"], photos[f"{j}_n"])
        for kind, (order, named) in ORDERS.items():
            said = role_check.judge_roles(three[order[0]], three[order[1]], DLIB68, three[order[2]])
            out[kind].append((k, bool(said), bool(said) and (named is None or named in said[0])))
        for other in (people[(k + d) % len(people)] for d in range(1, others + 1)):
            said = role_check.judge_roles(photos[f"{i}_n"], photos[f"{other}_s"], DLIB68, photos[f"{j}_n"])
            out["two people"].append((k, bool(said), bool(said)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    datasets.add_argument(parser, "london", holds="the London Set folder")
    parser.add_argument("--others", type=int, default=5, help="other people's smiles per person (default: 5)")
    parser.add_argument("--write-template", action="store_true", help="write the mean neutral face and the smile's direction first")
    args = parser.parse_args()
    people, photos = load(args.data)
    if args.write_template:
        face, direction = learn(people, photos)
        document = {"people": len(people), "landmarks": np.round(face, 5).tolist(), "smile": np.round(direction, 5).tolist()}
        TEMPLATE.write_text(json.dumps(document) + "\n")
        print(f"wrote {TEMPLATE}")
    print(f"bounds: SURELY_SAME {role_check.SURELY_SAME}, SAME_PERSON {role_check.SAME_PERSON}, MIN_SWAP {role_check.MIN_SWAP},")
    print(f"GATE {role_check.GATE}, RIDGE {RIDGE}; each person judged with the face and smile learnt without them")
    for kind, rows in judged(people, photos, args.others).items():
        flags = np.array([f for _, f, _ in rows])
        named = np.array([n for _, _, n in rows])
        halves = [np.mean([f for k, f, _ in rows if k % 2 == h]) for h in (0, 1)]
        print(
            f"{kind:34s} flagged {flags.sum():3d} of {len(flags):3d} ({flags.mean():5.1%}; even half {halves[0]:5.1%},"
            f" odd half {halves[1]:5.1%})" + ("" if ORDERS.get(kind, (0, None))[1] is None else f", its boxes named {named.mean():5.1%}")
        )


if __name__ == "__main__":
    main()
