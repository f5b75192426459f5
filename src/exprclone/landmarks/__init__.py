"""Landmarks: what the 68 points are, how they are measured, and where they come from.

- :mod:`.layout`: the 68-point layout as data (which points are the mouth, the eyes, ...).
- :mod:`.align`: similarity alignment of landmark sets, the eye distance, the face's box.
- :mod:`.lips`: the inner-lip polygon kept valid.
- :mod:`.backends`: the landmarkers by name, each loaded once: dlib's (:mod:`.dlib`) and
  MediaPipe's face mesh (:mod:`.facemesh`, with :mod:`.blazeface` and :mod:`.mesh_layout`).
- :mod:`.crowd`: every face of a group photo, small or large (BlazeFace proposes, dlib's HOG confirms).
- :mod:`.blendshapes`: how much of each of 52 named expressions a face shows (MediaPipe's Face
  Landmarker: its 478-point mesh and blendshape model), for judging any expression.
"""
