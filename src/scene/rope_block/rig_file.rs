//! The rig of a scene file: `[block]`, `[[lug]]`, `[[sling]]` and `[[hook]]` tables read into a
//! [`RigOverride`], with the file and line in every message. The format is in
//! `docs/rope_block_rig.md`:
//!
//! ```toml
//! [block]
//! box = [20.0, 14.0, 8.0]      # length, breadth, height [m] (or mesh = "block.obj", mesh_scale)
//! mass = 250e3                 # [kg]; or plate_thickness [m] and plate_density [kg/m3]
//! cog = [0.0, 0.0, 3.5]        # [m], design frame; default: the shell's area centroid
//! inertia = [ixx, iyy, izz, ixy, ixz, iyz]   # [kg m2] about the cog; default: thin shell
//! position = [0.0, 0.0, 0.0]   # start: world position of the design frame's origin [m]
//! orientation = [1.0, 0.0, 0.0, 0.0]   # design to world, unit quaternion [w, x, y, z];
//!                              # or roll_pitch_yaw = [r, p, y] [rad], R = Rz(y) Ry(p) Rx(r)
//!
//! [[lug]]                      # lug 0, 1, ... in file order
//! position = [7.0, 7.3, 7.0]   # [m], design frame
//!
//! [[sling]]
//! lug = 0                      # index of the lug
//! hook = 0                     # index of the hook
//! length = 22.5                # unstretched [m]; or length_factor (1: just taut)
//! ea = 1.6e8                   # [N]; mass_per_length [kg/m], diameter [m], damping [N s],
//! breaking_load = 2.5e6        # [N] (each defaults to the rope_* parameter)
//! route = "over_edge"          # "straight", "over_edge" (default) or via = [x, y, z] on an edge
//!
//! [[hook]]
//! position = [0.0, 0.0, 27.0]  # start position [m], world
//! crane = 0                    # crane id (a label)
//! ```
//!
//! Each table given replaces that part of the scenario's rig (a `[block]` alone keeps the
//! scenario's lugs, slings and hooks); relative mesh paths are relative to the scene file's folder.

use super::params::Route;
use super::rig::{
    BlockGeometry, BlockPose, BlockRig, Lug, MAX_RIG_HOOKS, MAX_RIG_LUGS, MAX_RIG_SLINGS, Plate,
    Rig, RigHook, RigSling, UNIT_QUATERNION_TOLERANCE,
};
use crate::math::{Mat3, Quat, Vec3};
use crate::rope::shell::parametric::BlockShape;
use crate::scene::scene_file::{SceneEntry, SceneTable, SceneValue};
use nalgebra::Quaternion;
use std::path::Path;

/// The parts of a rig a scene file gives.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RigOverride {
    pub block: Option<BlockRig>,
    pub lugs: Option<Vec<Lug>>,
    pub slings: Option<Vec<RigSling>>,
    pub hooks: Option<Vec<RigHook>>,
}

impl RigOverride {
    /// `base` with the parts given here.
    pub fn apply(&self, base: &Rig) -> Rig {
        Rig {
            block: self.block.clone().unwrap_or_else(|| base.block.clone()),
            lugs: self.lugs.clone().unwrap_or_else(|| base.lugs.clone()),
            slings: self.slings.clone().unwrap_or_else(|| base.slings.clone()),
            hooks: self.hooks.clone().unwrap_or_else(|| base.hooks.clone()),
        }
    }

    /// True when nothing is given.
    pub fn is_empty(&self) -> bool {
        self == &RigOverride::default()
    }
}

/// Reads the rig tables of a scene file `origin`; a relative mesh path is taken relative to
/// `dir` (the scene file's folder).
pub fn read_rig(
    tables: &[SceneTable],
    origin: &str,
    dir: Option<&Path>,
) -> Result<RigOverride, String> {
    let mut rig = RigOverride::default();
    for t in tables {
        let (count, cap, cap_name) = match t.name.as_str() {
            "lug" => (
                rig.lugs.as_ref().map_or(0, Vec::len),
                MAX_RIG_LUGS,
                "MAX_RIG_LUGS",
            ),
            "sling" => (
                rig.slings.as_ref().map_or(0, Vec::len),
                MAX_RIG_SLINGS,
                "MAX_RIG_SLINGS",
            ),
            "hook" => (
                rig.hooks.as_ref().map_or(0, Vec::len),
                MAX_RIG_HOOKS,
                "MAX_RIG_HOOKS",
            ),
            _ => (0, 1, ""),
        };
        if count == cap {
            return Err(format!(
                "{origin}:{}: [[{}]] {count} is one too many: a rig has at most {cap} (the cap {cap_name}; docs/bounded_inputs.md)",
                t.line, t.name
            ));
        }
        let mut r = Reader {
            t,
            origin,
            used: vec![false; t.entries.len()],
        };
        match t.name.as_str() {
            "block" => rig.block = Some(r.block(dir)?),
            "lug" => rig.lugs.get_or_insert_with(Vec::new).push(Lug {
                position: r.vec3("position")?.ok_or_else(|| r.missing("position"))?,
            }),
            "sling" => {
                let s = r.sling()?;
                rig.slings.get_or_insert_with(Vec::new).push(s);
            }
            "hook" => rig.hooks.get_or_insert_with(Vec::new).push(RigHook {
                position: r.vec3("position")?.ok_or_else(|| r.missing("position"))?,
                crane: r.index("crane")?.unwrap_or(0) as u32,
            }),
            other => {
                return Err(format!(
                    "{origin}:{}: unknown table `[{other}]` for RopeBlock",
                    t.line
                ));
            }
        }
        r.unused()?;
    }
    Ok(rig)
}

/// Reads the keys of one table, remembering which were used.
struct Reader<'a> {
    t: &'a SceneTable,
    origin: &'a str,
    used: Vec<bool>,
}

impl Reader<'_> {
    fn what(&self) -> String {
        match self.t.name.as_str() {
            "block" => "[block]".into(),
            n => format!("[[{n}]] {}", self.t.index),
        }
    }

    fn at(&self, line: usize, msg: impl std::fmt::Display) -> String {
        format!("{}:{line}: {} {msg}", self.origin, self.what())
    }

    fn missing(&self, key: &str) -> String {
        self.at(self.t.line, format!("needs `{key}`"))
    }

    fn get(&mut self, key: &str) -> Option<&SceneEntry> {
        let i = self.t.entries.iter().position(|e| e.name == key)?;
        self.used[i] = true;
        Some(&self.t.entries[i])
    }

    fn real(&mut self, key: &str) -> Result<Option<f64>, String> {
        let Some(e) = self.get(key).cloned() else {
            return Ok(None);
        };
        match e.value {
            SceneValue::Real(x) => Ok(Some(x)),
            SceneValue::Integer(i) => Ok(Some(i as f64)),
            _ => Err(self.at(e.line, format!("`{key}` must be a number"))),
        }
    }

    fn positive(&mut self, key: &str, unit: &str) -> Result<Option<f64>, String> {
        let line = self.get(key).map_or(0, |e| e.line);
        match self.real(key)? {
            Some(x) if x <= 0.0 => {
                Err(self.at(line, format!("`{key}` must be > 0 [{unit}], got {x}")))
            }
            x => Ok(x),
        }
    }

    fn index(&mut self, key: &str) -> Result<Option<usize>, String> {
        let Some(e) = self.get(key).cloned() else {
            return Ok(None);
        };
        match e.value {
            SceneValue::Integer(i) if (0..=1_000_000).contains(&i) => Ok(Some(i as usize)),
            _ => Err(self.at(
                e.line,
                format!("`{key}` must be an index (an integer from 0)"),
            )),
        }
    }

    fn reals(&mut self, key: &str, n: &[usize]) -> Result<Option<(Vec<f64>, usize)>, String> {
        let Some(e) = self.get(key).cloned() else {
            return Ok(None);
        };
        match e.value {
            SceneValue::Reals(v) if n.contains(&v.len()) => Ok(Some((v, e.line))),
            _ => Err(self.at(
                e.line,
                format!(
                    "`{key}` must be an array of {} numbers",
                    n.iter()
                        .map(|k| k.to_string())
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            )),
        }
    }

    fn vec3(&mut self, key: &str) -> Result<Option<Vec3>, String> {
        Ok(self
            .reals(key, &[3])?
            .map(|(v, _)| Vec3::new(v[0], v[1], v[2])))
    }

    fn string(&mut self, key: &str) -> Result<Option<(String, usize)>, String> {
        let Some(e) = self.get(key).cloned() else {
            return Ok(None);
        };
        match e.value {
            SceneValue::String(s) => Ok(Some((s, e.line))),
            _ => Err(self.at(e.line, format!("`{key}` must be a string"))),
        }
    }

    /// Refuses a key no reader asked for.
    fn unused(&self) -> Result<(), String> {
        match self.used.iter().position(|u| !u) {
            None => Ok(()),
            Some(i) => {
                let e = &self.t.entries[i];
                Err(self.at(
                    e.line,
                    format!("has no key `{}` (keys: {})", e.name, keys_of(&self.t.name)),
                ))
            }
        }
    }

    fn block(&mut self, dir: Option<&Path>) -> Result<BlockRig, String> {
        let dims = self.reals("box", &[3])?;
        let mesh = self.string("mesh")?;
        let scale = self.positive("mesh_scale", "-")?;
        let geometry = match (dims, mesh) {
            (Some((d, line)), None) => {
                if d.iter().any(|x| *x <= 0.0) {
                    return Err(self.at(line, "`box` dimensions must be > 0 [m]"));
                }
                BlockGeometry::Shape(BlockShape {
                    length: d[0],
                    breadth: d[1],
                    height: d[2],
                    bilge_radius: 0.0,
                    ..BlockShape::default()
                })
            }
            (None, Some((file, _))) => {
                let p = Path::new(&file);
                let path = match dir {
                    Some(d) if p.is_relative() => d.join(p),
                    _ => p.to_path_buf(),
                };
                BlockGeometry::Mesh {
                    file: path.to_string_lossy().into_owned(),
                    scale: scale.unwrap_or(1.0),
                }
            }
            (Some(_), Some((_, line))) => {
                return Err(self.at(line, "give either `box` or `mesh`, not both"));
            }
            (None, None) => return Err(self.missing("box` or `mesh")),
        };
        let mass = self.positive("mass", "kg")?;
        let thickness = self.positive("plate_thickness", "m")?;
        let density = self.positive("plate_density", "kg/m3")?;
        let plate = match (thickness, density) {
            (Some(thickness), Some(density)) => Some(Plate { thickness, density }),
            (None, None) => None,
            _ => {
                return Err(self.missing("plate_thickness` and `plate_density"));
            }
        };
        let cog = self.vec3("cog")?;
        let inertia = self.reals("inertia", &[6, 9])?.map(|(v, _)| {
            if v.len() == 9 {
                Mat3::from_row_slice(&v)
            } else {
                Mat3::new(v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2])
            }
        });
        let pose = self.pose()?;
        Ok(BlockRig {
            geometry,
            mass,
            plate,
            cog,
            inertia,
            pose,
        })
    }

    /// The block's start pose: `position` [m] (world position of the design frame's origin) and
    /// `orientation = [w, x, y, z]` (unit quaternion, design to world) or `roll_pitch_yaw`
    /// [rad] (`R = Rz(yaw) Ry(pitch) Rx(roll)`, world axes); `None` when neither is given.
    fn pose(&mut self) -> Result<Option<BlockPose>, String> {
        let position = self.vec3("position")?;
        let quat = self.reals("orientation", &[4])?;
        let rpy = self.reals("roll_pitch_yaw", &[3])?;
        let orientation = match (quat, rpy) {
            (Some(_), Some((_, line))) => {
                return Err(self.at(
                    line,
                    "give either `orientation` or `roll_pitch_yaw`, not both",
                ));
            }
            (Some((q, line)), None) => {
                let q = Quaternion::new(q[0], q[1], q[2], q[3]);
                if (q.norm() - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
                    return Err(self.at(
                        line,
                        format!(
                            "`orientation` must be a unit quaternion [w, x, y, z], its norm is {}",
                            q.norm()
                        ),
                    ));
                }
                Some(Quat::from_quaternion(q))
            }
            (None, Some((a, _))) => Some(Quat::from_euler_angles(a[0], a[1], a[2])),
            (None, None) => None,
        };
        Ok(match (position, orientation) {
            (None, None) => None,
            (p, q) => Some(BlockPose {
                position: p.unwrap_or_else(Vec3::zeros),
                orientation: q.unwrap_or_else(Quat::identity),
            }),
        })
    }

    fn sling(&mut self) -> Result<RigSling, String> {
        let lug = self.index("lug")?.ok_or_else(|| self.missing("lug"))?;
        let hook = self.index("hook")?.ok_or_else(|| self.missing("hook"))?;
        let mut s = RigSling::new(lug, hook);
        s.length = self.positive("length", "m")?;
        s.length_factor = self.positive("length_factor", "-")?.unwrap_or(1.0);
        s.ea = self.positive("ea", "N")?;
        s.mass_per_length = self.positive("mass_per_length", "kg/m")?;
        s.diameter = self.positive("diameter", "m")?;
        s.breaking_load = self.positive("breaking_load", "N")?;
        let line = self.get("damping").map_or(0, |e| e.line);
        s.damping = match self.real("damping")? {
            Some(d) if d < 0.0 => {
                return Err(self.at(line, format!("`damping` must be >= 0 [N s], got {d}")));
            }
            d => d,
        };
        let via = self.vec3("via")?;
        s.route = match (self.string("route")?, via) {
            (None, None) => Route::OverEdge,
            (None, Some(v)) => Route::Via(v),
            (Some((r, line)), via) => match (r.as_str(), via) {
                ("over_edge", None) => Route::OverEdge,
                ("straight", None) => Route::Straight,
                ("via", Some(v)) => Route::Via(v),
                _ => {
                    return Err(self.at(
                        line,
                        format!("`route` = \"{r}\": use \"over_edge\", \"straight\", or `via = [x, y, z]` alone"),
                    ));
                }
            },
        };
        Ok(s)
    }
}

fn keys_of(table: &str) -> &'static str {
    match table {
        "block" => {
            "box, mesh, mesh_scale, mass, plate_thickness, plate_density, cog, inertia, position, orientation, roll_pitch_yaw"
        }
        "lug" => "position",
        "sling" => {
            "lug, hook, length, length_factor, ea, mass_per_length, diameter, damping, breaking_load, route, via"
        }
        "hook" => "position, crane",
        _ => "",
    }
}
