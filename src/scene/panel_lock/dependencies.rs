//! What PanelLock's outputs depend on in initialization mode (the `dependencies` of its
//! `InitialUnknowns`).
//!
//! The array starts stowed and at rest, so at initialization:
//! - rates, contact and hinge peak forces, lock times, latch flags, the tip speed, kinetic energy,
//!   dissipated energy, input work and the solver counters do not depend on any known, but for
//!   the factorization counter: the joint-coordinate integrator (`integrator` item 4) evaluates
//!   its first stage, one Cholesky factorization, when it starts; it and `solver_integrator`
//!   depend on the integrator the run uses, the choice and, through `auto`, the two switches it
//!   resolves by ([`INTEGRATOR_USED`]);
//! - a hinge angle is its stowed angle (hinge 0: measured from the root lock angle; hinges 1-6
//!   exist only for enough panels);
//! - the root interface loads and their peaks (the start's magnitudes) come from the initial
//!   accelerations and the elements across the root hinge: masses, geometry, springs, gravity,
//!   cables, the satellite, the root motor torque and, for all but the torque about the hinge
//!   axes, the satellite loads (the inputs); and from the integrator at round-off
//!   (the joint-coordinate integrator starts from the state its joint angles map to, the
//!   others from the maximal projections, and the multipliers solved there differ in the last
//!   bits);
//! - the potential energy from the same parameters, without the inputs;
//! - the satellite's centre of mass from `satellite_cg` (the satellite starts at rest with the
//!   identity attitude, the system with zero momentum, the flexible panels undeformed).
//!
//! Solver settings, contact-law and latch parameters and damping coefficients act only once the
//! array moves. `tests/fmi/initial_dependencies.rs` checks these declarations by perturbing every
//! known in several configurations: the input dependencies are exact there, the parameter
//! dependencies a superset of what the perturbations show (never missing one).

use super::ports::{REAL_PARAMS, SATELLITE_LOAD_INPUTS};
use crate::scene::param_spec::motion_only_names;
use crate::scene::port::{ModelInfo, PortSpec};

/// Knowns that do not act on the initial (stowed, resting) state but for `integrator`
/// ([`ROUND_OFF_ONLY`]): the real parameters declared motion-only
/// ([`crate::scene::param_spec::RealSpec::motion_only`]: the solver knobs, damping, latch and
/// contact parameters) and these choices and switches (a choice's Integer twin
/// ([`crate::scene::choice`]) with its choice).
const MOTION_ONLY_CHOICES: [&str; 5] = [
    "load_frame",
    "load_frame_number",
    "contact_law",
    "contact_law_number",
    "latches",
];

/// Every known that does not act on the initial state (see [`MOTION_ONLY_CHOICES`]).
fn motion_only() -> Vec<&'static str> {
    let mut names = MOTION_ONLY_CHOICES.to_vec();
    names.extend(motion_only_names(REAL_PARAMS));
    names
}

/// The integrator choice and its Integer twin: act on the root-hinge reactions at initialization
/// at round-off only (the starts of the joint-coordinate and maximal integrators differ in the
/// last bits), on nothing else there but the factorization counter.
const ROUND_OFF_ONLY: [&str; 2] = ["integrator", "integrator_number"];

/// What decides the integrator a run uses: the choice, its Integer twin and, with `auto`, the
/// switches that rule out the joint-coordinate integrator (flexible panels, a free satellite).
const INTEGRATOR_USED: [&str; 4] = [
    "integrator",
    "integrator_number",
    "flexible_panels",
    "free_satellite",
];

/// The root interface loads, which the root motor torque reaches at initialization (the motor
/// acts across the root hinge, so it is part of the interface torque; through the array's
/// accelerations it reaches the forces too).
const MOTOR_DRIVEN: [&str; 7] = [
    "root_force_x",
    "root_force_y",
    "root_force_z",
    "root_torque_x",
    "root_torque_y",
    "root_peak_force",
    "root_peak_torque",
];

/// The interface torque about the hinge axes: the elements across the root hinge (spring and
/// motor at rest), which the satellite loads do not reach (the shaft turns freely about its
/// axis, and the elements act on the relative motion only).
const AXIAL_TORQUE: &str = "root_torque_z";

/// The knowns `unknown` depends on in initialization mode (see the module documentation).
pub fn initial_dependencies(info: &ModelInfo, unknown: &PortSpec) -> Option<Vec<String>> {
    let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let name = unknown.name.as_str();
    let deps = if name == "solver_factorizations" || name == "solver_integrator" {
        names(&INTEGRATOR_USED)
    } else if name == "hinge0_angle" {
        names(&["root_stowed_angle", "root_lock_angle"])
    } else if name.starts_with("hinge") && name.ends_with("_angle") {
        names(&["n_panels", "panel_stowed_angle", "panel_lock_angle"])
    } else if MOTOR_DRIVEN.contains(&name) {
        info.knowns_except(&motion_only())
    } else if name == "potential_energy" || name == AXIAL_TORQUE {
        let mut excluded = motion_only();
        if name == "potential_energy" {
            excluded.extend(ROUND_OFF_ONLY);
            excluded.push("root_motor_torque");
        }
        excluded.extend(SATELLITE_LOAD_INPUTS.iter().map(|(n, _, _)| *n));
        info.knowns_except(&excluded)
    } else if let Some(axis) = name.strip_prefix("satellite_").filter(|a| a.len() == 1) {
        vec![format!("satellite_cg_{axis}")]
    } else {
        Vec::new()
    };
    Some(deps)
}
