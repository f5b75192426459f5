"""What the commands share: the options' arguments, the three photos and their landmark files, the eigenface basis."""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from ..errors import ExprCloneError, naming
from ..options import Options, changed, flag, key, names, offered, spec
from ..roles import ROLES, TARGET_NEUTRAL

if TYPE_CHECKING:
    import numpy as np

    from ..expressions import Expression
    from ..geometry.eigenface import Eigenfaces
    from ..pipeline.request import Request
    from ..pipeline.result import CloneResult

T = TypeVar("T")


class Interrupted(Exception):
    """Ctrl-C, after the command has said what it leaves (batch: the rows finished; serve: "stopped"):
    :func:`exprclone.cli.main.main` adds nothing and exits with its status for Ctrl-C."""


def value_type(cls: type, name: str) -> Callable[[str], Any]:
    """An argparse type: the option ``name`` of ``cls`` as a word of the command line gives it, read by its spec's
    ``parse`` and checked by its ``check`` (:class:`~exprclone.options.Spec`)."""
    option = spec(cls, name)

    def read(text: str) -> Any:
        try:
            return option.check(text if option.parse is None else option.parse(text), key(cls, name))
        except ExprCloneError as e:
            raise argparse.ArgumentTypeError(e.problem) from None
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None

    return read


def add_options(p: Any, cls: type, chosen: tuple[str, ...] | None = None) -> None:
    """The options of ``cls`` (:class:`~exprclone.options.Options` or another value of option fields) that the
    command line offers, of ``chosen``, each an argument made from its spec: ``--strength S``, ``--no-mouth``, ``--global-landmarks
    FILE``; a switch on by default is a flag that turns it off, its help what giving the flag does (the spec's
    ``flag_help``). ``p`` is a parser or a group of one. Arguments not given are None: :func:`options_of` leaves them as
    they are."""
    default = cls()
    for name in offered(cls, "cli", chosen):
        option, given = spec(cls, name), flag(cls, name)
        value = getattr(default, name)
        if option.file:
            p.add_argument(given, dest=name, metavar=option.metavar, help=option.help)
        elif option.kind is bool:
            action, said = ("store_false", option.flag_help) if value else ("store_true", option.help)
            p.add_argument(given, dest=name, action=action, default=None, help=said)
        else:
            shown = "" if value is None else f" (default: {value:g})" if isinstance(value, float) else f" (default: {value})"
            read = None if option.choices else value_type(cls, name)
            p.add_argument(given, dest=name, type=read, choices=option.choices, metavar=option.metavar, help=option.help + shown)


def options_of(args: argparse.Namespace, cls: type[T], chosen: tuple[str, ...] | None = None, base: T | None = None) -> T:
    """The options of ``cls`` given on the command line (:func:`add_options`; files aside: the command reads them), the
    others as in ``base`` (the defaults if None)."""
    given = {name: getattr(args, name, None) for name in offered(cls, "cli", chosen) if not spec(cls, name).file}
    return changed(cls, base, {name: value for name, value in given.items() if value is not None})


#: what each photo (:data:`exprclone.roles.ROLES`) is, for the help.
PHOTO_HELP = (
    "photo of the source person, neutral (not with --expression)",
    "photo of the source person with the expression (not with --expression)",
    "photo of the target person, neutral",
)


def add_inputs(p: argparse.ArgumentParser, chosen: tuple[str, ...] | None = None) -> None:
    """The three photos (or the target's and ``--expression``), their optional landmark files and the clone's options
    (of ``chosen``, all by default)."""
    for role, what in zip(ROLES, PHOTO_HELP):
        if role == TARGET_NEUTRAL:
            p.add_argument(role, help=what)
        else:
            p.add_argument(role, nargs="?", help=what)
    add_expression(p, "instead of the source's two photos: give the target's photo alone")
    for role in ROLES:
        which = role.replace("_", "-")
        p.add_argument(
            f"--{which}-landmarks",
            metavar="FILE",
            help=f"landmarks of the {which.replace('-', ' ')} photo (.json, or a WebMorph .tem) instead of detecting them",
        )
    chosen = chosen or names(Options)
    gi = tuple(n for n in ("global_warp", "global_landmarks") if n in chosen)
    add_options(p.add_mutually_exclusive_group(), Options, gi)  # given GI replaces the global warp
    add_options(p, Options, tuple(n for n in chosen if n not in gi))


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


def load_eigenfaces(path: str, landmarker: str) -> Eigenfaces:
    """The basis named by ``--eigenfaces``: a .npz, or a folder of photos of one person to train on (their landmarks
    placed by ``landmarker``)."""
    from ..geometry.eigenface import Eigenfaces, train
    from ..io.images import PHOTO_SUFFIXES, load_image
    from ..landmarks.backends import shared
    from ..landmarks.layout import DLIB68

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


def with_eigenfaces(args: argparse.Namespace, options: Options) -> Options:
    """``options`` with the basis ``--eigenfaces`` names, if it names one (:func:`load_eigenfaces`)."""
    if getattr(args, "eigenfaces", None) is None:
        return options
    return dataclasses.replace(options, eigenfaces=load_eigenfaces(args.eigenfaces, str(options.landmarker)))


@dataclass(frozen=True)
class Asked:
    """What ``clone`` and ``compare`` are asked on the command line: the request of its files, read
    (:func:`exprclone.io.inputs.gather`), and what each photo is (its path, or the built-in expression's part).

    Attributes
    ----------
    request : Request
    names : dict of str to str
        Each photo's role (:data:`exprclone.roles.ROLES`), and ``global_landmarks`` if given, to its path: what errors
        and the record name.
    """

    request: Request
    names: dict[str, str]

    @property
    def options(self) -> Options:
        return self.request.options

    @property
    def images(self) -> tuple[np.ndarray, ...]:
        """The three photos, in the order of :data:`~exprclone.roles.ROLES`."""
        return tuple(p.image for p in self.request.photos)

    def clone(self, methods: tuple[str, ...], options: Options | None = None) -> dict[str, CloneResult]:
        """The request's clone by ``methods`` (with other ``options`` if given): its errors name the command line's files."""
        from ..pipeline import request as door  # (the pipeline when a command runs, not for --help)

        request = self.request if options is None else dataclasses.replace(self.request, options=options)
        with naming(self.names):
            return door.prepare(request, methods).render()


def load_inputs(args: argparse.Namespace) -> Asked:
    """The three photos named on the command line (or the target's and a built-in expression), their landmark files
    and the clone's options (:func:`options_of`; the files they name read), gathered into one request."""
    from ..io.inputs import Source, gather  # (the pipeline when a command runs, not for --help)

    source_photos(args)
    files = [getattr(args, f"{role}_landmarks") for role in ROLES]
    if args.expression is None:
        names = {role: getattr(args, role) for role in ROLES}
    else:
        chosen = load_expression(args.expression)
        names = {role: f"--expression {chosen.name} ({part})" for role, part in zip(ROLES, ("neutral", "expression"))}
        names[TARGET_NEUTRAL] = args.target_neutral
    photos = [None if args.expression is not None and role != TARGET_NEUTRAL else Source(names[role]) for role in ROLES]
    given = None if not getattr(args, "global_landmarks", None) else Source(args.global_landmarks)
    if given is not None:
        names["global_landmarks"] = given.name
    with naming(names):
        request = gather(
            photos,
            [None if f is None else Source(f) for f in files],
            with_eigenfaces(args, options_of(args, Options)),
            expression=args.expression,
            global_landmarks=given,
        )
    return Asked(request, names)
