"""The scores of exprclone evaluate: they must measure what they claim."""

import cv2
import numpy as np
import pytest

from exprclone.evaluation.london import Dataset
from exprclone.evaluation.report import contrast_table
from exprclone.evaluation.runner import smile_strength, variants
from exprclone.evaluation.scores import GREY_WARMTH, TEETH_SHOWN, landmark_error, teeth, warmth
from exprclone.evaluation.statistics import contrasts, summarise
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68


def test_result_equal_to_the_real_smile_scores_zero(photo):
    _, truth = photo("003", "smile")
    err = landmark_error(truth, truth, DLIB68)
    assert err == {"overall": 0.0, "mouth": 0.0, "eyes_brows": 0.0}


def test_similarity_transformed_copy_scores_the_same(photo):
    _, truth = photo("003", "smile")
    _, result = photo("003")
    t = np.array([[0.9 * np.cos(0.2), -0.9 * np.sin(0.2), 40.0], [0.9 * np.sin(0.2), 0.9 * np.cos(0.2), -25.0]])
    a, b = landmark_error(result, truth, DLIB68), landmark_error(align.apply(t, result), truth, DLIB68)
    assert a == pytest.approx(b, rel=1e-9)
    assert a["overall"] > 0


def test_no_change_scores_worse_than_the_real_smile(photo):
    errors = {}
    for face_id in ("001", "003", "126"):
        _, neutral = photo(face_id)
        _, smile = photo(face_id, "smile")
        errors[face_id] = (smile_strength(neutral, smile), landmark_error(neutral, smile, DLIB68))
        assert errors[face_id][1]["overall"] > landmark_error(smile, smile, DLIB68)["overall"] + 0.005
    # for the broadest of these smiles the change is mostly at the mouth
    _, broadest = max(errors.values(), key=lambda e: e[0])
    assert broadest["mouth"] > broadest["eyes_brows"]


def test_smile_strength_is_zero_for_no_change_and_positive_for_a_smile(photo):
    _, neutral = photo("126")
    _, smile = photo("126", "smile")
    assert smile_strength(neutral, neutral) == pytest.approx(0.0, abs=1e-9)
    assert smile_strength(neutral, smile) > 0.0


@pytest.mark.parametrize("which, people, drawn", [("london", 3, 4), ("london_full", 72, 20)])
def test_pairs_are_reproducible_and_of_different_people(which, people, drawn, request):
    data = Dataset.open(request.getfixturevalue(which))
    assert len(data.ids) == people
    p1, p2 = data.pairs(drawn, seed=3), data.pairs(drawn, seed=3)
    assert p1 == p2 and len(set(p1)) == drawn and all(a != b for a, b in p1)
    assert data.pairs(drawn, seed=4) != p1
    assert len(data.pairs(0, seed=0)) == people * (people - 1)


def test_teeth_tell_smiles_showing_teeth_from_closed_mouths(photo):
    showing = [teeth(*photo(face_id, "smile"), DLIB68) for face_id in ("126", "107")]
    closed = [teeth(*photo(face_id, kind), DLIB68) for face_id, kind in (("126", "neutral"), ("003", "smile"), ("001", "smile"))]
    assert min(showing) >= TEETH_SHOWN > max(closed), (showing, closed)


def test_teeth_covered_with_lip_colour_stop_counting(photo):
    image, landmarks = photo("107", "smile")
    inner, outer = (np.zeros(image.shape[:2], np.uint8) for _ in range(2))
    cv2.fillPoly(inner, [np.round(landmarks[list(DLIB68.mouth_inner)]).astype(np.int32)], 1)
    cv2.fillPoly(outer, [np.round(landmarks[list(DLIB68.mouth_outer)]).astype(np.int32)], 1)
    lip_colour = np.median(image[(outer > 0) & (inner == 0)], axis=0)
    left = (inner > 0) & (np.arange(image.shape[1]) < landmarks[62, 0])[None, :]
    before = teeth(image, landmarks, DLIB68)
    half, whole = image.copy(), image.copy()
    half[left] = lip_colour
    whole[inner > 0] = lip_colour
    assert before >= TEETH_SHOWN
    assert 0 < teeth(half, landmarks, DLIB68) < 0.8 * before  # a broad smile shows teeth on both sides
    assert teeth(whole, landmarks, DLIB68) == 0


def test_yellow_teeth_as_saturated_as_the_lips_still_count(photo):
    """Teeth are told by being brighter than the lips and far less red, not by being paler: a smile's teeth made as
    saturated as its lips but yellow (a dull pasted mouth's, a smoker's) still show; made as red as the lips, they do not.
    (The paste's saturation rule read 0 for the yellow ones.)"""
    image, landmarks = photo("107", "smile")
    inner, outer = (np.zeros(image.shape[:2], np.uint8) for _ in range(2))
    cv2.fillPoly(inner, [np.round(landmarks[list(DLIB68.mouth_inner)]).astype(np.int32)], 1)
    cv2.fillPoly(outer, [np.round(landmarks[list(DLIB68.mouth_outer)]).astype(np.int32)], 1)
    hsv, lightness = cv2.cvtColor(image, cv2.COLOR_RGB2HSV), cv2.cvtColor(image, cv2.COLOR_RGB2Lab)[..., 0]
    lips = (outer > 0) & (inner == 0)
    lip = np.median(hsv[lips], axis=0)  # the lips' hue, saturation and value
    bright = (inner > 0) & (lightness > np.median(lightness[lips]))  # the teeth, and what else is lighter than the lips
    before = teeth(image, landmarks, DLIB68)
    painted = {}
    for name, hue in (("yellow", 25), ("red", lip[0])):  # (OpenCV's hue, 0-180: 25 is a yellow, the lips' a red)
        recoloured = hsv.copy()
        recoloured[bright, 0], recoloured[bright, 1] = hue, lip[1]
        painted[name] = teeth(cv2.cvtColor(recoloured, cv2.COLOR_HSV2RGB), landmarks, DLIB68)
    assert before >= TEETH_SHOWN and painted["yellow"] >= 0.8 * before and painted["red"] < TEETH_SHOWN, (before, painted)


@pytest.mark.parametrize("source, target, shown", [("107", "024", True), ("063", "043", True), ("003", "126", False)])
def test_the_judge_reads_clones_teeth_as_the_eye_does(london_full, source, target, shown):
    """Clones of ``exprclone evaluate``'s gallery whose teeth are plainly visible (107 onto 024, 063 onto 043: the judge
    read 0.000 and 0.001 there) show teeth; a clone whose closed lips are glossy (003 onto 126, of the samples) does not."""
    from exprclone.evaluation.runner import JUDGE, clone_pair, photo
    from exprclone.landmarks.backends import shared

    data = Dataset.open(london_full)
    paths = (data.path(source, False), data.path(source, True), data.path(target, False))
    result = clone_pair(data, (source, target), ("e+md",), {p: shared(JUDGE).detect(photo(p)) for p in paths})["e+md"]
    score = teeth(result.image, shared(JUDGE).detect(result.image), DLIB68)
    assert (score >= TEETH_SHOWN) == shown, score


def test_summary_counts_failures_and_never_drops_them():
    def row(method, pair, mouth, failed="", smile=0.05):
        score = "" if failed else mouth
        return {
            "source": pair[0],
            "target": pair[1],
            "method": method,
            "target_smile": smile,
            "failed": failed,
            "overall": score,
            "mouth": score,
            "eyes_brows": score,
            "identity": "" if failed else 0.3 + mouth * 10,
            "teeth": "" if failed else 0.0,
            "source_teeth": 0.0,
        }

    rows = [
        row("global", "ab", 0.02, smile=0.3),
        row("global", "ac", 0.0, failed="no face found"),
        row("global", "ad", 0.04),
        row("e+md", "ab", 0.01, smile=0.3),
        row("e+md", "ac", 0.03),
        row("e+md", "ad", 0.035),
    ]
    g, e = summarise(rows)
    assert g["pairs"] == 3 and g["failed"] == 1 and e["failed"] == 0
    assert g["overall_mean"] == pytest.approx(0.03) and g["same_person"] == pytest.approx(0.5)
    # paired with global only where both succeeded: (0.01 - 0.02 + 0.035 - 0.04) / 2
    assert e["mouth_vs_baseline"] == pytest.approx(-0.0075) and g["mouth_vs_baseline"] == 0
    assert summarise(rows, strong_only=True)[0]["pairs"] == 1


def scored(method, pair, mouth, identity=0.3, variant="", failed="", teeth=0.0, source_teeth=0.0):
    """A row of pairs.csv with the scores that matter here."""
    return dict(
        source=pair[0],
        target=pair[1],
        method=method,
        target_smile=0.1,
        failed=failed,
        overall=mouth,
        mouth=mouth,
        eyes_brows=mouth,
        identity=identity,
        teeth="" if failed else teeth,
        source_teeth=source_teeth,
        variant=variant,
    )


def test_summary_counts_teeth_against_the_source():
    def row(method, pair, teeth, source_teeth, failed=""):
        return scored(method, pair, 0.02, failed=failed, teeth=teeth, source_teeth=source_teeth)

    shows, closed = 2 * TEETH_SHOWN, 0.0
    rows = [
        row("e+md", "ab", shows, shows),
        row("e+md", "ac", closed, shows),
        row("e+md", "ad", shows, shows),
        row("e+md", "ae", "", shows, failed="no face found"),  # failures are counted apart
        row("e+md", "ba", shows, closed),
        row("e+md", "bc", closed, closed),
        row("global", "ab", closed, shows),
        row("global", "ba", closed, closed),
    ]
    e, g = summarise(rows)
    assert (e["teeth_sources"], e["teeth_kept"]) == (3, pytest.approx(2 / 3))
    assert (e["closed_sources"], e["teeth_invented"]) == (2, pytest.approx(1 / 2))
    assert (g["teeth_sources"], g["teeth_kept"], g["closed_sources"], g["teeth_invented"]) == (1, 0.0, 1, 0.0)
    assert e["failed"] == 1


def test_variants_pair_with_global_in_their_own_variant_and_with_the_paper():
    rows = [
        scored("global", "ab", 0.04, 0.30),
        scored("elastic", "ab", 0.05, 0.31),
        scored("global", "ac", 0.02, 0.20),
        scored("elastic", "ac", 0.02, 0.25),
        scored("global [rbf]", "ab", 0.03, 0.28, " [rbf]"),
        scored("elastic [rbf]", "ab", 0.01, 0.29, " [rbf]"),
        scored("global [rbf]", "ac", 0.01, 0.20, " [rbf]"),
        scored("elastic [rbf]", "ac", 0.0, 0.0, " [rbf]", failed="no face found"),
    ]
    by_method = {s["method"]: s for s in summarise(rows)}
    assert by_method["elastic"]["mouth_vs_baseline"] == pytest.approx((0.01 + 0.0) / 2)
    assert by_method["elastic [rbf]"]["mouth_vs_baseline"] == pytest.approx(0.01 - 0.03)  # ac failed: left out
    lines = {c["compared"]: c for c in contrasts(rows)}
    assert list(lines) == ["elastic - global", "elastic [rbf] - global [rbf]", "global [rbf] - global", "elastic [rbf] - elastic"]
    assert lines["elastic - global"]["pairs"] == 2 and lines["elastic - global"]["mouth_mean"] == pytest.approx(0.005)
    assert lines["elastic [rbf] - global [rbf]"]["pairs"] == 1 and lines["elastic [rbf] - global [rbf]"]["mouth_mean"] == pytest.approx(
        -0.02
    )
    g = lines["global [rbf] - global"]
    assert g["pairs"] == 2 and g["mouth_mean"] == pytest.approx((-0.01 - 0.01) / 2) and g["identity_mean"] == pytest.approx(-0.01)
    assert lines["elastic [rbf] - elastic"]["pairs"] == 1 and lines["elastic [rbf] - elastic"]["mouth_mean"] == pytest.approx(-0.04)
    assert "| global [rbf] - global | 2 | -0.0100 ± 0.0000 |" in contrast_table(contrasts(rows))


def test_song_et_als_method_is_paired_with_global_warping_and_eri_and_e_md_with_it():
    """Figs. 16-17's comparisons, pair by pair: Song et al.'s against global + ERI, E+MD against Song et al.'s."""
    rows = [scored(m, pair, mouth, 0.2) for pair in ("ab", "ac") for m, mouth in (("global+eri", 0.04), ("song", 0.05), ("e+md", 0.03))]
    lines = {c["compared"]: c for c in contrasts(rows)}
    assert list(lines) == ["e+md - global+eri", "song - global+eri", "e+md - song"]
    assert lines["song - global+eri"]["mouth_mean"] == pytest.approx(0.01) and lines["e+md - song"]["mouth_mean"] == pytest.approx(-0.02)


def test_variants_are_every_combination_named_after_their_options():
    chosen = variants(("similarity", "rbf"), ("mesh", "tps"), (1.0,))
    assert [label for label, _ in chosen] == ["", " [tps]", " [rbf]", " [rbf, tps]"]
    said = lambda o: (o.global_warp, o.image_warp, o.strength, o.retarget)  # noqa: E731
    assert said(chosen[3][1]) == ("rbf", "tps", 1.0, True)
    assert [label for label, _ in variants(strengths=(0.5, 1.0))] == ["", " [S=0.5]"]
    default = said(chosen[0][1])
    retargets = [(label, said(o)) for label, o in variants(retargets=(False, True))]
    assert retargets == [("", default), (" [no retarget]", default[:3] + (False,))]


def darkened(image, landmarks, gains):
    """``image`` with a fold darkened by ``gains`` (R, G, B) on both cheeks, as a smile's nasolabial folds."""
    fold = np.zeros(image.shape[:2], np.float32)
    iod = align.interocular(landmarks, DLIB68)
    for corner, wing in ((48, 31), (54, 35)):
        cv2.line(fold, tuple(int(v) for v in landmarks[wing]), tuple(int(v) for v in landmarks[corner]), 1.0, int(0.12 * iod))
    fold = cv2.GaussianBlur(fold, (0, 0), 0.04 * iod)[..., None]
    return np.clip(image * (1 + fold * (np.float32(gains) - 1)) + 0.5, 0, 255).astype(np.uint8)


def test_warmth_tells_a_dimmed_fold_from_a_warm_one(photo):
    """A fold that dims R, G and B alike keeps the chroma-to-lightness proportion (1); one whose G and B fall further
    than R, as real skin's do, measures warmer; a photo with no fold has nothing to measure."""
    neutral, points = photo("003")
    grey = warmth(darkened(neutral, points, (0.75, 0.75, 0.75)), points, neutral, points, DLIB68)
    warm = warmth(darkened(neutral, points, (0.82, 0.74, 0.72)), points, neutral, points, DLIB68)
    assert abs(grey - 1.0) < 0.03 and warm > GREY_WARMTH + 0.05
    assert np.isnan(warmth(neutral, points, neutral, points, DLIB68))


def test_real_smiles_have_warm_shadows(photo):
    """The packaged people's real smiles, against their neutral photos: warmer than a dimmed copy would be."""
    found = [warmth(*photo(person, "smile"), *photo(person), DLIB68) for person in ("001", "003", "126")]
    measured = [w for w in found if not np.isnan(w)]
    assert len(measured) >= 2 and min(measured) > GREY_WARMTH, found
