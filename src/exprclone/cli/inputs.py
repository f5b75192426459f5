"""What the commands share: argument types, the three photos and their options, the eigenface basis."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ExprCloneError
from ..options import GLOBAL_WARPS, IMAGE_WARPS, REGIONS, STRENGTH_RANGE

#: the three photos' roles (as the core names them in errors) and their options' stems.
ROLES = ("source_neutral", "source_expression", "target_neutral")
#: image files a folder of eigenface training photos may hold.
PHOTO_SUFFIXES = {".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp"}


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


def strength_arg(text: str) -> float:
    """An argparse type: a number within :data:`exprclone.options.STRENGTH_RANGE`."""
    low, high = STRENGTH_RANGE
    try:
        value = float(text)
    except ValueError:
        value = None
    if value is None or not low <= value <= high:
        raise argparse.ArgumentTypeError(f"expected a number from {low:g} to {high:g}, got {text!r}")
    return value


def regions_arg(text: str) -> tuple[str, ...]:
    """An argparse type: comma-separated names of :data:`exprclone.options.REGIONS`."""
    names = tuple(n.strip() for n in text.split(","))
    bad = [n for n in names if n not in REGIONS]
    if bad:
        raise argparse.ArgumentTypeError(f"unknown region {bad[0]!r}; choose from: {', '.join(REGIONS)}")
    return names


def add_inputs(p: argparse.ArgumentParser) -> None:
    """The three photos, their optional landmark files and the clone options."""
    p.add_argument("source_neutral", help="photo of the source person, neutral")
    p.add_argument("source_expression", help="photo of the source person with the expression")
    p.add_argument("target_neutral", help="photo of the target person, neutral")
    add_lambda(p, "elasticity ratio k_A'/k_N; auto picks it by the DB metric (default)")
    for role in ROLES:
        which = role.replace("_", "-")
        p.add_argument(
            f"--{which}-landmarks",
            metavar="FILE",
            help=f"landmarks of the {which.replace('-', ' ')} photo (.json, or a WebMorph .tem) instead of detecting them",
        )
    add_eigenfaces(p)
    add_mouth(p)
    add_transfer(p, given=True)


def add_transfer(p: argparse.ArgumentParser, given: bool) -> None:
    """The options of :class:`exprclone.options.Options`: the global and image warps, strength, regions and
    retargeting (``given``: also ``--global-landmarks``, the landmarks of one expression)."""
    warps = p.add_mutually_exclusive_group()
    warps.add_argument(
        "--global-warp",
        choices=GLOBAL_WARPS,
        help="how the source's motion reaches the target (GI): similarity, the paper's (default), or rbf, by the local"
        " Jacobian of a radial-basis-function map between the two neutral faces (Seol and Lewis; Figs. 19-20)",
    )
    if given:
        warps.add_argument(
            "--global-landmarks",
            metavar="FILE",
            help="the target's expression landmarks from any other method (.json or .tem), taken as GI and refined (Fig. 21)",
        )
    p.add_argument(
        "--image-warp",
        choices=IMAGE_WARPS,
        help="how the photo follows its landmarks: mesh, piecewise-affine (default), or tps, a smooth thin-plate spline",
    )
    p.add_argument(
        "--strength",
        type=strength_arg,
        metavar="S",
        help="how much of the expression to transfer: 0 leaves the target as it is, 1 (default) all of it, up to 2",
    )
    p.add_argument(
        "--only",
        type=regions_arg,
        metavar="REGIONS",
        help=f"transfer the motion of these regions only ({','.join(REGIONS)}), the others held where they are",
    )
    p.add_argument(
        "--no-retarget",
        dest="retarget",
        action="store_false",
        default=None,
        help="run the paper's global and local stages: the source's motion as it is, and its own organ shapes"
        " (by default the motion is cleaned and each organ keeps the target's own shape; README: Fidelity to the target)",
    )


def transfer_options(args: argparse.Namespace, target_shape: tuple[int, ...] | None = None) -> dict:
    """The options of :class:`exprclone.options.Options` given on the command line (``--global-landmarks`` read for a
    target photo of ``target_shape``); those not given are left to the defaults."""
    from ..io.landmarks import read_landmarks

    given = getattr(args, "global_landmarks", None)
    options = dict(global_warp=args.global_warp, image_warp=args.image_warp, strength=args.strength, only=args.only, retarget=args.retarget)
    options["global_landmarks"] = None if given is None else read_landmarks(given, target_shape)
    return {k: v for k, v in options.items() if v is not None}


def add_lambda(p: argparse.ArgumentParser, help: str) -> None:
    p.add_argument("--lambda", dest="lambda_k", type=lambda_arg, default="auto", metavar="auto|FLOAT", help=help)


def add_eigenfaces(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--eigenfaces", metavar="PATH", help="eigenface basis for the DB metric: a .npz, or a folder of face photos to train one on"
    )


def add_mouth(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-mouth",
        dest="mouth",
        action="store_false",
        help="leave an opened mouth's stretched lips instead of pasting the source's teeth",
    )


def load_eigenfaces(path: str | None):
    """The basis named by ``--eigenfaces``: None (packaged), a .npz, or a folder of photos of one person to train on."""
    if path is None:
        return None
    from ..eigenface import Eigenfaces, train
    from ..io.images import load_image
    from ..layout import DLIB68
    from ..pipeline import default_detector

    p = Path(path)
    if p.is_dir():
        photos = sorted(str(q) for q in p.iterdir() if q.suffix.lower() in PHOTO_SUFFIXES)
        if len(photos) < 3:
            raise ExprCloneError(path, f"needs at least 3 face photos to train eigenfaces, found {len(photos)}")
        images = [load_image(q) for q in photos]
        return train(((im, default_detector().detect(im, q)) for im, q in zip(images, photos)), DLIB68)
    try:
        return Eigenfaces.load(p)
    except (OSError, ValueError, KeyError) as e:
        raise ExprCloneError(path, f"not an eigenface basis (.npz with mean, components, size): {e}") from None


def load_inputs(args: argparse.Namespace) -> tuple[dict[str, str], list, dict]:
    """The three photos as named on the command line (role to path), loaded, and the options for :func:`exprclone.clone`."""
    from ..io.images import load_image
    from ..io.landmarks import read_landmarks

    paths = {role: getattr(args, role) for role in ROLES}
    images = [load_image(p) for p in paths.values()]
    files = [getattr(args, f"{role}_landmarks") for role in ROLES]
    landmarks = tuple(None if f is None else read_landmarks(f, im.shape) for f, im in zip(files, images))
    options = dict(lambda_k=args.lambda_k, landmarks=landmarks, eigenfaces=load_eigenfaces(args.eigenfaces), mouth=args.mouth)
    options.update(transfer_options(args, images[2].shape))
    if args.global_landmarks:
        paths["global_landmarks"] = args.global_landmarks
    return paths, images, options
