//! Parameters of the PanelLock scene, with their defaults and validation.

use crate::contact::LawKind;
use crate::integrator::{IntegratorKind, Settings};

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
    /// (principal moments, [kg m^2]).
    pub free_satellite: bool,
    pub satellite_mass: f64,
    pub satellite_inertia: [f64; 3],
    /// Integrator and its settings.
    pub integrator: IntegratorKind,
    pub settings: Settings,
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
            integrator: IntegratorKind::Bdf,
            settings: Settings {
                rtol: 1e-6,
                atol: 1e-8,
                h_max: 0.02,
                ..Settings::default()
            },
        }
    }
}

impl PanelLockParams {
    /// Number of hinges (root hinge plus one per panel).
    pub fn n_hinges(&self) -> usize {
        self.n_panels + 1
    }

    /// Mass of one panel [kg].
    pub fn panel_mass(&self) -> f64 {
        self.panel_areal_density * self.panel_length * self.panel_width
    }

    /// Checks every value; `Err` names the parameter and the accepted range.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=6).contains(&self.n_panels) {
            return Err(format!("n_panels must be 1..=6, got {}", self.n_panels));
        }
        let positive = [
            ("panel_length", self.panel_length),
            ("panel_width", self.panel_width),
            ("panel_areal_density", self.panel_areal_density),
            ("panel_thickness", self.panel_thickness),
            ("yoke_length", self.yoke_length),
            ("yoke_mass", self.yoke_mass),
            ("hinge_mass", self.hinge_mass),
            ("hinge_gyration_radius", self.hinge_gyration_radius),
            ("cam_radius", self.cam_radius),
            ("groove_width", self.groove_width),
            ("groove_depth", self.groove_depth),
            ("pin_radius", self.pin_radius),
            ("contact_stiffness", self.contact_stiffness),
            ("contact_exponent", self.contact_exponent),
            ("restitution", self.restitution),
            ("satellite_mass", self.satellite_mass),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be finite and > 0, got {v}"));
            }
        }
        let non_negative = [
            ("root_spring_preload", self.root_spring_preload),
            ("root_spring_stiffness", self.root_spring_stiffness),
            ("panel_spring_preload", self.panel_spring_preload),
            ("panel_spring_stiffness", self.panel_spring_stiffness),
            ("hinge_damping", self.hinge_damping),
            ("cable_stiffness", self.cable_stiffness),
            ("cable_damping", self.cable_damping),
            ("stop_stiffness", self.stop_stiffness),
            ("stop_damping", self.stop_damping),
        ];
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{name} must be finite and >= 0, got {v}"));
            }
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
                    "{name} hinge travel {:.4} rad must be below pi (stow the panels a little open)",
                    lock - stow
                ));
            }
        }
        if let Some(g) = self.gravity.filter(|g| !g.is_finite()) {
            return Err(format!("gravity must be finite, got {g}"));
        }
        if self
            .satellite_inertia
            .iter()
            .any(|v| !(v.is_finite() && *v > 0.0))
        {
            return Err("satellite_inertia must be three finite positive moments".into());
        }
        if self.cable_loop && self.cable_stiffness == 0.0 {
            return Err(
                "cable_loop is on but cable_stiffness is 0: switch the loop off instead".into(),
            );
        }
        self.settings.validate().map(|_| ())
    }
}
