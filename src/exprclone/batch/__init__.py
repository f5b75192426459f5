"""Many clones at once, on all cores or on a Dask cluster (``exprclone batch``): to come."""
