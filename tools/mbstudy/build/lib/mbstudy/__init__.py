"""Parameter studies of the mbcosim FMUs: a study described in TOML, its cases run through fmpy
on a Dask cluster (embedded or remote), results as Parquet and CSV. See docs/parameter_studies.md."""
