"""Build the built-in expressions shipped in src/exprclone/data/expressions/ from the London Set.

    python tools/build_expressions.py [--data ../shared/data/london] [-o src/exprclone/data/expressions]
    python tools/build_expressions.py --folds 4 -o folds/     # held-out prototypes, for exprclone evaluate

The prototypes (:data:`PROTOTYPES`) are shape-normalised composites of the people's neutral and
smiling photos (:mod:`exprclone.expressions.composite`), their landmarks detected:

- ``smile``: of the people whose real smile shows teeth (:func:`exprclone.evaluation.scores.teeth`):
  an open smile, as broad as the London Set's broad smiles;
- ``smile-gentle``: of every person: the average smile, lips parted a little.

Whether a composite's averaged mouth interior is sharp enough to paste is measured: it is kept
if it shows teeth by that measure and is no blurrier (:func:`exprclone.mouth.camera.blur_sigma` of the
inner lips' box, in outer-eye-corner distances) than the blurriest of its people's real smiles
that show teeth. Otherwise (on the London Set both composites' interiors are twice as blurred as
the blurriest real smile) the interior is that of the real smile, among its people's that show
teeth, whose lips are nearest the average smile's (:func:`exprclone.expressions.composite.mouth_distance`),
warped to the average shape. ``--interior composite`` or ``donor`` forces either, and names the
prototypes after it (``smile-composite``), to be scored beside the others.

``smile-001``, ``smile-003``, ``smile-126`` are the sample people's own smiles (the photos shipped
in :mod:`exprclone.data`, their landmarks detected); they are written without ``--folds``.

``surprise``, ``sad`` and ``angry`` (:data:`EDITED`) are made by the expression editor from its controls
(:mod:`exprclone.expressions.editor`) on the gentle prototype's neutral composite, which is their neutral photo too;
they are written without ``--folds``, after the prototypes (from the ones written), or alone with ``--edited``:

    python tools/build_expressions.py --edited

With ``--folds K`` the people are dealt into K folds (seeded) and each prototype is written K
times, ``OUT/fold-k/NAME.json`` made without fold k's people: ``exprclone evaluate --expression
OUT/fold-1/smile.json,...,OUT/fold-K/smile.json`` scores each person with the one made without them.
"""

import argparse
import os
from pathlib import Path

import numpy as np

from exprclone import data as samples
from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.evaluation.scores import TEETH_SHOWN, teeth
from exprclone.expressions import composite
from exprclone.expressions.editor import Editor, describe, request
from exprclone.expressions.files import Expression, read, write
from exprclone.io.images import load_image
from exprclone.landmarks import align
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth.camera import blur_sigma

ROOT = Path(__file__).resolve().parents[1]
CREDIT = "Face Research Lab London Set (DeBruine and Jones 2017, CC BY 4.0)"
#: each prototype's name, what it is, and whose photos it averages: those whose smile shows teeth, or everyone.
PROTOTYPES = {"smile": ("an open prototype smile", True), "smile-gentle": ("a gentle prototype smile", False)}
#: the expressions the editor makes, each of its controls' values and what it is.
EDITED = {
    "surprise": ({"brows_up": 1.0, "mouth_open": 0.7}, "surprise: the brows raised, the jaw dropped"),
    "sad": (
        {"frown": 0.7, "brows_up": 0.35, "eyes_closed": 0.15},
        "sadness: the mouth corners down, the brows raised a little, the lids lowered",
    ),
    "angry": ({"brows_down": 1.0, "frown": 0.3}, "anger: the brows drawn down and together, the mouth corners down a little"),
}
#: the built-in expression whose neutral photo the editor's expressions are made on (and share).
EDITED_ON = "smile-gentle"


def sharpness(face: composite.Face) -> tuple[float, float]:
    """The mouth's teeth (:func:`teeth`) and the blur of what a clone pastes (:func:`blur_sigma` of the inner lips'
    box), in outer-eye-corner distances."""
    mouth = align.box(face.points[list(DLIB68.mouth_inner)], face.image.shape)
    return teeth(face.image, face.points, DLIB68), blur_sigma(face.image[mouth]) / align.interocular(face.points, DLIB68)


def prototype(name: str, people: list[str], pairs: dict, interior: str) -> Expression:
    """The prototype of ``people`` (their ``pairs`` of Faces), its interior chosen as the module's docstring says."""
    built = composite.build([pairs[p] for p in people])
    own_teeth, own_blur = sharpness(built.expression)
    real = {p: sharpness(pairs[p][1]) for p in people}
    showing = [p for p in people if real[p][0] >= TEETH_SHOWN]
    blurs = np.array([real[p][1] for p in showing])
    soft = own_teeth < TEETH_SHOWN or own_blur > blurs.max()
    print(f"  {name}, composite of {len(people)}: teeth {own_teeth:.4f} (shown from {TEETH_SHOWN}), blur {own_blur:.4f};", end=" ")
    print(f"the {len(showing)} real smiles showing teeth: blur {blurs.min():.4f}-{blurs.max():.4f} (median {np.median(blurs):.4f})")
    expression, source = built.expression, "its own averaged mouth interior"
    if interior == "donor" or (interior == "auto" and soft):
        donor = min(showing, key=lambda p: composite.mouth_distance(pairs[p][1].points, built.expression.points))
        expression = composite.with_interior(built.expression, pairs[donor][1])
        source = f"the mouth interior of person {donor}'s smile"
        distance = composite.mouth_distance(pairs[donor][1].points, built.expression.points)
        print(f"  {'too soft to paste: ' if soft else ''}interior from {donor} (lips {distance:.3f} mouth widths from the", end=" ")
        print(f"average's; teeth {real[donor][0]:.4f}, blur {real[donor][1]:.4f}); with it: blur {sharpness(expression)[1]:.4f}")
    what = PROTOTYPES[name][0]
    description = f"{what}: the composites of {len(people)} people's neutral and smiling photos, with {source}; {CREDIT}"
    return Expression(name if interior == "auto" else f"{name}-{interior}", description, tuple(people), built.neutral, expression)


def sample_smile(face_id: str) -> tuple[Expression, dict[str, str]]:
    """A sample person's own smile, and where its photos already are (relative to the expressions' folder)."""
    kinds = {"neutral": "neutral", "expression": "smile"}
    faces = []
    for kind in kinds.values():
        image = load_image(samples.path(face_id, kind))
        faces.append(composite.Face(image, default_detector().detect(image, str(samples.path(face_id, kind)))))
    paths = {part: os.path.relpath(samples.path(face_id, kind), samples.folder() / "expressions") for part, kind in kinds.items()}
    return Expression(f"smile-{face_id}", f"person {face_id}'s own smile; {CREDIT}", (face_id,), *faces), paths


def edited(folder: Path) -> None:
    """Write the editor's expressions (:data:`EDITED`) in ``folder``, made on :data:`EDITED_ON`'s neutral photo there."""
    base = read(folder / f"{EDITED_ON}.json")
    editor = Editor.of(request(base.neutral.image, base.neutral.points))
    for name, (values, what) in EDITED.items():
        result = editor.render(values)
        face = composite.Face(result.image, result.landmarks["final"])
        said = f"{what}: made by the expression editor ({describe(values)}) on the {EDITED_ON} prototype's neutral composite; {CREDIT}"
        neutral = os.path.relpath(base.files[0], folder)
        print(write(Expression(name, said, base.people, base.neutral, face), folder, {"neutral": neutral}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, "london", holds="the London Set folder")
    parser.add_argument("-o", "--out", default=str(ROOT / "src/exprclone/data/expressions"))
    parser.add_argument("--folds", type=int, default=0, help="K >= 2: each prototype K times, each made without one fold of people")
    parser.add_argument("--seed", type=int, default=0, help="how the people are dealt into folds")
    parser.add_argument("--interior", choices=("auto", "composite", "donor"), default="auto", help="the mouth interior (auto: measured)")
    parser.add_argument("--edited", action="store_true", help="write the editor's expressions alone, from the prototypes in --out")
    args = parser.parse_args()
    if args.edited:
        edited(Path(args.out))
        return
    if args.folds == 1 or args.folds < 0:
        parser.error("--folds: 0 (the shipped expressions) or at least 2")
    data = Dataset.open(args.data)
    pairs = {}
    for face_id in data.ids:
        photos = [load_image(data.path(face_id, smiling)) for smiling in (False, True)]
        pairs[face_id] = tuple(composite.Face(im, default_detector().detect(im, face_id)) for im in photos)
    showing = {p for p in data.ids if teeth(pairs[p][1].image, pairs[p][1].points, DLIB68) >= TEETH_SHOWN}
    order = np.random.default_rng(args.seed).permutation(len(data.ids))
    folds = [(Path(args.out), set())] if args.folds == 0 else []
    folds += [(Path(args.out) / f"fold-{k + 1}", {data.ids[i] for i in order[k :: args.folds]}) for k in range(args.folds)]
    for out, held_out in folds:
        out.mkdir(parents=True, exist_ok=True)
        print(f"{out}: {len(held_out)} people held out")
        for name, (_, open_only) in PROTOTYPES.items():
            people = [p for p in data.ids if p not in held_out and (p in showing or not open_only)]
            print(write(prototype(name, people, pairs, args.interior), out))
    for face_id in samples.PEOPLE if args.folds == 0 else ():
        expression, photos = sample_smile(face_id)
        print(write(expression, out, photos))
    if args.folds == 0:
        edited(Path(args.out))


if __name__ == "__main__":
    main()
