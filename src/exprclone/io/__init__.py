"""Files, streams and frames at the edge of the package.

:mod:`.images` (photos), :mod:`.video` (video files, with sound) and
:mod:`.landmarks` (JSON and ``.tem`` landmark files, with the template map
:mod:`.frl_template`), :mod:`.record` (a clone's JSON record), :mod:`.frames` (frames
for a viewer: the portrait at the output's size, side by side) and :mod:`.progress`
(the progress of long jobs on a terminal or in a log). The core never imports these.
"""
