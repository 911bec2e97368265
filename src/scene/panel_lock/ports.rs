//! The PanelLock variable table: parameters (mapped onto [`PanelLockParams`]), the motor input and
//! the outputs, with value references by base type.

use super::params::PanelLockParams;
use crate::contact::LawKind;
use crate::integrator::IntegratorKind;
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType, ValueRef, Variability};
use std::sync::OnceLock;

/// Model identifier.
pub const IDENTIFIER: &str = "PanelLock";
/// Largest number of hinges the outputs cover (6 panels plus the root hinge).
pub const MAX_HINGES: usize = 7;

/// A real parameter: its port and how it maps onto the scene parameters.
pub struct RealParam {
    pub name: &'static str,
    pub unit: Option<&'static str>,
    pub description: &'static str,
    pub get: fn(&PanelLockParams) -> f64,
    pub set: fn(&mut PanelLockParams, f64),
    /// Unit shown in the documentation where none can be declared.
    pub unit_note: Option<&'static str>,
}

macro_rules! real_param {
    ($name:literal, $field:ident, $unit:expr, $desc:literal) => {
        real_param!($name, $field, $unit, None, $desc)
    };
    ($name:literal, $field:ident, $unit:expr, $note:expr, $desc:literal) => {
        RealParam {
            name: $name,
            unit: $unit,
            description: $desc,
            get: |p| p.$field,
            set: |p, v| p.$field = v,
            unit_note: $note,
        }
    };
}

/// Real parameters, value references 0.. in this order.
pub static REAL_PARAMS: &[RealParam] = &[
    real_param!(
        "panel_length",
        panel_length,
        Some("m"),
        "Panel length along the deployment direction."
    ),
    real_param!(
        "panel_width",
        panel_width,
        Some("m"),
        "Panel width along the hinge axis."
    ),
    real_param!(
        "panel_areal_density",
        panel_areal_density,
        Some("kg/m2"),
        "Panel mass per area (honeycomb with cells)."
    ),
    real_param!(
        "panel_thickness",
        panel_thickness,
        Some("m"),
        "Panel thickness (for its inertia)."
    ),
    real_param!(
        "yoke_length",
        yoke_length,
        Some("m"),
        "Yoke length from root hinge to first panel hinge."
    ),
    real_param!("yoke_mass", yoke_mass, Some("kg"), "Yoke mass."),
    real_param!(
        "hinge_mass",
        hinge_mass,
        Some("kg"),
        "Mass of each hinge body."
    ),
    real_param!(
        "hinge_gyration_radius",
        hinge_gyration_radius,
        Some("m"),
        "Radius of gyration of each hinge body."
    ),
    real_param!(
        "root_spring_preload",
        root_spring_preload,
        Some("N.m"),
        "Root deployment spring torque at the lock angle."
    ),
    real_param!(
        "root_spring_stiffness",
        root_spring_stiffness,
        Some("N.m/rad"),
        "Root deployment spring stiffness."
    ),
    real_param!(
        "panel_spring_preload",
        panel_spring_preload,
        Some("N.m"),
        "Panel-hinge deployment spring torque at the lock angle."
    ),
    real_param!(
        "panel_spring_stiffness",
        panel_spring_stiffness,
        Some("N.m/rad"),
        "Panel-hinge deployment spring stiffness."
    ),
    real_param!(
        "hinge_damping",
        hinge_damping,
        Some("N.m.s/rad"),
        "Viscous damping of every hinge shaft."
    ),
    real_param!(
        "root_lock_angle",
        root_lock_angle,
        Some("rad"),
        "Root hinge deployment angle at lock-up; more than 0.2 rad above root_stowed_angle, and less than pi rad above it."
    ),
    real_param!(
        "panel_lock_angle",
        panel_lock_angle,
        Some("rad"),
        "Panel hinge deployment angle at lock-up; more than 0.2 rad above panel_stowed_angle, and less than pi rad above it."
    ),
    real_param!(
        "root_stowed_angle",
        root_stowed_angle,
        Some("rad"),
        "Root hinge angle when stowed (t = 0); below root_lock_angle - 0.2 rad."
    ),
    real_param!(
        "panel_stowed_angle",
        panel_stowed_angle,
        Some("rad"),
        "Panel hinge angle when stowed (t = 0); below panel_lock_angle - 0.2 rad."
    ),
    real_param!(
        "stop_stiffness",
        stop_stiffness,
        Some("N.m/rad"),
        "Stiffness of the stow stops (folded stack on its snubbers)."
    ),
    real_param!(
        "stop_damping",
        stop_damping,
        Some("N.m.s/rad"),
        "Damping of the stow stops."
    ),
    real_param!(
        "cam_radius",
        cam_radius,
        Some("m"),
        "Latch cam radius; larger than groove_depth + groove_width / 2 (with latches)."
    ),
    real_param!(
        "groove_width",
        groove_width,
        Some("m"),
        "Latch groove width; at least 2 pin_radius (with latches)."
    ),
    real_param!(
        "groove_depth",
        groove_depth,
        Some("m"),
        "Latch groove depth; at least pin_radius, below cam_radius (with latches)."
    ),
    real_param!("pin_radius", pin_radius, Some("m"), "Latch pin radius."),
    real_param!(
        "contact_stiffness",
        contact_stiffness,
        None,
        Some("N/m^n"),
        "Pin/groove contact stiffness k in N/m^n with n = contact_exponent (F = k delta^n ...); no unit is declared because its dimension depends on n."
    ),
    real_param!(
        "contact_exponent",
        contact_exponent,
        None,
        "Contact force exponent n (1.5 for metals)."
    ),
    real_param!(
        "restitution",
        restitution,
        None,
        "Coefficient of restitution of the damped contact laws, in (0, 1]."
    ),
    real_param!(
        "cable_stiffness",
        cable_stiffness,
        Some("N.m/rad"),
        "Closed cable loop stiffness (per rad of the inboard hinge); > 0 with cable_loop."
    ),
    real_param!(
        "cable_damping",
        cable_damping,
        Some("N.m.s/rad"),
        "Closed cable loop damping."
    ),
    real_param!(
        "satellite_mass",
        satellite_mass,
        Some("kg"),
        "Satellite mass (free-floating satellite only)."
    ),
    RealParam {
        name: "gravity",
        unit: Some("m/s2"),
        description: "Gravity along -z (the hinge axes) when gravity_on.",
        get: |p| p.gravity.unwrap_or(9.81),
        set: |p, v| p.gravity = p.gravity.map(|_| v),
        unit_note: None,
    },
    real_param!(
        "modal_damping_ratio",
        modal_damping_ratio,
        None,
        "Modal damping ratio of the flexible panels' modes (flexible_panels only)."
    ),
    real_param!(
        "panel_youngs_modulus",
        panel_youngs_modulus,
        Some("Pa"),
        "Equivalent Young's modulus of the honeycomb panel plate (flexible_panels only)."
    ),
    real_param!(
        "panel_poisson",
        panel_poisson,
        None,
        "Equivalent Poisson ratio of the panel plate (flexible_panels only)."
    ),
    real_param!(
        "panel_nonstructural_mass",
        panel_nonstructural_mass,
        Some("kg/m2"),
        "Non-structural areal mass (cells, harness), part of panel_areal_density and below it (flexible_panels only)."
    ),
    RealParam {
        name: "rtol",
        unit: None,
        description: "Relative error tolerance of the adaptive integrators: held per second of simulated time with rigid panels, per step with flexible panels.",
        get: |p| p.settings.rtol,
        set: |p, v| p.settings.rtol = v,
        unit_note: None,
    },
    RealParam {
        name: "atol",
        unit: None,
        description: "Absolute error tolerance of the integrator (m, rad, m/s, rad/s).",
        get: |p| p.settings.atol,
        set: |p, v| p.settings.atol = v,
        unit_note: Some("m, rad, m/s, rad/s"),
    },
    RealParam {
        name: "h_max",
        unit: Some("s"),
        description: "Largest internal step.",
        get: |p| p.settings.h_max,
        set: |p, v| p.settings.h_max = v,
        unit_note: None,
    },
];

/// Value reference of the motor-torque input (after the real parameters).
pub fn vr_motor() -> ValueRef {
    REAL_PARAMS.len() as ValueRef
}

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
pub const GLOBAL_OUTPUTS: [(&str, Option<&str>, &str); 11] = [
    (
        "root_force_x",
        Some("N"),
        "Root hinge shaft constraint force on the root hinge body, world x.",
    ),
    (
        "root_force_y",
        Some("N"),
        "Root hinge shaft constraint force, world y.",
    ),
    (
        "root_force_z",
        Some("N"),
        "Root hinge shaft constraint force, world z.",
    ),
    (
        "root_torque_x",
        Some("N.m"),
        "Root hinge shaft constraint torque about the hinge point, world x.",
    ),
    (
        "root_torque_y",
        Some("N.m"),
        "Root hinge shaft constraint torque, world y.",
    ),
    (
        "root_torque_z",
        Some("N.m"),
        "Root hinge shaft constraint torque, world z (axial part: 0, carried by spring/latch/motor).",
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
];

/// Value reference of hinge `k`'s output `j` (index into [`HINGE_OUTPUTS`]).
pub fn vr_hinge(k: usize, j: usize) -> ValueRef {
    (REAL_PARAMS.len() + 1 + k * HINGE_OUTPUTS.len() + j) as ValueRef
}

/// Value reference of global output `j`.
pub fn vr_global(j: usize) -> ValueRef {
    (REAL_PARAMS.len() + 1 + MAX_HINGES * HINGE_OUTPUTS.len() + j) as ValueRef
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

/// Integrator enumeration items (1-based), in [`IntegratorKind::ALL`] order.
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

/// Integrator from its enumeration item number.
pub fn integrator_of(code: i32) -> IntegratorKind {
    IntegratorKind::ALL[(code.clamp(1, 3) - 1) as usize]
}

/// Enumeration item number (1-based) of an integrator.
pub fn integrator_code(kind: IntegratorKind) -> i32 {
    IntegratorKind::ALL
        .iter()
        .position(|k| *k == kind)
        .map_or(0, |i| i as i32 + 1)
}

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
        let mut ports = Vec::new();
        ports.push(integer("n_panels", ivr::N_PANELS, Causality::Parameter, Variability::Fixed, PortType::Integer { start: Some(d.n_panels as i32), min: Some(1), max: Some(6) }, "Number of panels outboard of the yoke (structure)."));
        ports.push(integer("integrator", ivr::INTEGRATOR, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "Integrator", items: INTEGRATORS, start: Some(integrator_code(d.integrator)) }, "Time integrator."));
        ports.push(integer("contact_law", ivr::CONTACT_LAW, Causality::Parameter, Variability::Fixed, PortType::Enumeration { type_name: "ContactLaw", items: CONTACT_LAWS, start: Some(law_code(d.contact_law)) }, "Pin/groove contact force law."));
        for (vr, (name, start, desc)) in [
            (bvr::FLEXIBLE_PANELS, ("flexible_panels", d.flexible_panels, "Flexible panels: modal bodies from a plate FE model reduced by Craig-Bampton at the hinge nodes (structure); off: rigid panels.")),
            (bvr::LATCHES, ("latches", d.latches, "Latch (pin and groove) at every hinge.")),
            (bvr::CABLE_LOOP, ("cable_loop", d.cable_loop, "Closed cable loops synchronizing consecutive hinges.")),
            (bvr::GRAVITY_ON, ("gravity_on", d.gravity.is_some(), "Gravity along -z (ground test with vertical hinge axes); off in orbit.")),
            (bvr::FREE_SATELLITE, ("free_satellite", d.free_satellite, "Free-floating satellite (else fixed to the inertial frame).")),
        ] {
            ports.push(PortSpec::boolean_parameter(name, vr, Variability::Fixed, start, desc));
        }
        ports.push(integer("n_modes", ivr::N_MODES, Causality::Parameter, Variability::Fixed, PortType::Integer { start: Some(d.n_modes as i32), min: Some(0), max: Some(400) }, "Craig-Bampton modes per flexible panel (structure); must be 0 with rigid panels."));
        for (i, p) in REAL_PARAMS.iter().enumerate() {
            let mut spec = PortSpec::real_parameter(p.name, i as ValueRef, Variability::Fixed, (p.get)(&d), p.unit, p.description);
            // the range the validation accepts (tests/declared_ranges.rs keeps them equal)
            if let Some(r) = super::params::declared_range(p.name) {
                if let Some(lo) = r.min {
                    spec = if r.open[0] { spec.with_open_min(lo) } else { spec.with_min(lo) };
                }
                if let Some(hi) = r.max {
                    spec = if r.open[1] { spec.with_open_max(hi) } else { spec.with_max(hi) };
                }
            }
            if let Some(note) = p.unit_note {
                spec = spec.with_unit_note(note);
            }
            ports.push(spec);
        }
        ports.push(PortSpec::real_input("root_motor_torque", vr_motor(), 0.0, Some("N.m"), "Root hinge motor torque (positive deploys), held over each step."));
        for k in 0..MAX_HINGES {
            for (j, (name, unit, desc)) in HINGE_OUTPUTS.iter().enumerate() {
                ports.push(PortSpec::real_output(&format!("hinge{k}_{name}"), vr_hinge(k, j), *unit, &format!("Hinge {k} (0 = root): {desc} Zero for hinges the array does not have.")));
            }
            ports.push(PortSpec::boolean_output(&format!("hinge{k}_latched"), bvr::LATCHED0 + k as ValueRef, &format!("Hinge {k}: the latch pin has dropped into the groove.")));
        }
        for (j, (name, unit, desc)) in GLOBAL_OUTPUTS.iter().enumerate() {
            ports.push(PortSpec::real_output(name, vr_global(j), *unit, desc));
        }
        for (vr, name, desc) in [
            (ivr::STEPS, "solver_steps", "Accepted integrator steps since the start."),
            (ivr::REJECTED, "solver_rejected_steps", "Rejected integrator steps since the start."),
            (ivr::NEWTON, "solver_newton_iterations", "Newton iterations since the start."),
            (ivr::FACTORIZATIONS, "solver_factorizations", "LU factorizations since the start."),
        ] {
            ports.push(integer(name, vr, Causality::Output, Variability::Discrete, PortType::Integer { start: None, min: None, max: None }, desc));
        }
        ModelInfo {
            identifier: IDENTIFIER,
            guid: "{b23179b7-19ab-46b9-96cf-06a74d2ce729}",
            description: "Deployment and lock-up of a solar array: yoke and panels joined by hinge bodies with preloaded torsion springs, pin/groove latches with a selectable contact law, stow stops, optional cable loops; rigid panels or flexible (Craig-Bampton modal) panels.",
            ports,
            default_stop_time: 60.0,
            default_step: 0.01,
            initial_dependencies: super::dependencies::initial_dependencies,
        }
    })
}
