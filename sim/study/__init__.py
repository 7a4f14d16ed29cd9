"""Studies of many trials: sweeps on local processes or Dask, the SQLite results file,
reports, per-step traces, provenance and figures."""
