"""The ``exprclone`` command.

Errors a user can cause come out as one line on stderr and exit status 2; warnings as
one line each. No output file is written unless the whole job succeeded.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from pathlib import Path

from .errors import ExprCloneError

EXIT_USAGE = 2
#: exit status after Ctrl-C (128 + SIGINT), as shells report it.
EXIT_INTERRUPTED = 130


def word_or_number(word: str, number: type):
    """An argparse type: ``word``, or a ``number`` (int or float) >= 0."""

    def parse(text: str) -> int | float | str:
        if text == word:
            return text
        try:
            value = number(text)
        except ValueError:
            value = None
        if value is None or not value >= 0:
            raise argparse.ArgumentTypeError(f"expected {word!r} or a number >= 0, got {text!r}")
        return value

    return parse


#: ``auto`` or a number >= 0 (``inf`` allowed: the local result).
lambda_arg = word_or_number("auto", float)
#: ``closed`` or a frame number.
frame_arg = word_or_number("closed", int)


def add_inputs(p: argparse.ArgumentParser) -> None:
    """The three photos, their optional landmark files and the clone options."""
    p.add_argument("source_neutral", help="photo of the source person, neutral")
    p.add_argument("source_expression", help="photo of the source person with the expression")
    p.add_argument("target_neutral", help="photo of the target person, neutral")
    p.add_argument(
        "--lambda",
        dest="lambda_k",
        type=lambda_arg,
        default="auto",
        metavar="auto|FLOAT",
        help="elasticity ratio k_A'/k_N; auto picks it by the DB metric (default)",
    )
    for which in ("source-neutral", "source-expression", "target-neutral"):
        p.add_argument(
            f"--{which}-landmarks",
            metavar="FILE",
            help=f"landmarks of the {which.replace('-', ' ')} photo (.json, or a WebMorph .tem) instead of detecting them",
        )
    p.add_argument(
        "--eigenfaces", metavar="PATH", help="eigenface basis for the DB metric: a .npz, or a folder of face photos to train one on"
    )
    p.add_argument(
        "--no-mouth",
        dest="mouth",
        action="store_false",
        help="leave an opened mouth's stretched lips instead of pasting the source's teeth",
    )


def build_parser() -> argparse.ArgumentParser:
    from .methods import METHODS

    parser = argparse.ArgumentParser(prog="exprclone", description="Facial expression cloning with elastic and muscle models (E+MD).")
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser("clone", help="put the source's expression on the target's face")
    add_inputs(c)
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")
    c.add_argument("--method", choices=METHODS, default="e+md", help="method of the paper's Fig. 11 (default: e+md)")
    c.add_argument("--save-json", metavar="OUT.json", help="write the landmarks of every stage, lambda_k and the DB curve")
    c = sub.add_parser("compare", help="the paper's Figs. 11-13 and the DB curve as one sheet")
    add_inputs(c)
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")
    e = sub.add_parser("evaluate", help="score every method against real smiles on many pairs")
    london = os.path.join(os.environ.get("EXPRCLONE_DATA", "../shared/data"), "london")
    e.add_argument(
        "--data",
        default=london,
        help=f"folder with neutral_front/ID_03.jpg and smiling_front/ID_08.jpg (default: {london}, from $EXPRCLONE_DATA)",
    )
    e.add_argument("--pairs", type=int, default=50, help="ordered pairs of different people, drawn with --seed (0: all; default 50)")
    e.add_argument("--seed", type=int, default=0)
    e.add_argument("--methods", default="all", help="comma-separated methods, or all (default)")
    e.add_argument("--out", default="report", help="report folder (default: report/)")
    e.add_argument("--jobs", type=int, default=1, help="processes to use (default 1)")
    v = sub.add_parser("video", help="drive a neutral portrait with a video of the source person")
    v.add_argument("target_neutral", help="photo of the target person, neutral (the portrait)")
    v.add_argument("driving_video", help="video of the source person (any format FFmpeg reads)")
    v.add_argument("-o", "--output", required=True, help="output video (.mp4, .mov or .mkv)")
    neutral = v.add_mutually_exclusive_group()
    neutral.add_argument("--source-neutral", metavar="IMAGE", help="a neutral photo of the source person (default: a video frame)")
    neutral.add_argument(
        "--neutral-frame",
        type=frame_arg,
        metavar="N|closed",
        help="the video frame (from 0) with the source's neutral face, or closed: the one whose mouth is most closed"
        " (default: the first frame with a face)",
    )
    v.add_argument("--method", choices=METHODS, default="e+md", help="method of the paper's Fig. 11 (default: e+md)")
    v.add_argument(
        "--lambda",
        dest="lambda_k",
        type=lambda_arg,
        default="auto",
        metavar="auto|FLOAT",
        help="elasticity ratio k_A'/k_N; auto: the DB metric's median choice on the 5 most expressive frames (default)",
    )
    v.add_argument("--lambda-per-frame", action="store_true", help="choose lambda_k by the DB metric on every frame (slower)")
    v.add_argument("--side-by-side", action="store_true", help="write the driving video and the result side by side")
    v.add_argument("--head-motion", action="store_true", help="carry the source's head motion over (a similarity of the whole frame)")
    v.add_argument("--size", type=int, metavar="PIXELS", help="scale the portrait so its longest side has this many pixels")
    v.add_argument("--no-smooth", dest="smooth", action="store_false", help="use the raw per-frame landmarks, without temporal smoothing")
    v.add_argument("--target-neutral-landmarks", metavar="FILE", help="landmarks of the portrait (.json or .tem) instead of detecting them")
    v.add_argument("--eigenfaces", metavar="PATH", help="eigenface basis for the DB metric: a .npz, or a folder of face photos")
    v.add_argument("--no-mouth", dest="mouth", action="store_false", help="do not paste the source's teeth into an opened mouth")
    return parser


def result_json(result, inputs: list[str]) -> dict:
    """The JSON record of a clone: inputs, method, lambda_k, DB curve, landmarks of each stage."""
    curve = result.db_curve
    number = lambda v: None if v is None else (v if v != float("inf") else "inf")  # noqa: E731
    return {
        "inputs": dict(zip(("source_neutral", "source_expression", "target_neutral"), inputs)),
        "method": result.method,
        "lambda_k": number(result.lambda_k),
        "db_curve": None
        if curve is None
        else [{"lambda_k": number(float(lam)), "db": float(db)} for lam, db in zip(curve.lambdas, curve.db)],
        "muscle_strengths": None if result.muscle_strengths is None else [float(h) for h in result.muscle_strengths],
        "unfolded_points": result.unfolded_points,
        "landmarks": {k: v.round(3).tolist() for k, v in result.landmarks.items()},
    }


def load_eigenfaces(path: str | None):
    """The basis named by ``--eigenfaces``: None (packaged), a .npz, or a folder to train on."""
    if path is None:
        return None
    from .eigenface import Eigenfaces, train
    from .layout import DLIB68
    from .pipeline import default_detector

    p = Path(path)
    if p.is_dir():
        photos = sorted(str(q) for q in p.iterdir() if q.suffix.lower() in {".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp"})
        if len(photos) < 3:
            raise ExprCloneError(f"{path}: needs at least 3 face photos to train eigenfaces, found {len(photos)}")
        return train(photos, default_detector(), DLIB68)
    try:
        return Eigenfaces.load(p)
    except (OSError, ValueError, KeyError) as e:
        raise ExprCloneError(f"{path}: not an eigenface basis (.npz with mean, components, size): {e}") from None


def load_inputs(args: argparse.Namespace) -> tuple[list[str], list, dict]:
    """The three photos as named on the command line, and the options for :func:`exprclone.clone`."""
    from .images import load_image
    from .landmark_files import read_landmarks

    inputs = [args.source_neutral, args.source_expression, args.target_neutral]
    images = [load_image(p) for p in inputs]
    files = (args.source_neutral_landmarks, args.source_expression_landmarks, args.target_neutral_landmarks)
    landmarks = tuple(None if f is None else read_landmarks(f, im.shape) for f, im in zip(files, images))
    options = dict(
        lambda_k=args.lambda_k, landmarks=landmarks, eigenfaces=load_eigenfaces(args.eigenfaces), names=tuple(inputs), mouth=args.mouth
    )
    return inputs, images, options


def run_clone(args: argparse.Namespace) -> None:
    from .images import atomic_write, check_output_path, save_image
    from .pipeline import clone

    inputs = [args.source_neutral, args.source_expression, args.target_neutral]
    check_output_path(args.output, inputs)
    if args.save_json:
        check_output_path(args.save_json, inputs + [args.output], extensions=[".json"])
    inputs, images, options = load_inputs(args)
    result = clone(*images, method=args.method, **options)
    save_image(args.output, result.image, inputs=inputs)
    if args.save_json:
        record = json.dumps(result_json(result, inputs), indent=1).encode()
        atomic_write(args.save_json, lambda f: f.write(record))
    extra = "" if result.lambda_k is None else f", lambda_k={result.lambda_k:g}"
    print(f"{args.output}: {args.method}{extra}")


def run_compare(args: argparse.Namespace) -> None:
    from .compare import sheet
    from .images import check_output_path, save_image
    from .pipeline import clone_methods

    check_output_path(args.output, [args.source_neutral, args.source_expression, args.target_neutral])
    inputs, images, options = load_inputs(args)
    results = clone_methods(*images, **options)
    save_image(args.output, sheet(results, images[1]), inputs=inputs)
    print(f"{args.output}: 7 methods, lambda_k={results['e+md'].lambda_k:g}")


def run_evaluate(args: argparse.Namespace) -> None:
    from pathlib import Path

    from .evaluate import Dataset, run, summarise, table, write_report
    from .methods import METHODS

    methods = METHODS if args.methods == "all" else tuple(m.strip() for m in args.methods.split(","))
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise ExprCloneError(f"--methods: unknown method {unknown[0]!r}; choose from: {', '.join(METHODS)}")
    data = Dataset.open(args.data)
    pairs = data.pairs(args.pairs, args.seed)
    rows, landmarks = run(data, pairs, methods, jobs=max(1, args.jobs))
    command = "exprclone evaluate " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["evaluate"] else "exprclone evaluate"
    write_report(Path(args.out), data, rows, landmarks, methods, command)
    print(table(summarise(rows)))
    print(f"strong smiles only:\n{table(summarise(rows, strong_only=True))}")
    print(f"report: {Path(args.out) / 'summary.md'}")


def run_video(args: argparse.Namespace) -> None:
    import numpy as np

    from . import video, video_io
    from .images import check_output_path, load_image
    from .landmark_files import read_landmarks
    from .progress import Bar

    inputs = [p for p in (args.target_neutral, args.driving_video, args.source_neutral) if p]
    check_output_path(args.output, inputs, extensions=video_io.EXTENSIONS)
    if args.size is not None and args.size < 16:
        raise ExprCloneError(f"--size: expected at least 16 pixels, got {args.size}")
    target = load_image(args.target_neutral)
    points = None if args.target_neutral_landmarks is None else read_landmarks(args.target_neutral_landmarks, target.shape)
    target, points = video.resize_portrait(target, points, args.size)
    source = None if args.source_neutral is None else (load_image(args.source_neutral), None)
    driver = video.Driver(
        target,
        points,
        args.driving_video,
        source_neutral=source,
        neutral_frame=args.neutral_frame,
        method=args.method,
        lambda_k=args.lambda_k,
        lambda_per_frame=args.lambda_per_frame,
        head_motion=args.head_motion,
        smooth=args.smooth,
        mouth=args.mouth,
        eigenfaces=load_eigenfaces(args.eigenfaces),
        target_name=args.target_neutral,
    )
    bar = Bar(sys.stderr, len(driver.points), "frames")

    def frames():
        for done, f in enumerate(driver.frames(), 1):
            yield video.side_by_side(f.driving, f.image) if args.side_by_side else f.image
            bar.update(done, f"{done / bar.elapsed:.1f} fps")

    written = video_io.write_video(args.output, frames(), driver.info.fps, audio_from=args.driving_video, inputs=inputs)
    rate = written / bar.elapsed
    lam = driver.lambda_k
    if lam is None:
        how = ""
    elif lam == "auto":
        how = ", lambda_k chosen per frame"
    else:
        how = f", lambda_k={lam:g}" + (
            f" (the DB metric's median on frames {', '.join(map(str, driver.lambda_frames))})" if driver.lambda_frames else ""
        )
    neutral = args.source_neutral if driver.neutral_index is None else f"frame {driver.neutral_index}"
    missing = [int(i) for i in np.flatnonzero(~driver.track.found)]
    if missing:
        shown = ", ".join(map(str, missing[:10])) + (", ..." if len(missing) > 10 else "")
        faces = f"no face on {len(missing)} frame(s) ({shown}): they hold the last landmarks found"
    else:
        faces = "a face on every frame"
    done = f"{args.output}: {written} frames at {float(driver.info.fps):g} fps, {args.method}{how}"
    print(f"{done}; neutral: {neutral}; {faces}; rendered at {rate:.1f} fps")


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings as one line each on stderr, no source location."""
    print(f"exprclone: warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    warnings.showwarning = show_warning
    try:
        {"clone": run_clone, "compare": run_compare, "evaluate": run_evaluate, "video": run_video}[args.command](args)
    except ExprCloneError as e:
        print(f"exprclone: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # the output, written under a temporary name, is already gone
        print("\nexprclone: interrupted; no output written", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0


if __name__ == "__main__":
    sys.exit(main())
