//! PanelLock's power port: the root motor's torque (`root_motor_torque`, input, about the root
//! hinge axis) beside the root hinge's rate (`hinge0_rate`, output), so a motor or drive model
//! can be joined to the array. The root interface wrench (`root_force_*`, `root_torque_*`) has no
//! flow input to pair with: the satellite's motion is computed inside the model
//! (docs/power_bonds.md), so it is not a port a master can close.

use crate::scene::power_port::{PortDomain, PowerPort};

/// The root motor port.
pub fn power_ports() -> Vec<PowerPort> {
    vec![PowerPort::new(
        "root_motor",
        PortDomain::AngularMechanical,
        &["root_motor_torque"],
        &["hinge0_rate"],
    )]
}
