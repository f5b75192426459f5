"""Integration: every method on real photos, and a real cross-person smile."""

import threading

import numpy as np
import pytest

import exprclone
from exprclone.errors import ExprCloneWarning
from exprclone.geometry import elastic, global_warp, local_warp, vtc
from exprclone.imaging import piecewise, warpers
from exprclone.landmarks import align, lips
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.methods import BY_NAME

MOUTH = list(DLIB68.mouth_outer)


def mouth_shape_distance(a, b):
    """Procrustes distance of two mouths: similarity-aligned, in units of the mouth's size."""
    t = align.fit_similarity(a[MOUTH], b[MOUTH])
    aligned = align.apply(t, a[MOUTH])
    return np.linalg.norm(aligned - b[MOUTH]) / np.linalg.norm(b[MOUTH] - b[MOUTH].mean(0))


@pytest.fixture(scope="module")
def results(pair):
    """Every method as the product runs it: the source's smile made as the target's own face makes it (retarget)."""
    images, landmarks = pair
    return exprclone.clone_methods(*images, landmarks=landmarks)


@pytest.fixture(scope="module")
def paper(pair):
    """Every method by the paper's stages exactly (``retarget=False``): GI, LI and the elastic model between them."""
    images, landmarks = pair
    return exprclone.clone_methods(*images, landmarks=landmarks, retarget=False)


def test_every_method_gives_an_image_of_the_target_size(pair, results):
    (_, _, target), _ = pair
    for method, r in results.items():
        assert r.image.shape == target.shape and r.image.dtype == np.uint8, method
        assert r.method == method and r.unfolded_points == 0
        assert not np.array_equal(r.image, target), method


def test_intermediates_are_reported(results, paper):
    r = paper["e+md"]
    assert {"source_neutral", "source_expression", "target_neutral", "global", "local", "elastic", "final"} <= set(r.landmarks)
    assert r.lambda_k in r.db_curve.lambdas and r.lambda_k == r.db_curve.best
    # the product's stages aim local re-shaping at the target's own face so moved: LI is GI, and there is nothing to balance
    own = results["e+md"]
    assert np.allclose(own.landmarks["local"], own.landmarks["global"], atol=1e-6) and own.lambda_k == 0 and own.db_curve is None
    assert r.eri.shape == r.muscle_mask.shape == r.image.shape[:2]
    assert r.muscle_mask.min() >= 1.0
    assert results["global"].lambda_k is None and results["global"].eri is None
    assert results["global+eri"].eri is not None and results["global+eri"].muscle_mask is None


def test_methods_differ_where_the_paper_says(paper):
    results = paper
    # local and global share nothing but the jaw; +eri only changes shading, not geometry
    assert not np.allclose(results["local"].landmarks["final"], results["global"].landmarks["final"])
    assert np.array_equal(results["global+eri"].landmarks["final"], results["global"].landmarks["final"])
    # MD strengthens details only where the mask exceeds 1
    emd, eri = results["e+md"], results["elastic+eri"]
    diff = np.abs(emd.image.astype(int) - eri.image).max(axis=2)
    assert diff[emd.muscle_mask == 1.0].max() <= 1 and diff.max() > 5


def test_fixed_lambda(pair):
    images, landmarks = pair
    r = exprclone.clone(*images, method="elastic", landmarks=landmarks, lambda_k=2.0)
    assert r.lambda_k == 2.0 and r.db_curve is None


@pytest.mark.filterwarnings("ignore:source_expression. the same photo as source_neutral")
def test_no_expression_leaves_the_target_as_it_was(pair):
    (sn, _, target), (sn_lm, _, tn_lm) = pair
    with pytest.warns(ExprCloneWarning, match="source_expression: the same photo as source_neutral, so there is no expression"):
        r = exprclone.clone(sn, sn, target, method="global+eri", landmarks=(sn_lm, sn_lm, tn_lm))
    assert np.abs(r.image.astype(int) - target).max() <= 2
    # local re-shaping aims at the target's own organs moved by the source: no motion, no change
    r = exprclone.clone(sn, sn, target, method="local", landmarks=(sn_lm, sn_lm, tn_lm))
    assert np.allclose(r.landmarks["final"], lips.uncross(tn_lm, DLIB68), atol=1e-6)
    # the paper's aim, the source's own organs, gives the target the source's nose and lips
    r = exprclone.clone(sn, sn, target, method="local", landmarks=(sn_lm, sn_lm, tn_lm), retarget=False)
    assert not np.allclose(r.landmarks["final"], tn_lm)


@pytest.mark.parametrize("warp_name", ["similarity", "rbf", "vtc"])
def test_without_retargeting_the_shape_stages_are_the_papers(pair, warp_name):
    """``retarget=False``: GI carries the source's own motion, LI gives each organ the source's own shape (Eqs. 1-2), and
    the elastic model balances the two (Eqs. 3-6), each stage exactly as its function of the paper computes it."""
    images, landmarks = pair
    s_neu, s_exp, t_neu = (lips.uncross(p, DLIB68) for p in landmarks)
    neighbours = piecewise.build_mesh(t_neu, images[2].shape, DLIB68).neighbours()
    tents = vtc.Tents.of(t_neu, neighbours)
    carry = dict(
        similarity=global_warp.global_landmarks,
        rbf=global_warp.rbf_landmarks,
        vtc=lambda sn, se, tn, layout: vtc.vtc_landmarks(sn, se, tn, layout, tents),
    )[warp_name]
    gi = carry(s_neu, s_exp, t_neu, DLIB68)
    li = local_warp.local_landmarks(gi, s_exp, DLIB68)
    paper = {"global": gi, "local": li, "elastic": elastic.elastic_landmarks(gi, li, neighbours, 1.0)}
    for retarget in (False, True):
        r = exprclone.clone(*images, method="elastic", lambda_k=1.0, landmarks=landmarks, global_warp=warp_name, retarget=retarget)
        assert r.options.retarget is retarget
        for stage, points in paper.items():
            same = np.allclose(r.landmarks[stage], points, rtol=0, atol=1e-9)
            assert same is not retarget, (stage, retarget)  # the paper's without retargeting; retargeting changes every stage


def test_the_papers_clone_moves_the_target_mouth_towards_the_source_smile(pair, paper):
    _, (_, source_smile, target_neutral) = pair
    before = mouth_shape_distance(target_neutral, source_smile)
    for method in ("global", "elastic", "e+md"):
        detected = default_detector().detect(paper[method].image)
        after = mouth_shape_distance(detected, source_smile)
        assert after < 0.85 * before, (method, before, after)


def test_bad_arguments_raise_the_project_error(pair):
    """One error type, a ValueError, that says which input is wrong (its role, not a file) and what is wrong with it."""
    images, landmarks = pair
    cases = [
        (dict(method="warp"), "method", "unknown method 'warp'"),
        (dict(lambda_k=-1), "lambda", "must be 'auto' or a number >= 0"),
        (dict(landmarks=(landmarks[0], landmarks[1][:60], landmarks[2])), "source_expression", "found 60 landmarks, expected 68"),
    ]
    for options, subject, problem in cases:
        with pytest.raises(exprclone.ExprCloneError) as caught:
            exprclone.clone(*images, **{"landmarks": landmarks, **options})
        assert isinstance(caught.value, ValueError) and caught.value.subject == subject and caught.value.problem.startswith(problem)
    with pytest.raises(exprclone.ExprCloneError, match="^target_neutral: no face found"):
        exprclone.clone(images[0], images[1], np.full((400, 400, 3), 128, np.uint8), landmarks=landmarks[:2] + (None,))
    with pytest.raises(exprclone.ExprCloneError, match="^source_neutral: expected an \\(H, W, 3\\) uint8"):
        exprclone.clone(images[0].astype(float), *images[1:], landmarks=landmarks)
    with pytest.raises(exprclone.ExprCloneError, match="^target_neutral: a file's path \\(portrait.jpg\\), not its image: read it with"):
        exprclone.clone(*images[:2], "portrait.jpg", landmarks=landmarks)


def test_methods_together_equal_methods_alone(pair, results):
    images, landmarks = pair
    for method in ("local", "e+md"):
        alone = exprclone.clone(*images, method=method, landmarks=landmarks)
        assert np.array_equal(alone.image, results[method].image), method
        assert alone.lambda_k == results[method].lambda_k


def test_photos_of_different_sizes(pair):
    import cv2

    (sn, se, target), _ = pair
    small = [cv2.resize(im, (700, 700), interpolation=cv2.INTER_AREA) for im in (sn, se)]
    r = exprclone.clone(*small, target, method="e+md")
    assert r.image.shape == target.shape
    # the motion is scaled into the target: the mouth widens as much as with full-size sources
    full = exprclone.clone(sn, se, target, method="global", landmarks=pair[1])
    width = lambda p: np.linalg.norm(p[54] - p[48])  # noqa: E731
    assert width(r.landmarks["global"]) == pytest.approx(width(full.landmarks["global"]), rel=0.03)


def test_given_global_landmarks_equal_to_the_default_gi_give_the_default_result(pair, results):
    """Fig. 21's setting: GI from outside, refined by the elastic model; given our own GI, our own result."""
    images, landmarks = pair
    given = exprclone.clone_methods(*images, landmarks=landmarks, global_landmarks=results["global"].landmarks["global"])
    for method, r in given.items():
        assert np.array_equal(r.image, results[method].image), method
        # Song et al.'s method keeps its own global warp, and says so
        assert r.lambda_k == results[method].lambda_k and r.options.global_stage == (BY_NAME[method].warp or "given")


def test_other_global_landmarks_are_refined_by_the_elastic_model(pair, results):
    images, landmarks = pair
    gi = results["global"].landmarks["global"] + np.random.default_rng(0).normal(0, 2, (68, 2))
    given = exprclone.clone_methods(*images, ("global", "elastic"), lambda_k=1.0, landmarks=landmarks, global_landmarks=gi)
    assert np.array_equal(given["global"].landmarks["global"], gi)
    assert not np.allclose(given["elastic"].landmarks["elastic"], gi)  # moved towards its own LI


@pytest.mark.parametrize("warp_name", ["rbf", "vtc"])
def test_another_global_warp_runs_every_method(pair, results, warp_name):
    images, landmarks = pair
    other = exprclone.clone_methods(*images, landmarks=landmarks, global_warp=warp_name)
    for method, r in other.items():
        assert r.image.shape == images[2].shape and r.options.global_warp == (BY_NAME[method].warp or warp_name), method
    assert not np.allclose(other["global"].landmarks["global"], results["global"].landmarks["global"])
    # local re-shaping starts from the other GI, and the DB metric measures against it
    assert np.array_equal(other["e+md"].landmarks["global"], other["global"].landmarks["global"])


def test_the_tps_image_warp_takes_the_same_geometry(pair, results):
    images, landmarks = pair
    tps = exprclone.clone_methods(*images, ("global", "e+md"), landmarks=landmarks, image_warp="tps")
    for method, r in tps.items():
        assert np.array_equal(r.landmarks["final"], results[method].landmarks["final"]), method
        assert not np.array_equal(r.image, results[method].image), method


@pytest.mark.parametrize(
    "options, subject, problem",
    [
        (dict(global_warp="affine"), "global_warp", "unknown global warp 'affine'"),
        (dict(image_warp="spline"), "image_warp", "unknown image warp 'spline'"),
        (dict(strength=2.5), "strength", "must be a number from 0 to 2"),
        (dict(strength="strong"), "strength", "must be a number from 0 to 2"),
        (dict(only="nose"), "only", "unknown region 'nose'"),
        (dict(retarget="no"), "retarget", "must be True or False"),
        (dict(only=()), "only", "unknown region ''"),
        (dict(global_landmarks=np.zeros((60, 2))), "global_landmarks", "found 60 landmarks, expected 68"),
        (dict(global_landmarks=np.full((68, 2), 5000.0)), "global_landmarks", "landmark 0 at (5000, 5000) is outside"),
        (dict(global_landmarks=np.full((68, 2), 50.0), global_warp="rbf"), "global_landmarks", "given landmarks replace"),
        (dict(speed=3), "speed", "not an option"),
    ],
)
def test_bad_options_raise_the_project_error(pair, options, subject, problem):
    images, landmarks = pair
    with pytest.raises(exprclone.ExprCloneError) as caught:
        exprclone.clone(*images, landmarks=landmarks, **options)
    assert caught.value.subject == subject and caught.value.problem.startswith(problem), caught.value


def test_the_registries_hold_every_option_value():
    from exprclone import options
    from exprclone.pipeline import stages

    assert set(stages.GLOBAL_WARPERS) == set(options.GLOBAL_WARPS)
    assert set(warpers.IMAGE_WARPERS) == set(options.IMAGE_WARPS)
    assert options.REGIONS == tuple(DLIB68.regions)


def test_the_db_metrics_candidates_start_from_the_image_e_md_gives_at_gi(pair):
    """What the DB metric carries to its candidates (:func:`exprclone.pipeline.render.synthesized` at GI) is E+MD's
    result at lambda_k = 0 bit for bit, whatever strength a render asks (lambda_k is chosen once for every strength)."""
    from exprclone.pipeline import render, stages
    from exprclone.pipeline.cloner import Cloner

    (sn, se, tn), (sn_lm, se_lm, tn_lm) = pair
    cloner = Cloner(sn, sn_lm, tn, tn_lm, retarget=False, strength=0.5)
    expression = stages.expression(cloner.faces, se, se_lm, cloner.options)
    gl = stages.shapes(cloner.faces, cloner.options, expression, {"global"}, render.synthesis(cloner.faces, expression, "mesh"))
    image, _ = render.synthesis(cloner.faces, expression, "mesh")(gl["global"].points)
    whole = cloner.changed(strength=1.0, lambda_k=0.0).clone_methods(se, se_lm, ("e+md",))["e+md"].image
    assert np.array_equal(image, whole)


def test_lambda_zero_gives_gi_bit_for_bit(pair):
    """With the paper's stages the elastic model at lambda_k = 0 is GI: elastic + ERI's image is global + ERI's (the
    compare sheet then says (f) = (d))."""
    images, landmarks = pair
    made = exprclone.clone_methods(*images, ("global+eri", "elastic+eri"), landmarks=landmarks, retarget=False, lambda_k=0.0)
    assert np.array_equal(made["elastic+eri"].image, made["global+eri"].image)
    assert not np.allclose(made["elastic+eri"].landmarks["local"], made["elastic+eri"].landmarks["global"])


def test_a_prepared_clone_renders_what_a_whole_clone_gives(pair, results):
    """clone() is prepare + render: rendered again with other cheap options (strength, regions, mouth), a prepared clone
    gives bit for bit the image a whole clone with those options gives; it refuses what needs preparing again."""
    images, landmarks = pair
    prepared = exprclone.prepare(*images, ("global", "e+md"), landmarks=landmarks)
    assert np.array_equal(prepared.render()["e+md"].image, results["e+md"].image)
    for cheap in ({"strength": 0.5}, {"only": ("mouth",), "mouth": False}):
        again = prepared.render(**cheap)["e+md"]
        whole = exprclone.clone(*images, landmarks=landmarks, **cheap)
        assert np.array_equal(again.image, whole.image) and again.options.strength == whole.options.strength
        assert not np.array_equal(again.image, results["e+md"].image)
    with pytest.raises(exprclone.ExprCloneError) as refused:
        prepared.render(global_warp="rbf")
    assert refused.value.subject == "global_warp" and "prepare" in refused.value.problem


def test_song_warps_by_vtc_whatever_the_options_and_paints_its_mesh_image(pair, results):
    """Song et al.'s method: the VTC transfer's geometry beside the others' (similarity GI here), its mesh image and the
    mouth interior; alone as with the others."""
    images, landmarks = pair
    song = results["song"]
    on_vtc = exprclone.clone(*images, method="global+eri", landmarks=landmarks, global_warp="vtc")
    assert np.array_equal(song.landmarks["global"], on_vtc.landmarks["global"])
    assert np.array_equal(song.landmarks["final"], on_vtc.landmarks["final"])
    assert not np.allclose(song.landmarks["global"], results["global+eri"].landmarks["global"])
    assert song.options.global_warp == "vtc" and song.lambda_k is None and song.muscle_mask is None
    assert song.eri is not None and not np.array_equal(song.image, on_vtc.image)
    alone = exprclone.clone(*images, method="song", landmarks=landmarks)
    assert np.array_equal(alone.image, song.image)


def test_song_takes_no_other_global_warp(pair):
    images, landmarks = pair
    for options, subject in ((dict(global_warp="rbf"), "global_warp"), (dict(global_landmarks=landmarks[2]), "global_landmarks")):
        with pytest.raises(exprclone.ExprCloneError, match=f"^{subject}: method song warps by its own global warp, vtc; drop"):
            exprclone.clone(*images, method="song", landmarks=landmarks, **options)
    assert exprclone.clone(*images, method="song", landmarks=landmarks, global_warp="vtc").options.global_warp == "vtc"


def test_a_prepared_clone_on_vtc_travels_to_another_process(pair):
    """The server sends prepared clones between processes: one on the VTC warp (its tents' factor is SciPy's, which
    cannot be pickled) renders there as here."""
    import pickle

    images, landmarks = pair
    prepared = exprclone.prepare(*images, ("song", "e+md"), landmarks=landmarks, global_warp="vtc")
    here = prepared.render(strength=0.5)
    there = pickle.loads(pickle.dumps(prepared)).render(strength=0.5)
    assert all(np.array_equal(here[m].image, there[m].image) for m in here)


def test_threads_cloning_at_once_get_what_each_gets_alone(photo):
    """``exprclone.clone`` from two threads at once, no landmarks given: the shared landmarkers (dlib's face detector,
    BlazeFace over tiles) and the role check's judge run in both. Each model takes one thread at a time: before, one
    thread's LiteRT call failed ("at least 1 reference to internal data") or dlib's detector found other faces."""
    triples = [(photo(s)[0], photo(s, "smile")[0], photo(t)[0]) for s, t in (("001", "003"), ("003", "001"))]
    alone = [exprclone.clone(*t, method="global").image for t in triples]
    differ, failed = [], []

    def clone(start):
        try:
            for k in range(4):
                i = (start + k) % len(triples)
                differ.append(not np.array_equal(exprclone.clone(*triples[i], method="global").image, alone[i]))
        except Exception as e:  # noqa: BLE001  # (a thread's failure is the test's)
            failed.append(repr(e))

    threads = [threading.Thread(target=clone, args=(s,)) for s in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failed and differ == [False] * 8, (failed, differ)
