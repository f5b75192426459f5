"""The pipeline of Fig. 5 that runs the parts: prepare a clone once, render it many times.

- :mod:`.methods`: the seven methods of Fig. 11 as data.
- :mod:`.options`: every option of a clone, declared once.
- :mod:`.checks`: the inputs checked at the door.
- :mod:`.stages`: the shape stages (GI, LI, the elastic model) as functions over prepared data.
- :mod:`.cloner`: the two neutral faces prepared once, and what a clone gives.
- :mod:`.role_check`: whether the source's two photos are in their roles.
- :mod:`.group`: a photo of several faces, each cloned in its own region and blended back.
- :mod:`.clone`: the entry points, :func:`exprclone.clone` and :func:`exprclone.clone_methods`.
"""
