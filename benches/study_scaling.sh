#!/usr/bin/env bash
# Parameter-study throughput on this machine (docs/parameter_studies.md): cases per minute of a
# RopeBlock study run serially, on an embedded Dask LocalCluster of 1 and of 2 workers, and the
# scheduler's overhead per task (empty tasks). `--cases N` (default 60), `--stop S` (simulated
# seconds per case, default 3). Installs what it needs
# (same set-up as tests/run_all.sh) and packs the FMUs.
set -euo pipefail
cd "$(dirname "$0")/.."
source tests/setup_env.sh
log "pack the FMUs"
cargo run --release --bin mbcosim -- pack
log "study throughput"
.venv/bin/python benches/study_scaling.py dist/RopeBlock.fmu "$@"
