"""The colour of teeth in white light, and the pull of the paste's colour toward it."""

import dataclasses

import cv2
import numpy as np
import pytest

from exprclone import drive
from exprclone.drive.framing import resize_portrait
from exprclone.io.video import read_frames
from exprclone.landmarks import align, lips
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import illuminant, measure, paste, teeth, tone


def in_mouth(image, points, factors):
    """The photo with the inside of its outer lips lit by ``factors`` (per channel): a light that the cues to the light do not see."""
    lit = image.astype(float)
    inside = np.zeros(image.shape[:2], np.uint8)
    cv2.fillPoly(inside, [np.round(points[list(DLIB68.mouth_outer)]).astype(np.int32)], 1)
    lit[inside > 0] *= factors
    return np.clip(lit + 0.5, 0, 255).astype(np.uint8)


@pytest.fixture(scope="module")
def smile(photo):
    """Source 126 shows her teeth (the packaged sample), target 003; the reference of that pair."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("003")
    se_lm = lips.uncross(se_lm, DLIB68)
    reference = tone.Reference.measure(tn, lips.uncross(tn_lm, DLIB68), DLIB68, (sn, lips.uncross(sn_lm, DLIB68)))
    return se, se_lm, reference


def read(image, points, reference):
    """What the paste's colour is made of: the source's teeth and cavity, its light, and the transfer's log gain."""
    gain = tone.tone_gain(image, points, reference, DLIB68)
    parts = measure.interior(image, points, DLIB68, gain)
    seen = teeth.Interior.read((image[parts[0]], image[parts[1]]), measure.mouth_width(points, DLIB68))
    return seen, tone.source_light(image, points, reference, DLIB68), np.log(gain)


def target_teeth(reference, width):
    """Teeth of the prior's colour under the target's light."""
    return teeth.prior_colour(width) + illuminant.split(illuminant.log_gain(reference.light, teeth.white_light())[0])[1]


def distance(a, b):
    """Distance between two log colours, per degree of freedom."""
    return float(np.sqrt(np.square(a - b).sum() / 2))


def pulled_teeth(seen, light, log_gain, reference):
    """The teeth's log colour once pasted, and the pull."""
    wanted, w = teeth.pull(seen.teeth, teeth.prior_colour(seen.width), teeth.TEETH_SPREAD, reference.light, light)
    colour = illuminant.split(log_gain)[1]
    return seen.teeth.log_colour + colour + w * (wanted - colour), w


def test_teeth_under_a_light_the_cues_miss_are_pasted_in_the_prior_colour(smile):
    """An orange light on the mouth alone: skin and eye whites say white, so the transfer keeps the orange; the pull does not.

    (Under a stronger one, teeth no longer look paler than lips: none are told, and there is nothing to pull.)
    """
    se, se_lm, reference = smile
    seen, light, log_gain = read(in_mouth(se, se_lm, [1.0, 0.85, 0.7]), se_lm, reference)
    wanted = target_teeth(reference, seen.width)
    assert distance(pulled_teeth(seen, light, log_gain, reference)[0], wanted) < teeth.TEETH_SPREAD / 2
    kept = seen.teeth.log_colour + illuminant.split(log_gain)[1]
    assert distance(kept, wanted) > 0.1  # the orange left on the teeth by the transfer alone


def test_the_pull_grows_with_the_light_the_cues_miss_and_never_jumps(smile):
    """From white to a strong orange on the mouth in small steps: the pull grows, the pasted teeth move less than the source's."""
    se, se_lm, reference = smile
    seen, pasted, pulls = [], [], []
    for blue in np.linspace(1.0, 0.55, 19):
        read_ = read(in_mouth(se, se_lm, [1.0, 1.0 - (1.0 - blue) / 2, blue]), se_lm, reference)
        colour, w = pulled_teeth(*read_, reference)
        seen.append(read_[0].teeth.log_colour)
        pasted.append(colour)
        pulls.append(w)
    assert np.all(np.diff(pulls) >= -0.02) and pulls[-1] > 0.95 > pulls[0]
    source_steps = np.linalg.norm(np.diff(seen, axis=0), axis=1)
    pasted_steps = np.linalg.norm(np.diff(pasted, axis=0), axis=1)
    # continuous: no step of the paste's colour larger than the source teeth's own step
    assert pasted_steps.max() <= source_steps.max(), (pasted_steps.max(), source_steps.max())


def test_teeth_and_cavity_each_take_their_own_pull_and_the_shades_between_blend(smile):
    """As bright as the teeth: the teeth's pull; as dark as the cavity: the cavity's colour; in between a blend, without a jump."""
    se, se_lm, reference = smile
    seen, light, log_gain = read(in_mouth(se, se_lm, [1.0, 0.85, 0.7]), se_lm, reference)
    assert seen.teeth is not None and seen.cavity is not None
    levels = np.exp(np.linspace(seen.cavity.brightness - 0.5, seen.teeth.brightness + 0.5, 41))
    grey = np.repeat(levels[:, None, None], 3, axis=2).astype(np.float32)  # (41, 1, 3): no colour of their own
    colour = illuminant.split(np.log(teeth.recolour(grey, log_gain, seen, reference.light, light, seen.width)[:, 0]))[1]
    (top, prior, _, spread), (bottom, cavity_prior, _, cavity_spread) = seen.priors(seen.width)
    teeth_gain, w = teeth.pull(top, prior, spread, reference.light, light)
    gain = illuminant.split(log_gain)[1]
    assert np.allclose(colour[-1], gain + w * (teeth_gain - gain), atol=1e-4)
    assert np.allclose(colour[-2], colour[-1], atol=1e-6)  # from the teeth's first quartile up, the teeth's pull whole
    wanted, w = teeth.pull(bottom, cavity_prior, cavity_spread, reference.light, light)
    target_cavity = bottom.log_colour + wanted  # the cavity's prior colour under the target's light
    assert np.allclose(colour[0], (1 - w) * gain + w * target_cavity, atol=1e-4)  # grey in, pulled toward the cavity's colour
    steps = np.linalg.norm(np.diff(colour, axis=0), axis=1)
    assert steps.max() < np.linalg.norm(colour[-1] - colour[0]) / 10  # no jump from one to the other


def test_teeth_pasted_on_a_larger_mouth_take_the_colour_real_teeth_show_at_that_size(smile):
    """The prior by mouth width: a small, compressed mouth reads its teeth redder; enlarged, they are given the larger mouth's colour."""
    se, se_lm, reference = smile
    small = cv2.resize(se, None, fx=0.25, fy=0.25, interpolation=cv2.INTER_AREA)
    seen, light, log_gain = read(in_mouth(small, se_lm / 4, [1.0, 0.85, 0.7]), se_lm / 4, reference)
    assert seen.width < teeth.WIDTHS[2]
    top = np.full((1, 1, 3), np.exp(seen.teeth.brightness + 0.5), np.float32)  # as bright as the teeth: their pull alone
    at = {
        width: illuminant.split(np.log(teeth.recolour(top, log_gain, seen, reference.light, light, width)[0, 0]))[1]
        for width in (seen.width, 200.0)
    }
    w = teeth.pull(seen.teeth, teeth.prior_colour(seen.width), teeth.TEETH_SPREAD, reference.light, light)[1]
    assert np.allclose(at[200.0] - at[seen.width], w * (teeth.prior_colour(200.0) - teeth.prior_colour(seen.width)), atol=1e-4)
    assert at[200.0][0] < at[seen.width][0]  # less red


def test_cues_that_disagree_make_the_light_less_certain(photo):
    image, points = photo("001")
    target = illuminant.Light.measure(*photo("003"), DLIB68)
    light = illuminant.Light.measure(image, points, DLIB68)
    skin_orange = illuminant.Light(light.log_colour + np.log([[1.0, 0.8, 0.5], [1.0, 1.0, 1.0]]), light.variance)
    assert illuminant.log_gain(target, skin_orange)[1] > 5 * illuminant.log_gain(target, light)[1]
    assert np.allclose(illuminant.log_gain(target, light)[0], np.log(illuminant.gain(target, light)))


def test_a_video_reads_its_teeth_once_and_the_paste_keeps_its_colour(grid_clip, photo):
    """The packaged clip (the issue's orange-lit speaker): one teeth reading, one colour of the gain in every frame."""
    portrait = resize_portrait(photo("003")[0], None, 256)[0]
    recording = drive.prepare(portrait, None, lambda: read_frames(grid_clip), 25.0, neutral_frame="closed")
    reference, layout = recording.driver.cloner.faces.mouth_reference, DLIB68
    assert reference.source_interior.teeth is not None and reference.source_interior.width < teeth.WIDTHS[1]
    colours = [
        illuminant.split(np.log(tone.tone_gain(f, lips.uncross(p, layout), reference, layout)))[1]
        for f, p in zip(read_frames(grid_clip), recording.points)
        if measure.opening(p, layout) >= measure.OPENING[1]
    ]
    assert len(colours) > 10 and np.ptp(colours, axis=0).max() < 1e-9


def test_a_video_reads_its_cameras_grain_once_and_every_paste_gets_it(grid_clip, photo):
    """The packaged clip: the driver's blur and noise read once, the median of its open frames'; a patch pasted from any
    frame is blurred and noised alike, where read on each frame it was not (its frames measure differently)."""
    portrait = resize_portrait(photo("003")[0], None, 256)[0]
    recording = drive.prepare(portrait, None, lambda: read_frames(grid_clip), 25.0, neutral_frame="closed")
    reference, layout = recording.driver.cloner.faces.mouth_reference, DLIB68
    opened = [
        (f, lips.uncross(p, layout))
        for f, p in zip(read_frames(grid_clip), recording.points)
        if measure.opening(p, layout) >= measure.OPENING[1]
    ]
    final = recording.driver.cloner.faces.t_neu
    scale = align.interocular(final, layout) / align.interocular(opened[0][1], layout)
    each = [paste.grain(f, p, reference, scale) for f, p in opened]
    blur = reference.source_grain[0]
    assert min(b for b, _ in each) <= blur <= max(b for b, _ in each) and np.ptp([n for _, n in each], axis=0).max() > 0
    patch, gain = np.full((16, 16, 3), 120.0, np.float32), np.ones(3)
    pasted = {
        read: [paste.match_grain(patch, paste.source_grain(f, p, measured, final, layout), reference.noise, gain) for f, p in opened[:6]]
        for read, measured in (("once", reference), ("each", dataclasses.replace(reference, source_grain=None)))
    }
    assert all(np.array_equal(pasted["once"][0], other) for other in pasted["once"][1:])
    assert not all(np.array_equal(pasted["each"][0], other) for other in pasted["each"][1:])
