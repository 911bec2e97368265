//! A lifting rig as data: the block (parametric box or mesh, mass, centre of gravity, inertia),
//! its lugs, the slings (length, EA, mass per length, diameter, damping, breaking load, which lug
//! to which hook) and 1-4 crane hooks. [`Rig::default`] is the built-in four-sling lift;
//! [`super::RopeBlockParams::structure`] builds every scene from a rig.
//!
//! Frames: lugs, the centre of gravity and via points are in the block's **design frame** (`x`
//! along its length, `y` across, `z` up from the bottom, as [`BlockShape`]); the inertia tensor is
//! about the centre of gravity, axes of the design frame; hook positions are in the world frame
//! (`z` up, gravity `-z`). Units SI.
//!
//! A sling value left `None` takes the scene-wide value (the FMU's `rope_*` parameters and
//! `block_mass`), so the built-in scenes keep answering to those parameters.

use super::params::Route;
use crate::math::{Mat3, Quat, Vec3};
use crate::rope::RopeProps;
use crate::rope::shell::parametric::BlockShape;

/// Largest deviation of a block orientation's norm from 1 accepted [-] (a quaternion written
/// with 12 significant digits is within 1e-11).
pub const UNIT_QUATERNION_TOLERANCE: f64 = 1e-9;

/// Most hooks a rig may have.
pub const MAX_RIG_HOOKS: usize = 4;

/// Most slings a rig may have: heavy lifts use 2-8 per hook, so 16 per hook on 4 hooks
/// (docs/bounded_inputs.md). Each sling is checked against the block when the scene is read,
/// inside `fmi2Instantiate`.
pub const MAX_RIG_SLINGS: usize = 64;

/// Most lugs a rig may have (lugs no sling uses are allowed: a block's lug plan); each is checked
/// against the block's shell when the scene is read.
pub const MAX_RIG_LUGS: usize = 256;

/// The block's shell geometry.
#[derive(Debug, Clone, PartialEq)]
pub enum BlockGeometry {
    /// The parametric block (a box when `bilge_radius` is 0).
    Shape(BlockShape),
    /// An OBJ or STL shell plate in the design frame; `scale` converts its units to metres.
    Mesh { file: String, scale: f64 },
}

/// A uniform plate from which the block's mass is derived: mass = shell area x thickness x
/// density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plate {
    /// Plate thickness [m] (stiffeners smeared in).
    pub thickness: f64,
    /// Steel density [kg/m^3] (7850 for steel).
    pub density: f64,
}

/// The block: geometry and mass properties.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockRig {
    pub geometry: BlockGeometry,
    /// Mass [kg]; `None`: from `plate`, else the scene-wide `block_mass`.
    pub mass: Option<f64>,
    /// Plate thickness and density to derive the mass from (used when `mass` is `None`).
    pub plate: Option<Plate>,
    /// Centre of gravity [m], design frame; `None`: the centroid of the shell area.
    pub cog: Option<Vec3>,
    /// Inertia about the centre of gravity [kg m^2], design-frame axes; `None`: a uniform thin
    /// shell of the block's mass.
    pub inertia: Option<Mat3>,
    /// Start pose of the design frame in the world; `None`: on the world frame. The scene settles
    /// to its static equilibrium from there.
    pub pose: Option<BlockPose>,
}

/// Where the block's design frame starts in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockPose {
    /// World position of the design frame's origin [m].
    pub position: Vec3,
    /// Rotation from the design frame to the world frame (a unit quaternion).
    pub orientation: Quat,
}

/// A lug (padeye) on the block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lug {
    /// Position [m], design frame; within [`LUG_TOLERANCE`] of the shell plate.
    pub position: Vec3,
}

/// Largest distance of a lug from the shell plate [m] (a padeye stands off its plate by less).
pub const LUG_TOLERANCE: f64 = 0.5;

/// A sling from a hook to a lug. `None` values take the scene-wide rope values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigSling {
    /// Lug index (into [`Rig::lugs`]).
    pub lug: usize,
    /// Hook index (into [`Rig::hooks`]).
    pub hook: usize,
    /// Unstretched length [m]; `None`: the length of the initial route times `length_factor`
    /// (1: just taut).
    pub length: Option<f64>,
    /// Unstretched length as a fraction of the initial route (used when `length` is `None`).
    pub length_factor: f64,
    /// Axial stiffness EA [N].
    pub ea: Option<f64>,
    /// Mass per unstretched length [kg/m].
    pub mass_per_length: Option<f64>,
    /// Nominal diameter [m].
    pub diameter: Option<f64>,
    /// Axial (Kelvin-Voigt) damping [N s].
    pub damping: Option<f64>,
    /// Minimum breaking load [N].
    pub breaking_load: Option<f64>,
    /// Initial route from hook to lug.
    pub route: Route,
}

impl RigSling {
    /// A sling from hook `hook` to lug `lug`, just taut, over the edge its straight path cuts,
    /// with the scene-wide rope values.
    pub fn new(lug: usize, hook: usize) -> Self {
        RigSling {
            lug,
            hook,
            length: None,
            length_factor: 1.0,
            ea: None,
            mass_per_length: None,
            diameter: None,
            damping: None,
            breaking_load: None,
            route: Route::OverEdge,
        }
    }

    /// This sling's rope: `base` (the scene-wide rope) with the sling's own values.
    pub fn props(&self, base: &RopeProps) -> RopeProps {
        RopeProps {
            ea: self.ea.unwrap_or(base.ea),
            mass_per_length: self.mass_per_length.unwrap_or(base.mass_per_length),
            diameter: self.diameter.unwrap_or(base.diameter),
            axial_damping: self.damping.unwrap_or(base.axial_damping),
            breaking_load: self.breaking_load.unwrap_or(base.breaking_load),
            ..*base
        }
    }
}

/// A crane hook.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigHook {
    /// Start position [m], world.
    pub position: Vec3,
    /// Crane the hook belongs to (a label for reports: two hooks of one crane share it).
    pub crane: u32,
}

/// A lifting rig.
#[derive(Debug, Clone, PartialEq)]
pub struct Rig {
    pub block: BlockRig,
    pub lugs: Vec<Lug>,
    pub slings: Vec<RigSling>,
    pub hooks: Vec<RigHook>,
}

impl Default for Rig {
    /// The default lift: a block of 18 m x 12 m x 7 m (2 m bilge in 8 facets) hanging from one
    /// hook 19 m above its deck by four slings from lugs on the side shell 1 m below the deck
    /// edge, 0.3 m off the plate, over the deck edges.
    fn default() -> Self {
        let (l, b, h) = (18.0, 12.0, 7.0);
        let lug = |sx: f64, sy: f64| Lug {
            position: Vec3::new(sx * 6.5, sy * (0.5 * b + 0.3), h - 1.0),
        };
        Rig {
            block: BlockRig {
                geometry: BlockGeometry::Shape(BlockShape {
                    length: l,
                    breadth: b,
                    height: h,
                    ..BlockShape::default()
                }),
                mass: None,
                plate: None,
                cog: None,
                inertia: None,
                pose: None,
            },
            lugs: vec![
                lug(1.0, 1.0),
                lug(-1.0, 1.0),
                lug(-1.0, -1.0),
                lug(1.0, -1.0),
            ],
            slings: (0..4).map(|k| RigSling::new(k, 0)).collect(),
            hooks: vec![RigHook {
                position: Vec3::new(0.0, 0.0, h + 19.0),
                crane: 0,
            }],
        }
    }
}

impl Rig {
    /// The parametric shape, if the block is one.
    pub fn shape(&self) -> Option<&BlockShape> {
        match &self.block.geometry {
            BlockGeometry::Shape(s) => Some(s),
            BlockGeometry::Mesh { .. } => None,
        }
    }

    /// Hook start positions [m], world.
    pub fn hook_positions(&self) -> Vec<Vec3> {
        self.hooks.iter().map(|h| h.position).collect()
    }

    /// Checks what can be checked without the mesh: counts, indices, finite and positive values.
    /// `Err` names the item and the value.
    pub fn validate(&self) -> Result<(), String> {
        if self.hooks.is_empty() || self.hooks.len() > MAX_RIG_HOOKS {
            return Err(format!(
                "a rig has 1 to {MAX_RIG_HOOKS} hooks, got {}",
                self.hooks.len()
            ));
        }
        if self.slings.is_empty() {
            return Err("at least one sling is needed".into());
        }
        if self.slings.len() > MAX_RIG_SLINGS {
            return Err(format!(
                "a rig has at most {MAX_RIG_SLINGS} slings (MAX_RIG_SLINGS; docs/bounded_inputs.md), got {}",
                self.slings.len()
            ));
        }
        if self.lugs.len() > MAX_RIG_LUGS {
            return Err(format!(
                "a rig has at most {MAX_RIG_LUGS} lugs (MAX_RIG_LUGS; docs/bounded_inputs.md), got {}",
                self.lugs.len()
            ));
        }
        for (k, h) in self.hooks.iter().enumerate() {
            if !h.position.iter().all(|x| x.is_finite()) {
                return Err(format!("hook {k}: position is not finite"));
            }
        }
        for (k, l) in self.lugs.iter().enumerate() {
            if !l.position.iter().all(|x| x.is_finite()) {
                return Err(format!("lug {k}: position is not finite"));
            }
        }
        let positive = |what: String, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{what} must be finite and > 0, got {v}"))
            }
        };
        let b = &self.block;
        if let Some(m) = b.mass {
            positive("block mass [kg]".into(), m)?;
        }
        if let Some(p) = b.plate {
            positive("block plate thickness [m]".into(), p.thickness)?;
            positive("block plate density [kg/m3]".into(), p.density)?;
        }
        if let Some(c) = b.cog
            && !c.iter().all(|x| x.is_finite())
        {
            return Err("block centre of gravity is not finite".into());
        }
        if let Some(i) = b.inertia {
            check_inertia(&i)?;
        }
        if let Some(pose) = b.pose {
            let q = pose.orientation.quaternion();
            if !(pose.position.iter().all(|x| x.is_finite())
                && q.coords.iter().all(|x| x.is_finite()))
            {
                return Err("block start pose is not finite".into());
            }
            if (q.norm() - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
                return Err(format!(
                    "block orientation must be a unit quaternion, |q| = {}",
                    q.norm()
                ));
            }
        }
        if let BlockGeometry::Mesh { scale, .. } = &b.geometry {
            positive("mesh scale".into(), *scale)?;
        }
        for (k, s) in self.slings.iter().enumerate() {
            if s.hook >= self.hooks.len() {
                return Err(format!(
                    "sling {k}: hook {} does not exist ({} hooks)",
                    s.hook,
                    self.hooks.len()
                ));
            }
            if s.lug >= self.lugs.len() {
                return Err(format!(
                    "sling {k}: lug {} does not exist ({} lugs)",
                    s.lug,
                    self.lugs.len()
                ));
            }
            positive(format!("sling {k}: length factor"), s.length_factor)?;
            for (name, v) in [
                ("length [m]", s.length),
                ("ea [N]", s.ea),
                ("mass_per_length [kg/m]", s.mass_per_length),
                ("diameter [m]", s.diameter),
                ("breaking_load [N]", s.breaking_load),
            ] {
                if let Some(v) = v {
                    positive(format!("sling {k}: {name}"), v)?;
                }
            }
            if let Some(d) = s.damping
                && !(d.is_finite() && d >= 0.0)
            {
                return Err(format!(
                    "sling {k}: damping [N s] must be finite and >= 0, got {d}"
                ));
            }
        }
        Ok(())
    }
}

/// Refuses an inertia tensor that is not symmetric positive definite or breaks the triangle
/// inequality of principal moments (no rigid body has it).
fn check_inertia(i: &Mat3) -> Result<(), String> {
    if !i.iter().all(|x| x.is_finite()) {
        return Err("block inertia is not finite".into());
    }
    let scale = i.trace().abs().max(1e-300);
    if (i - i.transpose()).amax() > 1e-9 * scale {
        return Err("block inertia must be symmetric".into());
    }
    let e = i.symmetric_eigenvalues();
    let (a, b, c) = (e[0], e[1], e[2]);
    if !(a.is_finite() && b.is_finite() && c.is_finite()) || a <= 0.0 || b <= 0.0 || c <= 0.0 {
        return Err(format!(
            "block inertia must be positive definite (principal moments {a:.4e}, {b:.4e}, {c:.4e} kg m2)"
        ));
    }
    let tol = 1e-9 * scale;
    if a > b + c + tol || b > a + c + tol || c > a + b + tol {
        return Err(format!(
            "block inertia: principal moments {a:.4e}, {b:.4e}, {c:.4e} kg m2 break the triangle inequality (no rigid body has them)"
        ));
    }
    Ok(())
}
