"""Files, streams and frames at the edge of the package.

:mod:`.inputs` (a clone's inputs, from files or bytes sent, gathered into the door's request),
:mod:`.images` (photos), :mod:`.video` (video files) with :mod:`.soundtrack` (their sound
carried into another), :mod:`.landmarks` (JSON and ``.tem`` landmark files, with the template
map :mod:`.frl_template`), :mod:`.documents` (JSON and CSV read and written safely),
:mod:`.record` (a clone's JSON record) and :mod:`.progress` (the progress of long jobs on a
terminal or in a log). The core never imports these.
"""
