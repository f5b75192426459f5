"""The pipeline of Fig. 5 that runs the parts: one request checked at one door, prepared once, rendered many times.

- :mod:`.request`: the front door: a :class:`~exprclone.pipeline.request.Request` (the photos, what is known of them,
  the options) checked, its landmarks placed, its roles checked, prepared.
- :mod:`.checks`: the inputs checked at the door.
- :mod:`.role_check`: whether the source's two photos are in their roles.
- :mod:`.faces`: the two neutral faces, prepared once for every expression cloned between them.
- :mod:`.stages`: the shape stages (GI, LI, the elastic model) as functions over prepared data.
- :mod:`.cloner`: the faces with the options (:class:`~exprclone.pipeline.cloner.Cloner`), one source expression
  prepared on them (:class:`~exprclone.pipeline.cloner.Prepared`).
- :mod:`.render`: the stages each image costs: FI, the ERI, the MD model, the mouth interior.
- :mod:`.result`: what a clone gives (:class:`~exprclone.pipeline.result.CloneResult`).
- :mod:`.group`: a photo of several faces, each cloned in its own region and blended back.
- :mod:`.clone`: the entry points of Python, :func:`exprclone.clone`, :func:`exprclone.clone_methods` and
  :func:`exprclone.prepare`.

The seven methods of Fig. 11 are data (:mod:`exprclone.methods`), the options are declared in :mod:`exprclone.options`.
"""
