"""Many clones in one run (``exprclone batch``): :mod:`.manifest` (what to do), :mod:`.job` (how: each photo detected
once, rows sharing faces prepared once, on local processes or a Dask cluster), :mod:`.rows` (the tasks a worker runs)."""
