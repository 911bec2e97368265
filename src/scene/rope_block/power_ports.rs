//! RopeBlock's power ports (docs/power_bonds.md): at every hook slot the slings' force on the
//! crane (`hookN_fx/fy/fz`, outputs, world axes) beside the hook's velocity (`hookN_vx/vy/vz`,
//! inputs), and the winch's line force (`hookN_winch_force`) beside its pay-out rate
//! (`hookN_payout_rate`). The hook port is the velocity-driven hook (`hook_command = velocity`,
//! the default); under `position` the velocity inputs are not read.

use super::ports::MAX_HOOKS;
use crate::scene::power_port::{PortDomain, PowerPort};

/// The hook and winch ports of every hook slot, hook 0 first.
pub fn power_ports() -> Vec<PowerPort> {
    let mut out = Vec::with_capacity(2 * MAX_HOOKS);
    for k in 0..MAX_HOOKS {
        let n = |s: &str| format!("hook{k}_{s}");
        let (f, v) = ([n("fx"), n("fy"), n("fz")], [n("vx"), n("vy"), n("vz")]);
        out.push(PowerPort::new(
            format!("hook{k}"),
            PortDomain::LinearMechanical,
            &f.each_ref().map(String::as_str),
            &v.each_ref().map(String::as_str),
        ));
        out.push(PowerPort::new(
            format!("hook{k}_winch"),
            PortDomain::LinearMechanical,
            &[&n("winch_force")],
            &[&n("payout_rate")],
        ));
    }
    out
}
