//! The start values an FMU declares are the parameters its model runs with when an importer sets
//! nothing: the parameters read back from a fresh instance's ports equal the Rust defaults.
//! (The integrator's start was a literal in the variable table; a new default would have left the
//! modelDescription claiming BDF while `PanelLockParams::default()` said otherwise.)

use mbcosim::scene::panel_lock::{PanelLockModel, PanelLockParams};
use mbcosim::scene::rope_block::{RopeBlockModel, RopeBlockParams};

#[test]
fn panel_lock_start_values_are_the_default_parameters() {
    let from_ports = PanelLockModel::new().params().unwrap();
    assert_eq!(from_ports, PanelLockParams::default());
}

#[test]
fn rope_block_start_values_are_the_default_parameters() {
    let from_ports = RopeBlockModel::new().params().unwrap();
    assert_eq!(from_ports, RopeBlockParams::default());
}
