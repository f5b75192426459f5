"""A photo's landmarks drawn as one-pixel dots, moved smoothly, and checked where a warp puts them (the mesh and TPS warps' tests)."""

import numpy as np


def smooth_motion(lm: np.ndarray) -> np.ndarray:
    """The landmarks moved by a smooth displacement of up to 8 pixels, as a clone moves them; it folds no triangle."""
    return lm + 8 * np.stack([np.sin(lm[:, 1] / 90), np.cos(lm[:, 0] / 70)], 1)


def dots(shape: tuple[int, ...], lm: np.ndarray) -> np.ndarray:
    """A black image of ``shape[:2]`` with a white pixel on every landmark."""
    image = np.zeros(shape[:2], np.uint8)
    for x, y in lm.round().astype(int):
        image[y, x] = 255
    return image


def assert_dots_land(out: np.ndarray, lm: np.ndarray, moved: np.ndarray) -> None:
    """Every dot of :func:`dots` that stands apart (12 pixels from the next) is within a pixel of its landmark's ``moved`` place."""
    expected = moved + (lm.round() - lm)  # each dot keeps its sub-pixel offset
    separate = [i for i in range(len(lm)) if np.sort(np.linalg.norm(lm - lm[i], axis=1))[1] > 12]
    assert len(separate) > 40
    for x, y in expected[separate]:
        xs, ys = int(round(x)), int(round(y))
        window = out[ys - 3 : ys + 4, xs - 3 : xs + 4]
        assert window.max() > 40
        wy, wx = np.unravel_index(window.argmax(), window.shape)
        assert np.hypot(xs - 3 + wx - x, ys - 3 + wy - y) <= 1.0
