"""Pixels: the raster helpers the stages share, and the image warps that make a photo follow its landmarks.

- :mod:`.raster`: luma, polygons, erosion, shrinking and enlarging.
- :mod:`.order`: medians and percentiles of large arrays, NumPy's, faster.
- :mod:`.piecewise`: the piecewise-affine warp over a Delaunay mesh (the paper's FI).
- :mod:`.tps`: the thin-plate-spline warp (Bookstein), smooth across the mesh's edges.
- :mod:`.warpers`: both as one kind of function, by name (``image_warp``).
"""
