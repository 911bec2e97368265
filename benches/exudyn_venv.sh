# Sourced by the Exudyn benchmarks: the venv benches/.venv-exudyn with the pinned Exudyn and
# numpy (made once), in VENV.
source benches/peer_venv.sh
peer_venv benches/.venv-exudyn exudyn exudyn 1.13.6 2.4.6
