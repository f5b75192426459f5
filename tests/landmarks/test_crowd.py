"""Every face of a group photo found, small or large, upright or turned, and nothing else."""

import numpy as np
import pytest

from exprclone import data as samples
from exprclone.evaluation.groups import make
from exprclone.landmarks import crowd
from exprclone.landmarks.facemesh import MeshDetector


@pytest.fixture(scope="module")
def mesh():
    return MeshDetector()


def found_people(boxes, people):
    """Which person's nose each box holds (None for a box over nobody)."""
    inside = [[b[0] <= p.landmarks[30][0] <= b[2] and b[1] <= p.landmarks[30][1] <= b[3] for p in people] for b in boxes]
    return [row.index(True) if any(row) else None for row in inside]


@pytest.mark.parametrize("tilt", [0, 30])
def test_small_and_large_faces_are_found_upright_or_turned(mesh, tilt):
    """Faces 90 to 400 pixels wide in a photo 1600 wide: the landmarker's own detector sees the largest alone."""
    widths = (90, 150, 400)
    image, people = make(samples.london(), samples.PEOPLE, widths, (1600, 1200), seed=2, tilts=(tilt, -tilt, tilt))
    boxes = crowd.find(image, mesh)
    assert sorted(found_people(boxes, people)) == [0, 1, 2]
    assert len(mesh.faces(image)) < 3
    for box, k in zip(boxes, found_people(boxes, people)):  # dlib's boxes: about as wide as the face
        assert box[2] - box[0] == pytest.approx(widths[k], rel=0.25)


def test_a_portrait_has_one_face_and_a_wall_none(mesh):
    assert len(crowd.find(samples.photo("126"), mesh)) == 1
    assert crowd.find(np.full((700, 900, 3), 128, np.uint8), mesh) == []


def test_a_proposal_over_no_face_is_not_confirmed():
    photo = samples.photo("003")
    assert crowd.confirm(photo, (20.0, 20.0, 220.0, 220.0)) is None
    box = crowd.confirm(photo, (400.0, 500.0, 950.0, 1050.0))
    assert box is not None and box[0] < 675 < box[2]


def test_tiles_cover_the_photo_and_overlap_by_half():
    tiles = crowd.tiles((1350, 1350), 512)
    covered = np.zeros((1350, 1350), bool)
    for x0, y0, x1, y1 in tiles:
        assert (x1 - x0, y1 - y0) == (512, 512)
        covered[y0:y1, x0:x1] = True
    assert covered.all() and crowd.tiles((300, 400), 512) == [(0, 0, 400, 300)]
