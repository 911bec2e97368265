//! The scene's plain parameter struct (what an FMU exposes as parameters) and its assembly into a
//! [`Structure`].
//!
//! Frames: the block's **design frame** has `x` along its length, `y` across, `z` up from the
//! bottom (as [`BlockShape`]); lugs are given in it. The block's body frame is the design frame
//! shifted to the centre of mass. The world frame has `z` up, gravity `-z`.

use super::rigging::{Waypoint, lay_rope, wrap_edge};
use super::structure::{BlockSpec, EndSpec, GroundSpec, Structure};
use crate::contact::{ContactLaw, LawKind};
use crate::integrator::IntegratorKind;
use crate::math::{Mat3, Quat, Vec3};
use crate::rope::shell::ShellMesh;
use crate::rope::shell::import::load;
use crate::rope::shell::mass::shell_mass_properties;
use crate::rope::shell::parametric::BlockShape;
use crate::rope::{HookInit, RopeProps};
use std::sync::Arc;

/// How a sling runs from its hook to its lug at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Route {
    /// Straight (no contact node at start; one is inserted if the rope later crosses an edge).
    Straight,
    /// Over the plate edge that the straight path cuts, at the shortest-path point.
    OverEdge,
    /// Through this point of a plate edge [m], block design frame (within 1 cm of the edge).
    Via(Vec3),
}

/// One sling: a rope from a hook to a lug on the block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlingParams {
    /// Hook index.
    pub hook: usize,
    /// Lug position [m], block design frame.
    pub lug: Vec3,
    /// Unstretched length as a fraction of the initial route length [-] (1: just taut).
    pub length_factor: f64,
    /// Initial route.
    pub route: Route,
}

/// Contact of the block with a flat, level ground (a turn-over that starts from or ends on the
/// ground, a block set down). The block touches it with the vertices of its hull, each through a
/// linear Flores law `k delta (1 + chi(e) delta_dot / v_ref)` ([`GROUND_REFERENCE_SPEED`]) and regularized Coulomb
/// friction ([`crate::effect::ground_contact`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundParams {
    /// Height of the ground [m], world z.
    pub height: f64,
    /// Stiffness per hull vertex [N/m] (the default 1e9 N/m sinks a 200 t block resting on four
    /// bottom corners by 0.5 mm: stiff supports such as steel or concrete blocks).
    pub stiffness: f64,
    /// Coefficient of restitution of an impact [-], in (0, 1].
    pub restitution: f64,
    /// Coulomb friction coefficient of the block on the ground [-] (steel on timber or concrete:
    /// about 0.3-0.5).
    pub mu: f64,
    /// Speed below which friction turns viscous [m/s] (no sticking: a block held at a fraction
    /// `r` of the friction limit creeps at `slip_speed r / sqrt(1 - r^2)`).
    pub slip_speed: f64,
}

/// Impact speed [m/s] at which the ground's restitution holds (a set-down speed): the contact
/// damping is `chi(e) k delta delta_dot / GROUND_REFERENCE_SPEED`, independent of the speed at
/// which a point touched down (see [`crate::effect::ground_contact`]).
pub const GROUND_REFERENCE_SPEED: f64 = 0.1;

impl Default for GroundParams {
    fn default() -> Self {
        GroundParams {
            height: 0.0,
            stiffness: 1e9,
            restitution: 0.5,
            mu: 0.3,
            slip_speed: 1e-3,
        }
    }
}

impl GroundParams {
    /// The normal law; `Err` names a bad value (also of the friction and the height).
    pub fn law(&self) -> Result<ContactLaw, String> {
        if !(self.mu.is_finite() && self.mu >= 0.0) {
            return Err(format!(
                "ground mu must be finite and >= 0, got {}",
                self.mu
            ));
        }
        positive("ground slip speed [m/s]", self.slip_speed)?;
        if !self.height.is_finite() {
            return Err(format!("ground height must be finite, got {}", self.height));
        }
        ContactLaw::new(LawKind::Flores, self.stiffness, 1.0, self.restitution)
            .and_then(|l| l.with_min_approach_speed(GROUND_REFERENCE_SPEED))
            .map_err(|e| format!("ground contact: {e}"))
    }

    /// The ground of the scene for a block whose shell mesh (block frame) is `mesh`.
    pub fn spec(&self, mesh: &ShellMesh) -> Result<GroundSpec, String> {
        let law = self.law()?;
        Ok(GroundSpec {
            height: self.height,
            law,
            mu: self.mu,
            slip_speed: self.slip_speed,
            points: mesh.hull_vertices().into_iter().map(|p| (0, p)).collect(),
        })
    }
}

/// Everything that defines a RopeBlock scene. `Default` is the default lift: a 200 t block of
/// 18 m x 12 m x 7 m (2 m bilge in 8 facets) hanging from one hook by four 60 mm steel slings of
/// about 22 m with 100 segments each, from lugs on the side shell 1 m below the deck edge, over the
/// deck edges, legs at about 25 degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct RopeBlockParams {
    /// Block mass [kg].
    pub block_mass: f64,
    /// Parametric block shape (used unless `mesh_file` is set).
    pub shape: BlockShape,
    /// OBJ or STL file of the shell plate in the design frame (overrides `shape`).
    pub mesh_file: Option<String>,
    /// Factor from the mesh file's units to metres.
    pub mesh_scale: f64,
    /// Inertia about the centre of mass [kg m^2], block frame; `None`: a uniform thin shell.
    pub inertia: Option<Mat3>,
    /// World position of the design-frame origin [m] and the block's orientation.
    pub block_origin: Vec3,
    pub block_orientation: Quat,
    /// Rope properties (all slings).
    pub rope: RopeProps,
    /// Segments per sling.
    pub segments: usize,
    /// Initial hook positions [m], world.
    pub hooks: Vec<Vec3>,
    pub slings: Vec<SlingParams>,
    /// Gravity [m/s^2] along -z (0: off).
    pub gravity: f64,
    /// Rope-edge contact on or off (off: ropes pass through the block).
    pub contact: bool,
    /// Block-ground contact (`None`: no ground, not assembled).
    pub ground: Option<GroundParams>,
    /// Start from the static equilibrium (hanging at rest).
    pub settle: bool,
    /// Integrator, tolerances, largest step [s].
    pub integrator: IntegratorKind,
    pub rtol: f64,
    pub atol: f64,
    pub h_max: f64,
    /// Generalized-alpha's spectral radius at infinite frequency [-] (1: no numerical damping,
    /// 0: unresolved modes removed within a step). RopeBlock uses 0: a lightly loaded sling's
    /// stiff axial modes (one segment against its neighbours, kHz, overdamped by the rope
    /// damping) ring at -rho_inf per step when unresolved, segments flip between slack and taut
    /// and the nonsmooth switches pump energy in (turn-over at 0.8: bursts of 36 us steps and
    /// 77 kJ of spurious dissipation after crane B's slings unload; at 0: none, 50x faster).
    pub rho_inf: f64,
    /// Number of contact-node output slots.
    pub contact_outputs: usize,
}

impl Default for RopeBlockParams {
    fn default() -> Self {
        let (l, b, h) = (18.0, 12.0, 7.0);
        let hook_height = h + 19.0;
        let lug = |sx: f64, sy: f64| Vec3::new(sx * 6.5, sy * (0.5 * b + 0.3), h - 1.0);
        let sling = |sx: f64, sy: f64| SlingParams {
            hook: 0,
            lug: lug(sx, sy),
            length_factor: 1.0,
            route: Route::OverEdge,
        };
        RopeBlockParams {
            block_mass: 200e3,
            shape: BlockShape {
                length: l,
                breadth: b,
                height: h,
                ..BlockShape::default()
            },
            mesh_file: None,
            mesh_scale: 1.0,
            inertia: None,
            block_origin: Vec3::zeros(),
            block_orientation: Quat::identity(),
            rope: RopeProps::default(),
            segments: 100,
            hooks: vec![Vec3::new(0.0, 0.0, hook_height)],
            slings: vec![
                sling(1.0, 1.0),
                sling(-1.0, 1.0),
                sling(-1.0, -1.0),
                sling(1.0, -1.0),
            ],
            gravity: 9.81,
            contact: true,
            ground: None,
            settle: true,
            integrator: IntegratorKind::GenAlpha,
            // rtol 3e-5: the lift costs what it does at 3e-4 (1,135 steps against 1,123, peak
            // sling tension to 0.002 % instead of 0.015 %; docs/rope_speed_bench.md), and slack
            // slings on a grounded block take fewer steps with a tighter energy balance (a
            // turn-over onto the ground: 6,687 steps and 1.4 kJ against 17,002 and 3.7 kJ; the
            // set-down until slack 1,146 steps and 14 J against 1,271 and 21 J): at 3e-4 the
            // Newton iterates of the slack segments are loose enough to trip more divergences;
            // 50 steps per period of the block's
            // 1.6 Hz bounce on the slings: with rho_inf 0 generalized-alpha damps that bounce by
            // 6 % per second at 0.025 s steps and 0.6 % at 0.0125 s (the physical damping is
            // 0.6 % of critical), the 12 s lift's hook-load history then stays within 1 % of the
            // weight of a rtol 1e-7 reference
            rtol: 3e-5,
            atol: 1e-6,
            h_max: 0.0125,
            rho_inf: 0.0,
            contact_outputs: 8,
        }
    }
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and > 0, got {v}"))
    }
}

impl RopeBlockParams {
    /// Checks every value; `Err` names the parameter and what is expected.
    pub fn validate(&self) -> Result<(), String> {
        positive("block mass [kg]", self.block_mass)?;
        positive("mesh scale", self.mesh_scale)?;
        positive("rtol", self.rtol)?;
        positive("atol", self.atol)?;
        positive("h_max [s]", self.h_max)?;
        if let Some(g) = &self.ground {
            g.law()?;
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return Err(format!("rho_inf must be in [0, 1], got {}", self.rho_inf));
        }
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(format!(
                "gravity must be finite and >= 0, got {}",
                self.gravity
            ));
        }
        if !(2..=100_000).contains(&self.segments) {
            return Err(format!(
                "segments per sling must be in 2..=100000, got {}",
                self.segments
            ));
        }
        if self.integrator == IntegratorKind::Dopri5 && self.segments > MAX_DOPRI5_SEGMENTS {
            return Err(format!(
                "integrator = dopri5 with segments = {} per sling: the explicit integrator is \
                 for coarse slings only (segments <= {MAX_DOPRI5_SEGMENTS}); its stable step \
                 shrinks with the segment length and one 0.05 s step at 100 segments took \
                 12 s CPU, at 263 segments 193 s (issue #25). Use gen_alpha or bdf",
                self.segments
            ));
        }
        if self.slings.is_empty() {
            return Err("at least one sling is needed".into());
        }
        if self.contact_outputs > 1000 {
            return Err(format!(
                "contact output slots must be <= 1000, got {}",
                self.contact_outputs
            ));
        }
        self.rope.validate("rope")?;
        for (k, h) in self.hooks.iter().enumerate() {
            if !h.iter().all(|x| x.is_finite()) {
                return Err(format!("hook {k}: position is not finite"));
            }
        }
        for (k, s) in self.slings.iter().enumerate() {
            if s.hook >= self.hooks.len() {
                return Err(format!(
                    "sling {k}: hook {} does not exist ({} hooks)",
                    s.hook,
                    self.hooks.len()
                ));
            }
            if !s.lug.iter().all(|x| x.is_finite()) {
                return Err(format!("sling {k}: lug position is not finite"));
            }
            positive(&format!("sling {k}: length factor"), s.length_factor)?;
        }
        if !self.block_origin.iter().all(|x| x.is_finite())
            || !self.block_orientation.coords.iter().all(|x| x.is_finite())
        {
            return Err("block origin or orientation is not finite".into());
        }
        Ok(())
    }

    /// The shell mesh in the design frame.
    pub fn design_mesh(&self) -> Result<ShellMesh, String> {
        match &self.mesh_file {
            Some(f) => load(std::path::Path::new(f), self.mesh_scale)
                .map_err(|e| format!("mesh_file `{f}` (mesh_scale {}): {e}", self.mesh_scale)),
            None => self.shape.mesh(),
        }
    }

    /// Assembles the structure: the block at its centre of mass, the hooks, the slings.
    pub fn structure(&self) -> Result<Structure, String> {
        self.validate()?;
        let design = self.design_mesh()?;
        let (com, shell_inertia) = shell_mass_properties(&design, self.block_mass);
        let inertia = self.inertia.unwrap_or(shell_inertia);
        let mesh = Arc::new(design.translated(&(-com))?);
        let rot = self.block_orientation;
        let position = self.block_origin + rot * com;
        let block = BlockSpec {
            name: "block".into(),
            mass: self.block_mass,
            inertia,
            mesh: self.contact.then(|| mesh.clone()),
            position,
            velocity: Vec3::zeros(),
            orientation: rot,
            omega: Vec3::zeros(),
            fixed: false,
        };
        let mut ropes = Vec::new();
        for (k, s) in self.slings.iter().enumerate() {
            let lug_local = s.lug - com;
            let lug_world = position + rot * lug_local;
            let hook = self.hooks[s.hook];
            let mut route = vec![Waypoint {
                position: hook,
                contact: None,
            }];
            let inv = rot.inverse();
            let via = match s.route {
                _ if !self.contact => None,
                Route::Straight => None,
                Route::OverEdge => wrap_edge(&mesh, &(inv * (hook - position)), &lug_local),
                Route::Via(p) => {
                    let x = p - com;
                    let (edge, d) = nearest_edge(&mesh, &x);
                    if d > 0.01 {
                        return Err(format!(
                            "sling {k}: via point is {d:.3} m from the nearest plate edge (must be on an edge)"
                        ));
                    }
                    let e = &mesh.edges[edge];
                    Some((edge, e.a + e.dir * (x - e.a).dot(&e.dir)))
                }
            };
            if let Some((edge, x)) = via {
                route.push(Waypoint {
                    position: position + rot * x,
                    contact: Some((0, edge, x)),
                });
            }
            route.push(Waypoint {
                position: lug_world,
                contact: None,
            });
            ropes.push(lay_rope(
                &format!("sling{k}"),
                self.rope,
                EndSpec::Hook(s.hook),
                EndSpec::Block {
                    block: 0,
                    local: lug_local,
                },
                &route,
                self.segments,
                s.length_factor,
            )?);
        }
        Ok(Structure {
            gravity: (self.gravity > 0.0).then(|| Vec3::new(0.0, 0.0, -self.gravity)),
            blocks: vec![block],
            loads: vec![],
            hooks: self.hooks.iter().map(|h| HookInit::at(*h)).collect(),
            ropes,
            forces: vec![],
            ground: self.ground.map(|g| g.spec(&mesh)).transpose()?,
        })
    }
}

/// The plate edge nearest to `x` (block frame) and the distance [m].
fn nearest_edge(mesh: &ShellMesh, x: &Vec3) -> (usize, f64) {
    let d = |k: usize| {
        let e = &mesh.edges[k];
        let t = (x - e.a).dot(&e.dir).clamp(0.0, e.length);
        (e.a + e.dir * t - x).norm()
    };
    (0..mesh.edges.len())
        .map(|k| (k, d(k)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, f64::INFINITY))
}

impl RopeBlockParams {
    /// The default block hanging straight below the hook from one sling of `segments` segments
    /// (19 m, from the deck's centre), without contact and with a plain box shape: the rope-
    /// resolution scene of the benchmarks and the stability suite.
    pub fn single_sling(segments: usize) -> Self {
        let base = Self::default();
        let h = base.shape.height;
        RopeBlockParams {
            segments,
            contact: false,
            hooks: vec![Vec3::new(0.0, 0.0, h + 19.0)],
            slings: vec![SlingParams {
                hook: 0,
                lug: Vec3::new(0.0, 0.0, h),
                length_factor: 1.0,
                route: Route::Straight,
            }],
            shape: BlockShape {
                bilge_radius: 0.0,
                ..base.shape
            },
            ..base
        }
    }

    /// A turn-over in the air: crane A holds two slings over the deck edge at `y = +B/2`, crane B
    /// two slings from lugs under the bottom plate around the bottom edge at `y = -B/2`; lowering
    /// hook B turns the block about its length.
    pub fn turnover() -> Self {
        let base = Self::default();
        let (b, h) = (base.shape.breadth, base.shape.height);
        let a = |sx: f64| SlingParams {
            hook: 0,
            lug: Vec3::new(sx * 5.0, 0.5 * b + 0.3, h - 1.0),
            length_factor: 1.0,
            route: Route::OverEdge,
        };
        let bsl = |sx: f64| SlingParams {
            hook: 1,
            lug: Vec3::new(sx * 5.0, -0.5 * b + 1.0, -0.3),
            length_factor: 1.0,
            route: Route::Via(Vec3::new(sx * 5.0, -0.5 * b, 0.0)),
        };
        RopeBlockParams {
            shape: BlockShape {
                bilge_radius: 0.0,
                ..base.shape
            },
            hooks: vec![
                Vec3::new(0.0, 0.5 * b + 2.0, h + 16.0),
                Vec3::new(0.0, -0.5 * b - 2.0, h + 16.0),
            ],
            slings: vec![a(1.0), a(-1.0), bsl(1.0), bsl(-1.0)],
            segments: 60,
            ..base
        }
    }
}

/// Most segments per sling [`RopeBlockParams::validate`] accepts with DOPRI5 (at 32 one 0.05 s
/// step of the default scene costs ~0.7 s CPU; the cost grows ~ segments^3.5).
pub const MAX_DOPRI5_SEGMENTS: usize = 32;
