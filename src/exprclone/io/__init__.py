"""Files in and out, at the edge of the package.

:mod:`.images` (photos), :mod:`.video` (video files, with sound) and
:mod:`.landmarks` (JSON and ``.tem`` landmark files, with the template map
:mod:`.frl_template`). The core never imports these.
"""
