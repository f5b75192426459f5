"""The package's layout: rooms by the parts of the method, stacked without circles, each option declared once, typed.

The import graph is built from the source (every import, those under ``TYPE_CHECKING`` and
inside functions included), as ``../shared/tools/imports.py`` builds it.
"""

import ast
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from exprclone.options import Driving, Framing, Options, key, names, spec

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "exprclone"
#: the rooms from the bottom up: each imports only from its own room and those below it. The package's face
#: (``exprclone/__init__.py``) hands the top names on; the outer rooms (io, cli, server, batch, study, evaluation,
#: expressions, data) stand on all of these.
RANKS = {
    "errors": 0,
    "roles": 0,
    "methods": 0,
    "landmarks": 1,
    "imaging": 2,
    "geometry": 3,
    "details": 4,
    "mouth": 5,
    "options": 6,
    "pipeline": 7,
    "drive": 8,
}
OUTER = 9
#: the rooms where the clone's options are read and handed on (a core room's functions take plain arguments, so that a
#: ``size`` of a crop or a ``layout`` of landmarks there is another thing than the option).
SURFACES = ("options", "pipeline", "drive", "cli", "server", "batch", "study", "evaluation", "expressions/__init__.py")


def modules() -> dict[str, Path]:
    found = {}
    for path in PACKAGE.rglob("*.py"):
        name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def imported(name: str, path: Path) -> list[tuple[str, str | None]]:
    """What module ``name`` imports (``TYPE_CHECKING`` imports too): ``(module, name)`` for each name taken from a
    module (``from . import eri``: ``(package, "eri")``), ``(module, None)`` for ``import module``."""
    parts = name.split(".") + (["__init__"] if path.name == "__init__.py" else [])
    found: list[tuple[str, str | None]] = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            target = (
                ".".join(parts[: len(parts) - node.level] + ([node.module] if node.module else [])) if node.level else node.module or ""
            )
            found += [(target, a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            found += [(a.name, None) for a in node.names]
    return found


#: where the package's face takes each of its names from (its ``TYPE_CHECKING`` imports are the lazy ones; a submodule
#: it imports to hand a lazy name on is not one of its names).
FACE = {t: m for m, t in imported("exprclone", PACKAGE / "__init__.py") if t and f"{m}.{t}" not in modules()}


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The package's modules that module ``name`` imports: a name imported from a package is a tie to its submodule of
    that name if there is one (``from . import eri`` ties to ``eri``), else to the package; a name imported from the
    package's face is a tie to the module the face takes it from (:data:`FACE`)."""
    found = set()
    for module, taken in imported(name, path):
        if taken is not None and f"{module}.{taken}" in known:
            found.add(f"{module}.{taken}")
        else:
            found.add(FACE.get(taken or "", module) if module == "exprclone" else module)
    return {t for t in found if t in known and t not in (name, "exprclone")}


def graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imports(name, path, known) for name, path in known.items()}


def circles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                found.append(sorted(group))

    for v in edges:
        if v not in index:
            visit(v)
    return found


def rank(module: str) -> int:
    room = module.split(".")[1] if "." in module else ""
    return RANKS.get(room, OUTER) if room else -1


def test_no_import_circle():
    assert circles(graph()) == []


def test_a_name_taken_from_the_packages_face_is_a_tie_to_its_module(tmp_path):
    """``from .. import Options`` in a room ties it to :mod:`exprclone.options` (the face only hands the name on): a
    circle through the face is a circle."""
    probe = tmp_path / "probe.py"
    probe.write_text("from .. import Options, data\nfrom ..methods import lookup\nimport exprclone\n")
    assert imports("exprclone.landmarks.probe", probe, modules()) == {"exprclone.options", "exprclone.data", "exprclone.methods"}
    assert FACE["clone"] == "exprclone.pipeline.clone" and FACE["Options"] == "exprclone.options"


def test_the_circle_finder_finds_one():
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_each_room_imports_only_its_own_and_those_below():
    upward = [f"{m} -> {t}" for m, targets in graph().items() if m != "exprclone" for t in targets if rank(t) > rank(m)]
    assert upward == []


#: the server's parts from the bottom up (FastAPI's "bigger applications"): what its routes and machinery share (its CPU
#: work, settings, forms, answers: rank 0), its machinery (pools, jobs, limits, the live protocol), its routes, the
#: application that mounts them.
SERVER_RANKS = {"runtime": 1, "routers": 2, "app": 3}


def server_rank(module: str) -> int | None:
    """The rank of a module of :mod:`exprclone.server` among the server's parts, None for any other module."""
    parts = module.split(".")
    return SERVER_RANKS.get(parts[2], 0) if parts[:2] == ["exprclone", "server"] and len(parts) > 2 else None


def test_the_servers_machinery_knows_no_route():
    """The runtime imports nothing of the routes nor of the application; the routes nothing of the application."""
    edges = graph()
    upward = [
        f"{m} -> {t}"
        for m, targets in edges.items()
        if server_rank(m) is not None
        for t in targets
        if (server_rank(t) or 0) > (server_rank(m) or 0)
    ]
    assert upward == [] and server_rank("exprclone.server.runtime.jobs") == 1 and server_rank("exprclone.server.work") == 0


def test_at_most_eight_modules_beside_the_rooms():
    top = [p.name for p in PACKAGE.glob("*.py") if p.name not in ("__init__.py", "__main__.py")]
    assert len(top) <= 8, top


def declarations(tree: ast.AST, names: set[str], flags: dict[str, str], keys: dict[str, str], surface: bool) -> list[tuple[str, int]]:
    """Where a tree declares an option again: a parameter or class field of its name with a default (None, "as the
    options say", aside) in a surface room, a command line flag of its, or a form field of its key."""
    found = []
    for node in ast.walk(tree):
        if surface and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            positional = a.posonlyargs + a.args
            pairs = list(zip(positional[len(positional) - len(a.defaults) :], a.defaults)) + list(zip(a.kwonlyargs, a.kw_defaults))
            found += [(arg.arg, node.lineno) for arg, d in pairs if arg.arg in names and d is not None and not _none(d)]
        if surface and isinstance(node, ast.ClassDef):
            fields = [s for s in node.body if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name) and s.value is not None]
            found += [(s.target.id, s.lineno) for s in fields if s.target.id in names and not _none(s.value)]
        if isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "add_argument":
            found += [(flags[a.value], node.lineno) for a in node.args if isinstance(a, ast.Constant) and a.value in flags]
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") in ("Form", "Query", "Body"):
            aliases = [k.value.value for k in node.keywords if k.arg == "alias" and isinstance(k.value, ast.Constant)]
            found += [(keys[a], node.lineno) for a in aliases if a in keys]
    return found


def _none(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and node.value is None


def test_each_option_is_declared_once():
    """Every option a surface offers is declared once, as its field (with its default, check and help); the command
    line's flags and the forms' fields are made from it. (``layout``, offered by no surface, is data of the code.)"""
    classes = {n: c for c in (Options, Driving, Framing) for n in names(c) if spec(c, n).surfaces}
    flags = {spec(c, n).flag or f"--{key(c, n).replace('_', '-')}": n for n, c in classes.items()}
    keys = {key(c, n): n for n, c in classes.items()}
    counts: dict[str, list[str]] = {n: [] for n in classes}
    for path in PACKAGE.rglob("*.py"):
        relative = path.relative_to(PACKAGE).as_posix()
        surface = any(relative == s or relative.startswith(f"{s}/") for s in SURFACES)
        for name, line in declarations(ast.parse(path.read_text()), set(classes), flags, keys, surface):
            counts[name].append(f"{relative}:{line}")
    again = {n: places for n, places in counts.items() if len(places) != 1}
    assert again == {}, again


def test_the_declaration_counter_sees_declarations_again():
    code = textwrap.dedent(
        """
        def clone(image, strength=1.0, only=None, *, mouth=True): ...
        class Request:
            method: str = "e+md"
            lambda_k: float | str | None = None
        parser.add_argument("--no-retarget", action="store_false")
        Annotated[str, Form(alias="lambda")]
        """
    )
    found = declarations(
        ast.parse(code),
        {"strength", "only", "mouth", "method", "lambda_k", "retarget"},
        {"--no-retarget": "retarget"},
        {"lambda": "lambda_k"},
        True,
    )
    assert sorted(n for n, _ in found) == ["lambda_k", "method", "mouth", "retarget", "strength"]


@pytest.mark.slow
def test_a_users_code_calling_clone_is_typed(tmp_path):
    """mypy, strict, on a user's snippet: ``exprclone.clone`` with three images, the result's fields typed."""
    snippet = tmp_path / "user.py"
    snippet.write_text(
        textwrap.dedent(
            """
            import numpy as np

            import exprclone

            photo = np.zeros((64, 64, 3), np.uint8)
            result: exprclone.CloneResult = exprclone.clone(photo, photo, photo, method="e+md", strength=0.5)
            image: np.ndarray = result.image
            prepared = exprclone.prepare(photo, photo, photo)
            again: dict[str, exprclone.CloneResult] = prepared.render(strength=0.5)
            options: exprclone.Options = exprclone.Options(method="global")
            """
        )
    )
    wrong = tmp_path / "wrong.py"
    wrong.write_text("import exprclone\n\nresult: int = exprclone.clone(1, 2, 3)\n")
    command = [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", str(tmp_path / "cache")]
    typed = subprocess.run([*command, str(snippet)], capture_output=True, text=True, cwd=tmp_path)
    assert typed.returncode == 0, typed.stdout
    untyped = subprocess.run([*command, str(wrong)], capture_output=True, text=True, cwd=tmp_path)
    assert untyped.returncode == 1 and "Incompatible types in assignment" in untyped.stdout, untyped.stdout
