"""The blendshape scores (MediaPipe's Face Landmarker, run from the package) on real photos and frames."""

import hashlib
from pathlib import Path

import numpy as np
import pytest
from conftest import LONDON, need_full_data

from exprclone import data as samples
from exprclone.errors import NoFaceError
from exprclone.io.images import load_image
from exprclone.io.landmarks import read_tem
from exprclone.io.video import read_frames
from exprclone.landmarks import blendshapes
from exprclone.landmarks.backends import shared
from exprclone.landmarks.blendshapes import EXPRESSION, NAMES, REGIONS, Blendshapes, indices
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth.measure import opening

PACKAGE = Path(blendshapes.__file__).parent / "mediapipe_models"
SMILE = indices(("mouthSmileLeft", "mouthSmileRight"))
BLINK = indices(("eyeBlinkLeft", "eyeBlinkRight"))
JAW = NAMES.index("jawOpen")


@pytest.fixture(scope="module")
def judge():
    return Blendshapes()


def test_the_models_are_read_from_the_package_as_the_notice_lists_them(judge):
    judge.scores(samples.photo("003"))
    notice = (PACKAGE / "NOTICE").read_text()
    for model in (judge.mesh._load()[1], judge._model):
        path = Path(model.path)
        assert path.parent == PACKAGE and (PACKAGE / "LICENSE").is_file()
        assert f"{path.name} " in notice and hashlib.sha256(path.read_bytes()).hexdigest() in notice


def test_every_name_is_in_one_region_but_the_gaze_and_neutral():
    assert len(NAMES) == len(set(NAMES)) == 52 and len(blendshapes.SUBSET) == len(set(blendshapes.SUBSET)) == 146
    assert sorted(EXPRESSION) == sorted(set(EXPRESSION))  # no name in two regions
    assert set(NAMES) - set(EXPRESSION) == {"_neutral"} | {n for n in NAMES if n.startswith("eyeLook")}
    assert "mouthSmileLeft" in REGIONS["mouth"] and "eyeBlinkRight" in REGIONS["eyes"] and "browInnerUp" in REGIONS["brows"]


def test_scores_do_not_depend_on_where_the_face_is_or_its_size(judge):
    points = judge.mesh.detect_mesh(samples.photo("126", "smile"))
    scores = judge.of_mesh(points)
    assert judge.of_mesh(1.7 * points + [-300.0, 120.0]) == pytest.approx(scores, abs=1e-4)
    # but stretched one way only, the face is another: the points are read in pixels, x and y alike
    assert np.abs(judge.of_mesh(points * [1.0, 0.6]) - scores).max() > 0.05


@pytest.mark.parametrize("face_id", samples.PEOPLE)
def test_the_iris_centres_lie_on_the_templates_pupils(judge, face_id):
    points = judge.mesh.detect_mesh(samples.photo(face_id))
    template = read_tem(samples.template(face_id))  # the 189 points: the pupils first, the subject's right eye first
    iod = np.linalg.norm(template[1] - template[0])
    assert points.shape == (478, 2)
    assert np.linalg.norm(points[[468, 473]] - template[:2], axis=1).max() < 0.05 * iod


def test_smile_scores_rise_from_every_london_neutral_photo_to_the_smile(judge):
    folder = need_full_data(LONDON / "smiling_front")
    people = sorted(p.name[:3] for p in folder.glob("*_08.jpg"))
    rise = []
    for face_id in people:
        neutral, smile = (
            load_image(LONDON / kind / f"{face_id}_{end}.jpg") for kind, end in (("neutral_front", "03"), ("smiling_front", "08"))
        )
        rise.append(judge.scores(smile)[SMILE].mean() - judge.scores(neutral)[SMILE].mean())
    assert len(people) == 72 and min(rise) > 0 and np.mean(rise) > 0.3  # 0.52 on average (the smile's 0.57, the neutral's 0.06)


def test_the_jaw_opens_with_the_mouth_and_the_lids_close_in_a_blink(judge, grid_clip):
    frames = list(read_frames(grid_clip))
    scores = np.array([judge.scores(frame) for frame in frames])
    points = [shared("dlib").detect(frame) for frame in frames]
    mouth = [opening(p, DLIB68) for p in points]
    lids = [np.mean([eye_aperture(p[list(eye)]) for eye in DLIB68.eyes]) for p in points]
    assert np.corrcoef(scores[:, JAW], mouth)[0, 1] > 0.8  # 0.96
    assert scores[:, BLINK].mean(1).max() > 0.5  # 0.68: the speaker blinks once
    assert np.corrcoef(scores[:, BLINK].mean(1), lids)[0, 1] < -0.5  # -0.74


def eye_aperture(eye: np.ndarray) -> float:
    """An eye's height over its width, from its six points (the corners first and fourth)."""
    return float((np.linalg.norm(eye[1] - eye[5]) + np.linalg.norm(eye[2] - eye[4])) / (2 * np.linalg.norm(eye[0] - eye[3])))


def test_a_photo_without_a_face_is_refused_naming_it(judge):
    wall = np.full((480, 640, 3), (120, 140, 160), np.uint8)
    with pytest.raises(NoFaceError, match="^wall.jpg: no face found"):
        judge.scores(wall, "wall.jpg")
    with pytest.raises(NoFaceError):
        blendshapes.scores(samples.photo("003")[:300, :300])  # a corner of the photo: hair and background
