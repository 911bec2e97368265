//! The array as data: per-hinge and per-panel values (scene-file `[[hinge]]` and `[[panel]]`
//! tables, `docs/panel_lock_array.md`) over the global parameters, resolved into the values each
//! hinge and panel is built with, checked, and digested for serialized FMU states.
//!
//! Hinge `k` is 0 (root: yoke on the satellite) to `n_panels` (the outer panel's inboard hinge);
//! panel `k` is 1 to `n_panels`, the table `[[panel]]` `i` being panel `i + 1`. A value a table
//! does not give is the global parameter's (`root_*` for hinge 0, `panel_*` for the others).

use super::params::{PanelLockParams, declared_range};
use crate::contact::LawKind;
use crate::scene::bytes::{ByteWriter, checksum64};

/// What one `[[hinge]]` table gives (`None`: the global parameter). SI units.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HingeTable {
    /// Line of the table's header in the scene file (0: not from a file), for messages.
    pub line: usize,
    /// Deployment spring stiffness [N m/rad] and torque at the lock angle [N m].
    pub spring_stiffness: Option<f64>,
    pub spring_preload: Option<f64>,
    /// Viscous shaft damping [N m s/rad].
    pub damping: Option<f64>,
    /// Coulomb friction torque of the shaft [N m] (`crate::effect::hinge_friction`).
    pub friction_torque: Option<f64>,
    /// Lock angle (groove centre) and stowed angle [rad], deployment angle of the hinge.
    pub lock_angle: Option<f64>,
    pub stowed_angle: Option<f64>,
    /// Latch contact law, stiffness [N/m^n], exponent n [-] and restitution e [-].
    pub contact_law: Option<LawKind>,
    pub contact_stiffness: Option<f64>,
    pub contact_exponent: Option<f64>,
    pub restitution: Option<f64>,
}

/// What one `[[panel]]` table gives (`None`: the global parameter). SI units.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PanelTable {
    /// Line of the table's header in the scene file (0: not from a file), for messages.
    pub line: usize,
    /// Length along the deployment direction [m], width along the hinge axis [m], thickness [m].
    pub length: Option<f64>,
    pub width: Option<f64>,
    pub thickness: Option<f64>,
    /// Areal density [kg/m^2], or the panel's mass [kg] (then the areal density is
    /// `mass / (length width)`); not both.
    pub areal_density: Option<f64>,
    pub mass: Option<f64>,
}

/// The values hinge `k` is built with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HingeValues {
    pub spring_stiffness: f64,
    pub spring_preload: f64,
    pub damping: f64,
    pub friction_torque: f64,
    pub lock_angle: f64,
    pub stowed_angle: f64,
    pub contact_law: LawKind,
    pub contact_stiffness: f64,
    pub contact_exponent: f64,
    pub restitution: f64,
}

/// The values panel `k` is built with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelValues {
    pub length: f64,
    pub width: f64,
    pub thickness: f64,
    pub areal_density: f64,
}

impl PanelValues {
    /// Mass [kg].
    pub fn mass(&self) -> f64 {
        self.areal_density * self.length * self.width
    }
}

impl PanelLockParams {
    /// The values of hinge `k` (0 = root): its `[[hinge]]` table over the globals.
    pub fn hinge(&self, k: usize) -> HingeValues {
        let t = self.hinge_tables.get(k).cloned().unwrap_or_default();
        let root = k == 0;
        let pick = |r: f64, p: f64| if root { r } else { p };
        HingeValues {
            spring_stiffness: t.spring_stiffness.unwrap_or(pick(
                self.root_spring_stiffness,
                self.panel_spring_stiffness,
            )),
            spring_preload: t
                .spring_preload
                .unwrap_or(pick(self.root_spring_preload, self.panel_spring_preload)),
            damping: t.damping.unwrap_or(self.hinge_damping),
            friction_torque: t.friction_torque.unwrap_or(self.hinge_friction_torque),
            lock_angle: t
                .lock_angle
                .unwrap_or(pick(self.root_lock_angle, self.panel_lock_angle)),
            stowed_angle: t
                .stowed_angle
                .unwrap_or(pick(self.root_stowed_angle, self.panel_stowed_angle)),
            contact_law: t.contact_law.unwrap_or(self.contact_law),
            contact_stiffness: t.contact_stiffness.unwrap_or(self.contact_stiffness),
            contact_exponent: t.contact_exponent.unwrap_or(self.contact_exponent),
            restitution: t.restitution.unwrap_or(self.restitution),
        }
    }

    /// The values of panel `k` (1 ..= n_panels): table `[[panel]]` `k - 1` over the globals.
    pub fn panel(&self, k: usize) -> PanelValues {
        let t = k
            .checked_sub(1)
            .and_then(|i| self.panel_tables.get(i))
            .cloned()
            .unwrap_or_default();
        let length = t.length.unwrap_or(self.panel_length);
        let width = t.width.unwrap_or(self.panel_width);
        let areal_density = match (t.mass, t.areal_density) {
            (Some(m), _) => m / (length * width),
            (None, Some(rho)) => rho,
            (None, None) => self.panel_areal_density,
        };
        PanelValues {
            length,
            width,
            thickness: t.thickness.unwrap_or(self.panel_thickness),
            areal_density,
        }
    }

    /// These parameters with the globals of panel `k` replaced by its own values (for the
    /// flexible panel's plate model, which reads the globals).
    pub fn with_panel(&self, k: usize) -> PanelLockParams {
        let v = self.panel(k);
        PanelLockParams {
            panel_length: v.length,
            panel_width: v.width,
            panel_thickness: v.thickness,
            panel_areal_density: v.areal_density,
            ..self.clone()
        }
    }

    /// Whether any hinge has Coulomb friction (the friction effect is assembled only then).
    pub fn has_hinge_friction(&self) -> bool {
        (0..self.n_hinges()).any(|k| self.hinge(k).friction_torque > 0.0)
    }

    /// Digest of every hinge's and panel's effective values: equal for two parameter sets that
    /// build the same array, whether the values come from tables or from the globals.
    pub fn array_digest(&self) -> u64 {
        let mut w = ByteWriter::new();
        w.u64(self.n_hinges() as u64);
        for k in 0..self.n_hinges() {
            let h = self.hinge(k);
            for v in [
                h.spring_stiffness,
                h.spring_preload,
                h.damping,
                h.friction_torque,
                h.lock_angle,
                h.stowed_angle,
                h.contact_stiffness,
                h.contact_exponent,
                h.restitution,
            ] {
                w.f64(v);
            }
            w.u8(LawKind::ALL
                .iter()
                .position(|l| *l == h.contact_law)
                .unwrap_or(0) as u8);
        }
        for k in 1..=self.n_panels {
            let p = self.panel(k);
            for v in [p.length, p.width, p.thickness, p.areal_density] {
                w.f64(v);
            }
        }
        checksum64(w.as_bytes())
    }

    /// Checks the tables against the array (`Err` names the table, its line and the key): no
    /// more tables than hinges and panels, every value within the range of the global parameter
    /// it overrides ([`declared_range`]), each hinge's stowed angle below its lock angle by
    /// 0.2 rad and its travel below pi, `mass` and `areal_density` not both, and, with flexible
    /// panels, each panel's areal density above `panel_nonstructural_mass`.
    pub fn validate_array(&self) -> Result<(), String> {
        let n = self.n_hinges();
        if self.hinge_tables.len() > n {
            let t = &self.hinge_tables[n];
            return Err(format!(
                "[[hinge]] {n}{}: too many [[hinge]] tables ({}): the array has {n} hinges, 0 (root) to {} (n_panels = {})",
                at_line(t.line),
                self.hinge_tables.len(),
                n - 1,
                self.n_panels
            ));
        }
        if self.panel_tables.len() > self.n_panels {
            let t = &self.panel_tables[self.n_panels];
            return Err(format!(
                "[[panel]] {}{}: too many [[panel]] tables ({}): the array has n_panels = {} panels",
                self.n_panels,
                at_line(t.line),
                self.panel_tables.len(),
                self.n_panels
            ));
        }
        for (k, t) in self.hinge_tables.iter().enumerate() {
            self.validate_hinge(k, t)?;
        }
        for (i, t) in self.panel_tables.iter().enumerate() {
            self.validate_panel(i, t)?;
        }
        Ok(())
    }

    fn validate_hinge(&self, k: usize, t: &HingeTable) -> Result<(), String> {
        let who = format!("[[hinge]] {k}{}", at_line(t.line));
        let side = if k == 0 { "root" } else { "panel" };
        let checks = [
            (
                "spring_stiffness",
                t.spring_stiffness,
                format!("{side}_spring_stiffness"),
                "N m/rad",
            ),
            (
                "spring_preload",
                t.spring_preload,
                format!("{side}_spring_preload"),
                "N m",
            ),
            ("damping", t.damping, "hinge_damping".into(), "N m s/rad"),
            (
                "friction_torque",
                t.friction_torque,
                "hinge_friction_torque".into(),
                "N m",
            ),
            (
                "lock_angle",
                t.lock_angle,
                format!("{side}_lock_angle"),
                "rad",
            ),
            (
                "stowed_angle",
                t.stowed_angle,
                format!("{side}_stowed_angle"),
                "rad",
            ),
            (
                "contact_stiffness",
                t.contact_stiffness,
                "contact_stiffness".into(),
                "N/m^n",
            ),
            (
                "contact_exponent",
                t.contact_exponent,
                "contact_exponent".into(),
                "-",
            ),
            ("restitution", t.restitution, "restitution".into(), "-"),
        ];
        for (key, value, global, unit) in checks {
            if let Some(v) = value {
                in_range(&who, key, v, &global, unit)?;
            }
        }
        let h = self.hinge(k);
        if h.stowed_angle >= h.lock_angle - 0.2 {
            return Err(format!(
                "{who}: stowed_angle = {} rad must be below lock_angle - 0.2 = {} rad (values from the table or {side}_stowed_angle / {side}_lock_angle)",
                h.stowed_angle,
                h.lock_angle - 0.2
            ));
        }
        if h.lock_angle - h.stowed_angle >= std::f64::consts::PI - 1e-3 {
            return Err(format!(
                "{who}: the travel lock_angle - stowed_angle = {:.4} rad must be below pi (stow the panels a little open)",
                h.lock_angle - h.stowed_angle
            ));
        }
        Ok(())
    }

    fn validate_panel(&self, i: usize, t: &PanelTable) -> Result<(), String> {
        let who = format!("[[panel]] {i} (panel {}){}", i + 1, at_line(t.line));
        if let (Some(_), Some(_)) = (t.mass, t.areal_density) {
            return Err(format!("{who}: give `mass` or `areal_density`, not both"));
        }
        let checks = [
            ("length", t.length, "panel_length", "m"),
            ("width", t.width, "panel_width", "m"),
            ("thickness", t.thickness, "panel_thickness", "m"),
            (
                "areal_density",
                t.areal_density,
                "panel_areal_density",
                "kg/m2",
            ),
        ];
        for (key, value, global, unit) in checks {
            if let Some(v) = value {
                in_range(&who, key, v, global, unit)?;
            }
        }
        let v = self.panel(i + 1);
        if let Some(m) = t.mass {
            if !(m.is_finite() && m > 0.0) {
                return Err(format!(
                    "{who}: `mass` must be finite and > 0 [kg], got {m}"
                ));
            }
            in_range(
                &who,
                "mass / (length width)",
                v.areal_density,
                "panel_areal_density",
                "kg/m2",
            )?;
        }
        if self.flexible_panels && v.areal_density <= self.panel_nonstructural_mass {
            return Err(format!(
                "{who}: the areal density {} kg/m2 must exceed panel_nonstructural_mass = {} kg/m2 with flexible panels",
                v.areal_density, self.panel_nonstructural_mass
            ));
        }
        Ok(())
    }
}

fn at_line(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(" (line {line})")
    }
}

/// `value` of `key` within the declared range of the global parameter `global` it overrides.
fn in_range(who: &str, key: &str, value: f64, global: &str, unit: &str) -> Result<(), String> {
    let r = declared_range(global).unwrap_or(super::params::DeclaredRange::closed(None, None));
    if r.contains(value) {
        return Ok(());
    }
    let lo = r.min.map_or("-inf".to_string(), |v| format!("{v}"));
    let hi = r.max.map_or("inf".to_string(), |v| format!("{v}"));
    Err(format!(
        "{who}: `{key}` = {value} [{unit}] is outside the range of {global}, {}{lo}, {hi}{}",
        if r.open[0] { "(" } else { "[" },
        if r.open[1] { ")" } else { "]" }
    ))
}
