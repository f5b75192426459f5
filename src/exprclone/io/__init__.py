"""Files, streams and documents at the edge of the package.

:mod:`.images` (photos), :mod:`.video` (video files, with sound) and
:mod:`.landmarks` (JSON and ``.tem`` landmark files, with the template map
:mod:`.frl_template`), :mod:`.record` (a clone's JSON record), :mod:`.documents` (JSON
from outside parsed within bounds, CSV cells a spreadsheet reads safely) and :mod:`.progress`
(the progress of long jobs on a terminal or in a log). The core never imports these.
"""
