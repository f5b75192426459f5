"""What the commands share: argument types, the three photos and their options, the eigenface basis."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ExprCloneError

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
    return paths, images, options
