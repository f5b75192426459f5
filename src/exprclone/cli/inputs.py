"""What the commands share: argument types, the three photos and their options, the eigenface basis."""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ExprCloneError, naming
from ..landmarkers import DEFAULT, LANDMARKERS
from ..options import GLOBAL_WARPS, IMAGE_WARPS, REGIONS, STRENGTH_RANGE, Options
from ..roles import ROLES, TARGET_NEUTRAL

if TYPE_CHECKING:
    import numpy as np

    from ..cloner import CloneResult
    from ..eigenface import Eigenfaces
    from ..expressions import Expression

#: what each photo (:data:`exprclone.roles.ROLES`) is, for the help.
PHOTO_HELP = (
    "photo of the source person, neutral (not with --expression)",
    "photo of the source person with the expression (not with --expression)",
    "photo of the target person, neutral",
)


def lambda_arg(text: str) -> float | str:
    """An argparse type: ``auto`` or a number >= 0 (``inf`` allowed: the local result), as
    :func:`exprclone.checks.parse_lambda` reads it."""
    from ..checks import parse_lambda  # numpy: loaded when the arguments are parsed, not when the parser is built

    try:
        return parse_lambda(text)
    except ExprCloneError as e:
        raise argparse.ArgumentTypeError(e.problem) from None


def frame_arg(text: str) -> int | str:
    """An argparse type: ``closed`` or a frame number (from 0)."""
    if text == "closed":
        return text
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected 'closed' or a number >= 0, got {text!r}")
    return value


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
    """The three photos (or the target's and ``--expression``), their optional landmark files and the clone options."""
    for role, what in zip(ROLES, PHOTO_HELP):
        if role == TARGET_NEUTRAL:
            p.add_argument(role, help=what)
        else:
            p.add_argument(role, nargs="?", help=what)
    add_expression(p, "instead of the source's two photos: give the target's photo alone")
    add_lambda(p, "elasticity ratio k_A'/k_N; auto picks it by the DB metric (default)")
    for role in ROLES:
        which = role.replace("_", "-")
        p.add_argument(
            f"--{which}-landmarks",
            metavar="FILE",
            help=f"landmarks of the {which.replace('-', ' ')} photo (.json, or a WebMorph .tem) instead of detecting them",
        )
    add_landmarker(p)
    add_eigenfaces(p)
    add_mouth(p)
    add_transfer(p, given=True)


def add_landmarker(p: argparse.ArgumentParser, what: str = "places the landmarks of photos without given ones") -> None:
    """``--landmarker``: one of :data:`exprclone.landmarkers.LANDMARKERS`."""
    p.add_argument(
        "--landmarker",
        choices=LANDMARKERS,
        default=DEFAULT,
        help=f"which landmarker {what}: dlib, whose model's licence excludes commercial use, or mesh, MediaPipe's face"
        f" mesh (Apache-2.0) (default: {DEFAULT})",
    )


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
        " (by default the motion is cleaned and each organ keeps the target's own shape)",
    )


def transfer_options(args: argparse.Namespace) -> Options:
    """The :class:`~exprclone.options.Options` given on the command line but ``--global-landmarks`` (read with the target
    photo, :func:`load_inputs`); those not given are the defaults."""
    default = Options()
    return Options(
        global_warp=args.global_warp or default.global_warp,
        image_warp=args.image_warp or default.image_warp,
        strength=default.strength if args.strength is None else args.strength,
        only=args.only,
        retarget=default.retarget if args.retarget is None else args.retarget,
    )


def add_expression(p: argparse.ArgumentParser, how: str) -> None:
    p.add_argument("--expression", metavar="NAME", help=f"a built-in expression (exprclone expressions lists them) {how}")


def load_expression(name: str) -> Expression:
    """The built-in expression ``--expression`` names (:func:`exprclone.expressions.load`); errors about ``--expression``."""
    from ..expressions import load

    with naming({"expression": "--expression"}):
        return load(name)


def source_photos(args: argparse.Namespace) -> list[str]:
    """The photo files named on the command line, checked: the source's two and the target's, or the target's alone
    with ``--expression`` (ExprCloneError otherwise)."""
    given = [p for p in (args.source_neutral, args.source_expression) if p is not None]
    if args.expression is not None:
        if given:
            raise ExprCloneError("--expression", "give the target's photo alone with a built-in expression: it replaces the source's two")
        landmarks = [f"--{role.replace('_', '-')}-landmarks" for role in ROLES[:2] if getattr(args, f"{role}_landmarks", None)]
        if landmarks:
            raise ExprCloneError(landmarks[0], "not with --expression: a built-in expression has its own landmarks")
        return [args.target_neutral]
    if len(given) < 2:
        raise ExprCloneError(
            ROLES[len(given)],
            "missing: give the source's neutral and expression photos before the target's, or the target's alone with"
            " --expression NAME (exprclone expressions lists the names)",
        )
    return [args.source_neutral, args.source_expression, args.target_neutral]


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


def load_eigenfaces(path: str | None, landmarker: str = DEFAULT) -> Eigenfaces | None:
    """The basis named by ``--eigenfaces``: None (packaged), a .npz, or a folder of photos of one person to train on
    (their landmarks placed by ``landmarker``)."""
    if path is None:
        return None
    from ..eigenface import Eigenfaces, train
    from ..io.images import PHOTO_SUFFIXES, load_image
    from ..layout import DLIB68
    from ..models import landmarker as shared

    p = Path(path)
    if p.is_dir():
        photos = sorted(str(q) for q in p.iterdir() if q.suffix.lower() in PHOTO_SUFFIXES)
        if len(photos) < 3:
            raise ExprCloneError(path, f"needs at least 3 face photos to train eigenfaces, found {len(photos)}")
        images = [load_image(q) for q in photos]
        return train(((im, shared(landmarker).detect(im, q)) for im, q in zip(images, photos)), DLIB68)
    try:
        return Eigenfaces.load(p)
    except (OSError, ValueError, KeyError) as e:
        raise ExprCloneError(path, f"not an eigenface basis (.npz with mean, components, size): {e}") from None


@dataclass(frozen=True)
class Inputs:
    """The three photos of ``clone`` and ``compare`` as the command line gives them, loaded, and how to clone them.

    Attributes
    ----------
    names : dict of str to str
        Each photo's role (:data:`exprclone.roles.ROLES`), and ``global_landmarks`` if given, to its path: what errors name.
    images : tuple of three ndarray of shape (H, W, 3), uint8 RGB
    landmarks : tuple of three ndarray of shape (N, 2) or None
        Given by a landmark file, or None (detected).
    lambda_k : float or "auto"
    eigenfaces : Eigenfaces or None
    mouth : bool
    options : Options
    landmarker : str
        Places the landmarks not given (:data:`exprclone.landmarkers.LANDMARKERS`).
    """

    names: dict[str, str]
    images: tuple[np.ndarray, np.ndarray, np.ndarray]
    landmarks: tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None]
    lambda_k: float | str
    eigenfaces: Eigenfaces | None
    mouth: bool
    options: Options
    landmarker: str = DEFAULT

    def clone(self, methods: tuple[str, ...]) -> dict[str, CloneResult]:
        """The photos cloned by ``methods`` (:func:`exprclone.clone_methods`); errors name the command line's files."""
        from ..pipeline import clone_methods

        with naming(self.names):
            return clone_methods(
                *self.images,
                methods,
                self.lambda_k,
                self.landmarks,
                landmarker=self.landmarker,
                eigenfaces=self.eigenfaces,
                mouth=self.mouth,
                options=self.options,
            )


def load_inputs(args: argparse.Namespace) -> Inputs:
    """The three photos named on the command line (or the target's and a built-in expression's two, their landmarks
    with them), loaded, their landmark files read, and the clone's options."""
    from ..io.images import load_image
    from ..io.landmarks import read_landmarks

    source_photos(args)
    files = [getattr(args, f"{role}_landmarks") for role in ROLES]
    if args.expression is None:
        paths = {role: getattr(args, role) for role in ROLES}
        sn, se, tn = (load_image(p) for p in paths.values())
        read = [None if f is None else read_landmarks(f, im.shape) for f, im in zip(files, (sn, se, tn))]
    else:
        chosen = load_expression(args.expression)
        paths = {role: f"--expression {chosen.name} ({part})" for role, part in zip(ROLES, ("neutral", "expression"))}
        paths[TARGET_NEUTRAL] = args.target_neutral
        sn, se, tn = chosen.neutral.image, chosen.expression.image, load_image(args.target_neutral)
        read = [chosen.neutral.points, chosen.expression.points, None if files[2] is None else read_landmarks(files[2], tn.shape)]
    options = transfer_options(args)
    if args.global_landmarks:
        options = dataclasses.replace(options, global_landmarks=read_landmarks(args.global_landmarks, tn.shape))
        paths["global_landmarks"] = args.global_landmarks
    eigenfaces = load_eigenfaces(args.eigenfaces, args.landmarker)
    given = (read[0], read[1], read[2])
    return Inputs(paths, (sn, se, tn), given, args.lambda_k, eigenfaces, args.mouth, options, args.landmarker)
