import subprocess
import sys

import cv2
import numpy as np
import pytest

from exprclone.errors import ExprCloneError, ExprCloneWarning
from exprclone.landmarks.dlib import Detector, model_path


@pytest.fixture(scope="module")
def detector():
    return Detector()


def test_model_ships_in_face_recognition_models():
    assert model_path("shape_predictor_68_face_landmarks.dat").endswith(".dat")
    with pytest.raises(ExprCloneError, match="missing"):
        model_path("no_such_model.dat")


def test_landmarks_are_placed_on_the_face(photo, detector):
    image, _ = photo("003")
    lm = detector.detect(image)
    assert lm.shape == (68, 2)
    assert lm[36, 0] < lm[39, 0] < lm[42, 0] < lm[45, 0]  # eye corners left to right
    assert lm[27:31, 1].tolist() == sorted(lm[27:31, 1])  # nose bridge runs down
    assert lm[19, 1] < lm[37, 1] < lm[30, 1] < lm[51, 1] < lm[57, 1] < lm[8, 1]  # brow, eye, nose, lips, chin


def test_small_photo_is_still_found(photo, detector):
    image, full = photo("003")
    small = cv2.resize(image, (240, 240), interpolation=cv2.INTER_AREA)
    lm = detector.detect(small) * (image.shape[1] / 240)
    iod = np.linalg.norm(full[45] - full[36])
    assert np.median(np.linalg.norm(lm - full, axis=1)) < 0.05 * iod


def test_several_faces_take_the_largest_with_a_warning(photo, detector):
    big, big_lm = photo("003")
    other, _ = photo("001")
    canvas = np.full((1350, 1600, 3), 230, np.uint8)
    canvas[:, :900] = big[:, 225:1125]  # the faces sit in the middle of the photos
    canvas[175:1175, 900:1600] = cv2.resize(other, (1000, 1000), interpolation=cv2.INTER_AREA)[:, 150:850]
    big_lm = big_lm - (225, 0)
    with pytest.warns(ExprCloneWarning, match="2 faces found, using the largest"):
        lm = detector.detect(canvas, "group.jpg")
    assert np.median(np.linalg.norm(lm - big_lm, axis=1)) < 3


def test_no_face_is_an_error_naming_the_image(detector):
    with pytest.raises(ExprCloneError, match="wall.png: no face found"):
        detector.detect(np.full((300, 300, 3), 128, np.uint8), "wall.png")


def test_strided_image_reads_as_its_pixels(photo, detector):
    """A view with padded rows (as video decoders return) must be read as the image it shows."""
    image, _ = photo("003")
    small = cv2.resize(image, (360, 360), interpolation=cv2.INTER_AREA)
    padded = np.zeros((360, 368, 3), np.uint8)
    padded[:, :360] = small
    view = padded[:, :360]
    assert not view.flags["C_CONTIGUOUS"]
    assert detector.faces(view) == detector.faces(small)
    assert np.array_equal(detector.detect(view), detector.detect(small))


@pytest.mark.parametrize("face", ["001_neutral", "001_smile", "003_neutral", "003_smile", "126_neutral", "126_smile"])
def test_the_landmarks_shipped_for_the_geometry_tests_are_what_detection_gives(photo, points, face):
    face_id, kind = face.split("_")
    assert np.array_equal(photo(face_id, kind)[1], points(face_id, kind))


#: two threads detecting at once with the process's one detector, each photo as many times: what each finds, alone.
THREADED = """
import sys, threading
import numpy as np
from exprclone import data
from exprclone.landmarks.backends import shared
detector = shared("dlib")
photos = [data.photo(p) for p in ("003", "126", "001")]
alone = [detector.detect(p) for p in photos]
differ = []
def detect(start):
    for k in range(45):
        i = (start + k) % len(photos)
        differ.append(not np.array_equal(detector.detect(photos[i]), alone[i]))
threads = [threading.Thread(target=detect, args=(s,)) for s in (0, 1)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(sum(differ), len(differ))
"""


def test_threads_detecting_at_once_find_what_each_finds_alone():
    """dlib's HOG detector keeps its image pyramid in itself and lets other threads run while it scans: two threads
    with one detector found other boxes (2 to 6 of these 90 landmark sets differed) or corrupted the heap (the process aborted),
    so it runs in a child process."""
    run = subprocess.run([sys.executable, "-c", THREADED], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-500:]
    assert run.stdout.split() == ["0", "90"]
