"""The server's machinery, below its routes (:mod:`exprclone.server.routers`): where the work runs and what bounds it.

:mod:`.state` (the running server's state, which routes reach as the dependency ``Server``),
:mod:`.processes` (pools of worker processes on this machine, :mod:`.pools`, that heal) or :mod:`.cluster` (a Dask
cluster), :mod:`.jobs` and :mod:`.shared_jobs` (video jobs, on this machine or on the cluster), :mod:`.edits`
(prepared clones kept for sliders), :mod:`.limits` (the upload limit, the work queue's gate, a client's pace and
share), :mod:`.clients` (who a request comes from), :mod:`.protocol` (the rules of the live WebSocket),
:mod:`.hosts` (the processes live sessions render in) and :mod:`.lifeline` (the children and temporary files tied
to the server's life). Nothing here knows a route.
"""
