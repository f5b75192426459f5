"""The code's own rules: short functions, one home for the photo roles, and methods read from their table, never
decoded from their names. (Modules are split by concept, not by length: tests/test_architecture.py.)"""

import ast
from pathlib import Path

import pytest

from exprclone.methods import METHODS
from exprclone.roles import ROLES

SOURCES = sorted((Path(__file__).resolve().parents[1] / "src" / "exprclone").rglob("*.py"))
#: the longest function body allowed, in lines of code (docstring, blank lines and comments aside).
MAX_LINES = 50


def code_lines(function: ast.FunctionDef, lines: list[str]) -> int:
    """Lines of code in a function's body, its docstring, blank lines and comment lines not counted."""
    body = function.body
    if isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        body = body[1:]
    numbers = {n for node in body for sub in ast.walk(node) if hasattr(sub, "lineno") for n in range(sub.lineno, sub.end_lineno + 1)}
    return sum(1 for n in numbers if lines[n - 1].strip() and not lines[n - 1].strip().startswith("#"))


def functions(path: Path):
    text = path.read_text()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node, text.splitlines()


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(p.parents[1])))
def test_no_function_is_longer_than_fifty_lines(path):
    long = {f.name: n for f, lines in functions(path) if (n := code_lines(f, lines)) > MAX_LINES}
    assert not long, long


def role_strings(tree: ast.AST) -> list[int]:
    """Lines that write a photo's role as a string (``"target_neutral"``) instead of naming it from :mod:`exprclone.roles`."""
    return sorted(node.lineno for node in ast.walk(tree) if isinstance(node, ast.Constant) and node.value in ROLES)


@pytest.mark.parametrize("path", [p for p in SOURCES if p.name != "roles.py"], ids=lambda p: str(p.relative_to(p.parents[1])))
def test_the_photo_roles_are_written_once(path):
    """Only roles.py spells the three photos' roles."""
    assert not role_strings(ast.parse(path.read_text())), path


def test_the_roles_rule_sees_a_role_written_out():
    assert role_strings(ast.parse('names = {"target_neutral": path, f"{role}_landmarks": 1}\n"""target_neutral: a docstring."""')) == [1]


def test_the_rule_counts_what_it_should():
    source = 'def f():\n    """Doc\n    string."""\n    # a comment\n\n    x = 1\n    return (x,\n            2)\n'
    ((function, lines),) = functions_of(source)
    assert code_lines(function, lines) == 3


def functions_of(source: str):
    tree = ast.parse(source)
    return [(n, source.splitlines()) for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)]


def decodes_a_method_name(tree: ast.AST) -> list[int]:
    """Lines that test a value for equality with a method's name, or take a name apart (split, endswith, startswith on '+')."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare) and any(isinstance(op, (ast.Eq, ast.NotEq)) for op in node.ops):
            constants = [c.value for c in [node.left, *node.comparators] if isinstance(c, ast.Constant)]
            if any(c in METHODS or c == "+eri" for c in constants):
                found.append(node.lineno)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in ("split", "endswith", "startswith"):
            if any(isinstance(a, ast.Constant) and isinstance(a.value, str) and "+" in a.value for a in node.args):
                found.append(node.lineno)
    return sorted(found)


@pytest.mark.parametrize("path", [p for p in SOURCES if p.name != "methods.py"], ids=lambda p: str(p.relative_to(p.parents[1])))
def test_no_module_decodes_a_method_from_its_name(path):
    """Only the table (methods.py) knows what a name means."""
    assert not decodes_a_method_name(ast.parse(path.read_text())), path


def test_the_decoding_rule_sees_what_the_old_pipeline_did():
    old = 'kinds = {m: "elastic" if m == "e+md" else m.split("+")[0] for m in methods}\nif m.endswith("+eri"): pass\n'
    assert decodes_a_method_name(ast.parse(old)) == [1, 1, 2]
