//! The FMI boundary and the model descriptions (one test binary for build speed, as
//! `tests/rope/`): the packed FMUs through the `fmi` crate (FMI 2.0 and 3.0), the exports against
//! the `fmi-sys` typedefs, PanelLock-PID coupling, the checked-in descriptions, initial
//! dependencies, start values, declared ranges and snapshot replays. `tests/fmi_overhead.rs`
//! stays a binary of its own: it times steps, which other tests running beside it would disturb.

#[path = "../common/mod.rs"]
mod common;

mod declared_ranges;
mod fmi3_importer;
mod fmi3_signatures;
mod fmi_coupling;
mod fmi_importer;
mod fmi_signatures;
mod initial_dependencies;
mod model_descriptions;
mod osp_ports;
mod snapshot_replay;
mod start_values;
