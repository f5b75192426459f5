"""The compare sheet (Figs. 11-13 and the DB curve): every panel where the paper puts it."""

import numpy as np
import pytest

from exprclone.errors import ExprCloneError
from exprclone.evaluation import figures
from exprclone.geometry.db_metric import DBCurve
from exprclone.methods import BY_NAME, FIG11
from exprclone.options import Options
from exprclone.pipeline.clone import CloneResult

CELL, BAR = figures.CELL, 24  # the caption bar's height


def panel(sheet, row, column):
    """A cell's picture, below its caption bar."""
    return sheet[row * CELL + BAR + 2 : (row + 1) * CELL - 2, column * CELL + 2 : (column + 1) * CELL - 2]


@pytest.fixture(scope="module")
def drawn(pair_points):
    """Results of flat grey, one shade per method (e+md the same as elastic+eri), and a DB curve with its minimum at 1.5."""
    (sn, se, tn), shape = pair_points
    shade = {m: 30 + 25 * k for k, m in enumerate(FIG11)}
    shade["e+md"] = shade["elastic+eri"]
    lambdas = np.array([0.0, 0.5, 1.0, 1.5, 3.0, np.inf])
    db = np.array([3.0, 2.6, 2.4, 2.1, 2.5, 2.9])
    curve = DBCurve(lambdas, db, db / 2, db / 2, 1.5)
    landmarks = {"target_neutral": tn, "source_expression": se}
    results = {m: CloneResult(np.full(shape, shade[m], np.uint8), m, landmarks, db_curve=curve) for m in FIG11}
    source = np.full(shape, 250, np.uint8)
    return figures.sheet(results, source), shade, curve


def test_fig_11_row_shows_each_method_in_its_panel_then_the_source(drawn):
    sheet, shade, _ = drawn
    assert sheet.shape == (3 * CELL, 8 * CELL, 3)
    for column, method in enumerate(FIG11):
        assert (panel(sheet, 0, column) == shade[method]).all(), method
    assert (panel(sheet, 0, 7) == 250).all()


def test_difference_panels_are_black_where_images_agree_and_full_scale_where_they_differ(drawn):
    sheet, _, _ = drawn
    # Fig. 12: (b)-(g) against (a); all differ from global, so each is normalised to 255
    assert all((panel(sheet, 1, k) == 255).all() for k in range(6))
    # Fig. 13: (b)-(a), (c)-(a), (d)-(a), (e)-(d), (f)-(d), (g)-(f): the last pair agrees
    assert all((panel(sheet, 2, k) == 255).all() for k in range(5))
    assert (panel(sheet, 2, 5) == 0).all()


def test_the_db_plot_marks_the_chosen_lambda_at_the_curves_minimum(drawn):
    sheet, _, curve = drawn
    plot = sheet[2 * CELL : 3 * CELL, 6 * CELL : 7 * CELL].astype(int)
    red = (plot[..., 0] > 180) & (plot[..., 1] < 60) & (plot[..., 2] < 60)
    ys, xs = np.nonzero(red)
    k = int(np.argmin(curve.db))
    x_expected = np.linspace(40, CELL - 12, len(curve.db))[k]
    assert red.sum() > 50 and abs(xs.mean() - x_expected) < 1.5
    assert abs(ys.mean() - (CELL - 40)) < 1.5  # the minimum sits on the bottom axis


@pytest.mark.parametrize("figure", ["16", "17"])
def test_figs_16_and_17_show_the_target_each_method_the_source_then_e_md_against_song(pair_points, figure):
    """Fig. 16: (a) target, (b)-(e) global + ERI, Song et al., elastic + ERI, E+MD, (f) source; Fig. 17: (a) target,
    (b)-(d) Song et al., elastic + ERI and E+MD on VTC, (e) source; then E+MD's difference to Song et al.'s and the DB
    curve."""
    (sn, se, tn), shape = pair_points
    methods, options = figures.figure_request(figure, Options(), False)
    assert methods == figures.FIG16[figure] and options.global_warp == ("vtc" if figure == "17" else "similarity")
    shade = {m: 30 + 25 * k for k, m in enumerate(methods)}
    landmarks = {"target_neutral": tn, "source_expression": se}
    curve = DBCurve(np.array([0.0, 1.0]), np.array([2.0, 1.0]), np.ones(2), np.ones(2), 1.0)
    results = {
        m: CloneResult(np.full(shape, shade[m], np.uint8), m, landmarks, db_curve=curve, options=options.ran_by(BY_NAME[m]))
        for m in methods
    }
    row = figures.fig16(results, np.full(shape, 10, np.uint8), np.full(shape, 250, np.uint8))
    assert row.shape == (CELL, (len(methods) + 4) * CELL, 3)
    assert (panel(row, 0, 0) == 10).all()
    for column, method in enumerate(methods, 1):
        assert (panel(row, 0, column) == shade[method]).all(), method
    assert (panel(row, 0, len(methods) + 1) == 250).all()
    assert (panel(row, 0, len(methods) + 2) == 255).all()  # E+MD and Song et al.'s differ everywhere


def test_figure_17_takes_no_other_global_warp():
    with pytest.raises(ExprCloneError, match="^global_warp: Fig. 17 shows the methods on Song et al.'s global warp"):
        figures.figure_request("17", Options(global_warp="rbf"), True)
    assert figures.figure_request("17", Options(global_warp="vtc"), True)[1].global_warp == "vtc"
