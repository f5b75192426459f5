"""Sphinx configuration of exprclone's documentation.

Build it with ``sphinx-build -W -b html docs OUT`` after ``pip install '.[docs]'``. The build
runs the gallery (``examples/``, on the samples shipped in :mod:`exprclone.data`), reads the
command line reference from the real parser and the HTTP reference from the app's own OpenAPI
schema (written below, at build time, into ``docs/reference/openapi.json``); the results pages
are files generated beforehand by ``tools/results.py``, only read here.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from sphinx.util import logging

import exprclone

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
logger = logging.getLogger(__name__)

project = "exprclone"
author = "the exprclone developers"
copyright = "the exprclone developers; code MIT, data CC BY 4.0"
version = release = exprclone.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    # MathJax 3 from the package's own copy, put in the build's _static/: the equations render with no network
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "sphinx_design",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "sphinxarg.ext",
    "sphinxcontrib.openapi",
]

exclude_patterns = [
    "_build",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "results/data/**",
    "reference/options-table.rst",  # included by reference/options.rst
]
templates_path: list[str] = []
html_static_path = ["_static"]
html_theme = "pydata_sphinx_theme"
html_title = f"exprclone {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "header_links_before_dropdown": 5,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_sidebars = {"index": [], "citing": []}
html_show_sourcelink = False

# numpydoc: the docstrings' sections; no autosummary tables of every method of a class
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"
# signatures show defaults as the source writes them (layout=DLIB68), not as their repr (the whole table)
autodoc_preserve_defaults = True
autosummary_generate = False

intersphinx_mapping: dict[str, tuple[str, None]] = {}

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "reset_modules": ("matplotlib",),
    "show_memory": False,
    "min_reported_time": 1,
    "abort_on_example_error": True,
    "plot_gallery": "True",
    # no pages of the examples' run times: they load their table's scripts from a CDN, and the site loads nothing from another host
    "write_computation_times": False,
}


def write_openapi(app) -> None:
    """The HTTP reference's source: the schema of the app that ``exprclone serve`` runs (no worker is started)."""
    from exprclone.server.app import create_app

    schema = create_app().openapi()
    target = DOCS / "reference" / "openapi.json"
    text = json.dumps(schema, indent=1, sort_keys=False) + "\n"
    if not target.exists() or target.read_text() != text:
        target.write_text(text)


def write_options(app) -> None:
    """The options' reference table (``reference/options-table.rst``), made from their one declaration
    (:mod:`exprclone.options`): each option's name on every surface, its default, its help (and a ``--no-X`` flag's),
    and its words on the page."""
    from exprclone.options import VALUES, flag, key, names, spec

    surfaces = {"cli": "command line", "form": "HTTP form", "json": "live", "manifest": "manifest"}
    rows = []
    for cls in VALUES:
        default = cls()
        for name in names(cls):
            option = spec(cls, name)
            if not option.surfaces:
                continue
            value = getattr(default, name)
            where = ", ".join(text for surface, text in surfaces.items() if surface in option.surfaces and surface != "cli")
            said = option.help + (f" (one of: {', '.join(option.choices)})" if option.choices else "")
            cells = [
                f"``{cls.__name__}.{name}``",
                f"``{flag(cls, name)}``" + (f": {option.flag_help}" if option.flag_help else "") if "cli" in option.surfaces else "",
                f"``{key(cls, name)}`` ({where})" if where else "",
                "" if value is None else f"``{value!r}``",
                said,
                "" if option.page is None else f"**{option.page.label}**: {option.page.sentence}",
            ]
            rows.append("   * - " + "\n     - ".join(cells))
    text = "\n".join(
        [
            ".. list-table::",
            "   :header-rows: 1",
            "   :widths: 14 16 16 8 28 18",
            "",
            "   * - Python",
            "     - command line",
            "     - field, where",
            "     - default",
            "     - what it does",
            "     - on the page",
            *rows,
            "",
        ]
    )
    target = DOCS / "reference" / "options-table.rst"
    if not target.exists() or target.read_text() != text:
        target.write_text(text)


def draw_architecture(app) -> None:
    """The architecture page's picture (:mod:`diagrams`), drawn into ``_static/architecture.png``."""
    import sys

    sys.path.insert(0, str(DOCS))
    from diagrams import draw

    draw(DOCS / "_static" / "architecture.png")


def check_source_links(app, exception) -> None:
    """Every "[docs]" link of the source pages (viewcode) leads to an entry that exists: a name documented under
    one module and defined in another can get a link to an anchor that is nowhere (a warning, so an error with -W)."""
    import re

    out = Path(app.outdir)
    if exception is not None or not (out / "_modules").is_dir():
        return
    anchors = {m for page in out.rglob("*.html") for m in re.findall(r'id="([^"]+)"', page.read_text(encoding="utf-8"))}
    for page in (out / "_modules").rglob("*.html"):
        for target in set(re.findall(r'href="[^"#]*#(exprclone\.[^"]+)"', page.read_text(encoding="utf-8"))) - anchors:
            logger.warning(f"{page.relative_to(out)}: its [docs] link to {target} leads nowhere")


def setup(app) -> None:
    os.environ.setdefault("MPLBACKEND", "agg")
    app.connect("build-finished", check_source_links)
    app.connect("builder-inited", write_openapi)
    app.connect("builder-inited", write_options)
    app.connect("builder-inited", draw_architecture)
