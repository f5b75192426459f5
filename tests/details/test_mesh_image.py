"""The mesh image (Song et al.): the ratio made on one mesh shared by both faces, filtered there, brought onto FI."""

import numpy as np
import pytest

import exprclone
from exprclone.details import stage
from exprclone.details.mesh_image import mesh_image, shared_mesh
from exprclone.imaging import piecewise
from exprclone.imaging.warpers import IMAGE_WARPERS
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline import render
from exprclone.pipeline.request import Request
from exprclone.pipeline.request import pair as cloner_of


@pytest.fixture(scope="module")
def made(pair):
    """001's smile prepared on 003 (a real London pair) by global warping + ERI and by Song et al.'s method: the faces,
    the expression photo and FI's control points of the VTC geometry."""
    (sn, se, tn), (sn_lm, se_lm, tn_lm) = pair
    cloner = cloner_of(Request.of(sn, None, tn, landmarks=(sn_lm, None, tn_lm), global_warp="vtc"))
    prepared = cloner.prepare(se, se_lm, ("global+eri", "song"))
    control, _ = render.geometry(cloner.faces, prepared.shapes["global"].points, cloner.transfer)
    return cloner.faces, prepared.photo, control


def ratios(faces, photo, dst, kind):
    """The ratio ``kind`` (the ERI or the mesh image) at FI's control points ``dst``."""
    make = stage.ratio_image if kind == "eri" else mesh_image
    warp = IMAGE_WARPERS["mesh"]
    return make(faces.mesh, dst, faces.target_image.shape, faces.ratio_faces, faces.source_neutral_ctrl, photo, faces.layout, warp)


def test_the_shared_mesh_is_half_way_between_the_two_faces(made):
    faces, _, _ = made
    mesh, n = faces.mesh, faces.mesh.n_landmarks
    shared = shared_mesh(mesh, faces.source_neutral_ctrl, DLIB68)
    placed = align.apply(align.fit_similarity(faces.source_neutral_ctrl[:n], mesh.points[:n]), faces.source_neutral_ctrl[:n])
    assert np.allclose(shared[:n], (mesh.points[:n] + placed) / 2)
    assert np.array_equal(shared[mesh.n_moving :], mesh.points[mesh.n_moving :])  # the image's border stays
    # one face twice: its own mesh
    assert np.allclose(shared_mesh(mesh, mesh.points, DLIB68), mesh.points)
    assert not piecewise.folded(mesh.points, shared, mesh.triangles).any()


def test_on_the_shared_mesh_itself_the_mesh_image_is_the_ratio_made_there(made):
    """Brought back onto the geometry it was made in, the ratio is as it was made: the warp back moves nothing."""
    faces, photo, _ = made
    shared = shared_mesh(faces.mesh, faces.source_neutral_ctrl, DLIB68)
    there, here = ratios(faces, photo, shared, "eri"), ratios(faces, photo, shared, "mesh")
    assert here.box == there.box
    assert np.allclose(here.eri, there.eri, atol=1e-5) and np.allclose(here.tint, there.tint, atol=1e-5)
    assert np.abs(there.eri - 1).max() > 0.05  # the smile shades the face


def test_the_mesh_image_shades_where_the_eri_does_but_is_made_elsewhere(made):
    """On FI's geometry the two ratios show one expression's shading: the same folds (they correlate closely), though
    the mesh image was filtered and masked in another frame (they are not the same)."""
    faces, photo, fi = made
    eri, mesh = ratios(faces, photo, fi, "eri"), ratios(faces, photo, fi, "mesh")
    a, b = np.log(eri.eri[eri.box]).ravel(), np.log(mesh.eri[eri.box]).ravel()
    assert np.corrcoef(a, b)[0, 1] > 0.9
    assert np.abs(a - b).max() > 1e-3


def test_a_source_without_expression_leaves_the_target_as_it_was(pair):
    (sn, _, target), (sn_lm, _, tn_lm) = pair
    with pytest.warns(exprclone.ExprCloneWarning, match="no expression to clone"):  # and it says so
        r = exprclone.clone(sn, sn, target, method="song", landmarks=(sn_lm, sn_lm, tn_lm))
    assert np.abs(r.image.astype(int) - target).max() <= 2
    assert np.allclose(r.eri, 1.0, atol=1e-3)
