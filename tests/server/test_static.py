"""The page's static files name no choice of an option: the methods, warps, landmarkers and lambdas come from the
server's answer (``GET /api/options``), which the page draws its controls from."""

import re
from pathlib import Path

import pytest

from exprclone.geometry.db_metric import LAMBDAS
from exprclone.landmarks.backends import LANDMARKERS
from exprclone.methods import METHODS
from exprclone.options import GLOBAL_WARPS, IMAGE_WARPS

STATIC = Path(__file__).resolve().parents[2] / "src" / "exprclone" / "server" / "static"
#: the names a page must not write: each as a value in code or markup (quoted, or an element's text).
NAMES = METHODS + GLOBAL_WARPS + IMAGE_WARPS + LANDMARKERS


def written(text: str, numbers: bool = True) -> list[str]:
    """The choices' names a text writes: a name quoted or as an element's text (``"e+md"``, ``>tps<``, ``value=rbf``), a
    method's name with its ``+`` anywhere, a warp's distinctive name as a word, a lambda the DB metric searches that is
    not a whole number (or infinity) as a number (unless not ``numbers``: a style's)."""
    found = [n for n in NAMES if re.search(rf"""["'`>=]{re.escape(n)}["'`<\s]""", text)]
    found += [n for n in METHODS if "+" in n and n in text]
    found += [n for n in GLOBAL_WARPS + IMAGE_WARPS if n not in ("mesh",) and re.search(rf"(?<![\w-]){n}(?![\w-])", text, re.I)]
    found += [f"{lam:g}" for lam in LAMBDAS[1:-1] if numbers and lam % 1 and re.search(rf"(?<![\d.]){lam:g}(?![\w.])", text)]
    return found + (["Infinity"] if "Infinity" in text else [])


@pytest.mark.parametrize("path", sorted(STATIC.glob("*.*")), ids=lambda p: p.name)
def test_no_static_file_names_a_method_a_warp_or_a_lambda(path):
    assert written(path.read_text(), numbers=path.suffix != ".css") == []


def test_the_rule_sees_what_the_page_wrote_before():
    before = """<option value="e+md" selected>(g) E+MD</option> const LAMBDAS = [0, 0.1, 0.35, 1, Infinity];
      o.global_warp !== "similarity" ? `global warp ${o.global_warp}` : "", <option value="rbf">RBF (Seol and Lewis)</option>"""
    assert set(written(before)) >= {"e+md", "similarity", "rbf", "0.1", "0.35", "Infinity"}
