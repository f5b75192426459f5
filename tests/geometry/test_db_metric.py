import numpy as np
import pytest
from conftest import LONDON, need_full_data

from exprclone.geometry import db_metric, eigenface, elastic
from exprclone.geometry.eigenface import default_eigenfaces
from exprclone.io.images import load_image
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline import render, stages
from exprclone.pipeline.request import Request
from exprclone.pipeline.request import pair as cloner_of


def test_db_on_the_straight_line_is_smallest_half_way():
    # candidates on the segment from the global result to the source: DB = e^(D-t) + e^t
    src, gl = np.zeros(8), np.full(8, 1.0)
    t = np.linspace(0, 1, 11)[:, None]
    db, to_source, to_global = db_metric.db_metric(gl + t * (src - gl), src, gl, 1.0)
    assert np.allclose(to_source + to_global, to_source[0])
    assert db.argmin() == 5
    assert db[0] == pytest.approx(np.exp(to_source[0]) + 1)


def test_distances_are_in_the_unit_given():
    rng = np.random.default_rng(0)
    e, src = rng.normal(size=(6, 16)), rng.normal(size=16)
    halved = db_metric.db_metric(e / 2, src / 2, e[0] / 2, 1.0)
    for a, b in zip(db_metric.db_metric(e, src, e[0], 2.0), halved):
        assert np.allclose(a, b)


def test_omega_zero_picks_the_candidate_nearest_the_source():
    rng = np.random.default_rng(0)
    e = rng.normal(size=(6, 16))
    src = e[4] + 0.01
    db, _, _ = db_metric.db_metric(e, src, e[0], 1.0, omega_db=0.0)
    assert db.argmin() == 4


def test_the_scale_is_one_persons_smile_from_their_neutral_face():
    """The stated unit of Eq. 7's distances: over the London Set's people (the shipped basis's training photos, their
    landmarks placed as tools/train_eigenfaces.py places them), a person's smile lies one unit from their own neutral
    face (root-mean-square); two people's neutral faces lie further apart than that."""
    basis, detect = default_eigenfaces(), default_detector().detect
    neutrals = sorted(need_full_data(LONDON / "neutral_front").glob("*.jpg"))
    crops = {}
    for path in neutrals + [LONDON / "smiling_front" / f"{p.name[:3]}_08.jpg" for p in neutrals]:
        image = load_image(path)
        crops[path.parent.name, path.name[:3]] = eigenface.crop(image, detect(image, str(path)), DLIB68, eigenface.FEATURE_SIZE)
    people = sorted({who for _, who in crops})
    e = {kind: basis.features(np.array([crops[kind, who] for who in people])) for kind in ("neutral_front", "smiling_front")}
    own = np.linalg.norm(e["smiling_front"] - e["neutral_front"], axis=1) / basis.unit
    assert np.sqrt(np.mean(own**2)) == pytest.approx(1.0, abs=0.01)  # (the axes are stored as float16)
    others = np.linalg.norm(e["neutral_front"] - np.roll(e["neutral_front"], 1, axis=0), axis=1) / basis.unit
    assert np.median(others) > np.median(own)


@pytest.fixture(scope="module")
def search(pair):
    """The paper's stages on the sample pair: the cloner, the expression, GI, LI, the candidates, E+MD's image at GI."""
    (sn, se, tn), (sn_lm, se_lm, tn_lm) = pair
    cloner = cloner_of(Request.of(sn, None, tn, landmarks=(sn_lm, None, tn_lm), retarget=False))
    faces = cloner.faces
    expression = stages.expression(faces, se, se_lm, cloner.options)
    synthesis = render.synthesis(faces, expression, "mesh")
    made = stages.shapes(faces, cloner.options, expression, {"local"}, synthesis)
    gl, lo = made["global"].points, made["local"].points
    lambdas = np.array(db_metric.LAMBDAS)
    candidates = list(elastic.elastic_landmarks(gl, lo, faces.neighbours, lambdas, db_metric.CANDIDATE_PASSES))
    image, control = synthesis(gl)
    return cloner, candidates, lambdas, image, db_metric.Synthesized.of(image, control, DLIB68, faces.mesh.n_landmarks)


def test_the_candidate_at_lambda_zero_is_gis_own_image(search):
    """lambda_k = 0 gives GI: its carried crop is the crop of E+MD's image at GI itself."""
    cloner, candidates, _, image, synthesized = search
    carried = db_metric.carried_crops(synthesized, cloner.faces.mesh, candidates[:1], DLIB68)[0]
    direct = eigenface.crop(image, candidates[0], DLIB68, eigenface.FEATURE_SIZE)
    assert np.abs(carried - direct).mean() < 0.5  # grey levels: resampling alone


def test_candidates_carry_the_shading_and_mouth_of_their_own_image(search, pair):
    """Candidates are scored as the image they would give: LI's carried crop lies closer to E+MD's own image at LI
    (its ERI and mouth made there) than to its bare warp of the target photo, and closer than GI's image does."""
    import exprclone

    cloner, candidates, _, _, synthesized = search
    images, landmarks = pair
    carried = db_metric.carried_crops(synthesized, cloner.faces.mesh, candidates[-1:], DLIB68)[0]
    at_li = {m: exprclone.clone(*images, method=m, landmarks=landmarks, retarget=False, lambda_k=np.inf).image for m in ("local", "e+md")}
    own, bare = (eigenface.crop(at_li[m], candidates[-1], DLIB68, eigenface.FEATURE_SIZE) for m in ("e+md", "local"))
    gi = db_metric.carried_crops(synthesized, cloner.faces.mesh, candidates[:1], DLIB68)[0]
    assert np.abs(carried - own).mean() < np.abs(carried - bare).mean()
    assert np.abs(carried - own).mean() < np.abs(gi - own).mean()


def test_choose_lambda_on_real_photos(search, pair):
    cloner, candidates, lambdas, _, synthesized = search
    (_, se_img, _), (_, se, _) = pair
    crop = eigenface.crop(se_img, se, DLIB68, eigenface.FEATURE_SIZE)
    curve = db_metric.choose_lambda(synthesized, cloner.faces.mesh, candidates, lambdas, crop, default_eigenfaces(), DLIB68)
    assert np.isfinite(curve.db).all() and curve.to_global[0] == 0
    assert curve.best == lambdas[curve.db.argmin()]
    assert np.allclose(curve.db, np.exp(curve.to_source) + np.exp(curve.to_global))
    assert np.all(np.diff(curve.to_global) >= -1e-3)  # candidates move away from GI as lambda grows
    with pytest.raises(ValueError):
        db_metric.choose_lambda(synthesized, cloner.faces.mesh, candidates[1:], lambdas[1:], crop, default_eigenfaces(), DLIB68)
