"""``exprclone clone``: the source's expression on the target's face, as an image (and a JSON record)."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

from ..options import REGIONS, Options
from .inputs import add_inputs, load_inputs, source_photos

if TYPE_CHECKING:
    from ..pipeline.result import CloneResult


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    c = sub.add_parser("clone", help="put the source's expression on the target's face")
    add_inputs(c)
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")
    c.add_argument("--save-json", metavar="OUT.json", help="write the landmarks of every stage, lambda_k and the DB curve")


def run(args: argparse.Namespace) -> None:
    from ..io.images import atomic_write, check_output_path, save_image
    from ..io.record import result_record

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


def describe(options: Options) -> str:
    """The options that are not the defaults, for the last line: ``, global warp rbf, strength 0.5``."""
    default, said = Options(), []
    if options.global_stage != default.global_stage:
        said.append(f"global warp {options.global_stage}")
    if options.image_warp != default.image_warp:
        said.append(f"image warp {options.image_warp}")
    if options.strength != default.strength:
        said.append(f"strength {options.strength:g}")
    if options.only is not None:
        said.append(f"only {','.join(options.only)}")
    said += [f"{r} strength {s:g}" for r in REGIONS if (s := getattr(options, f"strength_{r}")) is not None]
    if options.strength_shading != default.strength_shading:
        said.append(f"shading strength {options.strength_shading:g}")
    if options.retarget != default.retarget:
        said.append("no retarget")
    return "".join(f", {s}" for s in said)
