"""``exprclone clone``: the source's expression on the target's face, as an image (and a JSON record)."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

from ..io.record import result_record
from ..options import Options, differing, flag, key, spec
from .inputs import add_inputs, load_inputs, source_photos

if TYPE_CHECKING:
    from ..pipeline.result import CloneResult


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    c = sub.add_parser("clone", help="put the source's expression on the target's face")
    add_inputs(c)
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")
    c.add_argument("--save-json", metavar="OUT.json", help="write the landmarks of every stage, lambda_k and the DB curve")


def run(args: argparse.Namespace) -> None:
    from ..io.images import (  # (numpy and the rest: loaded when the command runs, not for --help)
        atomic_write,
        check_output_path,
        save_image,
    )

    paths = source_photos(args)
    check_output_path(args.output, paths)
    if args.save_json:
        check_output_path(args.save_json, paths + [args.output], extensions=[".json"])
    inputs = load_inputs(args)
    method = inputs.options.method
    result = inputs.clone((method,))[method]
    save_image(args.output, result.image, inputs=paths)
    if args.save_json:
        record = json.dumps(result_record(result, inputs.names), indent=1).encode()
        atomic_write(args.save_json, lambda f: f.write(record))
    extra = "" if result.lambda_k is None else f", lambda_k={result.lambda_k:g}"
    source = "" if args.expression is None else f", expression {args.expression}"
    print(f"{args.output}: {method}{source}{extra}{faces_cloned(result)}{describe(result.options)}")


def faces_cloned(result: CloneResult) -> str:
    """The faces of a photo of several that were cloned, for the last line: ``, faces 1,2,4 of 5`` (none for one face)."""
    if not result.face_results:
        return ""
    done = [str(face.number) for face in result.face_results if face.result is not None]
    return f", face{'s' if len(done) != 1 else ''} {','.join(done) or 'none'} of {len(result.face_results)}"


#: the options the last line says apart (the method first, lambda_k as chosen, the faces cloned).
SAID_APART = ("method", "lambda_k", "faces")


def describe(options: Options) -> str:
    """The options that are not the defaults, for the last line: ``, global warp rbf, strength 0.5, no retarget``: each
    by its key's words and its value (a file's: ``given``), a switch by its flag's words (``no retarget``)."""
    said = []
    for name, value in differing(options).items():
        if name in SAID_APART or "cli" not in spec(Options, name).surfaces:
            continue
        if isinstance(value, bool):
            said.append(flag(Options, name).lstrip("-").replace("-", " "))
            continue
        words = key(Options, name).replace("_", " ")
        shown = f"{value:g}" if isinstance(value, float) else ",".join(map(str, value)) if isinstance(value, tuple) else value
        said.append(f"{words} {shown if isinstance(shown, str) else 'given'}")
    return "".join(f", {s}" for s in said)
