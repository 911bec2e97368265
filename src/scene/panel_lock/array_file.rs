//! The array tables of a PanelLock scene file, `[[hinge]]` and `[[panel]]`, read into
//! [`HingeTable`]s and [`PanelTable`]s with the file and line in every message (format:
//! `docs/panel_lock_array.md`):
//!
//! ```toml
//! [[hinge]]                    # hinge 0 (root), 1, ... in file order, or `index = k`
//! spring_stiffness = 0.1       # [N m/rad]     each key defaults to the global parameter:
//! spring_preload = 0.6         # [N m]         root_* / panel_* spring and angles,
//! damping = 0.02               # [N m s/rad]   hinge_damping,
//! friction_torque = 0.01       # [N m]         hinge_friction_torque,
//! lock_angle = 1.5708          # [rad]
//! stowed_angle = 0.0           # [rad]
//! contact_law = "hertz"        # contact_law, contact_stiffness [N/m^n],
//! contact_stiffness = 1e7      # contact_exponent [-], restitution [-]
//!
//! [[panel]]                    # panel 1, 2, ... in file order, or `index = k` (1-based)
//! length = 2.0                 # [m]
//! width = 1.5                  # [m]
//! thickness = 0.025            # [m]
//! areal_density = 1.5          # [kg/m2]; or mass [kg]
//! ```
//!
//! Ranges and the count against `n_panels` are checked with the other parameters
//! ([`PanelLockParams::validate_array`](super::PanelLockParams::validate_array)).

use super::array::{HingeTable, PanelTable};
use super::ports::CONTACT_LAWS;
use crate::contact::LawKind;
use crate::scene::scene_file::{SceneEntry, SceneTable, SceneValue};

const HINGE_KEYS: &str = "index, spring_stiffness, spring_preload, damping, friction_torque, lock_angle, stowed_angle, contact_law, contact_stiffness, contact_exponent, restitution";
const PANEL_KEYS: &str = "index, length, width, thickness, areal_density, mass";

/// Largest index a table may give (far above any array; keeps a typo from allocating).
const MAX_INDEX: i64 = 64;

/// The `[[hinge]]` and `[[panel]]` tables of scene file `origin`, hinge 0 and panel 1 first
/// (a table skipped by `index` keys is empty: the globals).
pub fn read_array(
    tables: &[SceneTable],
    origin: &str,
) -> Result<(Vec<HingeTable>, Vec<PanelTable>), String> {
    let mut hinges: Vec<Option<HingeTable>> = Vec::new();
    let mut panels: Vec<Option<PanelTable>> = Vec::new();
    for t in tables {
        let mut r = Reader {
            t,
            origin,
            used: vec![false; t.entries.len()],
        };
        match t.name.as_str() {
            "hinge" => {
                let k = r.slot(&hinges, 0)?;
                let h = r.hinge()?;
                r.unused(HINGE_KEYS)?;
                put(&mut hinges, k, h, || {
                    r.at(t.line, format!("hinge {k} is given twice"))
                })?;
            }
            "panel" => {
                let k = r.slot(&panels, 1)?;
                let p = r.panel()?;
                r.unused(PANEL_KEYS)?;
                put(&mut panels, k, p, || {
                    r.at(t.line, format!("panel {} is given twice", k + 1))
                })?;
            }
            other => {
                return Err(format!(
                    "{origin}:{}: unknown table `[{other}]` for PanelLock (its tables: [[hinge]], [[panel]])",
                    t.line
                ));
            }
        }
    }
    Ok((
        hinges.into_iter().map(Option::unwrap_or_default).collect(),
        panels.into_iter().map(Option::unwrap_or_default).collect(),
    ))
}

fn put<T>(
    v: &mut Vec<Option<T>>,
    k: usize,
    item: T,
    twice: impl Fn() -> String,
) -> Result<(), String> {
    if v.len() <= k {
        v.resize_with(k + 1, || None);
    }
    if v[k].is_some() {
        return Err(twice());
    }
    v[k] = Some(item);
    Ok(())
}

/// Reads the keys of one table, remembering which were used.
struct Reader<'a> {
    t: &'a SceneTable,
    origin: &'a str,
    used: Vec<bool>,
}

impl Reader<'_> {
    fn at(&self, line: usize, msg: impl std::fmt::Display) -> String {
        format!(
            "{}:{line}: [[{}]] {} {msg}",
            self.origin, self.t.name, self.t.index
        )
    }

    fn get(&mut self, key: &str) -> Option<SceneEntry> {
        let i = self.t.entries.iter().position(|e| e.name == key)?;
        self.used[i] = true;
        Some(self.t.entries[i].clone())
    }

    fn real(&mut self, key: &str) -> Result<Option<f64>, String> {
        let Some(e) = self.get(key) else {
            return Ok(None);
        };
        match e.value {
            SceneValue::Real(x) => Ok(Some(x)),
            SceneValue::Integer(i) => Ok(Some(i as f64)),
            _ => Err(self.at(e.line, format!("`{key}` must be a number"))),
        }
    }

    /// The array position this table fills: its `index` key (counted from `base`), else the
    /// one after the previous table's.
    fn slot<T>(&mut self, so_far: &[Option<T>], base: i64) -> Result<usize, String> {
        let Some(e) = self.get("index") else {
            return Ok(so_far.len());
        };
        match e.value {
            SceneValue::Integer(i) if (base..=MAX_INDEX).contains(&i) => Ok((i - base) as usize),
            _ => Err(self.at(
                e.line,
                format!("`index` must be an integer from {base} to {MAX_INDEX}"),
            )),
        }
    }

    fn law(&mut self) -> Result<Option<LawKind>, String> {
        let Some(e) = self.get("contact_law") else {
            return Ok(None);
        };
        let names: Vec<&str> = CONTACT_LAWS.iter().map(|(n, _)| *n).collect();
        let found = match &e.value {
            SceneValue::String(s) => names.iter().position(|n| n.eq_ignore_ascii_case(s)),
            _ => None,
        };
        match found.and_then(|i| LawKind::ALL.get(i)) {
            Some(l) => Ok(Some(*l)),
            None => Err(self.at(
                e.line,
                format!("`contact_law` must be one of \"{}\"", names.join("\", \"")),
            )),
        }
    }

    fn hinge(&mut self) -> Result<HingeTable, String> {
        Ok(HingeTable {
            line: self.t.line,
            spring_stiffness: self.real("spring_stiffness")?,
            spring_preload: self.real("spring_preload")?,
            damping: self.real("damping")?,
            friction_torque: self.real("friction_torque")?,
            lock_angle: self.real("lock_angle")?,
            stowed_angle: self.real("stowed_angle")?,
            contact_law: self.law()?,
            contact_stiffness: self.real("contact_stiffness")?,
            contact_exponent: self.real("contact_exponent")?,
            restitution: self.real("restitution")?,
        })
    }

    fn panel(&mut self) -> Result<PanelTable, String> {
        Ok(PanelTable {
            line: self.t.line,
            length: self.real("length")?,
            width: self.real("width")?,
            thickness: self.real("thickness")?,
            areal_density: self.real("areal_density")?,
            mass: self.real("mass")?,
        })
    }

    /// Refuses a key no reader asked for.
    fn unused(&self, keys: &str) -> Result<(), String> {
        match self.used.iter().position(|u| !u) {
            None => Ok(()),
            Some(i) => {
                let e = &self.t.entries[i];
                Err(self.at(e.line, format!("has no key `{}` (keys: {keys})", e.name)))
            }
        }
    }
}
