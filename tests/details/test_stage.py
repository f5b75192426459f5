import numpy as np

from exprclone.details import eri, muscle, stage
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68
from exprclone.pipeline import render
from exprclone.pipeline.request import Request, pair


def test_the_eri_changes_no_pixel_outside_its_box_and_its_box_is_tight(photo):
    """The ERI's box holds every pixel the details may change (126's smile, teeth and all, onto 003): outside it the ratio
    is 1, and the details applied over the whole photo (the tint 0 outside the box) give what they give applied in the box
    alone; it is the part of the face box where the expression's shading lies, not the whole face box."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("003")
    cloner = pair(Request.of(sn, None, tn, landmarks=(sn_lm, None, tn_lm)))
    prepared = cloner.prepare(se, se_lm, ("e+md",))
    fi = render.fi(cloner.faces, *render.geometry(cloner.faces, prepared.shapes["elastic"].points, cloner.transfer), "mesh")
    ratio = render.ratio(cloner.faces, fi.control, prepared.photo, cloner.transfer, "mesh")
    box = ratio.box
    outside = np.ones(tn.shape[:2], bool)
    outside[box] = False
    assert ratio.tint.shape == ratio.eri[box].shape + (2,) and (ratio.eri[outside] == 1).all()

    final = fi.control[: cloner.faces.mesh.n_landmarks]
    centres, radii = muscle.areas(final, DLIB68)
    importance = muscle.importance_mask(tn.shape[:2], centres, radii, np.full(len(radii), 0.5), muscle.mask_step(radii))
    tint = np.zeros(tn.shape[:2] + (2,), np.float32)
    tint[box] = ratio.tint
    whole = eri.apply_details(fi.image, ratio.eri, importance, tint)
    in_box = fi.image.copy()
    in_box[box] = eri.apply_details(fi.image[box], ratio.eri[box], importance[box], ratio.tint)
    assert np.array_equal(whole, in_box) and not np.array_equal(whole, fi.image)

    iod = align.interocular(final, DLIB68)
    face = align.box(fi.control[: cloner.faces.mesh.n_moving], tn.shape, stage.ERI_MARGIN * iod, closed=False)
    area = [(rows.stop - rows.start) * (cols.stop - cols.start) for rows, cols in (box, face)]
    assert 0 < area[0] < 0.6 * area[1]
