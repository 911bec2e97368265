//! The RopeBlock variable table: structural parameters, the hook inputs and the outputs of
//! [`super::RopeBlockScene`], with value references by base type. This table is the single source
//! of truth: `modelDescription/RopeBlock.xml` is generated from it.
//!
//! Output names are the scene's output names with `.` replaced by `_` (`hook0.load` ->
//! `hook0_load`), so the model maps scene outputs onto ports by name. Slot counts are fixed
//! ([`MAX_HOOKS`], [`MAX_SLINGS`], [`MAX_CONTACT_SLOTS`]) so the table is static; slots a scene
//! does not fill read 0 (contact slot sling index -1).
//!
//! Frames: world `z` up (gravity `-z`); the block's *design frame* has `x` along its length, `y`
//! across, `z` up from the bottom; the block frame is the design frame moved to the centre of
//! mass.

use super::params::RopeBlockParams;
use crate::integrator::IntegratorKind;
use crate::scene::choice;
use crate::scene::param_spec::{Bounds, Range, RealSpec, solver};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType, ValueRef, Variability};
use std::sync::OnceLock;

/// Integrator enumeration items (1-based, the same codes as PanelLock's), as RopeBlock runs them
/// (see [`super::scene::solver_settings`]).
pub static INTEGRATORS: &[(&str, &str)] = &[
    (
        "gen_alpha",
        "Generalized-alpha, index 3, adaptive, rho_inf 0 (unresolved rope modes removed within a step)",
    ),
    (
        "bdf",
        "Variable-order BDF 1-2 on the stabilized index-2 form (orders 3-5 are not A-stable on the sling modes)",
    ),
    (
        "dopri5",
        "Dormand-Prince 5(4), index 1 with projection (explicit: only for very coarse slings)",
    ),
];

/// Integrator from its enumeration item number (1-based; clamped to [`INTEGRATORS`], whose
/// port refuses other numbers).
pub fn integrator_of(code: i32) -> IntegratorKind {
    IntegratorKind::ALL[(code.clamp(1, INTEGRATORS.len() as i32) - 1) as usize]
}

/// Model identifier.
pub const IDENTIFIER: &str = "RopeBlock";
/// Hooks the inputs and outputs cover (a rig has at most four; the turn-over scene has two).
pub const MAX_HOOKS: usize = super::rig::MAX_RIG_HOOKS;
/// Slings the outputs cover (both scenes have four; a rig's slings beyond are simulated but not
/// reported, and initialization logs a warning).
pub const MAX_SLINGS: usize = 4;
/// Contact-node output slots in the table (`contact_outputs` selects how many are filled).
pub const MAX_CONTACT_SLOTS: usize = 8;

/// A fixed range `[min, max]`.
const fn range(min: f64, max: f64) -> Bounds {
    Bounds::Fixed(Range::closed(Some(min), Some(max)))
}

/// A real parameter mapped onto a field of [`RopeBlockParams`] (range physically meaningful for
/// a ship-block lift, and bounding the work of one step).
macro_rules! rp {
    ($name:literal, $unit:expr, $min:expr, $max:expr, $desc:literal, $($field:tt)+) => {
        RealSpec::new(
            $name,
            $unit,
            range($min, $max),
            $desc,
            |p: &RopeBlockParams| p.$($field)+,
            |p: &mut RopeBlockParams, v| p.$($field)+ = v,
        )
    };
}

/// A ground parameter: a field of the ground (its defaults when the scene has none; the
/// ground is dropped again when `ground_contact` is off, [`super::cosim`]).
macro_rules! ground {
    ($name:literal, $unit:expr, $min:expr, $max:expr, $desc:literal, $field:ident) => {
        RealSpec::new(
            $name,
            $unit,
            range($min, $max),
            $desc,
            |p: &RopeBlockParams| p.ground.clone().unwrap_or_default().$field,
            |p: &mut RopeBlockParams, v| p.ground.get_or_insert_with(Default::default).$field = v,
        )
    };
}

/// Real parameter value references (indices into [`REAL_PARAMS`]).
pub mod rvr {
    use super::ValueRef;
    pub const BLOCK_MASS: ValueRef = 0;
    pub const ROPE_EA: ValueRef = 1;
    pub const ROPE_MASS_PER_LENGTH: ValueRef = 2;
    pub const ROPE_DAMPING: ValueRef = 3;
    pub const ROPE_DIAMETER: ValueRef = 4;
    pub const MU: ValueRef = 5;
    pub const BENDING_STIFFNESS: ValueRef = 6;
    pub const DRAG_COEFFICIENT: ValueRef = 7;
    pub const FLUID_DENSITY: ValueRef = 8;
    pub const GRAVITY: ValueRef = 9;
    pub const RTOL: ValueRef = 10;
    pub const ATOL: ValueRef = 11;
    pub const H_MAX: ValueRef = 12;
    pub const MESH_SCALE: ValueRef = 13;
    pub const GROUND_HEIGHT: ValueRef = 14;
    pub const GROUND_STIFFNESS: ValueRef = 15;
    pub const GROUND_RESTITUTION: ValueRef = 16;
    pub const GROUND_MU: ValueRef = 17;
    pub const GROUND_SLIP_SPEED: ValueRef = 18;
    pub const ROPE_BREAKING_LOAD: ValueRef = 19;
    pub const HOOK_RAMP_TIME: ValueRef = 20;
}

/// Real parameters, value references 0.. in this order (see [`rvr`]). All are fixed (structural:
/// set before initialization).
pub static REAL_PARAMS: &[RealSpec<RopeBlockParams>] = &[
    rp!(
        "block_mass",
        Some("kg"),
        1e3,
        1e7,
        "Block mass.",
        block_mass
    ),
    rp!(
        "rope_ea",
        Some("N"),
        1e5,
        1e10,
        "Axial stiffness EA of every sling.",
        rope.ea
    ),
    rp!(
        "rope_mass_per_length",
        Some("kg/m"),
        0.1,
        200.0,
        "Sling mass per unstretched length.",
        rope.mass_per_length
    ),
    rp!(
        "rope_damping",
        Some("N.s"),
        0.0,
        1e9,
        "Axial (Kelvin-Voigt) damping of every sling: tension += damping x strain rate.",
        rope.axial_damping
    )
    .motion_only(),
    rp!(
        "rope_diameter",
        Some("m"),
        0.005,
        0.3,
        "Nominal sling diameter (drag area).",
        rope.diameter
    )
    .motion_only(),
    rp!(
        "mu",
        None,
        0.0,
        2.0,
        "Coulomb friction coefficient rope on plate edge [-]; used only when `friction`.",
        rope.friction
    )
    .motion_only(),
    rp!(
        "bending_stiffness",
        Some("N.m2"),
        0.0,
        1e7,
        "Bending stiffness EI of the slings; used only when `bending`.",
        rope.bending_stiffness
    )
    .start(2.0e3),
    rp!(
        "drag_coefficient",
        None,
        0.0,
        5.0,
        "Drag coefficient of the rope cross-section [-]; used only when `drag`.",
        rope.drag_coefficient
    )
    .motion_only()
    .start(1.2),
    rp!(
        "fluid_density",
        Some("kg/m3"),
        0.0,
        2000.0,
        "Density of the surrounding fluid (air 1.225, sea water 1025); used only when `drag`.",
        rope.fluid_density
    )
    .motion_only(),
    rp!(
        "gravity",
        Some("m/s2"),
        0.0,
        20.0,
        "Gravity along world -z; used only when `gravity_on`.",
        gravity
    ),
    solver::rtol(),
    solver::atol(),
    solver::h_max(),
    RealSpec::new(
        "mesh_scale",
        None,
        range(1e-6, 1e6),
        "Factor from the units of `mesh_file` to metres.",
        // not a field of the parameters: read from its port with mesh_file (super::cosim)
        |_| 1.0,
        |_, _| {},
    )
    .start(1.0),
    ground!(
        "ground_height",
        Some("m"),
        -1e3,
        1e3,
        "Height of the level ground, world z; used only when `ground_contact`.",
        height
    ),
    ground!(
        "ground_stiffness",
        Some("N/m"),
        1e5,
        1e13,
        "Ground stiffness per block hull vertex (linear Flores law); used only when `ground_contact`.",
        stiffness
    ),
    ground!(
        "ground_restitution",
        None,
        0.01,
        1.0,
        "Coefficient of restitution of the block hitting the ground; used only when `ground_contact`.",
        restitution
    )
    .motion_only(),
    ground!(
        "ground_mu",
        None,
        0.0,
        2.0,
        "Coulomb friction coefficient of the block on the ground; used only when `ground_contact`.",
        mu
    )
    .motion_only(),
    ground!(
        "ground_slip_speed",
        Some("m/s"),
        1e-6,
        1.0,
        "Speed below which ground friction turns viscous (no sticking: a block held at a fraction r of the friction limit creeps at ground_slip_speed r / sqrt(1 - r^2)); used only when `ground_contact`.",
        slip_speed
    )
    .motion_only(),
    rp!(
        "rope_breaking_load",
        Some("N"),
        1e3,
        1e9,
        "Minimum breaking load of every sling (a [[sling]] of the scene file may give its own): utilisation outputs, and a scene whose slings carry more at rest is refused.",
        rope.breaking_load
    ),
    rp!(
        "hook_ramp_time",
        Some("s"),
        0.0,
        super::params::MAX_HOOK_RAMP,
        "Time over which a hook reaches a new velocity or pay-out command, linearly from the current one (0: at once, the integrator restarts at every change; > 0: hook position and velocity stay continuous and the integrator keeps its history); with hook_command = position, the shortest duration of a move to a new position target.",
        hook_ramp
    )
    .motion_only(),
];

/// Integer value references (parameters first, then outputs; slot `i`'s sling and slip at
/// [`ivr_slot`]).
pub mod ivr {
    use super::ValueRef;
    pub const SCENARIO: ValueRef = 0;
    pub const SEGMENTS: ValueRef = 1;
    pub const INTEGRATOR: ValueRef = 2;
    pub const CONTACT_OUTPUTS: ValueRef = 3;
    /// `hook_command` (enumeration [`super::HOOK_COMMANDS`]).
    pub const HOOK_COMMAND: ValueRef = 4;
    pub const CONTACT_COUNT: ValueRef = 5;
    pub const REBUILDS: ValueRef = 6;
    /// First contact-slot integer output.
    pub const SLOT0: ValueRef = 7;
    /// `integrator_number`, the Integer twin of `integrator` ([`crate::scene::choice`]), after
    /// the contact slots' outputs.
    pub const INTEGRATOR_NUMBER: ValueRef = SLOT0 + 2 * super::MAX_CONTACT_SLOTS as ValueRef;
    /// `hook_command_number`, the Integer twin of `hook_command`.
    pub const HOOK_COMMAND_NUMBER: ValueRef = INTEGRATOR_NUMBER + 1;
    /// `friction_law` (enumeration [`crate::rope::friction::FRICTION_LAWS`]).
    pub const FRICTION_LAW: ValueRef = HOOK_COMMAND_NUMBER + 1;
    /// `friction_law_number`, the Integer twin of `friction_law`.
    pub const FRICTION_LAW_NUMBER: ValueRef = FRICTION_LAW + 1;
}

/// Items of the `hook_command` enumeration (1-based): what the hook inputs command.
pub static HOOK_COMMANDS: &[(&str, &str)] = &[
    (
        "velocity",
        "hookN_vx/vy/vz: hook velocity, reached linearly over hook_ramp_time (hookN_dx/dy/dz ignored)",
    ),
    (
        "position",
        "hookN_dx/dy/dz: hook position as a displacement from its start position, reached at rest along a cubic over hook_ramp_time or longer (hookN_vx/vy/vz ignored)",
    ),
];

/// Codes of the `hook_command` items.
pub mod hook_command {
    /// Velocity commands (`hookN_vx/vy/vz`).
    pub const VELOCITY: i32 = 1;
    /// Position commands (`hookN_dx/dy/dz`).
    pub const POSITION: i32 = 2;
}

/// Integer value reference of contact slot `i`'s field `j` (0 sling, 1 slip).
pub fn ivr_slot(i: usize, j: usize) -> ValueRef {
    ivr::SLOT0 + (2 * i + j) as ValueRef
}

/// Boolean value references (effect switches).
pub mod bvr {
    use super::ValueRef;
    pub const FRICTION: ValueRef = 0;
    pub const BENDING: ValueRef = 1;
    pub const DRAG: ValueRef = 2;
    pub const CONTACT: ValueRef = 3;
    pub const GRAVITY_ON: ValueRef = 4;
    pub const GROUND_CONTACT: ValueRef = 5;
}

/// String value reference of `mesh_file`.
pub const SVR_MESH_FILE: ValueRef = 0;

/// Largest hook speed and winch pay-out rate accepted [m/s], either way: crane hooks move and
/// winches pay out below about 2 m/s; a forged state with a pay-out rate of -375 m/s shortened
/// the slings by 19 m per 0.05 s step and the solver crawled (adversarial benchmark, seed 3).
pub const MAX_HOOK_SPEED: f64 = 10.0;

/// Largest hook displacement command accepted [m], either way along each world axis.
pub const MAX_HOOK_DISPLACEMENT: f64 = 200.0;

/// Per-hook inputs: (suffix, unit, description). Indices 0-2 velocity, 3 pay-out rate, 4-6
/// displacement ([`HOOK_VELOCITY`], [`HOOK_PAYOUT`], [`HOOK_DISPLACEMENT`]).
pub const HOOK_INPUTS: [(&str, &str, &str); 7] = [
    ("vx", "m/s", "velocity, world x"),
    ("vy", "m/s", "velocity, world y"),
    ("vz", "m/s", "velocity, world z (up)"),
    (
        "payout_rate",
        "m/s",
        "winch pay-out rate (positive lengthens the slings on this hook)",
    ),
    (
        "dx",
        "m",
        "position: displacement from the start position, world x",
    ),
    (
        "dy",
        "m",
        "position: displacement from the start position, world y",
    ),
    (
        "dz",
        "m",
        "position: displacement from the start position, world z (up)",
    ),
];
/// Inputs per hook.
pub const N_HOOK_INPUTS: usize = HOOK_INPUTS.len();
/// Index of the first velocity input in [`HOOK_INPUTS`].
pub const HOOK_VELOCITY: usize = 0;
/// Index of the pay-out rate in [`HOOK_INPUTS`].
pub const HOOK_PAYOUT: usize = 3;
/// Index of the first displacement input in [`HOOK_INPUTS`].
pub const HOOK_DISPLACEMENT: usize = 4;

/// Real value reference of hook `k`'s input `j` (index into [`HOOK_INPUTS`]).
pub fn vr_input(k: usize, j: usize) -> ValueRef {
    (REAL_PARAMS.len() + k * HOOK_INPUTS.len() + j) as ValueRef
}

fn first_output() -> usize {
    REAL_PARAMS.len() + MAX_HOOKS * HOOK_INPUTS.len()
}

/// Per-hook real outputs (scene suffixes).
pub const HOOK_OUTPUTS: [(&str, &str, &str); 5] = [
    ("x", "m", "position, world x"),
    ("y", "m", "position, world y"),
    ("z", "m", "position, world z"),
    ("load", "N", "magnitude of the slings' pull on the hook"),
    (
        "fz",
        "N",
        "world z component of the slings' pull on the hook (negative when it carries weight)",
    ),
];
/// Per-sling real outputs: (suffix, unit, description).
pub const SLING_OUTPUTS: [(&str, Option<&str>, &str); 4] = [
    (
        "tension_hook",
        Some("N"),
        "tension of the segment at the hook [N]",
    ),
    (
        "tension_lug",
        Some("N"),
        "tension of the segment at the lug [N]",
    ),
    (
        "utilisation",
        None,
        "utilisation: highest segment tension over the sling's breaking load [-]",
    ),
    (
        "angle",
        Some("rad"),
        "angle of the segment at the hook to the vertical [rad]",
    ),
];
/// Per-contact-slot real outputs.
pub const SLOT_OUTPUTS: [(&str, Option<&str>, &str); 5] = [
    (
        "normal",
        Some("N"),
        "normal force N of the plate edge on the rope at the communication point: the rope's pull -(T_prev e_prev + T_next e_next) along the contact normal n (the rope's turn bisector perpendicular to the edge, towards the plate), positive when the plate pushes [N]",
    ),
    (
        "friction",
        Some("N"),
        "magnitude of the friction force of the plate edge on the rope at the communication point, |(F_e, F_r)| with F_e along the edge (the edge hold) and F_r along the rope (the pull across the edge); at most mu N while sticking, mu N while sliding, exactly 0 with friction off [N]",
    ),
    ("x", Some("m"), "node position, block design frame x"),
    ("y", Some("m"), "node position, block design frame y"),
    ("z", Some("m"), "node position, block design frame z"),
];
/// Block real outputs (scene suffixes after `block.`).
pub const BLOCK_OUTPUTS: [(&str, Option<&str>, &str); 13] = [
    ("x", Some("m"), "centre of mass, world x"),
    ("y", Some("m"), "centre of mass, world y"),
    ("z", Some("m"), "centre of mass, world z"),
    (
        "qw",
        None,
        "orientation quaternion (block to world), scalar part",
    ),
    ("qx", None, "orientation quaternion, x"),
    ("qy", None, "orientation quaternion, y"),
    ("qz", None, "orientation quaternion, z"),
    ("vx", Some("m/s"), "velocity of the centre of mass, world x"),
    ("vy", Some("m/s"), "velocity of the centre of mass, world y"),
    ("vz", Some("m/s"), "velocity of the centre of mass, world z"),
    ("wx", Some("rad/s"), "angular velocity, block frame x"),
    ("wy", Some("rad/s"), "angular velocity, block frame y"),
    ("wz", Some("rad/s"), "angular velocity, block frame z"),
];
/// Energy outputs (scene suffixes after `energy.`).
pub const ENERGY_OUTPUTS: [(&str, &str); 5] = [
    ("kinetic", "kinetic energy"),
    (
        "potential",
        "potential energy (gravity, rope strain, bending)",
    ),
    (
        "dissipated",
        "energy dissipated since the start (damping, friction, drag)",
    ),
    (
        "input",
        "work done by the hooks and winches since the start",
    ),
    (
        "events",
        "change of kinetic plus potential energy at contact-node insertions and moves (negative is a loss)",
    ),
];

/// Ground outputs (scene suffixes after `ground.`).
pub const GROUND_OUTPUTS: [(&str, &str); 2] = [
    ("normal", "total normal force of the ground on the block"),
    (
        "friction",
        "magnitude of the total friction force of the ground on the block",
    ),
];

/// Per-hook power-bond outputs (scene suffixes, as [`super::scene::BOND_OUTPUTS`]): (suffix,
/// unit, description). Listed after `daf`, so the older outputs keep their value references.
pub const BOND_OUTPUTS: [(&str, &str, &str); 7] = [
    (
        "fx",
        "N",
        "world x component of the slings' force on the crane at the hook (power bond with hook#_vx)",
    ),
    (
        "fy",
        "N",
        "world y component of the slings' force on the crane at the hook (power bond with hook#_vy)",
    ),
    (
        "power",
        "W",
        "power the crane delivers into the model at the hook, -(force on the crane) . (hook velocity)",
    ),
    (
        "work",
        "J",
        "work the crane has done on the model at the hook since the start (the power integrated inside the solver's steps)",
    ),
    (
        "winch_force",
        "N",
        "line force of the winch, the power conjugate of the pay-out rate: -dV/dL of the slings' strain energy plus the axial damping tension's share T_d l/L per sling (EA (e + e^2/2) per sling at rest; power bond with hook#_payout_rate)",
    ),
    (
        "winch_power",
        "W",
        "power the winch delivers into the model, -winch_force x pay-out rate",
    ),
    (
        "winch_work",
        "J",
        "work the winch has done on the model since the start (integrated inside the solver's steps)",
    ),
];

/// Real value references of the outputs, in table order.
pub fn vr_output(index: usize) -> ValueRef {
    (first_output() + index) as ValueRef
}

/// Real output names with their unit and description, in value-reference order.
pub fn real_outputs() -> Vec<(String, Option<&'static str>, String)> {
    let mut v = Vec::new();
    for k in 0..MAX_HOOKS {
        for (s, u, d) in HOOK_OUTPUTS {
            let note = if k == 0 {
                ""
            } else {
                " (0 when the rig has no such hook)"
            };
            v.push((
                format!("hook{k}_{s}"),
                Some(u),
                format!("Hook {k}: {d} [{u}]{note}."),
            ));
        }
    }
    for r in 0..MAX_SLINGS {
        for (s, u, d) in SLING_OUTPUTS {
            v.push((
                format!("sling{r}_{s}"),
                u,
                format!("Sling {r}: {d}; 0 when the rig has no sling {r}."),
            ));
        }
    }
    for i in 0..MAX_CONTACT_SLOTS {
        for (s, u, d) in SLOT_OUTPUTS {
            v.push((
                format!("contact{i}_{s}"),
                u,
                format!("Contact slot {i}: {d}; 0 for an empty slot."),
            ));
        }
    }
    for (s, u, d) in BLOCK_OUTPUTS {
        v.push((format!("block_{s}"), u, format!("Block: {d}.")));
    }
    for (s, d) in ENERGY_OUTPUTS {
        v.push((
            format!("energy_{s}"),
            Some("J"),
            format!("Energy: {d} [J]."),
        ));
    }
    for (s, d) in GROUND_OUTPUTS {
        v.push((
            format!("ground_{s}"),
            Some("N"),
            format!("Ground: {d} [N]; 0 without `ground_contact`."),
        ));
    }
    v.push((
        "daf".into(),
        None,
        "Dynamic amplification factor: the hooks' total vertical load over the weight of block and slings [-] (1 hanging at rest; below 1 while the ground carries part; 0 without gravity).".into(),
    ));
    for k in 0..MAX_HOOKS {
        for (s, u, d) in BOND_OUTPUTS {
            let note = if k == 0 {
                ""
            } else {
                " (0 when the rig has no such hook)"
            };
            v.push((
                format!("hook{k}_{s}"),
                Some(u),
                format!("Hook {k}: {} [{u}]{note}.", d.replace('#', &k.to_string())),
            ));
        }
    }
    v
}

/// Scenario numbers of the `scenario` parameter.
pub mod scenario {
    /// One hook, four slings over the deck edges ([`super::RopeBlockParams::default`]).
    pub const LIFT: i32 = 0;
    /// Two hooks, two slings each ([`super::RopeBlockParams::turnover`]).
    pub const TURNOVER: i32 = 1;
}

fn int_port(
    name: &str,
    vr: ValueRef,
    causality: Causality,
    variability: Variability,
    ty: PortType,
    description: &str,
) -> PortSpec {
    PortSpec {
        name: name.into(),
        vr,
        causality,
        variability,
        ty,
        unit: None,
        description: description.into(),
    }
}

fn int_param(name: &str, vr: ValueRef, start: i32, min: i32, max: i32, d: &str) -> PortSpec {
    let ty = PortType::Integer {
        start: Some(start),
        min: Some(min),
        max: Some(max),
    };
    int_port(name, vr, Causality::Parameter, Variability::Fixed, ty, d)
}

fn int_output(name: &str, vr: ValueRef, d: &str) -> PortSpec {
    let ty = PortType::Integer {
        start: None,
        min: None,
        max: None,
    };
    int_port(name, vr, Causality::Output, Variability::Discrete, ty, d)
}

/// The model's static description.
pub fn info() -> &'static ModelInfo {
    static INFO: OnceLock<ModelInfo> = OnceLock::new();
    INFO.get_or_init(|| {
        let d = RopeBlockParams::default();
        let mut ports = vec![
            int_param("scenario", ivr::SCENARIO, scenario::LIFT, 0, 1, "0: lift (one hook, four slings over the deck edges); 1: turn-over (two hooks, two slings each, hook 1's slings around the bottom edge)."),
            int_param("segments", ivr::SEGMENTS, d.segments as i32, 2, 400, "Segments per sling (resolution)."),
            int_port("integrator", ivr::INTEGRATOR, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "Integrator", items: INTEGRATORS, start: Some(1) }, "Time integrator."),
            choice::number_twin("integrator", INTEGRATORS, ivr::INTEGRATOR_NUMBER),
            int_param("contact_outputs", ivr::CONTACT_OUTPUTS, MAX_CONTACT_SLOTS as i32, 0, MAX_CONTACT_SLOTS as i32, "Contact slots filled in the outputs (the table always has 8; the rest read 0)."),
            int_port("hook_command", ivr::HOOK_COMMAND, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "HookCommand", items: HOOK_COMMANDS, start: Some(hook_command::VELOCITY) }, "What the hook inputs command: velocity (hookN_vx/vy/vz) or position (hookN_dx/dy/dz, displacements from the start position); hookN_payout_rate in both."),
            choice::number_twin("hook_command", HOOK_COMMANDS, ivr::HOOK_COMMAND_NUMBER),
            int_port("friction_law", ivr::FRICTION_LAW, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "FrictionLaw", items: crate::rope::friction::FRICTION_LAWS, start: Some(crate::rope::friction::FrictionLaw::EdgeFirst.code()) }, "How a contact node's Coulomb cone splits friction between the edge and the rope once it slides: edge_first (the edge keeps its load, the rope the rest) or pseudo_coefficient (the rope paper's radial scaling of the combined tangential force); docs/rope_friction.md."),
            choice::number_twin("friction_law", crate::rope::friction::FRICTION_LAWS, ivr::FRICTION_LAW_NUMBER),
        ];
        for (vr, name, start, desc) in [
            (bvr::FRICTION, "friction", true, "Coulomb friction between rope and plate edges (off: frictionless, `mu` ignored)."),
            (bvr::BENDING, "bending", false, "Bending stiffness of the slings (off: not assembled, `bending_stiffness` ignored)."),
            (bvr::DRAG, "drag", false, "Quadratic fluid drag on the rope nodes (off: not assembled, `drag_coefficient` and `fluid_density` ignored)."),
            (bvr::CONTACT, "contact", true, "Rope-plate contact (off: slings run straight and pass through the block)."),
            (bvr::GRAVITY_ON, "gravity_on", true, "Gravity along world -z (off: `gravity` ignored)."),
            (bvr::GROUND_CONTACT, "ground_contact", false, "Contact of the block's hull vertices with a level ground at `ground_height`, with friction (off: no ground, not assembled, the `ground_*` values ignored)."),
        ] {
            ports.push(PortSpec::boolean_parameter(name, vr, Variability::Fixed, start, desc));
        }
        ports.push(PortSpec {
            name: "mesh_file".into(),
            vr: SVR_MESH_FILE,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            ty: PortType::String { start: Some("") },
            unit: None,
            description: "OBJ or STL shell plate in the design frame, relative to the FMU resources folder or absolute; empty: the parametric 18 m x 12 m x 7 m block.".into(),
        });
        for (i, p) in REAL_PARAMS.iter().enumerate() {
            ports.push(p.port(i as ValueRef, &d));
        }
        for k in 0..MAX_HOOKS {
            for (j, (s, u, desc)) in HOOK_INPUTS.iter().enumerate() {
                let note = if k == 0 { "" } else { " Accepted and ignored when the rig has no such hook." };
                let (how, bound) = if j >= HOOK_DISPLACEMENT {
                    (format!("used when hook_command = position; reached at rest along a cubic (position and velocity continuous) over hook_ramp_time, or longer so that the move's own speed stays within {} m/s; at most {MAX_HOOK_DISPLACEMENT} m either way", super::runner::HOOK_MOVE_SPEED), MAX_HOOK_DISPLACEMENT)
                } else if j == HOOK_PAYOUT {
                    (format!("reached linearly over hook_ramp_time from the previous command, then held; at most {MAX_HOOK_SPEED} m/s either way"), MAX_HOOK_SPEED)
                } else {
                    (format!("used when hook_command = velocity; reached linearly over hook_ramp_time from the previous command (position stays continuous), then held; at most {MAX_HOOK_SPEED} m/s either way"), MAX_HOOK_SPEED)
                };
                ports.push(
                    PortSpec::real_input(&format!("hook{k}_{s}"), vr_input(k, j), 0.0, Some(u), &format!("Hook {k} command: {desc}; {how}.{note}"))
                        .with_min(-bound)
                        .with_max(bound),
                );
            }
        }
        for (i, (name, unit, desc)) in real_outputs().into_iter().enumerate() {
            ports.push(PortSpec::real_output(&name, vr_output(i), unit, &desc));
        }
        ports.push(int_output("contact_count", ivr::CONTACT_COUNT, "Number of contact nodes (also those beyond the reported slots)."));
        ports.push(int_output("contact_rebuilds", ivr::REBUILDS, "Model rebuilds for contact-node changes since the start."));
        for i in 0..MAX_CONTACT_SLOTS {
            ports.push(int_output(&format!("contact{i}_sling"), ivr_slot(i, 0), &format!("Contact slot {i}: sling index; -1 for an empty slot.")));
            ports.push(int_output(&format!("contact{i}_slip"), ivr_slot(i, 1), &format!("Contact slot {i}: slip along the rope (0 stick or friction off, 1 forward, -1 backward).")));
        }
        ModelInfo {
            identifier: IDENTIFIER,
            guid: "{72837ef2-af5d-4268-b848-abbcd5919726}",
            description: "Ship-block lift with lumped-mass wire-rope slings contacting the block's shell plate edges through contact nodes with Coulomb friction; one-hook lift or two-hook turn-over.",
            ports,
            default_stop_time: 10.0,
            default_step: 0.05,
            initial_dependencies: super::dependencies::initial_dependencies,
        }
    })
}
