import cv2
import numpy as np
import pytest

from exprclone.imaging import order
from exprclone.mouth.tone import face_box


def face_statistics(photo):
    """What the mouth's camera measures take medians and percentiles of, on a real face: each channel's noise response
    (integers, many ties), the same after a blur (no ties), and the luma's gradient magnitudes."""
    image, landmarks = photo("003")
    face = face_box(image, landmarks)
    laplacian = np.array([[1, -2, 1], [-2, 4, -2], [1, -2, 1]], np.float32)
    noise = [np.abs(cv2.filter2D(f, -1, laplacian)) for f in (face, cv2.GaussianBlur(face, (0, 0), 1.3))]
    luma = cv2.cvtColor(face, cv2.COLOR_RGB2GRAY)
    gradient = cv2.magnitude(cv2.Sobel(luma, cv2.CV_32F, 1, 0), cv2.Sobel(luma, cv2.CV_32F, 0, 1))
    return [channel for n in noise for channel in cv2.split(n)] + [gradient]


def test_the_median_and_percentiles_of_a_face_are_numpys(photo):
    for values in face_statistics(photo):
        assert order.median(values) == np.median(values) and order.median(values).dtype == np.median(values).dtype
        assert order.median(values[:-1, :-1]) == np.median(values[:-1, :-1])  # the other parity of the count
        for q in (0.5, 25, 50, 98, 99.9):
            assert order.percentile(values, q) == np.percentile(values, q)


def test_column_medians_are_numpys(photo):
    image, _ = photo("003")
    pixels = image.reshape(-1, 3)[::7]
    for values in (pixels, pixels.astype(np.float32) / 255, np.log1p(pixels[:-1].astype(float))):
        got, want = order.median(values, 0), np.median(values, 0)
        assert got.dtype == want.dtype and np.array_equal(got, want)


def test_a_nan_gives_nan_and_few_values_numpys_answer():
    values = np.arange(1001, dtype=np.float32)
    values[500] = np.nan
    assert np.isnan(np.median(values)) and np.isnan(order.median(values))
    for few in (np.array([3.0]), np.array([2.0, 1.0]), np.array([4, 1, 3], np.uint8)):
        assert order.median(few) == np.median(few) and order.percentile(few, 30) == np.percentile(few, 30)
    with pytest.raises(ValueError, match="axis 0"):
        order.median(np.zeros((3, 3)), 1)
