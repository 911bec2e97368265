//! Parameters of the PanelLock scene, with their defaults and validation.

use crate::contact::LawKind;
pub use crate::effect::body_load::LoadFrame;
use crate::integrator::{IntegratorKind, Settings};
pub use crate::scene::param_spec::ENVELOPE_DECADES;
use crate::scene::param_spec::{Bounds, Range, SolverKnobs, find};

/// How a flexible panel's finite-element model is reduced to modal coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reduction {
    /// Craig-Bampton: body frame clamped at the inboard hinge node; the outboard hinge node's
    /// three DOFs (w, theta_x, theta_y) as interface coordinates (inner panels), plus `n_modes`
    /// fixed-interface modes.
    CraigBampton,
    /// The first `n_modes` elastic free-free modes (mean-axis frame).
    FreeInterface,
}

/// Over what the adaptive integrators hold their local error tolerance (sets
/// [`Settings::error_per_unit_step`] when the scene is built, [`PanelLockParams::solver_settings`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ErrorControl {
    /// Per unit step with rigid panels, per step with flexible ones: per step, an impact and the
    /// deployment before it accumulate the error of every step (generalized-alpha at rtol 1e-3:
    /// 1.4 % on the rigid scene's peak lock force, against 0.07 % per unit step); per unit step,
    /// the flexible panels' modal transient at t = 0 costs thousands of steps in the first
    /// half second (BDF rtol 1e-4: 5,865 to 0.5 s, against 7,000-8,000 per step for 65 s)
    /// (docs/panel_lock_defaults.md).
    #[default]
    ByPanels,
    /// The whole tolerance for every step.
    PerStep,
    /// The tolerance per second of simulated time, shared among the steps.
    PerUnitStep,
}

/// Everything that defines a PanelLock run. SI units; angles in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelLockParams {
    /// Number of panels outboard of the yoke (1..=6).
    pub n_panels: usize,
    /// Panel length along the deployment direction [m], width along the hinge axis [m],
    /// areal density [kg/m^2] and thickness [m].
    pub panel_length: f64,
    pub panel_width: f64,
    pub panel_areal_density: f64,
    pub panel_thickness: f64,
    /// Yoke (the frame between satellite and first panel): length [m] and mass [kg].
    pub yoke_length: f64,
    pub yoke_mass: f64,
    /// Mass of each hinge body [kg] and its radius of gyration about any axis [m].
    pub hinge_mass: f64,
    pub hinge_gyration_radius: f64,
    /// Deployment springs: torque at the lock angle (preload) [N m] and stiffness [N m/rad], for
    /// the root hinge and for the panel hinges.
    pub root_spring_preload: f64,
    pub root_spring_stiffness: f64,
    pub panel_spring_preload: f64,
    pub panel_spring_stiffness: f64,
    /// Viscous hinge damping [N m s/rad] (friction of the hinge shaft); the effect is off at 0.
    pub hinge_damping: f64,
    /// Coulomb friction torque of every hinge shaft [N m] (`crate::effect::hinge_friction`,
    /// regularized over a slip rate of 1e-4 rad/s); the effect is assembled only when some hinge
    /// has friction.
    pub hinge_friction_torque: f64,
    /// Per-hinge values over the globals (scene-file `[[hinge]]` tables, hinge 0 = root first;
    /// hinges beyond them use the globals), see [`super::array`].
    pub hinge_tables: Vec<super::array::HingeTable>,
    /// Per-panel values over the globals (scene-file `[[panel]]` tables, panel 1 first).
    pub panel_tables: Vec<super::array::PanelTable>,
    /// Lock angles [rad]: root hinge and panel hinges (deployment angle at the groove centre).
    pub root_lock_angle: f64,
    pub panel_lock_angle: f64,
    /// Stowed angles [rad] (deployment angle at t = 0).
    pub root_stowed_angle: f64,
    pub panel_stowed_angle: f64,
    /// Latch: cam radius, groove width and depth, pin radius [m].
    pub cam_radius: f64,
    pub groove_width: f64,
    pub groove_depth: f64,
    pub pin_radius: f64,
    /// Stow stops (the folded stack resting on its snubbers): stiffness [N m/rad] and damping
    /// [N m s/rad] of a unilateral stop at each hinge's stowed angle.
    pub stop_stiffness: f64,
    pub stop_damping: f64,
    /// Whether each hinge has a latch (an effect switch for the whole array).
    pub latches: bool,
    /// Contact law of the pin/groove walls, stiffness [N/m^n], exponent n, restitution e.
    pub contact_law: LawKind,
    pub contact_stiffness: f64,
    pub contact_exponent: f64,
    pub restitution: f64,
    /// Closed cable loops between consecutive hinges (effect switch), their stiffness
    /// [N m/rad] and damping [N m s/rad].
    pub cable_loop: bool,
    pub cable_stiffness: f64,
    pub cable_damping: f64,
    /// Gravity along -z (the hinge axes, as in a ground test with vertical hinges) [m/s^2]; off when
    /// `None` (orbit).
    pub gravity: Option<f64>,
    /// Free-floating satellite (else fixed to the inertial frame), its mass [kg] and inertia
    /// (principal moments about its centre of mass along the satellite body axes x, y, z,
    /// [kg m^2]; each at most the sum of the other two).
    pub free_satellite: bool,
    pub satellite_mass: f64,
    pub satellite_inertia: [f64; 3],
    /// Satellite centre of mass relative to the root-hinge attachment point, in the satellite
    /// body frame [m] (parallel to the world frame at t = 0; see docs/panel_lock_satellite.md).
    /// The default puts it 1 m behind the root hinge, on the side away from the array.
    pub satellite_cg: [f64; 3],
    /// Frame of the satellite force and torque inputs (free satellite only).
    pub load_frame: LoadFrame,
    /// Flexible panels (structural switch): each panel is a modal body from a plate FE model,
    /// reduced by [`PanelLockParams::reduction`] to `n_modes` modes, hinge frames riding on the
    /// attachment nodes (mid-width of the inboard and outboard edges). Off: rigid panels and no
    /// modal coordinates at all.
    pub flexible_panels: bool,
    /// Number of (fixed-interface or free-free) modes per panel; 0 when `flexible_panels` is off.
    pub n_modes: usize,
    /// Equivalent homogeneous plate of the honeycomb sandwich: Young's modulus [Pa] (giving its
    /// bending rigidity over `panel_thickness`) and Poisson ratio [-].
    pub panel_youngs_modulus: f64,
    pub panel_poisson: f64,
    /// Non-structural areal mass (cells, harness) [kg/m^2], part of `panel_areal_density`; the
    /// equivalent structural density is `(panel_areal_density - this) / panel_thickness`.
    pub panel_nonstructural_mass: f64,
    /// Plate mesh: elements along the length and along the width (even, so that the hinge
    /// attachment nodes sit at mid-width).
    pub panel_mesh: [usize; 2],
    /// Modal damping ratio of the panel modes [-].
    pub modal_damping_ratio: f64,
    /// Reduction method of the flexible panels.
    pub reduction: Reduction,
    /// Integrator (`None`: `integrator = auto`, resolved by [`PanelLockParams::integrator_kind`])
    /// and its settings (`settings.error_per_unit_step` is replaced by what `error_control` says,
    /// and `rtol` / `atol` of 0 by the integrator's own [`default_tolerances`], when the scene is
    /// built: [`PanelLockParams::solver_settings`]).
    pub integrator: Option<IntegratorKind>,
    pub settings: Settings,
    pub error_control: ErrorControl,
}

impl SolverKnobs for PanelLockParams {
    fn knobs(&self) -> [f64; 3] {
        [self.settings.rtol, self.settings.atol, self.settings.h_max]
    }

    fn knobs_mut(&mut self) -> [&mut f64; 3] {
        let s = &mut self.settings;
        [&mut s.rtol, &mut s.atol, &mut s.h_max]
    }
}

impl Default for PanelLockParams {
    fn default() -> Self {
        PanelLockParams {
            n_panels: 3,
            panel_length: 2.0,
            panel_width: 1.5,
            panel_areal_density: 1.5,
            panel_thickness: 0.025,
            yoke_length: 1.0,
            yoke_mass: 2.0,
            hinge_mass: 0.3,
            hinge_gyration_radius: 0.03,
            root_spring_preload: 0.6,
            root_spring_stiffness: 0.1,
            panel_spring_preload: 0.4,
            panel_spring_stiffness: 0.05,
            hinge_damping: 0.02,
            hinge_friction_torque: 0.0,
            hinge_tables: Vec::new(),
            panel_tables: Vec::new(),
            root_lock_angle: std::f64::consts::FRAC_PI_2,
            panel_lock_angle: std::f64::consts::PI,
            root_stowed_angle: 0.0,
            panel_stowed_angle: 5f64.to_radians(),
            cam_radius: 0.03,
            groove_width: 0.012,
            groove_depth: 0.008,
            pin_radius: 0.005,
            stop_stiffness: 200.0,
            stop_damping: 2.0,
            latches: true,
            contact_law: LawKind::LankaraniNikravesh,
            contact_stiffness: 1e7,
            contact_exponent: 1.5,
            restitution: 0.8,
            cable_loop: false,
            cable_stiffness: 50.0,
            cable_damping: 0.5,
            gravity: None,
            free_satellite: false,
            satellite_mass: 800.0,
            satellite_inertia: [300.0, 350.0, 250.0],
            satellite_cg: [-1.0, 0.0, 0.0],
            load_frame: LoadFrame::Body,
            flexible_panels: false,
            n_modes: 0,
            panel_youngs_modulus: DEFAULT_PANEL_E,
            panel_poisson: 0.3,
            panel_nonstructural_mass: 0.6,
            panel_mesh: [8, 4],
            modal_damping_ratio: 0.005,
            reduction: Reduction::CraigBampton,
            // auto: dopri5_tree at rtol 1e-9 for rigid panels on a fixed satellite (every
            // hinge's peak within 1 % at any communication step, docs/auto_integrator.md),
            // generalized-alpha at rtol 1e-4 otherwise (the cheapest setting measured to hold the
            // peak lock force, the root lock time and the flexible panels' post-lock frequency
            // within 1 % with a margin of 5x or more, and to resolve the stiffest Table 1 latch,
            // k 1e8, n 0.9, where rtol 3e-4 does not: docs/panel_lock_defaults.md)
            integrator: None,
            settings: Settings {
                rtol: 0.0,
                atol: 0.0,
                h_max: 0.02,
                ..Settings::default()
            },
            error_control: ErrorControl::ByPanels,
        }
    }
}

/// Default relative and absolute error tolerances of generalized-alpha, BDF and DOPRI5 (absolute
/// in m, rad, m/s, rad/s): what `rtol = 0` / `atol = 0` mean with them.
pub const DEFAULT_RTOL: f64 = 1e-4;
pub const DEFAULT_ATOL: f64 = 1e-6;
/// Default relative and absolute error tolerances of the joint-coordinate pairs (dopri5_tree):
/// an explicit step there costs a tenth of an implicit one, and at 1e-9 every hinge's peak latch
/// force holds within 1 % at every communication step for about the CPU of generalized-alpha at
/// 1e-4 (docs/auto_integrator.md).
pub const TREE_RTOL: f64 = 1e-9;
pub const TREE_ATOL: f64 = 1e-11;

/// The tolerances `(rtol, atol)` an integrator runs with when `rtol` / `atol` are 0 (their start
/// values).
pub fn default_tolerances(kind: IntegratorKind) -> (f64, f64) {
    match kind {
        IntegratorKind::Dopri5Tree => (TREE_RTOL, TREE_ATOL),
        _ => (DEFAULT_RTOL, DEFAULT_ATOL),
    }
}

/// Default equivalent Young's modulus of the panel plate [Pa]; see the scene documentation.
pub const DEFAULT_PANEL_E: f64 = 3.0e9;
/// Cam radius of the paper configuration [m] ([`PanelLockParams::flexible`]).
pub const PAPER_CAM_RADIUS: f64 = 0.05;

/// Modes per flexible panel when the FMU's `n_modes` is left at 0 with `flexible_panels` on:
/// the paper configuration's count ([`PanelLockParams::flexible`] as docs/panel_lock_defaults.md
/// measured it), so that switching flexible panels on alone gives a working scene.
pub const DEFAULT_FLEX_MODES: usize = 10;

impl PanelLockParams {
    /// The paper configuration: the default array with flexible panels of `n_modes`
    /// Craig-Bampton modes each and zero-backlash latches (groove width = pin diameter) on a
    /// 50 mm cam, so that the locked array vibrates as a structure whose stiffness includes the
    /// preloaded pin/wall contact (see the scene documentation for the tuning).
    pub fn flexible(n_modes: usize) -> Self {
        let d = PanelLockParams::default();
        PanelLockParams {
            flexible_panels: true,
            n_modes,
            cam_radius: PAPER_CAM_RADIUS,
            groove_width: 2.0 * d.pin_radius,
            ..d
        }
    }

    /// Equivalent structural density of the panel plate [kg/m^3].
    pub fn panel_structural_density(&self) -> f64 {
        (self.panel_areal_density - self.panel_nonstructural_mass) / self.panel_thickness
    }

    /// Number of plate nodes of one panel.
    pub fn panel_nodes(&self) -> usize {
        (self.panel_mesh[0] + 1) * (self.panel_mesh[1] + 1)
    }

    /// Largest `n_modes` the panel mesh supports with the chosen reduction: the plate's DOFs
    /// (3 per node) less the clamped frame node and, with inner panels, the outboard interface
    /// node (Craig-Bampton), or less the 3 rigid-body modes (free-interface).
    pub fn max_modes(&self) -> usize {
        let dofs = 3 * self.panel_nodes();
        match self.reduction {
            Reduction::CraigBampton if self.n_panels > 1 => dofs - 6,
            Reduction::CraigBampton | Reduction::FreeInterface => dofs - 3,
        }
    }

    /// The flexible-panel checks (see [`PanelLockParams::validate`]).
    fn validate_flexible(&self) -> Result<(), String> {
        if !self.flexible_panels {
            if self.n_modes > 0 {
                return Err(format!(
                    "n_modes = {} requested but flexible_panels is off: rigid panels have no modes \
                     (switch flexible_panels on, or set n_modes = 0)",
                    self.n_modes
                ));
            }
            return Ok(());
        }
        if self.n_modes == 0 {
            return Err(
                "flexible_panels is on but n_modes is 0: request at least one mode per panel"
                    .into(),
            );
        }
        let e = self.panel_youngs_modulus;
        if !(e.is_finite() && e > 0.0) {
            return Err(format!(
                "panel_youngs_modulus must be finite and > 0, got {e}"
            ));
        }
        envelope(
            "panel_youngs_modulus",
            e,
            Self::default().panel_youngs_modulus,
            true,
        )?;
        if !(self.modal_damping_ratio.is_finite() && (0.0..1.0).contains(&self.modal_damping_ratio))
        {
            return Err(format!(
                "modal_damping_ratio must be in [0, 1), got {}",
                self.modal_damping_ratio
            ));
        }
        if !(self.panel_poisson.is_finite()
            && (MIN_PANEL_POISSON..=MAX_PANEL_POISSON).contains(&self.panel_poisson))
        {
            return Err(format!(
                "panel_poisson must be in [{MIN_PANEL_POISSON}, {MAX_PANEL_POISSON}] (the isotropic range (-1, 0.5) less 0.01 at each end, where the plate model degenerates), got {}",
                self.panel_poisson
            ));
        }
        let nsm = self.panel_nonstructural_mass;
        if !(nsm.is_finite() && nsm >= 0.0 && nsm < self.panel_areal_density) {
            return Err(format!(
                "panel_nonstructural_mass must be in [0, panel_areal_density = {}) kg/m^2 (the rest \
                 is the honeycomb's structural mass), got {nsm}",
                self.panel_areal_density
            ));
        }
        let [nx, ny] = self.panel_mesh;
        if !(1..=40).contains(&nx) || !(2..=40).contains(&ny) || ny % 2 != 0 {
            return Err(format!(
                "panel_mesh must be 1..=40 elements along the length and an even 2..=40 across \
                 the width (hinge nodes at mid-width), got {nx} x {ny}"
            ));
        }
        if self.n_modes > self.max_modes() {
            return Err(format!(
                "n_modes = {} exceeds the {} modes the {nx} x {ny} panel mesh has with {:?} \
                 reduction",
                self.n_modes,
                self.max_modes(),
                self.reduction
            ));
        }
        Ok(())
    }

    /// The latch geometry in the parameters' names (the latch itself checks the same in its
    /// symbols, `w_g`, `r_p`, ..., when it is built).
    fn validate_latch(&self) -> Result<(), String> {
        let (r_c, w_g, d_g, r_p) = (
            self.cam_radius,
            self.groove_width,
            self.groove_depth,
            self.pin_radius,
        );
        if w_g < 2.0 * r_p {
            return Err(format!(
                "groove_width = {w_g} m must be >= 2 pin_radius = {} m (the pin must fit into the groove)",
                2.0 * r_p
            ));
        }
        if d_g < r_p {
            return Err(format!(
                "groove_depth = {d_g} m must be >= pin_radius = {r_p} m (a shallower groove lets the walls cam the pin out)"
            ));
        }
        if d_g >= r_c {
            return Err(format!(
                "groove_depth = {d_g} m must be < cam_radius = {r_c} m"
            ));
        }
        if 0.5 * w_g >= r_c - d_g {
            return Err(format!(
                "groove_width = {w_g} m must be < 2 (cam_radius - groove_depth) = {} m (a groove narrow compared with its floor radius)",
                2.0 * (r_c - d_g)
            ));
        }
        Ok(())
    }

    /// Number of hinges (root hinge plus one per panel).
    pub fn n_hinges(&self) -> usize {
        self.n_panels + 1
    }

    /// Mass of one panel [kg].
    pub fn panel_mass(&self) -> f64 {
        self.panel_areal_density * self.panel_length * self.panel_width
    }

    /// `(name, value, default)` of the parameters declared [`Bounds::Positive`] (`positive`)
    /// or [`Bounds::NonNegative`], in declaration order.
    fn envelope_values(&self, positive: bool) -> Vec<(&'static str, f64, f64)> {
        let d = Self::default();
        super::ports::REAL_PARAMS
            .iter()
            .filter(|s| match s.bounds {
                Bounds::Positive { .. } => positive,
                Bounds::NonNegative { .. } => !positive,
                Bounds::Fixed(_) => false,
            })
            .map(|s| (s.name, (s.get)(self), (s.get)(&d)))
            .collect()
    }

    /// Checks every value; `Err` names the parameter and the accepted range.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=6).contains(&self.n_panels) {
            return Err(format!("n_panels must be 1..=6, got {}", self.n_panels));
        }
        let positive = self.envelope_values(true);
        for &(name, v, _) in &positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be finite and > 0, got {v}"));
            }
        }
        // The envelope (issue #25, docs/adversarial_harness.md): three decades either side of
        // the default (six until the declared ranges came from it, docs/fmu_docs.md). Beyond it mass and stiffness ratios overflow the inertia tensors or make the
        // Newton matrix singular, and the failure could not name the parameter.
        for &(name, v, d) in &positive {
            envelope(name, v, d, true)?;
        }
        let non_negative = self.envelope_values(false);
        for &(name, v, _) in &non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{name} must be finite and >= 0, got {v}"));
            }
        }
        for &(name, v, d) in &non_negative {
            envelope(name, v, d, false)?;
        }
        if self.hinge_friction_torque > MAX_HINGE_FRICTION_TORQUE {
            return Err(format!(
                "hinge_friction_torque = {} N m is above {MAX_HINGE_FRICTION_TORQUE} N m (friction above the deployment springs' preloads keeps the array stowed, and its regularized slope makes the equations stiff beyond what the integrators resolve)",
                self.hinge_friction_torque
            ));
        }
        if self.latches {
            self.validate_latch()?;
        }
        if self.restitution > 1.0 {
            return Err(format!(
                "restitution must be in (0, 1], got {}",
                self.restitution
            ));
        }
        for (name, v) in [
            ("root", self.root_lock_angle),
            ("panel", self.panel_lock_angle),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= std::f64::consts::PI) {
                return Err(format!("{name}_lock_angle must be in (0, pi] rad, got {v}"));
            }
        }
        let spans = [
            ("root", self.root_stowed_angle, self.root_lock_angle),
            ("panel", self.panel_stowed_angle, self.panel_lock_angle),
        ];
        for (name, stow, lock) in spans {
            if !(stow.is_finite() && stow >= 0.0 && stow < lock - 0.2) {
                return Err(format!(
                    "{name}_stowed_angle must be in [0, {name}_lock_angle - 0.2] rad, got {stow}"
                ));
            }
            if lock - stow >= std::f64::consts::PI - 1e-3 {
                return Err(format!(
                    "{name} hinge travel {name}_lock_angle - {name}_stowed_angle = {:.4} rad must be below pi (stow the panels a little open)",
                    lock - stow
                ));
            }
        }
        if let Some(g) = self.gravity.filter(|g| !g.is_finite()) {
            return Err(format!("gravity must be finite, got {g}"));
        }
        if let Some(g) = self.gravity {
            envelope("gravity", g.abs(), 9.81, false)?;
        }
        self.validate_satellite()?;
        if self.cable_loop && self.cable_stiffness == 0.0 {
            return Err(
                "cable_loop is on but cable_stiffness is 0: switch the loop off instead".into(),
            );
        }
        self.validate_deployment_speed()?;
        self.validate_array()?;
        if self.integrator == Some(IntegratorKind::Dopri5Tree)
            && (self.free_satellite || self.flexible_panels)
        {
            let why = if self.free_satellite {
                "free_satellite is on (the satellite floats, so the array is no tree hanging from the ground)"
            } else {
                "flexible_panels is on (modal bodies)"
            };
            return Err(format!(
                "integrator = dopri5_tree takes rigid panels on a fixed satellite, but {why}: choose gen_alpha, bdf or dopri5"
            ));
        }
        self.validate_flexible()?;
        self.solver_settings().validate().map(|_| ())
    }

    /// The integrator the scene runs with: the chosen one, or with `integrator = auto` (`None`)
    /// dopri5_tree (joint coordinates) for rigid panels on a fixed satellite, the only array it
    /// takes, and generalized-alpha otherwise.
    pub fn integrator_kind(&self) -> IntegratorKind {
        self.integrator
            .unwrap_or(if self.flexible_panels || self.free_satellite {
                IntegratorKind::GenAlpha
            } else {
                IntegratorKind::Dopri5Tree
            })
    }

    /// The integrator settings the scene runs with: `settings` with `rtol` / `atol` of 0 replaced
    /// by the [`default_tolerances`] of [`PanelLockParams::integrator_kind`], and the error held
    /// per step or per unit step as `error_control` says.
    pub fn solver_settings(&self) -> Settings {
        let per_unit_step = match self.error_control {
            ErrorControl::ByPanels => !self.flexible_panels,
            ErrorControl::PerStep => false,
            ErrorControl::PerUnitStep => true,
        };
        let (rtol, atol) = default_tolerances(self.integrator_kind());
        let or_default = |v: f64, d: f64| if v == 0.0 { d } else { v };
        Settings {
            rtol: or_default(self.settings.rtol, rtol),
            atol: or_default(self.settings.atol, atol),
            error_per_unit_step: per_unit_step,
            ..self.settings
        }
    }

    /// Upper estimates of the tip speeds [m/s] the deployment springs give at lock, with the
    /// springs' whole work (preload over the travel plus the linear part) going into the lightest
    /// thing each one drives: the outer panel about its hinge (`m L^2 / 3`), and for the root
    /// spring the yoke with the stowed panels at its end (`(m_yoke / 3 + n m_panel) L_yoke^2`).
    /// Damping, gravity, cable loops and the satellite's recoil are left out (all lower it).
    pub fn deployment_tip_speeds(&self) -> [f64; 2] {
        let work = |preload: f64, stiffness: f64, travel: f64| {
            preload * travel + 0.5 * stiffness * travel * travel
        };
        let m_p = self.panel_mass();
        let w_p = work(
            self.panel_spring_preload,
            self.panel_spring_stiffness,
            self.panel_lock_angle - self.panel_stowed_angle,
        );
        let panel = (6.0 * w_p / m_p).sqrt();
        let w_r = work(
            self.root_spring_preload,
            self.root_spring_stiffness,
            self.root_lock_angle - self.root_stowed_angle,
        );
        let m_r = self.yoke_mass / 3.0 + self.n_panels as f64 * m_p;
        let root = (2.0 * w_r / m_r).sqrt();
        [root, panel]
    }

    /// Refuses springs that would throw the array into the latches faster than
    /// [`MAX_DEPLOYMENT_TIP_SPEED`] (see [`Self::deployment_tip_speeds`]).
    /// Upper estimates of the angular rates at lock [rad/s]: the yoke's about the root hinge
    /// and the outer panel's about its hinge ([`Self::deployment_tip_speeds`] over the lengths).
    pub fn deployment_rates(&self) -> [f64; 2] {
        let [root, panel] = self.deployment_tip_speeds();
        [root / self.yoke_length, panel / self.panel_length]
    }

    /// For a solver failure's message: when the springs drive the yoke or a panel more than
    /// [`FAST_DEPLOYMENT_FACTOR`] times faster (in angular rate) than in the default scene, a
    /// sentence naming the parameters that set that rate (a millimetre yoke under the default
    /// spring turns at hundreds of rad/s while the panels span metres, and the steps this needs
    /// reach round-off); else empty.
    pub fn fast_deployment_note(&self) -> String {
        let [root, panel] = self.deployment_rates();
        let [root0, panel0] = Self::default().deployment_rates();
        // (which spring, its parameters on which length, what it swings, rate, default rate)
        let (spring, length, driven, rate, rate0) = if root > FAST_DEPLOYMENT_FACTOR * root0 {
            (
                "root",
                format!("yoke_length = {} m", self.yoke_length),
                format!(
                    "the yoke (yoke_mass = {} kg, carrying the stowed panels)",
                    self.yoke_mass
                ),
                root,
                root0,
            )
        } else if panel > FAST_DEPLOYMENT_FACTOR * panel0 {
            (
                "panel",
                format!("panel_length = {} m", self.panel_length),
                format!("the outer panel (mass {:.3e} kg)", self.panel_mass()),
                panel,
                panel0,
            )
        } else {
            return String::new();
        };
        let (preload, stiffness) = if spring == "root" {
            (self.root_spring_preload, self.root_spring_stiffness)
        } else {
            (self.panel_spring_preload, self.panel_spring_stiffness)
        };
        format!(
            "; note: {spring}_spring_preload = {preload} N m and {spring}_spring_stiffness = {stiffness} N m/rad on {length} swing {driven} at up to {rate:.3e} rad/s, {:.0} times the default scene's: a longer or heavier body or a weaker {spring} spring brings the steps back",
            rate / rate0
        )
    }

    fn validate_deployment_speed(&self) -> Result<(), String> {
        let [root, panel] = self.deployment_tip_speeds();
        let d = Self::default().deployment_tip_speeds();
        if panel > MAX_DEPLOYMENT_TIP_SPEED {
            return Err(format!(
                "panel_spring_preload = {} N m and panel_spring_stiffness = {} N m/rad over the \
                 travel panel_lock_angle - panel_stowed_angle = {:.4} rad would swing the outer \
                 panel (panel_areal_density x panel_length x panel_width = {:.4e} kg) to about \
                 {panel:.3e} m/s at its tip; the latch's contact law is for impacts far below \
                 the elastic wave speed: keep it below {MAX_DEPLOYMENT_TIP_SPEED} m/s (default \
                 scene: {:.2} m/s) with a weaker spring or a heavier panel",
                self.panel_spring_preload,
                self.panel_spring_stiffness,
                self.panel_lock_angle - self.panel_stowed_angle,
                self.panel_mass(),
                d[1]
            ));
        }
        if root > MAX_DEPLOYMENT_TIP_SPEED {
            return Err(format!(
                "root_spring_preload = {} N m and root_spring_stiffness = {} N m/rad over the \
                 travel root_lock_angle - root_stowed_angle = {:.4} rad would swing the yoke \
                 (yoke_mass = {} kg, yoke_length = {} m, carrying the stowed panels) to about \
                 {root:.3e} m/s at its tip; the latch's contact law is for impacts far below the \
                 elastic wave speed: keep it below {MAX_DEPLOYMENT_TIP_SPEED} m/s (default scene: \
                 {:.2} m/s) with a weaker spring or a heavier yoke",
                self.root_spring_preload,
                self.root_spring_stiffness,
                self.root_lock_angle - self.root_stowed_angle,
                self.yoke_mass,
                self.yoke_length,
                d[0]
            ));
        }
        Ok(())
    }
}

/// How many times the default scene's deployment angular rate makes a solver failure's message
/// name the springs and lengths ([`PanelLockParams::fast_deployment_note`]).
pub const FAST_DEPLOYMENT_FACTOR: f64 = 100.0;

/// Largest hinge Coulomb friction torque [N m] [`PanelLockParams::validate`] accepts (the
/// default 0 gives the decades of the envelope nothing to scale): twice the larger default
/// spring preload (0.6 N m) would keep the default array stowed, and above it the friction
/// law's viscous slope `T_f / w_s` (1e4 N m s/rad at 1 N m) outgrows the stiffest hinge damping
/// the envelope allows (20 N m s/rad) by 500 times, so explicit integration stalls without a
/// message that could name the parameter (found by the adversarial harness at 1e300 N m).
pub const MAX_HINGE_FRICTION_TORQUE: f64 = 1.0;

/// Largest deployment tip speed [m/s] [`PanelLockParams::validate`] accepts (upper estimate,
/// [`PanelLockParams::deployment_tip_speeds`]): 2 % of the elastic wave speed of aluminium
/// (about 5 km/s), where a quasi-static contact law such as Hertz with Lankarani-Nikravesh
/// damping stops being a model of the impact; 70 times the default scene's 1.4 m/s, and above
/// every parameter alone within [`ENVELOPE_DECADES`] of its default (44 m/s at most).
pub const MAX_DEPLOYMENT_TIP_SPEED: f64 = 100.0;

/// The range [`PanelLockParams::validate`] accepts for the real parameter `name` on its own (the
/// others at their defaults; relations between parameters, such as the latch geometry or
/// `panel_nonstructural_mass < panel_areal_density`, are in the parameters' descriptions), as
/// its declaration in [`super::ports::REAL_PARAMS`] gives it. `None` for names not declared.
pub fn declared_range(name: &str) -> Option<DeclaredRange> {
    find(super::ports::REAL_PARAMS, name).map(|s| s.range(&PanelLockParams::default()))
}

/// A parameter's range as [`declared_range`] gives it.
pub type DeclaredRange = Range;

/// Smallest and largest `panel_poisson` [-] (see [`declared_range`]).
pub const MIN_PANEL_POISSON: f64 = -0.99;
pub const MAX_PANEL_POISSON: f64 = 0.49;

/// `v` within [`ENVELOPE_DECADES`] of `default` (above only unless `both_sides`; a zero default
/// has no envelope).
fn envelope(name: &str, v: f64, default: f64, both_sides: bool) -> Result<(), String> {
    let k = 10f64.powi(ENVELOPE_DECADES);
    if default <= 0.0 {
        return Ok(());
    }
    if v > default * k || (both_sides && v < default / k) {
        return Err(format!(
            "{name} = {v} is outside the model's envelope [{}, {}] ({ENVELOPE_DECADES} decades around the default {default}; beyond it the mass and stiffness ratios make the equations singular)",
            if both_sides { default / k } else { 0.0 },
            default * k
        ));
    }
    Ok(())
}
