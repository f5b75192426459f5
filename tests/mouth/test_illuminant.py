"""The light on a face, read from its skin and its eye whites."""

import numpy as np

from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import illuminant


def closed_eyes(points):
    """The landmarks with each upper lid lowered onto the lower one."""
    closed = points.copy()
    for eye in DLIB68.eyes:
        corner, up1, up2, corner2, low2, low1 = eye
        closed[up1], closed[up2] = closed[low1], closed[low2]
    return closed


def test_with_closed_eyes_the_skin_alone_tells_the_light(photo):
    image, points = photo("001")
    target = illuminant.Light.measure(*photo("025"), DLIB68)
    light = illuminant.Light.measure(image, closed_eyes(points), DLIB68)
    assert illuminant.eye_openness(closed_eyes(points), DLIB68) == 0 and np.isinf(light.variance[1]).all()
    skin_ratio = np.exp(target.log_colour[0] - light.log_colour[0])
    assert np.allclose(illuminant.gain(target, light), skin_ratio)
    # open, the eye whites count too, and more than the skin for the brightness (skin
    # ranges from pale to dark, eye whites far less)
    open_eyes = illuminant.Light.measure(image, points, DLIB68)
    both = illuminant.gain(target, open_eyes)
    sclera_ratio = np.exp(target.log_colour[1] - open_eyes.log_colour[1])
    brightness = [illuminant.split(np.log(g))[0] for g in (both, skin_ratio, sclera_ratio)]
    assert abs(brightness[0] - brightness[2]) < abs(brightness[0] - brightness[1])


def test_with_no_cue_on_either_photo_the_map_is_the_identity(photo):
    image, points = photo("001")
    blank = np.full_like(image, 255)  # every pixel clipped: nothing to read
    light = illuminant.Light.measure(blank, points, DLIB68)
    assert np.isinf(light.variance).all()
    assert np.array_equal(illuminant.gain(illuminant.Light.measure(image, points, DLIB68), light), np.ones(3))


def test_the_map_back_undoes_the_map(photo):
    a, b = illuminant.Light.measure(*photo("001"), DLIB68), illuminant.Light.measure(*photo("025"), DLIB68)
    assert np.allclose(illuminant.gain(a, b) * illuminant.gain(b, a), 1.0)
    assert not np.allclose(illuminant.gain(a, b), 1.0, atol=0.05)  # two people, two readings
