"""Judge the expression editor's controls on London people held out of their learning, and print the table.

    python tools/judge_editor.py [--data ../shared/data/london] [--people 20] [--csv OUT.csv]

The people (:func:`exprclone.evaluation.editor_judge.held_out`: 20 of the London Set, dealt by a seed) are none of
those the built controls were calibrated on (``tools/train_expression_controls.py``), and the GRID clips hold none of
them. The shipped smile model is learnt from all 72 people, so here the smile is the one of a model learnt without
the people judged (:meth:`exprclone.geometry.expression_shape.ExpressionShape.learn` on the others), as broad as the
upper quartile of those others' own smiles (:func:`exprclone.expressions.controls.smile_share`). Each person's
neutral photo is edited by every control at 0, 0.5 and 1 and scored by the blendshape model and dlib's identity
descriptor (:mod:`exprclone.evaluation.editor_judge`, which says what each column is).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import time

from exprclone.data import sets as datasets
from exprclone.evaluation import editor_judge
from exprclone.evaluation.london import Dataset
from exprclone.expressions import editor as editing
from exprclone.expressions.controls import default_motions, smile_share
from exprclone.geometry.expression_shape import ExpressionShape
from exprclone.io.images import load_image
from exprclone.landmarks.backends import shared
from exprclone.landmarks.blendshapes import Blendshapes
from exprclone.landmarks.layout import DLIB68
from exprclone.options import Options
from exprclone.pipeline.role_check import descriptor


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, "london", holds="the London Set")
    parser.add_argument("--people", type=int, default=editor_judge.HELD_OUT, help="how many people judge (held out)")
    parser.add_argument("--csv", metavar="OUT.csv", help="write the table's rows")
    args = parser.parse_args()
    start = time.perf_counter()
    data = Dataset.open(args.data)
    judged = editor_judge.held_out(data.ids, args.people)
    detect = shared("dlib")
    faces = {i: tuple(detect.detect(load_image(p), p) for p in (data.path(i, False), data.path(i, True))) for i in data.ids}
    others = [faces[i] for i in data.ids if i not in judged]
    model = ExpressionShape.learn(others, DLIB68)
    motions = dataclasses.replace(default_motions(), smile_share=smile_share(model, others, DLIB68))
    print(f"judged on {len(judged)} people ({', '.join(judged)}); the smile learnt from the {len(others)} others", flush=True)
    judge, people = Blendshapes(), []
    for name in judged:
        photo = load_image(data.path(name, False))
        editor = editing.Editor.of(editing.request(photo, faces[name][0], Options(expression_shape=model)), motions)
        people.append(editor_judge.person(name, editor, descriptor(photo, faces[name][0]), judge, detect))
        print(f"  {name}", flush=True)
    rows = editor_judge.summary(people)
    print(editor_judge.table(rows))
    print(f"({time.perf_counter() - start:.0f} s)")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
