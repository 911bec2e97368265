//! What RopeBlock's outputs depend on in initialization mode (the `dependencies` of its
//! `InitialUnknowns`).
//!
//! The block starts hanging at rest in static equilibrium with the hooks at their scenario
//! positions, so no output depends on an input (the hook commands act from the first step on):
//! - hook positions depend on the scenario only;
//! - the contact slots (where the slings touch the plate edges, which sling, how many) on the
//!   rigging geometry: scenario, mesh, the contact switch and the number of reported slots;
//!   whether a node slips on the friction switch;
//! - forces, tensions (and the slings' utilisation and angle, the amplification factor), the block
//!   pose and the potential energy on the statics: everything that
//!   shapes the equilibrium (masses, rope stiffness and resolution, gravity, geometry, contact,
//!   bending, ground contact);
//! - velocities, kinetic energy, dissipation, input work and the solver counters on nothing.
//!
//! The equilibrium is settled with the rope sliding freely over the edges and then every node
//! sticking, so the friction coefficient does not shape it; solver settings, damping and drag
//! (nothing moves) do not either. `tests/fmi/initial_dependencies.rs` checks these declarations by
//! perturbing every known in several configurations: the input dependencies (none) are exact,
//! the parameter dependencies a superset of what the perturbations show (never missing one).

use super::ports::REAL_PARAMS;
use crate::scene::param_spec::motion_only_names;
use crate::scene::port::{Causality, ModelInfo, PortSpec};

/// Parameters that do not act on the initial equilibrium (nor does any input): the real
/// parameters declared motion-only ([`crate::scene::param_spec::RealSpec::motion_only`]: solver
/// knobs, damping, friction, drag, the hook ramp) and these.
const NOT_STATICS_CHOICES: [&str; 8] = [
    "integrator",
    "integrator_number",
    "hook_command",
    "hook_command_number",
    "friction_law",
    "friction_law_number",
    "contact_outputs",
    "drag",
];

/// Every parameter that does not act on the initial equilibrium.
fn not_statics() -> Vec<&'static str> {
    let mut names = NOT_STATICS_CHOICES.to_vec();
    names.extend(motion_only_names(REAL_PARAMS));
    names
}

/// Knowns that place the contact nodes: the rigging geometry.
const CONTACT_GEOMETRY: [&str; 6] = [
    "scenario",
    "segments",
    "contact",
    "contact_outputs",
    "mesh_file",
    "mesh_scale",
];

/// The knowns `unknown` depends on in initialization mode (see the module documentation).
pub fn initial_dependencies(info: &ModelInfo, unknown: &PortSpec) -> Option<Vec<String>> {
    let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let name = unknown.name.as_str();
    let axis = name.ends_with("_x") || name.ends_with("_y") || name.ends_with("_z");
    let deps = if name.starts_with("hook") && axis {
        names(&["scenario"])
    } else if name.starts_with("contact") && (axis || name.ends_with("_sling")) {
        names(&CONTACT_GEOMETRY)
    } else if name == "contact_count" {
        names(&["scenario", "segments", "contact", "mesh_file", "mesh_scale"])
    } else if name.starts_with("contact") && name.ends_with("_slip") {
        let mut n = names(&CONTACT_GEOMETRY);
        n.push("friction".into());
        n
    } else if STATICS_OUTPUTS.iter().any(|s| name.contains(s)) {
        let mut n = info.knowns_except(&not_statics());
        n.retain(|k| {
            info.port_by_name(k)
                .is_some_and(|p| p.causality != Causality::Input)
        });
        if name.starts_with("contact") {
            n.push("contact_outputs".into());
        }
        n
    } else {
        Vec::new()
    };
    Some(deps)
}

/// Parts of the names of outputs set by the initial equilibrium (the slings' utilisation and
/// angle and the amplification factor `daf` with the tensions, hook loads and forces and the
/// winches' line forces; the bonds' powers and work read 0 at the start, the hooks at rest).
const STATICS_OUTPUTS: [&str; 16] = [
    "_utilisation",
    "_angle",
    "daf",
    "_load",
    "_fx",
    "_fy",
    "_fz",
    "_winch_force",
    "tension",
    "_normal",
    "_friction",
    "block_q",
    "block_x",
    "block_y",
    "block_z",
    "potential",
];
