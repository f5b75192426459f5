"""How well :mod:`exprclone.pipeline.role_check` tells photos given in the wrong boxes: on the London Set (72 people),
on its photos made grey, relit or given another white balance, and on GRID's speakers.

For every person i, with j the next person in the set's order as the target (and as the other person): the right
order (i's neutral, i's smile, j's neutral), every other order of those three photos, and two people as the source
(i's neutral with each of the next ``--others`` people's smiles). Then each change of light of :mod:`exprclone.testing.lighting`
(grey, relit by +-15% from one ear to the other either way, a warm and a cool white balance): the right order with the
smile changed, with both source photos changed, and the two swapped, both changed; the landmarks found afresh on every
changed photo, as the door finds them. Then every GRID clip (``--grid``): its most closed frame as the neutral face
(:func:`exprclone.drive.driver.closed_mouth_frame`) and each frame whose mouth opens at least half as far as the clip
opens it most as the expression, in the right order and swapped. It prints how often each is flagged, and for the
orders that swap the target's photo with one of the source's, how often the warning names those two boxes. The mean
neutral face and the scores at rest are learnt without the person judged (leave-one-out; for GRID, from all 72), so
every rate is measured on a person they never saw; the rates are printed for each half of the set (even and odd
places) too. With ``--edited``, every person's neutral photo is also edited by the expression editor
(:mod:`exprclone.expressions.editor`) into each built-in expression it makes (surprise, sad, angry:
``tools/build_expressions.py``'s :data:`EDITED`) and by each of :data:`CONTROLS` alone at 1 and at 0.5, the landmarks
found afresh on the edited photo: the neutral photo and its edit in the right order, and swapped.

    PYTHONPATH=src python tools/role_check.py [--data ../shared/data] [--write-template] [--noise] [--edited]

``--write-template`` first writes ``src/exprclone/data/neutral_face.json``: the mean of the 72 neutral faces'
detected landmarks (:data:`exprclone.pipeline.role_check.NEUTRAL_FACE`) and their blendshape scores' mean and spread
(:data:`~exprclone.pipeline.role_check.REST`). ``--noise`` prints how far each of the check's five views moves when a
photo is only made grey, relit or rebalanced (the standard deviation over the set's 144 photos and the five
changes): :data:`~exprclone.pipeline.role_check.MARGINS`.
"""

import argparse
import json
from pathlib import Path

import numpy as np
from build_expressions import EDITED

from exprclone.data import sets as datasets
from exprclone.drive.driver import closed_mouth_frame
from exprclone.errors import ExprCloneError
from exprclone.expressions.editor import Editor, request
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.landmarks import align
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure
from exprclone.pipeline import role_check
from exprclone.testing.lighting import changes

TEMPLATE = Path(__file__).resolve().parents[1] / "src" / "exprclone" / "data" / "neutral_face.json"
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
#: a GRID frame is an expression when its mouth opens at least this share of the clip's widest opening.
OPEN = 0.5
#: the expression editor's controls whose edits alone are judged (``--edited``), each at 1 and at 0.5.
CONTROLS = ("mouth_open", "pucker", "frown", "brows_up", "brows_down", "eyes_closed", "smile")
Photos = dict[tuple[str, str, str], role_check.Face]


def face(image: np.ndarray, name: str) -> role_check.Face:
    """The role check's view of a photo, its landmarks found as the door finds them."""
    return role_check.Face.of(image, default_detector().detect(image, name), DLIB68)


def load(data: Path) -> tuple[list[str], Photos]:
    """Every person's neutral (``n``) and smiling (``s``) photo, as it is (``as is``) and changed by each change of
    light (:mod:`exprclone.testing.lighting`), by (person, kind, change)."""
    people = sorted(p.stem[:3] for p in (data / "neutral_front").glob("*_03.jpg"))
    if not people:
        raise SystemExit(f"no London Set photos in {data}/neutral_front (give --data)")
    photos: Photos = {}
    for i in people:
        for kind, path in (("n", data / "neutral_front" / f"{i}_03.jpg"), ("s", data / "smiling_front" / f"{i}_08.jpg")):
            photos[i, kind, "as is"] = original = face(load_image(path), str(path))
            for change, image in changes(original.image, original.points).items():
                photos[i, kind, change] = face(image, f"{path} ({change})")
    return people, photos


def grid_pairs(folder: Path) -> dict[str, list[tuple[role_check.Face, role_check.Face]]]:
    """Each GRID clip's (closed frame, open frame) pairs (the module's notes), by clip."""
    out = {}
    for clip in sorted(folder.glob("*.mpg")):
        seen = []
        for k, frame in enumerate(read_frames(clip)):
            try:
                seen.append(face(frame, f"{clip.name} frame {k}"))
            except ExprCloneError:  # no face found in the frame
                seen.append(None)
        usable = np.array([f is not None for f in seen])
        points = np.array([f.points if f is not None else np.zeros((68, 2)) for f in seen])
        opening = np.array([measure.opening(p, DLIB68) if ok else -1.0 for p, ok in zip(points, usable)])
        closed = seen[closed_mouth_frame(points, usable, DLIB68)]
        assert closed is not None
        out[clip.stem] = [(closed, f) for f, o in zip(seen, opening) if f is not None and o >= OPEN * opening.max()]
    return out


def mean_face(shapes: list[np.ndarray]) -> np.ndarray:
    """The mean of faces, each rigidly aligned on the mean (twice), outer eye corners at (0, 0) and (1, 0)."""
    units = [s / align.interocular(s, DLIB68) for s in shapes]
    mean = units[0]
    for _ in range(3):
        mean = np.mean([align.apply(align.fit_rigid(u, mean, DLIB68), u) for u in units], axis=0)
        i, j = DLIB68.eye_corners
        mean = align.apply(align.fit_similarity(mean[[i, j]], np.array([[0.0, 0.0], [1.0, 0.0]])), mean)
    return mean


def learn(people: list[str], photos: Photos) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """The mean neutral face of ``people`` and their neutral photos' expression scores' mean and spread (the standard
    deviation and :data:`~exprclone.pipeline.role_check.REST_FLOOR` in quadrature), set in the module as it uses them."""
    role_check.NEUTRAL_FACE = mean_face([photos[i, "n", "as is"].points for i in people])
    rest = np.array([photos[i, "n", "as is"].scores[role_check.EXPRESSION] for i in people])
    role_check.REST = rest.mean(0), np.sqrt(rest.var(0) + role_check.REST_FLOOR**2)
    return role_check.NEUTRAL_FACE, role_check.REST


def flagged(neutral: role_check.Face, expression: role_check.Face, target: role_check.Face | None = None) -> list[str]:
    return role_check.judge_roles(neutral, expression, DLIB68, target)


def judged(people: list[str], photos: Photos, others: int) -> dict[str, list[tuple[int, bool, bool]]]:
    """For each kind of mistake, (the person's place, whether it was flagged, whether the warning named the right boxes)."""
    out: dict[str, list[tuple[int, bool, bool]]] = {}
    lit = sorted({c for _, _, c in photos} - {"as is"})
    for k, i in enumerate(people):
        learn([j for j in people if j != i], photos)  # leave-one-out
        j = people[(k + 1) % len(people)]
        three = (photos[i, "n", "as is"], photos[i, "s", "as is"], photos[j, "n", "as is"])
        for kind, (order, named) in ORDERS.items():
            said = flagged(three[order[0]], three[order[1]], three[order[2]])
            out.setdefault(kind, []).append((k, bool(said), bool(said) and (named is None or named in said[0])))
        for other in (people[(k + d) % len(people)] for d in range(1, others + 1)):
            said = flagged(photos[i, "n", "as is"], photos[other, "s", "as is"], photos[j, "n", "as is"])
            out.setdefault("two people", []).append((k, bool(said), bool(said)))
        for change in lit:
            n, s = photos[i, "n", change], photos[i, "s", change]
            for kind, pair in (
                (f"right order, smile {change}", (three[0], s)),
                (f"right order, both {change}", (n, s)),
                (f"swapped, both {change}", (s, n)),
            ):
                said = flagged(*pair, three[2])
                out.setdefault(kind, []).append((k, bool(said), bool(said)))
    return out


def noise(people: list[str], photos: Photos) -> None:
    """How far each view of the check moves with the light alone (:data:`~exprclone.pipeline.role_check.MARGINS`)."""
    learn(people, photos)
    moved = [
        role_check.says(photos[i, kind, "as is"], changed, DLIB68) * role_check.MARGINS
        for (i, kind, change), changed in photos.items()
        if change != "as is"
    ]
    spread = np.std(moved, axis=0)
    print(
        f"the light alone moves: rise by {spread[0]:.3g}, from_rest by {spread[1]:.3g}, expressiveness by {spread[2]:.3g},"
        f" smiling by {spread[3]:.3g}, width by {spread[4]:.3g}"
    )
    print(f"(standard deviations over {len(moved)} changed photos; the margins used: {role_check.MARGINS})")


def edits() -> dict[str, dict[str, float]]:
    """The editor's values of each edit judged (``--edited``), by name: the built-in expressions, then each control."""
    made = {name: values for name, (values, _) in EDITED.items()}
    return made | {f"{control} {value:g}": {control: value} for control in CONTROLS for value in (1.0, 0.5)}


def edited(people: list[str], photos: Photos) -> None:
    """How often a neutral photo and its edit are flagged, in the right order and swapped (the module's notes)."""
    made = edits()
    flags = {name: np.zeros(2, int) for name in made}
    for i in people:
        learn([j for j in people if j != i], photos)  # leave-one-out
        neutral = photos[i, "n", "as is"]
        editor = Editor.of(request(neutral.image, neutral.points))
        for name, values in made.items():
            changed = face(editor.render(values).image, f"{i} edited ({name})")
            flags[name] += (bool(flagged(neutral, changed)), bool(flagged(changed, neutral)))
    for name, (right, swapped) in flags.items():
        print(f"edited {name:16s} right order flagged {right:2d} of {len(people)}, swapped flagged {swapped:2d} of {len(people)}")


def report(kind: str, rows: list[tuple[int, bool, bool]]) -> None:
    flags = np.array([f for _, f, _ in rows])
    named = np.array([n for _, _, n in rows])
    halves = [np.mean([f for k, f, _ in rows if k % 2 == h]) for h in (0, 1)]
    print(
        f"{kind:34s} flagged {flags.sum():3d} of {len(flags):3d} ({flags.mean():5.1%}; even half {halves[0]:5.1%},"
        f" odd half {halves[1]:5.1%})" + ("" if ORDERS.get(kind, (0, None))[1] is None else f", its boxes named {named.mean():5.1%}")
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    datasets.add_argument(parser, holds="the data folder (london/ and grid/)")
    parser.add_argument("--others", type=int, default=5, help="other people's smiles per person (default: 5)")
    parser.add_argument("--write-template", action="store_true", help="write the mean neutral face and the scores at rest first")
    parser.add_argument("--noise", action="store_true", help="print how far the light alone moves each view")
    parser.add_argument("--no-grid", dest="grid", action="store_false", help="leave GRID's clips out")
    parser.add_argument("--edited", action="store_true", help="judge the neutral photos edited by the expression editor too")
    args = parser.parse_args()
    people, photos = load(args.data / "london")
    if args.write_template:
        face_, (mean, spread) = learn(people, photos)
        document = {
            "people": len(people),
            "landmarks": np.round(face_, 5).tolist(),
            "rest_mean": np.round(mean, 5).tolist(),
            "rest_spread": np.round(spread, 5).tolist(),
        }
        TEMPLATE.write_text(json.dumps(document) + "\n")
        print(f"wrote {TEMPLATE}")
    if args.noise:
        noise(people, photos)
    print(f"bounds: SURELY_SAME {role_check.SURELY_SAME}, SAME_PERSON {role_check.SAME_PERSON}, MARGINS {role_check.MARGINS},")
    print(
        f"CAP {role_check.CAP}, SWAPPED {role_check.SWAPPED}, TOP {role_check.TOP}, REST_FLOOR {role_check.REST_FLOOR};"
        " each person judged with the face and scores at rest learnt without them"
    )
    for kind, rows in judged(people, photos, args.others).items():
        report(kind, rows)
    if args.edited:
        edited(people, photos)
    if args.grid:
        learn(people, photos)
        for clip, pairs in grid_pairs(args.data / "grid").items():
            right = sum(bool(flagged(n, e)) for n, e in pairs)
            swapped = sum(bool(flagged(e, n)) for n, e in pairs)
            print(f"GRID {clip:16s} right order flagged {right:2d} of {len(pairs):2d}, swapped flagged {swapped:2d} of {len(pairs):2d}")


if __name__ == "__main__":
    main()
