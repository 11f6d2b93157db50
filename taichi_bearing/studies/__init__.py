"""Studies over many runs: cells of varied case keys, running them on a pool or a Dask
cluster, what each run gives, passage statistics, convergence, and the study reports."""
