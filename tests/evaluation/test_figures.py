"""The compare sheet (Figs. 11-13, the DB curve and its terms, the default's row): every panel where the paper puts it,
and the words that say which panels are equal and why."""

import numpy as np
import pytest

from exprclone.errors import ExprCloneError
from exprclone.evaluation import db_words, figures, panels
from exprclone.geometry.db_metric import DBCurve
from exprclone.methods import BY_NAME, FIG11
from exprclone.options import Options
from exprclone.pipeline.clone import CloneResult

CELL, BAND, HEIGHT = panels.CELL, panels.BAND, panels.HEIGHT


def picture(sheet, row, column, title=True):
    """A panel's picture, below its caption's band (and the sheet's title band)."""
    top = (BAND if title else 0) + row * HEIGHT + BAND
    return sheet[top + 2 : top + CELL - 2, column * CELL + 2 : (column + 1) * CELL - 2]


def band(sheet, row, column, title=True):
    """A panel's caption band."""
    top = (BAND if title else 0) + row * HEIGHT
    return sheet[top : top + BAND, column * CELL : (column + 1) * CELL]


def red(image):
    return (image[..., 0] > 150) & (image[..., 1] < 60) & (image[..., 2] < 60)


CURVE = DBCurve(
    np.array([0.0, 0.5, 1.0, 1.5, 3.0, np.inf]),
    np.array([3.0, 2.6, 2.4, 2.1, 2.5, 2.9]),
    np.array([1.0, 0.8, 0.7, 0.5, 0.6, 0.9]),
    np.array([0.0, 0.1, 0.2, 0.3, 0.5, 0.6]),
    1.5,
)


def results_of(pair_points, shade, options, curve=CURVE, lambda_k=1.5):
    (sn, se, tn), shape = pair_points
    landmarks = {"target_neutral": tn, "source_expression": se, "global": tn, "local": tn + 1.0}
    return {
        m: CloneResult(
            np.full(shape, shade[m], np.uint8),
            m,
            landmarks,
            lambda_k if BY_NAME[m].uses_lambda else None,
            curve if BY_NAME[m].uses_lambda else None,
            options=options.ran_by(BY_NAME[m]),
        )
        for m in FIG11
    }


@pytest.fixture(scope="module")
def drawn(pair_points):
    """The paper's results of flat grey, one shade per method (e+md the same as elastic+eri), a DB curve with its
    minimum at 1.5; the default's with (b), (c) as (a) and (e), (f) as (d), as retarget makes them."""
    _, shape = pair_points
    shade = {m: 30 + 25 * k for k, m in enumerate(FIG11)}
    shade["e+md"] = shade["elastic+eri"]
    paper = results_of(pair_points, shade, Options(retarget=False))
    own = dict(
        shade, local=shade["global"], elastic=shade["global"], **{"local+eri": shade["global+eri"], "elastic+eri": shade["global+eri"]}
    )
    own["e+md"] = 240
    default = results_of(pair_points, own, Options(), curve=None, lambda_k=0.0)
    photos = (np.full(shape, 5, np.uint8), np.full(shape, 250, np.uint8), np.full(shape, 10, np.uint8))
    return figures.sheet(paper, photos, default), figures.sheet(paper, photos), shade, own


def test_fig_11_row_shows_the_target_each_method_in_its_panel_then_the_source(drawn):
    sheet, alone, shade, _ = drawn
    assert sheet.shape == (BAND + 4 * HEIGHT, 9 * CELL, 3) and alone.shape == (BAND + 3 * HEIGHT, 9 * CELL, 3)
    assert (picture(sheet, 0, 0) == 10).all()  # the target's neutral face
    for column, method in enumerate(FIG11, 1):
        assert (picture(sheet, 0, column) == shade[method]).all(), method
    assert (picture(sheet, 0, 8) == 250).all()


def test_difference_panels_are_black_where_images_agree_and_full_scale_where_they_differ(drawn):
    sheet, _, _, _ = drawn
    # Fig. 12, under (b)-(g): each against (a); all differ from global, so each is normalised to 255
    assert all((picture(sheet, 1, k) == 255).all() for k in range(2, 8))
    # Fig. 13: (b)-(a), (c)-(a), (d)-(a), (e)-(d), (f)-(d), (g)-(f): the last pair agrees, and the panel says so
    assert all((picture(sheet, 2, k) == 255).all() for k in range(2, 7))
    equal = picture(sheet, 2, 7)
    assert np.mean(equal == 0) > 0.9 and equal.max() <= 200 and red(band(sheet, 2, 7)).any()
    assert not red(band(sheet, 2, 6)).any()


def test_the_db_plot_marks_the_chosen_lambda_at_the_curves_minimum(drawn):
    sheet, _, _, _ = drawn
    plot = sheet[BAND + HEIGHT : BAND + 2 * HEIGHT, 8 * CELL : 9 * CELL].astype(int)
    chosen = red(plot)
    chosen[:BAND] = False  # (the caption)
    ys, xs = np.nonzero(chosen)
    k = int(np.argmin(CURVE.db))
    assert chosen.sum() > 50 and abs(xs.mean() - np.linspace(52, CELL - 16, len(CURVE.db))[k]) < 1.5
    assert abs(ys.mean() - (HEIGHT - 66)) < 1.5  # the minimum sits on the bottom axis


def test_the_defaults_row_sits_under_the_papers_and_says_which_panels_are_equal(drawn):
    sheet, _, _, own = drawn
    for column, method in enumerate(FIG11, 1):
        assert (picture(sheet, 3, column) == own[method]).all(), method
    notes = [red(band(sheet, 3, column)).any() for column in range(1, 8)]
    assert notes == [False, True, True, False, True, True, False]  # (b), (c) = (a); (e), (f) = (d)
    assert (picture(sheet, 3, 8) == 255).all()  # the default's E+MD against the paper's


def test_equal_panels_and_why(pair_points):
    shade = {m: 30 + 25 * k for k, m in enumerate(FIG11)}
    shade.update(elastic=shade["global"], **{"elastic+eri": shade["global+eri"]})
    paper = results_of(pair_points, shade, Options(retarget=False), lambda_k=0.0)
    same = figures.same_as(paper)
    assert same == {"elastic": "global", "elastic+eri": "global+eri"}
    assert figures.why_same("elastic", "global", paper["elastic"]) == "lambda_k = 0 (the DB metric) keeps GI"
    given = results_of(pair_points, shade, Options(retarget=False), curve=None, lambda_k=0.0)
    assert figures.why_same("elastic", "global", given["elastic"]) == "lambda_k = 0 (given) keeps GI"
    default = results_of(pair_points, shade, Options(), curve=None, lambda_k=0.0)
    assert figures.why_same("local", "global", default["local"]) == "retarget makes LI GI"
    assert figures.why_same("elastic", "global", default["elastic"]) == "retarget makes LI GI: nothing to balance"


def test_the_terms_of_the_db_metric_in_words(pair_points):
    """At lambda_k = 0, the chosen value and LI: each term and their sum; why the chosen one won."""
    result = results_of(pair_points, dict.fromkeys(FIG11, 0), Options(retarget=False))["e+md"]
    said = db_words.terms_words(result)
    lines = [s if isinstance(s, str) else s[0] for s in said]
    assert lines[1] == "lambda_k 0 (GI): e^1.00 + e^0.00 = 2.72 + 1.00 = 3.00"
    assert lines[2].startswith("lambda_k 1.5, chosen: e^0.50 + e^0.30") and not isinstance(said[2], str)  # in red
    assert lines[3].startswith("lambda_k inf (LI): e^0.90 + e^0.60")
    assert "falls by" in lines[-1]
    kept = DBCurve(CURVE.lambdas, CURVE.db, CURVE.to_source, CURVE.to_global, 0.0)
    lines = db_words.terms_words(CloneResult(result.image, "e+md", result.landmarks, 0.0, kept, options=result.options))
    assert lines[-1] == "LI lies at cosine 0.17 towards the source; a step from GI lowers DB only above e^-1.00 = 0.37."
    assert db_words.lambda_words(result)[-1] == "The DB metric (Eqs. 7-8) chose 1.5 of 6 candidates."


def test_figure_11_is_drawn_by_the_papers_stages_and_the_defaults_unless_retarget_is_off():
    paper, default = figures.figure_request("11", Options(), False)
    assert paper.methods == default.methods == FIG11 and not paper.options.retarget and default.options.retarget
    (alone,) = figures.figure_request("11", Options(retarget=False, strength=0.5), False)
    assert not alone.options.retarget and alone.options.strength == 0.5


@pytest.mark.parametrize("figure", ["16", "17"])
def test_figs_16_and_17_show_the_target_each_method_the_source_then_e_md_against_song(pair_points, figure):
    """Fig. 16: (a) target, (b)-(e) global + ERI, Song et al., elastic + ERI, E+MD, (f) source; Fig. 17: (a) target,
    (b)-(d) Song et al., elastic + ERI and E+MD on VTC, (e) source; then E+MD's difference to Song et al.'s and the DB
    curve."""
    (sn, se, tn), shape = pair_points
    (run,) = figures.figure_request(figure, Options(), False)
    methods, options = run.methods, run.options
    assert methods == figures.FIG16[figure] and options.global_warp == ("vtc" if figure == "17" else "similarity")
    shade = {m: 30 + 25 * k for k, m in enumerate(methods)}
    landmarks = {"target_neutral": tn, "source_expression": se}
    curve = DBCurve(np.array([0.0, 1.0]), np.array([2.0, 1.0]), np.ones(2), np.ones(2), 1.0)
    results = {
        m: CloneResult(np.full(shape, shade[m], np.uint8), m, landmarks, db_curve=curve, options=options.ran_by(BY_NAME[m]))
        for m in methods
    }
    row = figures.fig16(results, np.full(shape, 10, np.uint8), np.full(shape, 250, np.uint8))
    assert row.shape == (HEIGHT, (len(methods) + 4) * CELL, 3)
    assert (picture(row, 0, 0, title=False) == 10).all()
    for column, method in enumerate(methods, 1):
        assert (picture(row, 0, column, title=False) == shade[method]).all(), method
    assert (picture(row, 0, len(methods) + 1, title=False) == 250).all()
    assert (picture(row, 0, len(methods) + 2, title=False) == 255).all()  # E+MD and Song et al.'s differ everywhere


def test_figure_17_takes_no_other_global_warp():
    with pytest.raises(ExprCloneError, match="^global_warp: Fig. 17 shows the methods on Song et al.'s global warp"):
        figures.figure_request("17", Options(global_warp="rbf"), True)
    assert figures.figure_request("17", Options(global_warp="vtc"), True)[0].options.global_warp == "vtc"
