//! The PanelLock variable table: parameters (mapped onto [`PanelLockParams`]), the motor input and
//! the outputs, with value references by base type.

use super::params::{
    DEFAULT_PANEL_E, LoadFrame, MAX_HINGE_FRICTION_TORQUE, MAX_PANEL_POISSON, MIN_PANEL_POISSON,
    PanelLockParams,
};
use super::satellite::MAX_CG_OFFSET;
use crate::contact::LawKind;
use crate::integrator::IntegratorKind;
use crate::scene::choice;
use crate::scene::param_spec::{Bounds, ENVELOPE_DECADES, Range, RealSpec, solver};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType, ValueRef, Variability};
use std::sync::OnceLock;

/// Model identifier.
pub const IDENTIFIER: &str = "PanelLock";
/// Largest number of hinges the outputs cover (6 panels plus the root hinge).
pub const MAX_HINGES: usize = 7;

/// Envelope factor: [`ENVELOPE_DECADES`] decades.
const ENVELOPE: f64 = 1e3;
const _: () = assert!(ENVELOPE_DECADES == 3);
/// Finite and > 0, three decades either side of the default.
const POSITIVE: Bounds = Bounds::Positive { cap: None };
/// Finite and >= 0, up to three decades above the default.
const NON_NEGATIVE: Bounds = Bounds::NonNegative { cap: None };
/// Lock angles: lock - 0.2 > stowed >= 0, and at most pi.
const LOCK_ANGLE: Bounds = Bounds::Fixed(Range {
    min: Some(0.2),
    max: Some(std::f64::consts::PI),
    open: [true, false],
    floor: None,
});
/// Stowed angles: stowed < lock - 0.2 <= pi - 0.2.
const STOWED_ANGLE: Bounds = Bounds::Fixed(Range {
    min: Some(0.0),
    max: Some(std::f64::consts::PI - 0.2),
    open: [false, true],
    floor: None,
});
/// Satellite centre-of-mass offsets [m].
const CG: Bounds = fixed(-MAX_CG_OFFSET, MAX_CG_OFFSET);

const fn fixed(min: f64, max: f64) -> Bounds {
    Bounds::Fixed(Range::closed(Some(min), Some(max)))
}

macro_rules! real_param {
    ($name:literal, $field:ident, $unit:expr, $bounds:expr, $desc:literal) => {
        RealSpec::new(
            $name,
            $unit,
            $bounds,
            $desc,
            |p: &PanelLockParams| p.$field,
            |p: &mut PanelLockParams, v| p.$field = v,
        )
    };
}

/// Real parameters, value references 0.. in this order.
pub static REAL_PARAMS: &[RealSpec<PanelLockParams>] = &[
    real_param!(
        "panel_length",
        panel_length,
        Some("m"),
        POSITIVE,
        "Panel length along the deployment direction."
    ),
    real_param!(
        "panel_width",
        panel_width,
        Some("m"),
        POSITIVE,
        "Panel width along the hinge axis."
    ),
    real_param!(
        "panel_areal_density",
        panel_areal_density,
        Some("kg/m2"),
        POSITIVE,
        "Panel mass per area (honeycomb with cells)."
    ),
    real_param!(
        "panel_thickness",
        panel_thickness,
        Some("m"),
        POSITIVE,
        "Panel thickness (for its inertia)."
    ),
    real_param!(
        "yoke_length",
        yoke_length,
        Some("m"),
        POSITIVE,
        "Yoke length from root hinge to first panel hinge."
    ),
    real_param!(
        "yoke_mass",
        yoke_mass,
        Some("kg"),
        POSITIVE,
        "Yoke mass."
    ),
    real_param!(
        "hinge_mass",
        hinge_mass,
        Some("kg"),
        POSITIVE,
        "Mass of each hinge body."
    ),
    real_param!(
        "hinge_gyration_radius",
        hinge_gyration_radius,
        Some("m"),
        POSITIVE,
        "Radius of gyration of each hinge body."
    ),
    real_param!(
        "root_spring_preload",
        root_spring_preload,
        Some("N.m"),
        NON_NEGATIVE,
        "Root deployment spring torque at the lock angle."
    ),
    real_param!(
        "root_spring_stiffness",
        root_spring_stiffness,
        Some("N.m/rad"),
        NON_NEGATIVE,
        "Root deployment spring stiffness."
    ),
    real_param!(
        "panel_spring_preload",
        panel_spring_preload,
        Some("N.m"),
        NON_NEGATIVE,
        "Panel-hinge deployment spring torque at the lock angle."
    ),
    real_param!(
        "panel_spring_stiffness",
        panel_spring_stiffness,
        Some("N.m/rad"),
        NON_NEGATIVE,
        "Panel-hinge deployment spring stiffness."
    ),
    real_param!(
        "hinge_damping",
        hinge_damping,
        Some("N.m.s/rad"),
        NON_NEGATIVE,
        "Viscous damping of every hinge shaft."
    )
    .motion_only(),
    real_param!(
        "root_lock_angle",
        root_lock_angle,
        Some("rad"),
        LOCK_ANGLE,
        "Root hinge deployment angle at lock-up; more than 0.2 rad above root_stowed_angle, and less than pi rad above it."
    ),
    real_param!(
        "panel_lock_angle",
        panel_lock_angle,
        Some("rad"),
        LOCK_ANGLE,
        "Panel hinge deployment angle at lock-up; more than 0.2 rad above panel_stowed_angle, and less than pi rad above it."
    ),
    real_param!(
        "root_stowed_angle",
        root_stowed_angle,
        Some("rad"),
        STOWED_ANGLE,
        "Root hinge angle when stowed (t = 0); below root_lock_angle - 0.2 rad."
    ),
    real_param!(
        "panel_stowed_angle",
        panel_stowed_angle,
        Some("rad"),
        STOWED_ANGLE,
        "Panel hinge angle when stowed (t = 0); below panel_lock_angle - 0.2 rad."
    ),
    real_param!(
        "stop_stiffness",
        stop_stiffness,
        Some("N.m/rad"),
        NON_NEGATIVE,
        "Stiffness of the stow stops (folded stack on its snubbers)."
    ),
    real_param!(
        "stop_damping",
        stop_damping,
        Some("N.m.s/rad"),
        NON_NEGATIVE,
        "Damping of the stow stops."
    )
    .motion_only(),
    real_param!(
        "cam_radius",
        cam_radius,
        Some("m"),
        POSITIVE,
        "Latch cam radius; larger than groove_depth + groove_width / 2 (with latches)."
    )
    .motion_only(),
    real_param!(
        "groove_width",
        groove_width,
        Some("m"),
        POSITIVE,
        "Latch groove width; at least 2 pin_radius (with latches)."
    )
    .motion_only(),
    real_param!(
        "groove_depth",
        groove_depth,
        Some("m"),
        POSITIVE,
        "Latch groove depth; at least pin_radius, below cam_radius (with latches)."
    )
    .motion_only(),
    real_param!(
        "pin_radius",
        pin_radius,
        Some("m"),
        POSITIVE,
        "Latch pin radius."
    )
    .motion_only(),
    real_param!(
        "contact_stiffness",
        contact_stiffness,
        None,
        POSITIVE,
        "Pin/groove contact stiffness k in N/m^n with n = contact_exponent (F = k delta^n ...); no unit is declared because its dimension depends on n."
    )
    .motion_only()
    .unit_note("N/m^n"),
    real_param!(
        "contact_exponent",
        contact_exponent,
        None,
        POSITIVE,
        "Contact force exponent n (1.5 for metals)."
    )
    .motion_only(),
    real_param!(
        "restitution",
        restitution,
        None,
        Bounds::Positive { cap: Some(1.0) },
        "Coefficient of restitution of the damped contact laws, in (0, 1]."
    )
    .motion_only(),
    real_param!(
        "cable_stiffness",
        cable_stiffness,
        Some("N.m/rad"),
        NON_NEGATIVE,
        "Closed cable loop stiffness (per rad of the inboard hinge); > 0 with cable_loop."
    ),
    real_param!(
        "cable_damping",
        cable_damping,
        Some("N.m.s/rad"),
        NON_NEGATIVE,
        "Closed cable loop damping."
    )
    .motion_only(),
    real_param!(
        "satellite_mass",
        satellite_mass,
        Some("kg"),
        POSITIVE,
        "Satellite mass (free-floating satellite only)."
    ),
    RealSpec::new(
        "satellite_inertia_x",
        Some("kg.m2"),
        POSITIVE,
        "Satellite principal moment of inertia about its body x axis, at its centre of mass (free-floating satellite only); at most satellite_inertia_y + satellite_inertia_z.",
        |p| p.satellite_inertia[0],
        |p, v| p.satellite_inertia[0] = v,
    ),
    RealSpec::new(
        "satellite_inertia_y",
        Some("kg.m2"),
        POSITIVE,
        "Satellite principal moment of inertia about its body y axis (free-floating satellite only); at most satellite_inertia_x + satellite_inertia_z.",
        |p| p.satellite_inertia[1],
        |p, v| p.satellite_inertia[1] = v,
    ),
    RealSpec::new(
        "satellite_inertia_z",
        Some("kg.m2"),
        POSITIVE,
        "Satellite principal moment of inertia about its body z axis (parallel to the hinge axes at t = 0; free-floating satellite only); at most satellite_inertia_x + satellite_inertia_y.",
        |p| p.satellite_inertia[2],
        |p, v| p.satellite_inertia[2] = v,
    ),
    RealSpec::new(
        "satellite_cg_x",
        Some("m"),
        CG,
        "Satellite centre of mass relative to the root-hinge attachment point, satellite body x (parallel to world x at t = 0; the array deploys along +x).",
        |p| p.satellite_cg[0],
        |p, v| p.satellite_cg[0] = v,
    ),
    RealSpec::new(
        "satellite_cg_y",
        Some("m"),
        CG,
        "Satellite centre of mass relative to the root-hinge attachment point, satellite body y.",
        |p| p.satellite_cg[1],
        |p, v| p.satellite_cg[1] = v,
    ),
    RealSpec::new(
        "satellite_cg_z",
        Some("m"),
        CG,
        "Satellite centre of mass relative to the root-hinge attachment point, satellite body z (along the hinge axes at t = 0).",
        |p| p.satellite_cg[2],
        |p, v| p.satellite_cg[2] = v,
    ),
    RealSpec::new(
        "gravity",
        Some("m/s2"),
        fixed(-9.81 * ENVELOPE, 9.81 * ENVELOPE),
        "Gravity along -z (the hinge axes) when gravity_on.",
        |p| p.gravity.unwrap_or(9.81),
        |p, v| p.gravity = p.gravity.map(|_| v),
    ),
    real_param!(
        "modal_damping_ratio",
        modal_damping_ratio,
        None,
        Bounds::Fixed(Range {
            min: Some(0.0),
            max: Some(1.0),
            open: [false, true],
            floor: None,
        }),
        "Modal damping ratio of the flexible panels' modes (flexible_panels only)."
    )
    .motion_only(),
    real_param!(
        "panel_youngs_modulus",
        panel_youngs_modulus,
        Some("Pa"),
        fixed(DEFAULT_PANEL_E / ENVELOPE, DEFAULT_PANEL_E * ENVELOPE),
        "Equivalent Young's modulus of the honeycomb panel plate (flexible_panels only)."
    ),
    real_param!(
        "panel_poisson",
        panel_poisson,
        None,
        fixed(MIN_PANEL_POISSON, MAX_PANEL_POISSON),
        "Equivalent Poisson ratio of the panel plate (flexible_panels only)."
    ),
    real_param!(
        "panel_nonstructural_mass",
        panel_nonstructural_mass,
        Some("kg/m2"),
        Bounds::Fixed(Range::closed(Some(0.0), None)),
        "Non-structural areal mass (cells, harness), part of panel_areal_density and below it (flexible_panels only)."
    ),
    solver::rtol().note(
        "Held per second of simulated time with rigid panels, per step with flexible panels."
    ),
    solver::atol(),
    solver::h_max(),
    real_param!(
        "hinge_friction_torque",
        hinge_friction_torque,
        Some("N.m"),
        Bounds::NonNegative {
            cap: Some(MAX_HINGE_FRICTION_TORQUE),
        },
        "Coulomb friction torque of every hinge shaft, opposing the hinge rate (regularized over a slip rate of 1e-4 rad/s); 0: no friction effect. Per hinge: [[hinge]] friction_torque in the scene file."
    )
    .motion_only(),
];

/// Value reference of the motor-torque input (after the real parameters).
pub fn vr_motor() -> ValueRef {
    REAL_PARAMS.len() as ValueRef
}

/// Number of real inputs: the motor torque and the six satellite loads.
pub const N_REAL_INPUTS: usize = 7;

/// Satellite load inputs after the motor torque, in this order (units, descriptions).
pub const SATELLITE_LOAD_INPUTS: [(&str, &str, &str); 6] = [
    (
        "satellite_force_x",
        "N",
        "Force on the satellite's centre of mass, x component in load_frame (free_satellite only; must stay 0 with a fixed satellite), held over each step.",
    ),
    (
        "satellite_force_y",
        "N",
        "Force on the satellite's centre of mass, y component in load_frame (free_satellite only).",
    ),
    (
        "satellite_force_z",
        "N",
        "Force on the satellite's centre of mass, z component in load_frame (free_satellite only).",
    ),
    (
        "satellite_torque_x",
        "N.m",
        "Torque on the satellite, x component in load_frame (free_satellite only; must stay 0 with a fixed satellite), held over each step.",
    ),
    (
        "satellite_torque_y",
        "N.m",
        "Torque on the satellite, y component in load_frame (free_satellite only).",
    ),
    (
        "satellite_torque_z",
        "N.m",
        "Torque on the satellite, z component in load_frame (free_satellite only).",
    ),
];

/// Value reference of satellite load input `j` ([`SATELLITE_LOAD_INPUTS`] order).
pub fn vr_satellite_load(j: usize) -> ValueRef {
    (REAL_PARAMS.len() + 1 + j) as ValueRef
}

/// Satellite and momentum outputs after the global outputs, in this order.
pub const SATELLITE_OUTPUTS: [(&str, Option<&str>, &str); 16] = [
    (
        "satellite_qw",
        None,
        "Satellite attitude quaternion (body to world), scalar part; 1 for a fixed satellite.",
    ),
    (
        "satellite_qx",
        None,
        "Satellite attitude quaternion (body to world), x part.",
    ),
    (
        "satellite_qy",
        None,
        "Satellite attitude quaternion (body to world), y part.",
    ),
    (
        "satellite_qz",
        None,
        "Satellite attitude quaternion (body to world), z part.",
    ),
    (
        "satellite_wx",
        Some("rad/s"),
        "Satellite angular rate, satellite body x (0 for a fixed satellite).",
    ),
    (
        "satellite_wy",
        Some("rad/s"),
        "Satellite angular rate, satellite body y.",
    ),
    (
        "satellite_wz",
        Some("rad/s"),
        "Satellite angular rate, satellite body z.",
    ),
    (
        "satellite_x",
        Some("m"),
        "Satellite centre of mass, world x (the world origin is the root-hinge attachment point at t = 0; a fixed satellite stays at satellite_cg).",
    ),
    (
        "satellite_y",
        Some("m"),
        "Satellite centre of mass, world y.",
    ),
    (
        "satellite_z",
        Some("m"),
        "Satellite centre of mass, world z.",
    ),
    (
        "satellite_vx",
        Some("m/s"),
        "Satellite centre-of-mass velocity, world x.",
    ),
    (
        "satellite_vy",
        Some("m/s"),
        "Satellite centre-of-mass velocity, world y.",
    ),
    (
        "satellite_vz",
        Some("m/s"),
        "Satellite centre-of-mass velocity, world z.",
    ),
    (
        "angular_momentum_x",
        Some("kg.m2/s"),
        "Total angular momentum of the moving bodies (satellite when free, hinges, yoke, panels) about their centre of mass, world x; conserved with a free satellite and no satellite torque or force.",
    ),
    (
        "angular_momentum_y",
        Some("kg.m2/s"),
        "Total angular momentum about the centre of mass, world y.",
    ),
    (
        "angular_momentum_z",
        Some("kg.m2/s"),
        "Total angular momentum about the centre of mass, world z.",
    ),
];

/// Per-hinge real outputs, in this order for hinge 0, 1, ...
pub const HINGE_OUTPUTS: [(&str, Option<&str>, &str); 5] = [
    (
        "angle",
        Some("rad"),
        "Deployment angle (0 stowed flat, lock angle at the groove centre).",
    ),
    ("rate", Some("rad/s"), "Deployment angle rate."),
    (
        "contact_force",
        Some("N"),
        "Pin/groove wall force now (front plus rear wall).",
    ),
    (
        "peak_force",
        Some("N"),
        "Largest pin/groove wall force so far.",
    ),
    (
        "lock_time",
        Some("s"),
        "Time of lock-up (latch engagement); until then 1 s before the start time (-1 for a start at 0).",
    ),
];

/// Global real outputs after the hinge outputs.
pub const GLOBAL_OUTPUTS: [(&str, Option<&str>, &str); 15] = [
    (
        "root_force_x",
        Some("N"),
        "Force of the array on the satellite at the root interface, world x: the root shaft's reaction plus every force element across the root hinge (spring, damper, friction, latch, stop, cable loop, motor); with gravity off, minus the rate of change of the array's linear momentum.",
    ),
    (
        "root_force_y",
        Some("N"),
        "Force of the array on the satellite at the root interface, world y.",
    ),
    (
        "root_force_z",
        Some("N"),
        "Force of the array on the satellite at the root interface, world z.",
    ),
    (
        "root_torque_x",
        Some("N.m"),
        "Torque of the array on the satellite about the root hinge's attachment point, world x: the root shaft's reaction torque plus the moments of every force element across the root hinge (spring, damper, friction, latch, stop, cable loop, motor).",
    ),
    (
        "root_torque_y",
        Some("N.m"),
        "Torque of the array on the satellite about the root hinge's attachment point, world y.",
    ),
    (
        "root_torque_z",
        Some("N.m"),
        "Torque of the array on the satellite about the root hinge's attachment point, world z (about the hinge axes).",
    ),
    (
        "tip_normal_velocity",
        Some("m/s"),
        "Velocity of the outer panel's tip midpoint along the panel normal.",
    ),
    ("kinetic_energy", Some("J"), "Kinetic energy."),
    (
        "potential_energy",
        Some("J"),
        "Potential energy (springs, stops, contacts, gravity).",
    ),
    (
        "energy_dissipated",
        Some("J"),
        "Energy dissipated since the start.",
    ),
    (
        "input_work",
        Some("J"),
        "Work done by the root motor since the start.",
    ),
    (
        "root_peak_force",
        Some("N"),
        "Largest magnitude of the root interface force (root_force_x/y/z) since the start, over every accepted integrator step.",
    ),
    (
        "root_peak_torque",
        Some("N.m"),
        "Largest magnitude of the root interface torque (root_torque_x/y/z) since the start, over every accepted integrator step.",
    ),
    (
        "root_power",
        Some("W"),
        "Power the satellite delivers into the array through the root interface (power bond of root_force/root_torque with the satellite's motion): -(root_force . v_O + root_torque . omega_satellite), world frame, v_O the attachment point's velocity; 0 for a fixed satellite.",
    ),
    (
        "root_work",
        Some("J"),
        "Work the satellite has done on the array through the root interface since the start, root_power integrated over every accepted integrator step.",
    ),
];

/// Value reference of hinge `k`'s output `j` (index into [`HINGE_OUTPUTS`]).
pub fn vr_hinge(k: usize, j: usize) -> ValueRef {
    (REAL_PARAMS.len() + N_REAL_INPUTS + k * HINGE_OUTPUTS.len() + j) as ValueRef
}

/// Value reference of global output `j`.
pub fn vr_global(j: usize) -> ValueRef {
    (REAL_PARAMS.len() + N_REAL_INPUTS + MAX_HINGES * HINGE_OUTPUTS.len() + j) as ValueRef
}

/// Value reference of satellite output `j` ([`SATELLITE_OUTPUTS`]).
pub fn vr_satellite_output(j: usize) -> ValueRef {
    vr_global(GLOBAL_OUTPUTS.len() + j)
}

/// Largest number of panels the per-panel outputs cover.
pub const MAX_PANELS: usize = 6;

/// Per-panel real outputs (panel 1 = the innermost), after the satellite outputs, in this order
/// for panel 1, 2, ...
pub const PANEL_OUTPUTS: [(&str, Option<&str>, &str); 4] = [
    (
        "tip_deflection",
        Some("m"),
        "Normal deflection of the outboard edge's mid-width point relative to the rigid panel (clamped at its inboard hinge), along the rigid panel's normal (that of tip_normal_velocity).",
    ),
    (
        "mode1",
        Some("m"),
        "Amplitude of the first fixed-interface mode, as the largest normal deflection it gives over the panel.",
    ),
    (
        "mode2",
        Some("m"),
        "Amplitude of the second fixed-interface mode, as the largest normal deflection it gives over the panel.",
    ),
    (
        "mode3",
        Some("m"),
        "Amplitude of the third fixed-interface mode, as the largest normal deflection it gives over the panel.",
    ),
];

/// Value reference of panel `k`'s (1-based) output `j` ([`PANEL_OUTPUTS`]).
pub fn vr_panel(k: usize, j: usize) -> ValueRef {
    vr_satellite_output(SATELLITE_OUTPUTS.len() + (k - 1) * PANEL_OUTPUTS.len() + j)
}

/// The locked structure's output, after the per-panel outputs (name, unit, description).
pub const LOCKED_FREQUENCY_OUTPUT: (&str, Option<&str>, &str) = (
    "locked_frequency",
    Some("Hz"),
    "Lowest undamped natural frequency of the locked array linearized about its static equilibrium (the model's own masses and stiffnesses: the latches' contact stiffness at their preload, the springs, the panels' modes, the joints), computed once when the last hinge locks (a latch never releases). 0 before every hinge has locked, without latches, and when no equilibrium is found (free-floating satellite; the log says why).",
);

/// Value reference of `locked_frequency` (after the last panel's outputs).
pub fn vr_locked_frequency() -> ValueRef {
    vr_panel(MAX_PANELS, PANEL_OUTPUTS.len() - 1) + 1
}

/// Integer value references.
pub mod ivr {
    use super::ValueRef;
    pub const N_PANELS: ValueRef = 0;
    pub const INTEGRATOR: ValueRef = 1;
    pub const CONTACT_LAW: ValueRef = 2;
    pub const STEPS: ValueRef = 3;
    pub const REJECTED: ValueRef = 4;
    pub const NEWTON: ValueRef = 5;
    pub const FACTORIZATIONS: ValueRef = 6;
    pub const N_MODES: ValueRef = 7;
    pub const LOAD_FRAME: ValueRef = 8;
    /// `integrator_number`, the Integer twin of `integrator` ([`crate::scene::choice`]).
    pub const INTEGRATOR_NUMBER: ValueRef = 9;
    /// `contact_law_number`, the Integer twin of `contact_law`.
    pub const CONTACT_LAW_NUMBER: ValueRef = 10;
    /// `load_frame_number`, the Integer twin of `load_frame`.
    pub const LOAD_FRAME_NUMBER: ValueRef = 11;
    /// `solver_integrator`: the integrator item the run uses (`auto` resolved).
    pub const INTEGRATOR_USED: ValueRef = 12;
}

/// Boolean value references (hinge `k` latched: `LATCHED0 + k`).
pub mod bvr {
    use super::ValueRef;
    pub const LATCHES: ValueRef = 0;
    pub const CABLE_LOOP: ValueRef = 1;
    pub const GRAVITY_ON: ValueRef = 2;
    pub const FREE_SATELLITE: ValueRef = 3;
    pub const LATCHED0: ValueRef = 4;
    /// After the latched outputs of [`super::MAX_HINGES`] hinges.
    pub const FLEXIBLE_PANELS: ValueRef = LATCHED0 + super::MAX_HINGES as ValueRef;
}

/// Integrator enumeration items (1-based): [`IntegratorKind::ALL`] in order, then the
/// joint-coordinate DOPRI5 ([`IntegratorKind::Dopri5Tree`], PanelLock only: the rigid array on a
/// fixed satellite is a tree).
pub static INTEGRATORS: &[(&str, &str)] = &[
    (
        "gen_alpha",
        "Generalized-alpha, index 3, adaptive (rho_inf 0.8)",
    ),
    (
        "bdf",
        "Variable-order BDF 1-5 on the stabilized index-2 form",
    ),
    (
        "dopri5",
        "Dormand-Prince 5(4), index 1 with projection (non-stiff scenes)",
    ),
    (
        "dopri5_tree",
        "Dormand-Prince 5(4) in joint coordinates (rigid panels on a fixed satellite; refused otherwise)",
    ),
    (
        "auto",
        "dopri5_tree for rigid panels on a fixed satellite, gen_alpha otherwise (rtol = 0 / atol = 0 then take that integrator's defaults)",
    ),
];

/// Contact-law enumeration items (1-based).
pub static CONTACT_LAWS: &[(&str, &str)] = &[
    ("hertz", "Hertz, F = k delta^n (elastic)"),
    (
        "lankarani_nikravesh",
        "Lankarani-Nikravesh hysteresis damping (the paper's)",
    ),
    ("hunt_crossley", "Hunt-Crossley damping"),
    ("flores", "Flores damping (valid for low restitution)"),
];

/// Load-frame enumeration items (1-based), in [`LoadFrame`] order.
pub static LOAD_FRAMES: &[(&str, &str)] = &[
    (
        "world",
        "Satellite force and torque components along the world axes",
    ),
    (
        "body",
        "Satellite force and torque components along the satellite body axes (turning with it)",
    ),
];

/// Load frame from its enumeration item number.
pub fn load_frame_of(code: i32) -> LoadFrame {
    if code == 1 {
        LoadFrame::World
    } else {
        LoadFrame::Body
    }
}

/// Enumeration item number (1-based) of a load frame.
pub fn load_frame_code(frame: LoadFrame) -> i32 {
    match frame {
        LoadFrame::World => 1,
        LoadFrame::Body => 2,
    }
}

/// Integrator from its enumeration item number (`None`: `auto`, the last item).
/// (RopeBlock's enumeration ends at 3, so its port refuses 4, PanelLock's `dopri5_tree`.)
pub fn integrator_of(code: i32) -> Option<IntegratorKind> {
    ENUMERATED_INTEGRATORS
        .get((code.clamp(1, INTEGRATORS.len() as i32) - 1) as usize)
        .copied()
}

/// Enumeration item number (1-based) of an integrator choice (`None`: `auto`; 0: not in the
/// enumeration).
pub fn integrator_code(kind: Option<IntegratorKind>) -> i32 {
    match kind {
        None => INTEGRATORS.len() as i32,
        Some(kind) => ENUMERATED_INTEGRATORS
            .iter()
            .position(|k| *k == kind)
            .map_or(0, |i| i as i32 + 1),
    }
}

/// The parameter's spelling of an integrator (its enumeration item name, e.g. `gen_alpha`).
pub fn integrator_name(kind: IntegratorKind) -> &'static str {
    match integrator_code(Some(kind)) {
        0 => kind.name(),
        c => INTEGRATORS[c as usize - 1].0,
    }
}

/// The kinds of [`INTEGRATORS`], item by item, before `auto`.
const ENUMERATED_INTEGRATORS: [IntegratorKind; 4] = [
    IntegratorKind::ALL[0],
    IntegratorKind::ALL[1],
    IntegratorKind::ALL[2],
    IntegratorKind::Dopri5Tree,
];

/// Enumeration item number (1-based) of a contact law.
pub fn law_code(law: LawKind) -> i32 {
    LawKind::ALL
        .iter()
        .position(|k| *k == law)
        .map_or(0, |i| i as i32 + 1)
}

/// Contact law from its enumeration item number.
pub fn law_of(code: i32) -> LawKind {
    [
        LawKind::Hertz,
        LawKind::LankaraniNikravesh,
        LawKind::HuntCrossley,
        LawKind::Flores,
    ][(code.clamp(1, 4) - 1) as usize]
}

fn integer(
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

/// The model's static description.
pub fn info() -> &'static ModelInfo {
    static INFO: OnceLock<ModelInfo> = OnceLock::new();
    INFO.get_or_init(|| {
        let d = PanelLockParams::default();
        let mut ports = vec![
            integer("n_panels", ivr::N_PANELS, Causality::Parameter, Variability::Fixed, PortType::Integer { start: Some(d.n_panels as i32), min: Some(1), max: Some(6) }, "Number of panels outboard of the yoke (structure)."),
            integer("integrator", ivr::INTEGRATOR, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "Integrator", items: INTEGRATORS, start: Some(integrator_code(d.integrator)) }, "Time integrator."),
            choice::number_twin("integrator", INTEGRATORS, ivr::INTEGRATOR_NUMBER),
            integer("contact_law", ivr::CONTACT_LAW, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "ContactLaw", items: CONTACT_LAWS, start: Some(law_code(d.contact_law)) }, "Pin/groove contact force law."),
            choice::number_twin("contact_law", CONTACT_LAWS, ivr::CONTACT_LAW_NUMBER),
        ];
        for (vr, (name, start, desc)) in [
            (bvr::FLEXIBLE_PANELS, ("flexible_panels", d.flexible_panels, "Flexible panels: modal bodies from a plate FE model reduced by Craig-Bampton at the hinge nodes (structure); off: rigid panels.")),
            (bvr::LATCHES, ("latches", d.latches, "Latch (pin and groove) at every hinge.")),
            (bvr::CABLE_LOOP, ("cable_loop", d.cable_loop, "Closed cable loops synchronizing consecutive hinges.")),
            (bvr::GRAVITY_ON, ("gravity_on", d.gravity.is_some(), "Gravity along -z (ground test with vertical hinge axes); off in orbit.")),
            (bvr::FREE_SATELLITE, ("free_satellite", d.free_satellite, "Free-floating satellite (else fixed to the inertial frame).")),
        ] {
            ports.push(PortSpec::boolean_parameter(name, vr, Variability::Fixed, start, desc));
        }
        ports.push(integer("load_frame", ivr::LOAD_FRAME, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "LoadFrame", items: LOAD_FRAMES, start: Some(load_frame_code(d.load_frame)) }, "Frame of the satellite_force_* and satellite_torque_* inputs: world or satellite body axes."));
        ports.push(choice::number_twin("load_frame", LOAD_FRAMES, ivr::LOAD_FRAME_NUMBER));
        ports.push(integer("n_modes", ivr::N_MODES, Causality::Parameter, Variability::Fixed, PortType::Integer { start: Some(d.n_modes as i32), min: Some(0), max: Some(400) }, "Craig-Bampton modes per flexible panel (structure); 0 with flexible panels takes 10, the paper configuration's count; must be 0 with rigid panels."));
        for (i, p) in REAL_PARAMS.iter().enumerate() {
            ports.push(p.port(i as ValueRef, &d));
        }
        ports.push(PortSpec::real_input("root_motor_torque", vr_motor(), 0.0, Some("N.m"), "Root hinge motor torque (positive deploys), held over each step."));
        for (j, (name, unit, desc)) in SATELLITE_LOAD_INPUTS.iter().enumerate() {
            ports.push(PortSpec::real_input(name, vr_satellite_load(j), 0.0, Some(*unit), desc));
        }
        for k in 0..MAX_HINGES {
            for (j, (name, unit, desc)) in HINGE_OUTPUTS.iter().enumerate() {
                ports.push(PortSpec::real_output(&format!("hinge{k}_{name}"), vr_hinge(k, j), *unit, &format!("Hinge {k} (0 = root): {desc} Zero for hinges the array does not have.")));
            }
            ports.push(PortSpec::boolean_output(&format!("hinge{k}_latched"), bvr::LATCHED0 + k as ValueRef, &format!("Hinge {k}: the latch pin has dropped into the groove.")));
        }
        for (j, (name, unit, desc)) in GLOBAL_OUTPUTS.iter().enumerate() {
            ports.push(PortSpec::real_output(name, vr_global(j), *unit, desc));
        }
        for (j, (name, unit, desc)) in SATELLITE_OUTPUTS.iter().enumerate() {
            ports.push(PortSpec::real_output(name, vr_satellite_output(j), *unit, desc));
        }
        for k in 1..=MAX_PANELS {
            for (j, (name, unit, desc)) in PANEL_OUTPUTS.iter().enumerate() {
                ports.push(PortSpec::real_output(&format!("panel{k}_{name}"), vr_panel(k, j), *unit, &format!("Panel {k} (1 = innermost): {desc} Zero with rigid panels, for panels the array does not have and for modes beyond n_modes.")));
            }
        }
        let (name, unit, desc) = LOCKED_FREQUENCY_OUTPUT;
        ports.push(PortSpec::real_output(name, vr_locked_frequency(), unit, desc));
        for (vr, name, desc) in [
            (ivr::STEPS, "solver_steps", "Accepted integrator steps since the start."),
            (ivr::REJECTED, "solver_rejected_steps", "Rejected integrator steps since the start."),
            (ivr::NEWTON, "solver_newton_iterations", "Newton iterations since the start."),
            (ivr::FACTORIZATIONS, "solver_factorizations", "LU factorizations since the start."),
            (ivr::INTEGRATOR_USED, "solver_integrator", "The integrator the run uses, as its `integrator` item number (1 gen_alpha, 2 bdf, 3 dopri5, 4 dopri5_tree): with `integrator = auto` the one it resolved to."),
        ] {
            ports.push(integer(name, vr, Causality::Output, Variability::Discrete, PortType::Integer { start: None, min: None, max: None }, desc));
        }
        ModelInfo {
            identifier: IDENTIFIER,
            guid: "{0d731b86-81f5-4830-8d8c-4a13aed89c98}",
            description: "Deployment and lock-up of a solar array: yoke and panels joined by hinge bodies with preloaded torsion springs, pin/groove latches with a selectable contact law, stow stops, optional cable loops; rigid panels or flexible (Craig-Bampton modal) panels.",
            ports,
            default_stop_time: 60.0,
            default_step: 0.01,
            initial_dependencies: super::dependencies::initial_dependencies,
        }
    })
}
