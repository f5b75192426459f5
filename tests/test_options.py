"""The options, declared once (:mod:`exprclone.options`): checked as they are made, and the same value from every surface.

Every surface's adapter is made from the same specs, so the same choices given as Python keywords, command line
words, form fields, a manifest's cells or a live message's JSON must give the same value.
"""

import argparse
import json

import pytest
from conftest import paper_terms
from fastapi import Depends, FastAPI
from fastapi.testclient import TestClient

from exprclone.cli.inputs import add_options, options_of
from exprclone.errors import ExprCloneError
from exprclone.options import ADVANCED, RENDER, SECTIONS, VALUES, Driving, Framing, Options, from_json, from_text, key, names, offered, spec
from exprclone.server.app import add_error_answers
from exprclone.server.forms import Asked, options_form

#: choices a user may make, each as its value and as the text a command line, a form or a manifest gives.
CHOICES = {
    "method": ("global+eri", "global+eri"),
    "lambda_k": (0.5, "0.5"),
    "mouth": (False, "false"),
    "landmarker": ("mesh", "mesh"),
    "global_warp": ("rbf", "rbf"),
    "image_warp": ("tps", "tps"),
    "strength": (1.5, "1.5"),
    "only": (("mouth", "eyes"), "mouth,eyes"),
    "strength_mouth": (1.3, "1.3"),
    "strength_eyes": (0.0, "0"),
    "strength_brows": (2.0, "2"),
    "strength_shading": (0.5, "0.5"),
    "retarget": (False, "false"),
    "neutral_frame": (12, "12"),
    "lambda_per_frame": (True, "true"),
    "smooth": (False, "false"),
    "head_motion": (True, "true"),
    "size": (256, "256"),
    "side_by_side": (True, "true"),
}
CLASSES = (Options, Driving, Framing)
#: the regions' own strengths (each, when given, overrides the 0 that ``only`` gives a region it leaves out).
REGION_STRENGTHS = ("strength_mouth", "strength_eyes", "strength_brows")


def same(a, b) -> bool:
    return all(getattr(a, n) == getattr(b, n) for n in names(type(a)) if n not in ("global_landmarks", "eigenfaces", "layout"))


def words(cls, chosen) -> list[str]:
    """The command line's words for ``chosen`` options of ``cls``: a flag alone for a switch."""
    out = []
    for name in chosen:
        option, (value, text) = spec(cls, name), CHOICES[name]
        flag = option.flag or f"--{key(cls, name).replace('_', '-')}"
        if option.kind is bool:
            out += [flag] if value != getattr(cls(), name) else []
        else:
            out += [flag, text]
    return out


@pytest.mark.parametrize("regions", ["only", "strengths"])
@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_surface_gives_the_same_value(cls, regions):
    left_out = REGION_STRENGTHS if regions == "only" else ("only",)
    choices = {n: c for n, c in CHOICES.items() if n not in left_out}
    parser = argparse.ArgumentParser()
    add_options(parser, cls)
    cli = [n for n in offered(cls, "cli") if n in choices]
    assert same(
        options_of(parser.parse_args(words(cls, [n for n in cli])), cls),
        cls(**{n: choices[n][0] for n in cli}),
    )
    manifest = [n for n in offered(cls, "manifest") if n in choices]
    assert same(from_text(cls, {key(cls, n): choices[n][1] for n in manifest}), cls(**{n: choices[n][0] for n in manifest}))
    live = [n for n in offered(cls, "json") if n in choices]
    message = json.loads(json.dumps({key(cls, n): list(choices[n][0]) if n == "only" else choices[n][0] for n in live}))
    assert same(from_json(cls, message), cls(**{n: choices[n][0] for n in live}))
    app = FastAPI()
    add_error_answers(app)

    @app.post("/form")
    async def form(asked: Asked = Depends(options_form(cls))) -> dict[str, list[str]]:
        assert same(asked.options, cls(**{n: choices[n][0] for n in asked.given}))
        return {"given": sorted(asked.given)}

    fields = [n for n in offered(cls, "form") if n in choices]
    answer = TestClient(app).post("/form", data={key(cls, n): choices[n][1] for n in fields})
    assert answer.status_code == 200 and answer.json()["given"] == sorted(fields)


@pytest.mark.parametrize(
    "change, subject",
    [
        ({"method": "emd"}, "method"),
        ({"lambda_k": -1}, "lambda"),
        ({"lambda_k": True}, "lambda"),
        ({"strength": 2.5}, "strength"),
        ({"only": "mouth,nose"}, "only"),
        ({"mouth": "yes"}, "mouth"),
        ({"landmarker": "hog"}, "landmarker"),
        ({"global_warp": "affine"}, "global_warp"),
        ({"image_warp": "bilinear"}, "image_warp"),
        ({"retarget": 1}, "retarget"),
        ({"global_warp": "rbf", "global_landmarks": [[0.0, 0.0]] * 68}, "global_landmarks"),
        ({"colour": True}, "colour"),
        ({"strength_mouth": -0.1}, "strength_mouth"),
        ({"strength_shading": None}, "strength_shading"),
    ],
)
def test_a_bad_option_is_refused_by_name(change, subject):
    with pytest.raises(ExprCloneError) as refused:
        Options.of(None, change)
    assert refused.value.subject == subject and "\n" not in str(refused.value)


def test_values_are_kept_as_the_options_hold_them():
    assert Options(strength=1).strength == 1.0 and isinstance(Options(strength=1).strength, float)
    assert Options(only="eyes, mouth").only == ("eyes", "mouth")
    assert Options(only=("mouth", "eyes", "brows")).only is None  # every region: the whole face
    assert Driving(neutral_frame="first").neutral_frame == "first" and Framing(size=None).size is None
    for cls, bad in ((Driving, {"neutral_frame": -1}), (Framing, {"size": 8})):
        with pytest.raises(ExprCloneError):
            cls(**bad)


def test_text_and_json_say_which_field_is_wrong():
    with pytest.raises(ExprCloneError, match=r"^strength: expected a number, got 'lots'$"):
        Options.from_text({"strength": "lots"})
    with pytest.raises(ExprCloneError, match=r"^lambda: must be 'auto' or a number >= 0, got 'x'$"):
        Options.from_text({"lambda": "x"})
    with pytest.raises(ExprCloneError, match=r"^only: must be a string or a list, got 3$"):
        Options.from_json({"only": 3})
    assert Options.from_text({"method": ""}).method == Options().method  # an empty cell is no choice
    assert Options.from_text({"lambda": "inf"}).lambda_k == float("inf")


def test_the_render_options_are_the_cheap_ones():
    """What a prepared clone renders again with: nothing its preparation (landmarks, lambda search, ERI inputs) uses."""
    assert set(RENDER) == {"mouth", "strength", "only", *REGION_STRENGTHS, "strength_shading"} and set(RENDER) <= set(names(Options))


def declared():
    """Every option offered outside Python: (its value's class, its name)."""
    return [(cls, n) for cls in VALUES for n in names(cls) if spec(cls, n).surfaces]


@pytest.mark.parametrize("cls, name", declared(), ids=lambda v: v if isinstance(v, str) else v.__name__)
def test_a_switch_on_by_default_is_a_flag_that_turns_it_off_and_says_so(cls, name):
    """``--no-mouth``'s help says what giving the flag does, not what the option does when on."""
    option = spec(cls, name)
    if option.kind is not bool or "cli" not in option.surfaces:
        return
    parser = argparse.ArgumentParser()
    add_options(parser, cls, (name,))
    (action,) = [a for a in parser._actions if a.dest == name]
    if getattr(cls(), name):
        assert action.option_strings == [f"--no-{key(cls, name).replace('_', '-')}"] and action.help == option.flag_help
        assert getattr(options_of(parser.parse_args(action.option_strings), cls, (name,)), name) is False
    else:
        assert option.flag_help is None and action.help == option.help


@pytest.mark.parametrize("cls, name", declared(), ids=lambda v: v if isinstance(v, str) else v.__name__)
def test_a_page_offers_the_values_allowed_in_words(cls, name):
    """A page's menu offers the values the option allows, each with a label, and each a value the option takes; a
    slider follows an option of its own value."""
    option, page = spec(cls, name), spec(cls, name).page
    if page is None:
        return
    assert page.label and page.sentence.endswith(".") and page.section in SECTIONS
    offered_values = [c.value for c in page.offered()]
    if option.choices:
        assert offered_values == list(option.choices)
    for value in offered_values:
        assert from_text(cls, {key(cls, name): value}) is not None and all(c.label for c in page.offered())
    assert page.follows is None or page.follows in names(cls)


def every_flag():
    """Every flag of every ``exprclone`` command (studies' subcommands too): ``(command, action)``."""
    from exprclone.cli.main import build_parser

    found, parsers = [], [("exprclone", build_parser())]
    while parsers:
        name, parser = parsers.pop()
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                parsers += [(f"{name} {word}", sub) for word, sub in action.choices.items()]
            else:
                found += [(name, action)] if action.option_strings else []
    return found


def test_every_no_flag_of_every_command_says_what_giving_it_does():
    """Each ``--no-X`` of every command turns an option declared on off, and its help is that option's ``flag_help``
    (what giving the flag does), never the option's own help (what it does when on): ``--no-mouth`` read "paste the
    source's mouth interior" once."""
    negative = [(name, a) for name, a in every_flag() if any(o.startswith("--no-") for o in a.option_strings)]
    assert {a.option_strings[0] for _, a in negative} >= {"--no-mouth", "--no-retarget", "--no-smooth"}, negative
    for name, action in negative:
        cls = next(c for c in VALUES if action.dest in names(c))  # (a --no-X of no option would fail here)
        option = spec(cls, action.dest)
        assert isinstance(action, argparse._StoreFalseAction) and getattr(cls(), action.dest) is True, (name, action.option_strings)
        assert option.flag_help and action.help == option.flag_help and action.help != option.help, (name, action.option_strings)
        on = option.help.split(";")[0].split(":")[0]  # what the option does when on, in its help's first words
        assert not action.help.startswith(on), (name, action.help)


def test_the_papers_words_are_only_in_the_advanced_sections():
    """An option whose page words (its label, sentence, or a choice's) use the paper's words or symbols (lambda_k, GI,
    a global warp...) sits in a section a page folds away as advanced; and the rule sees the words it is about."""
    assert paper_terms("Balance λk") and paper_terms("Global warp") and paper_terms("(g) E+MD") and not paper_terms("Whole expression")
    for cls, name in declared():
        page = spec(cls, name).page
        if page is None:
            continue
        words = " ".join([page.label, page.sentence, *(f"{c.label} {c.sentence}" for c in page.offered())])
        if paper_terms(words):
            assert page.section in ADVANCED, (name, paper_terms(words))
    advanced = {n for cls, n in declared() if spec(cls, n).page and spec(cls, n).page.section in ADVANCED}
    assert {"method", "lambda_k", "global_warp", "image_warp", "landmarker", "retarget", "lambda_per_frame"} <= advanced
