//! The scene's plain parameter struct (what an FMU exposes as parameters) and its assembly into a
//! [`Structure`].
//!
//! Frames: the block's **design frame** has `x` along its length, `y` across, `z` up from the
//! bottom (as [`BlockShape`]); lugs are given in it. The block's body frame is the design frame
//! shifted to the centre of mass. The world frame has `z` up, gravity `-z`.

use super::rig::{BlockGeometry, BlockRig, Lug, Rig, RigHook, RigSling};
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
    /// Block mass [kg] where the rig gives none (the FMU's `block_mass`).
    pub block_mass: f64,
    /// The rig: block geometry and mass properties, lugs, slings, hooks.
    pub rig: Rig,
    /// World position of the design-frame origin [m] and the block's orientation.
    pub block_origin: Vec3,
    pub block_orientation: Quat,
    /// Rope properties of every sling where the rig gives none (EA, mass per length, diameter,
    /// damping, breaking load), and of all slings (friction, bending, drag).
    pub rope: RopeProps,
    /// Segments per sling.
    pub segments: usize,
    /// Time over which a hook reaches a newly commanded velocity or pay-out rate [s].
    pub hook_ramp: f64,
    /// Gravity [m/s^2] along -z (0: off).
    pub gravity: f64,
    /// Rope-edge contact on or off (off: ropes pass through the block).
    pub contact: bool,
    /// Block-ground contact (`None`: no ground, not assembled).
    pub ground: Option<GroundParams>,
    /// Start from the static equilibrium (hanging at rest).
    pub settle: bool,
    /// Integrator, tolerances (0: [`DEFAULT_RTOL`] / [`DEFAULT_ATOL`], see
    /// [`RopeBlockParams::tolerances`]), largest step [s].
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

impl crate::scene::param_spec::SolverKnobs for RopeBlockParams {
    fn knobs(&self) -> [f64; 3] {
        [self.rtol, self.atol, self.h_max]
    }

    fn knobs_mut(&mut self) -> [&mut f64; 3] {
        [&mut self.rtol, &mut self.atol, &mut self.h_max]
    }
}

impl Default for RopeBlockParams {
    fn default() -> Self {
        RopeBlockParams {
            block_mass: 200e3,
            rig: Rig::default(),
            block_origin: Vec3::zeros(),
            block_orientation: Quat::identity(),
            rope: RopeProps::default(),
            segments: 100,
            hook_ramp: DEFAULT_HOOK_RAMP,
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
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
            h_max: 0.0125,
            rho_inf: 0.0,
            contact_outputs: 8,
        }
    }
}

/// The relative tolerance RopeBlock runs with by default, and when `rtol = 0` (the shared
/// declaration's "integrator's own default"; the reasons at [`RopeBlockParams::default`]).
pub const DEFAULT_RTOL: f64 = 3e-5;
/// The absolute tolerance (m, rad, m/s, rad/s) by default and when `atol = 0`.
pub const DEFAULT_ATOL: f64 = 1e-6;

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and > 0, got {v}"))
    }
}

impl RopeBlockParams {
    /// `(rtol, atol)` the integrator runs with: a value of 0 takes [`DEFAULT_RTOL`] /
    /// [`DEFAULT_ATOL`].
    pub fn tolerances(&self) -> (f64, f64) {
        let or_default = |v: f64, d: f64| if v == 0.0 { d } else { v };
        (
            or_default(self.rtol, DEFAULT_RTOL),
            or_default(self.atol, DEFAULT_ATOL),
        )
    }

    /// Checks every value; `Err` names the parameter and what is expected.
    pub fn validate(&self) -> Result<(), String> {
        positive("block mass [kg]", self.block_mass)?;
        if !(self.hook_ramp.is_finite() && (0.0..=MAX_HOOK_RAMP).contains(&self.hook_ramp)) {
            return Err(format!(
                "hook ramp time must be in [0, {MAX_HOOK_RAMP}] s, got {}",
                self.hook_ramp
            ));
        }
        let (rtol, atol) = self.tolerances();
        positive("rtol", rtol)?;
        positive("atol", atol)?;
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
        let total = self.segments.saturating_mul(self.rig.slings.len());
        if total > MAX_ROPE_SEGMENTS {
            return Err(format!(
                "{} slings of {} segments are {total} rope segments, over the cap of \
                 {MAX_ROPE_SEGMENTS} in a scene (MAX_ROPE_SEGMENTS; docs/bounded_inputs.md): \
                 use fewer segments per sling",
                self.rig.slings.len(),
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
        if self.contact_outputs > 1000 {
            return Err(format!(
                "contact output slots must be <= 1000, got {}",
                self.contact_outputs
            ));
        }
        self.rope.validate("rope")?;
        self.rig.validate()?;
        for (k, sl) in self.rig.slings.iter().enumerate() {
            sl.props(&self.rope).validate(&format!("sling {k}"))?;
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
        match &self.rig.block.geometry {
            BlockGeometry::Mesh { file, scale } => load(std::path::Path::new(file), *scale)
                .map_err(|e| format!("mesh_file `{file}` (mesh_scale {scale}): {e}")),
            BlockGeometry::Shape(shape) => shape.mesh(),
        }
    }

    /// The block's mesh file, if it is one.
    pub fn mesh_file(&self) -> Option<&str> {
        match &self.rig.block.geometry {
            BlockGeometry::Mesh { file, .. } => Some(file),
            BlockGeometry::Shape(_) => None,
        }
    }

    /// Block mass [kg]: the rig's, else derived from its plate, else [`Self::block_mass`].
    pub fn mass_of(&self, design: &ShellMesh) -> f64 {
        let b = &self.rig.block;
        match (b.mass, b.plate) {
            (Some(m), _) => m,
            (None, Some(p)) => design.area() * p.thickness * p.density,
            (None, None) => self.block_mass,
        }
    }

    /// Centre of gravity [m] (design frame), inertia about it [kg m^2] and mass [kg] of the
    /// block whose shell is `design`.
    pub fn mass_properties(&self, design: &ShellMesh) -> (Vec3, Mat3, f64) {
        let mass = self.mass_of(design);
        let (centroid, shell_inertia) = shell_mass_properties(design, mass);
        let b = &self.rig.block;
        let com = b.cog.unwrap_or(centroid);
        // a thin shell about a moved centre of gravity: parallel-axis theorem
        let d = com - centroid;
        let shifted =
            shell_inertia + (Mat3::identity() * d.norm_squared() - d * d.transpose()) * mass;
        (com, b.inertia.unwrap_or(shifted), mass)
    }

    /// Assembles the structure: the block at its centre of mass, the hooks, the slings.
    pub fn structure(&self) -> Result<Structure, String> {
        self.validate()?;
        let design = self.design_mesh()?;
        let (com, inertia, mass) = self.mass_properties(&design);
        positive("block mass [kg]", mass)?;
        let mesh = Arc::new(design.translated(&(-com))?);
        let rot = self.block_orientation;
        let position = self.block_origin + rot * com;
        let block = BlockSpec {
            name: "block".into(),
            mass,
            inertia,
            mesh: self.contact.then(|| mesh.clone()),
            position,
            velocity: Vec3::zeros(),
            orientation: rot,
            omega: Vec3::zeros(),
            fixed: false,
        };
        let hooks = self.rig.hook_positions();
        let mut ropes = Vec::new();
        for (k, s) in self.rig.slings.iter().enumerate() {
            let lug_local = self.rig.lugs[s.lug].position - com;
            let route = self.route(k, &mesh, position, com, &hooks)?;
            let factor = match s.length {
                Some(l) => l / route_length(&route),
                None => s.length_factor,
            };
            ropes.push(lay_rope(
                &format!("sling{k}"),
                s.props(&self.rope),
                EndSpec::Hook(s.hook),
                EndSpec::Block {
                    block: 0,
                    local: lug_local,
                },
                &route,
                self.segments,
                factor,
            )?);
        }
        Ok(Structure {
            gravity: (self.gravity > 0.0).then(|| Vec3::new(0.0, 0.0, -self.gravity)),
            blocks: vec![block],
            loads: vec![],
            hooks: hooks.iter().map(|h| HookInit::at(*h)).collect(),
            ropes,
            forces: vec![],
            dampers: vec![],
            ground: self.ground.map(|g| g.spec(&mesh)).transpose()?,
        })
    }

    /// The initial route of sling `k` (world): hook, the edge point it wraps (if any), lug.
    /// `mesh` is in the block frame (centre of mass `com`, design frame, at world `position`).
    pub(crate) fn route(
        &self,
        k: usize,
        mesh: &ShellMesh,
        position: Vec3,
        com: Vec3,
        hooks: &[Vec3],
    ) -> Result<Vec<Waypoint>, String> {
        let s = &self.rig.slings[k];
        let rot = self.block_orientation;
        let lug_local = self.rig.lugs[s.lug].position - com;
        let lug_world = position + rot * lug_local;
        let hook = hooks[s.hook];
        let mut route = vec![Waypoint {
            position: hook,
            contact: None,
        }];
        let inv = rot.inverse();
        let via = match s.route {
            _ if !self.contact => None,
            Route::Straight => None,
            Route::OverEdge => wrap_edge(mesh, &(inv * (hook - position)), &lug_local),
            Route::Via(p) => {
                let x = p - com;
                let (edge, d) = nearest_edge(mesh, &x);
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
        Ok(route)
    }
}

/// Length of a route [m] (sum of its legs).
pub fn route_length(route: &[Waypoint]) -> f64 {
    route
        .windows(2)
        .map(|w| (w[1].position - w[0].position).norm())
        .sum()
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
        let shape = box_of(&base.rig);
        let h = shape.height;
        let mut sling = RigSling::new(0, 0);
        sling.route = Route::Straight;
        RopeBlockParams {
            segments,
            contact: false,
            rig: Rig {
                block: BlockRig {
                    geometry: BlockGeometry::Shape(shape),
                    ..base.rig.block.clone()
                },
                lugs: vec![Lug {
                    position: Vec3::new(0.0, 0.0, h),
                }],
                slings: vec![sling],
                hooks: vec![RigHook {
                    position: Vec3::new(0.0, 0.0, h + 19.0),
                    crane: 0,
                }],
            },
            ..base
        }
    }

    /// A turn-over in the air: crane A holds two slings over the deck edge at `y = +B/2`, crane B
    /// two slings from lugs under the bottom plate around the bottom edge at `y = -B/2`; lowering
    /// hook B turns the block about its length.
    pub fn turnover() -> Self {
        let base = Self::default();
        let shape = box_of(&base.rig);
        let (b, h) = (shape.breadth, shape.height);
        let lugs = vec![
            Lug {
                position: Vec3::new(5.0, 0.5 * b + 0.3, h - 1.0),
            },
            Lug {
                position: Vec3::new(-5.0, 0.5 * b + 0.3, h - 1.0),
            },
            Lug {
                position: Vec3::new(5.0, -0.5 * b + 1.0, -0.3),
            },
            Lug {
                position: Vec3::new(-5.0, -0.5 * b + 1.0, -0.3),
            },
        ];
        let bsl = |lug: usize, sx: f64| RigSling {
            route: Route::Via(Vec3::new(sx * 5.0, -0.5 * b, 0.0)),
            ..RigSling::new(lug, 1)
        };
        RopeBlockParams {
            rig: Rig {
                block: BlockRig {
                    geometry: BlockGeometry::Shape(shape),
                    ..base.rig.block.clone()
                },
                lugs,
                slings: vec![
                    RigSling::new(0, 0),
                    RigSling::new(1, 0),
                    bsl(2, 1.0),
                    bsl(3, -1.0),
                ],
                hooks: vec![
                    RigHook {
                        position: Vec3::new(0.0, 0.5 * b + 2.0, h + 16.0),
                        crane: 0,
                    },
                    RigHook {
                        position: Vec3::new(0.0, -0.5 * b - 2.0, h + 16.0),
                        crane: 1,
                    },
                ],
            },
            segments: 60,
            ..base
        }
    }
}

/// The default rig's block as a plain box (no bilge).
fn box_of(rig: &Rig) -> BlockShape {
    BlockShape {
        bilge_radius: 0.0,
        ..rig.shape().copied().unwrap_or_default()
    }
}

/// Default time over which a hook reaches a new command [s].
pub const DEFAULT_HOOK_RAMP: f64 = 0.5;
/// Longest hook ramp time accepted [s].
pub const MAX_HOOK_RAMP: f64 = 60.0;

/// Most segments per sling [`RopeBlockParams::validate`] accepts with DOPRI5 (at 32 one 0.05 s
/// step of the default scene costs ~0.7 s CPU; the cost grows ~ segments^3.5).
pub const MAX_DOPRI5_SEGMENTS: usize = 32;

/// Most rope segments a scene may have over all its slings: 64 slings (the rig's cap) of 400
/// segments (the FMU's largest `segments`); the scene is built and settled at initialization,
/// and its cost grows with this total (docs/bounded_inputs.md).
pub const MAX_ROPE_SEGMENTS: usize = 25_600;
