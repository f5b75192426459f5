"""How blurred and how noisy a photo is: two estimators measured on any image.

The mouth interior pasted from the source photo (:mod:`exprclone.mouth.paste`) is given
the target photo's sharpness and noise; these measure both.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..imaging import order, raster

#: the second blur of the gradient-ratio sharpness estimate (pixels).
REBLUR = 1.0
#: share of a face's pixels, the strongest gradients, taken as its edges.
EDGE_SHARE = 0.02


def blur_sigma(image: np.ndarray) -> float:
    """How blurred an image is: the Gaussian sigma (pixels) of its edges.

    The gradient-ratio estimate of Zhuo and Sim: an edge blurred by ``sigma`` and
    blurred again by ``sigma_0`` (:data:`REBLUR`) keeps ``1 / R`` of its gradient, with
    ``R = sqrt(sigma**2 + sigma_0**2) / sigma``, so ``sigma = sigma_0 / sqrt(R**2 - 1)``;
    the median over the strongest gradients (:data:`EDGE_SHARE` of the pixels, edges).
    Sobel's own smoothing adds the same amount to every estimate, so two estimates
    compare.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3) or (H, W)

    Returns
    -------
    float

    References
    ----------
    S. Zhuo and T. Sim, "Defocus map estimation from a single image", Pattern
    Recognition 44(9), 2011.

    Examples
    --------
    >>> step = np.zeros((64, 64), np.float32)
    >>> step[:, 32:] = 200
    >>> soft = blur_sigma(cv2.GaussianBlur(step, (0, 0), 3.0))
    >>> sharp = blur_sigma(cv2.GaussianBlur(step, (0, 0), 1.0))
    >>> bool(2.5 < soft < 3.5 and sharp < soft)
    True
    """
    luma = raster.luma(np.asarray(image, np.float32))

    def gradient(im: np.ndarray) -> np.ndarray:
        return cv2.magnitude(cv2.Sobel(im, cv2.CV_32F, 1, 0), cv2.Sobel(im, cv2.CV_32F, 0, 1))

    g = gradient(luma)
    edges = g >= max(order.percentile(g, 100 * (1 - EDGE_SHARE)), 1e-3)
    ratio = g[edges] / np.maximum(gradient(cv2.GaussianBlur(luma, (0, 0), REBLUR))[edges], 1e-6)
    ratio = ratio[ratio > 1.0 + 1e-4]
    return float(order.median(REBLUR / np.sqrt(ratio**2 - 1))) if len(ratio) else 0.0


def noise_sigma(image: np.ndarray) -> np.ndarray:
    """Standard deviation of each channel's noise.

    Immerkaer's estimate, in its robust form: the mask ``N`` below cancels every plane
    and every quadratic surface, so ``I * N`` is the noise times ``N``, whose norm is 6;
    its median absolute value over 0.6745 is the robust standard deviation (edges are
    few, so the median ignores them).

    ``N = [[1, -2, 1], [-2, 4, -2], [1, -2, 1]]``

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), float32

    Returns
    -------
    ndarray of shape (3,)

    References
    ----------
    J. Immerkaer, "Fast noise variance estimation", Computer Vision and Image
    Understanding 64(2), 1996.

    Examples
    --------
    >>> noise = np.random.default_rng(0).normal(0, 5.0, (200, 200, 3)).astype(np.float32)
    >>> noise_sigma(noise + 100).round(1).tolist()
    [5.0, 5.0, 5.0]
    """
    mask = np.array([[1, -2, 1], [-2, 4, -2], [1, -2, 1]], np.float32)
    response = cv2.filter2D(np.asarray(image, np.float32), -1, mask)
    np.abs(response, out=response)
    # a channel at a time, each contiguous (cv2.split): the median of interleaved channels took 2.5 times as long
    return np.array([order.median(channel) for channel in cv2.split(response[1:-1, 1:-1])]) / (0.6745 * 6)
