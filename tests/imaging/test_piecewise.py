import cv2
import numpy as np
import pytest
from dots import assert_dots_land, dots, smooth_motion
from scipy.spatial import Delaunay

from exprclone.imaging import piecewise
from exprclone.landmarks.layout import DLIB68


def test_identity_when_landmarks_do_not_move(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    out = piecewise.warp(target, mesh.points, mesh.control_points(lm), mesh.triangles)
    assert out.shape == target.shape and out.dtype == target.dtype
    assert np.abs(out.astype(int) - target).max() <= 1


def test_mesh_covers_the_whole_image_without_folds(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    map_x, _ = piecewise.inverse_maps(mesh.points, mesh.points, mesh.triangles, target.shape[:2])
    assert (map_x > -1).all()  # no pixel is left outside every triangle
    assert not piecewise.folded(mesh.points, mesh.points, mesh.triangles).any()
    assert set(range(mesh.n_moving)) <= set(np.unique(mesh.triangles))  # every landmark is a vertex


def test_landmarks_land_where_asked(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    moved = smooth_motion(lm)
    dst, n_fixed = piecewise.unfold(mesh.points, mesh.control_points(moved), mesh.triangles, mesh.n_moving)
    assert n_fixed == 0
    assert_dots_land(piecewise.warp(dots(target.shape, lm), mesh.points, dst, mesh.triangles), lm, moved)


def test_forehead_moves_with_the_brows_and_border_stays(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    raised = lm.copy()
    brows = list(DLIB68.brows[0] + DLIB68.brows[1])
    raised[brows, 1] -= 10
    ctrl = mesh.control_points(raised)
    forehead = mesh.forehead
    assert np.allclose(ctrl[forehead] - mesh.points[forehead], (0, -10))
    assert np.array_equal(ctrl[mesh.n_moving :], mesh.points[mesh.n_moving :])


def test_unfold_removes_a_fold(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    bad = lm.copy()
    bad[30] = lm[8] + (0, 15)  # nose tip dragged below the chin: many triangles flip
    dst = mesh.control_points(bad)
    assert piecewise.folded(mesh.points, dst, mesh.triangles).any()
    fixed, n = piecewise.unfold(mesh.points, dst, mesh.triangles, mesh.n_moving)
    assert n > 0 and not piecewise.folded(mesh.points, fixed, mesh.triangles).any()
    assert np.array_equal(fixed[mesh.n_moving :], dst[mesh.n_moving :])  # the border never moves


@pytest.mark.parametrize("face_id", ["003", "029", "103"])
def test_an_opening_mouth_is_stretched_evenly(photo, face_id):
    """Each column of the new mouth opening samples one point of the closed lip line."""
    target, lm = photo(face_id)
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    opened = lm.copy()
    opened[[61, 62, 63], 1] -= 12
    opened[[65, 66, 67], 1] += 12
    dst = mesh.control_points(opened)
    map_x, map_y = piecewise.inverse_maps(mesh.points, dst, mesh.triangles, target.shape[:2])
    upper, lower = opened[[61, 62, 63]], opened[[67, 66, 65]]
    spreads = []
    for x in range(int(np.ceil(upper[0, 0])), int(upper[2, 0])):
        top = np.interp(x, upper[:, 0], upper[:, 1]) + 2
        bottom = np.interp(x, lower[:, 0], lower[:, 1]) - 2
        column = map_x[int(np.ceil(top)) : int(bottom), x]
        spreads.append(np.ptp(column))
        # the column maps into the slit between the closed lips
        rows = map_y[int(np.ceil(top)) : int(bottom), x]
        assert rows.min() >= np.interp(x, lm[[61, 62, 63], 0], lm[[61, 62, 63], 1]) - 1
        assert rows.max() <= np.interp(x, lm[[67, 66, 65], 0], lm[[67, 66, 65], 1]) + 1
    # each column samples (nearly) one point of the lip line: a vertical smear, no zig-zag
    assert max(spreads) < 3.0, max(spreads)


def test_maps_are_each_triangles_affine_map(pair):
    """The strip-wise float32 maps equal ``[x y 1] @ coeffs[label]`` evaluated in float64."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    moved = lm + 6 * np.stack([np.sin(lm[:, 1] / 50), np.cos(lm[:, 0] / 40)], 1)
    dst, _ = piecewise.unfold(mesh.points, mesh.control_points(moved), mesh.triangles, mesh.n_moving)
    shape = (target.shape[0] - 7, target.shape[1] - 3)  # not a whole number of strips
    pa = piecewise.PiecewiseAffine.build(mesh.points, dst, mesh.triangles, shape)
    ys, xs = np.mgrid[: shape[0], : shape[1]]
    c = pa.coeffs[pa.labels]
    exact = [xs * c[..., 0, k] + ys * c[..., 1, k] + c[..., 2, k] for k in (0, 1)]
    for got, want in zip(piecewise.inverse_maps(mesh.points, dst, mesh.triangles, shape), exact):
        assert got.shape == shape and got.dtype == np.float32
        # float32 rounding: about 1e-4 px, 1e-2 on the slivers between the lips whose
        # coefficients are large
        err = np.abs(got - want)
        assert np.quantile(err, 0.999) < 1e-3 and err.max() < 2e-2


@pytest.mark.parametrize("channels", [(), (3,)])
def test_strip_wise_warp_equals_one_remap_with_the_whole_maps(pair, channels):
    (_, _, target), (_, _, lm) = pair
    image = target if channels else target[..., 1].copy()
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    dst = mesh.control_points(lm + 5 * np.stack([np.cos(lm[:, 1] / 60), np.sin(lm[:, 0] / 50)], 1))
    out = piecewise.warp(image, mesh.points, dst, mesh.triangles)
    map_x, map_y = piecewise.inverse_maps(mesh.points, dst, mesh.triangles, image.shape[:2])
    assert np.array_equal(out, cv2.remap(image, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE))


def test_meshes_of_more_than_255_triangles(pair):
    """Past 255 triangles the labels are int32 and gathered by numpy instead of cv2.LUT."""
    (_, _, target), _ = pair
    rng = np.random.default_rng(0)
    corners = np.array([[-0.5, -0.5], [299.5, -0.5], [-0.5, 199.5], [299.5, 199.5]])
    pts = np.concatenate([corners, rng.uniform(5, 195, (300, 2)) * (1.5, 1)])
    tri = Delaunay(pts).simplices
    assert len(tri) > 255
    image = target[500:700, 500:800]
    assert piecewise.PiecewiseAffine.build(pts, pts, tri, image.shape[:2]).labels.dtype == np.int32
    assert np.abs(piecewise.warp(image, pts, pts, tri).astype(int) - image).max() <= 1


def test_a_window_of_the_output_is_that_window_of_the_whole_warp(pair):
    """Triangles outside a small output are dropped; that changes none of its pixels."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    dst = mesh.control_points(lm + 6 * np.stack([np.cos(lm[:, 1] / 70), np.sin(lm[:, 0] / 45)], 1))
    whole = piecewise.warp(target, mesh.points, dst, mesh.triangles)
    assert np.array_equal(piecewise.warp(target, mesh.points, dst, mesh.triangles, (300, 200)), whole[:300, :200])
    x0, y0 = int(lm[:, 0].min()), int(lm[:, 1].min())
    window = piecewise.warp(target, mesh.points, dst - (x0, y0), mesh.triangles, (250, 400))
    assert np.abs(window.astype(int) - whole[y0 : y0 + 250, x0 : x0 + 400]).max() <= 1


def test_a_closed_slit_maps_into_the_source(pair):
    """A triangle of no area (collinear lips) still gets a finite map."""
    (_, _, target), _ = pair
    src = np.array([[-0.5, -0.5], [99.5, -0.5], [-0.5, 79.5], [99.5, 79.5], [30, 40], [50, 40], [70, 40]])
    dst = src.copy()
    tri = np.array([[0, 1, 4], [1, 5, 4], [1, 6, 5], [1, 3, 6], [3, 2, 6], [2, 5, 6], [2, 4, 5], [0, 4, 2], [4, 5, 6]])
    pa = piecewise.PiecewiseAffine.build(src, dst, tri, (80, 100))
    assert np.isfinite(pa.coeffs).all()
    image = target[600:680, 600:700]
    assert np.abs(piecewise.warp(image, src, dst, tri).astype(int) - image).max() <= 1


def test_maps_solved_together_are_each_solved_alone(pair):
    """warp.affines (the DB metric's candidates) gives each labelling the table it gets alone: outputs of different
    sizes, triangles dropped from one and not the other, a closed slit (pinv), 8-bit and 32-bit labels."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    dst = mesh.control_points(lm + 6 * np.stack([np.cos(lm[:, 1] / 70), np.sin(lm[:, 0] / 45)], 1))
    slit = mesh.control_points(lm)
    pairs = np.array(DLIB68.lip_pairs)
    slit[pairs[:, 0]] = slit[pairs[:, 1]] = slit[pairs].mean(axis=1)  # the inner lips closed: slivers of no area
    assert not (np.abs(piecewise.signed_areas(slit, mesh.triangles)) > 1e-6).all()
    corners = np.array([[-0.5, -0.5], [299.5, -0.5], [-0.5, 199.5], [299.5, 199.5]])
    many = np.concatenate([corners, np.random.default_rng(0).uniform(5, 195, (300, 2)) * (1.5, 1)])
    fine = Delaunay(many).simplices.astype(np.int32)
    groups = [
        (
            mesh.points,
            [
                piecewise.Labelling.of(dst, mesh.triangles, target.shape[:2]),
                piecewise.Labelling.of(slit, mesh.triangles, target.shape[:2]),
                piecewise.Labelling.of(dst - lm.min(0), mesh.triangles, (120, 90)),
            ],
        ),
        (many, [piecewise.Labelling.of(many + 3, fine, (200, 300)), piecewise.Labelling.of(many - 5, fine, (100, 150))]),
    ]
    assert len({len(lab.triangles) for lab in groups[0][1]}) == 2
    assert {lab.labels.dtype for lab in groups[1][1]} == {np.dtype(np.uint8), np.dtype(np.int32)}
    for src, labellings in groups:
        for lab, together in zip(labellings, piecewise.affines(labellings, src), strict=True):
            alone = lab.affine(src)
            assert together.labels is lab.labels and np.array_equal(together.coeffs, alone.coeffs)
            # the table is the triangles' own maps: each triangle's corners in the output go to its corners in the source
            tri = lab.triangles
            d = np.concatenate([lab.dst[tri], np.ones((len(tri), 3, 1))], axis=2)
            solid = np.abs(piecewise.signed_areas(lab.dst, tri)) > 1e-6
            assert np.allclose((d @ together.coeffs[1 : len(tri) + 1])[solid], src[tri][solid], atol=1e-6)


def test_neighbours_are_the_landmarks_sharing_a_triangle(pair):
    """Mesh.neighbours: for each landmark, in order and once each, every other landmark it shares a triangle with (a
    triangle's three vertices are joined by its edges); forehead, mid-lip and border points are not landmarks."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    got = mesh.neighbours()
    assert len(got) == mesh.n_landmarks == 68
    for i, found in enumerate(got):
        shared = {int(j) for t in mesh.triangles if i in t for j in t if j != i and j < mesh.n_landmarks}
        assert found.tolist() == sorted(shared), i
