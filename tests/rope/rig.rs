//! Test rigs: a rope wrapped over one or more plate edges of a block, pulled at both ends.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::Profile;
use mbcosim::rope::shell::ShellMesh;
use mbcosim::rope::{RopeProps, SlipMode};
use mbcosim::scene::rope_block::{
    BlockSpec, BodyRef, ContactSettings, EndSpec, ForceSpec, LoadSpec, NodeContact, NodeSpec,
    RopeBlockSim, RopeSpec, Structure,
};
use std::sync::Arc;

/// Friction coefficient of the steel rope of issue #19.
pub const STEEL_MU: f64 = 0.2;

/// The steel rope of issue #19: EA 7.5e7 N, 6.4 kg/m, mu 0.2, axial damping 7.5e3 N s.
pub fn steel_rope() -> RopeProps {
    RopeProps {
        mass_per_length: 6.4,
        ea: 7.5e7,
        axial_damping: 7.5e3,
        friction: STEEL_MU,
        ..RopeProps::default()
    }
}

/// A prism along z of the given cross-section (x, y), counter-clockwise, from z = -h to h.
pub fn prism(section: &[(f64, f64)], h: f64) -> ShellMesh {
    let n = section.len();
    let mut v: Vec<Vec3> = section.iter().map(|&(x, y)| Vec3::new(x, y, -h)).collect();
    v.extend(section.iter().map(|&(x, y)| Vec3::new(x, y, h)));
    let (cx, cy) = section.iter().fold((0.0, 0.0), |a, p| {
        (a.0 + p.0 / n as f64, a.1 + p.1 / n as f64)
    });
    v.push(Vec3::new(cx, cy, -h));
    v.push(Vec3::new(cx, cy, h));
    let (c0, c1) = (2 * n as u32, 2 * n as u32 + 1);
    let n32 = n as u32;
    let mut t = Vec::new();
    for k in 0..n32 {
        let k1 = (k + 1) % n32;
        t.push([k, k1, k1 + n32]);
        t.push([k, k1 + n32, k + n32]);
        t.push([c0, k1, k]);
        t.push([c1, k + n32, k1 + n32]);
    }
    ShellMesh::new(v, t, 1e-3).unwrap()
}

/// A knife-edge wedge with its apex edge along z through the origin, pointing up (+y), with the
/// given full apex angle [rad].
pub fn wedge(apex: f64) -> ShellMesh {
    let h = 1.0;
    let w = h * (0.5 * apex).tan();
    prism(&[(0.0, 0.0), (-w, -h), (w, -h)], 1.0)
}

/// A regular polygon of `m` sides and circumradius `r`, a vertex-pair symmetric about the y
/// axis, as a prism along z.
pub fn polygon(m: usize, r: f64) -> ShellMesh {
    let d = 2.0 * std::f64::consts::PI / m as f64;
    let sec: Vec<(f64, f64)> = (0..m)
        .map(|j| {
            let a = 0.5 * std::f64::consts::PI + 0.5 * d + j as f64 * d;
            (r * a.cos(), r * a.sin())
        })
        .collect();
    prism(&sec, 1.0)
}

/// How the block is held.
#[derive(Debug, Clone, Copy)]
pub enum Hold {
    /// Welded to the ground.
    Fixed,
    /// Free, of the given mass [kg], with forces balancing the rope's pull at the strand
    /// departure points.
    Free(f64),
}

/// A rope wrapped over `vertices` (contact nodes on plate edges of `mesh`, block frame = world),
/// leaving the first vertex towards `e1` and the last towards `e2` in straight strands of
/// `strand` [m] with `nodes` interior nodes each, ending at loads of `end_mass` pulled by
/// `T1 = f1(t)` and `T2 = f2(t)` [N]. Initial tensions: `t_init[j]` on wrapped segment `j`
/// (strand 1, chords, strand 2).
pub struct Wrap {
    pub mesh: Arc<ShellMesh>,
    pub vertices: Vec<Vec3>,
    pub e1: Vec3,
    pub e2: Vec3,
    pub strand: f64,
    pub nodes: usize,
    pub props: RopeProps,
    pub t_init: Vec<f64>,
    pub end_mass: f64,
    pub f1: Profile,
    pub f2: Profile,
    pub hold: Hold,
    pub gravity: Option<Vec3>,
    pub mode: SlipMode,
    /// Tension gradient along strand 1 and strand 2 [N/m], from the vertex towards the end.
    pub grad: [f64; 2],
    /// Share of its lumped mass a contact node keeps; the rest goes to its neighbours.
    pub contact_mass: f64,
}

/// Nearest plate edge to `p`.
pub fn edge_at(mesh: &ShellMesh, p: &Vec3) -> usize {
    let d = |k: usize| {
        let e = &mesh.edges[k];
        let t = (p - e.a).dot(&e.dir).clamp(0.0, e.length);
        (e.a + e.dir * t - p).norm()
    };
    (0..mesh.edges.len())
        .min_by(|&a, &b| d(a).total_cmp(&d(b)))
        .unwrap()
}

impl Wrap {
    /// A rope over `vertices` of `mesh` leaving along `e1` and `e2`, both ends pulled by a
    /// constant `t` [N] on 50 kg loads, starting at `t` everywhere in forward slip without
    /// gravity: 2 m strands of 3 interior nodes, contact nodes keeping their whole mass, the
    /// nodes fixed on their edges. Tests change what they need with `..Wrap::pulled(..)`.
    pub fn pulled(
        mesh: ShellMesh,
        vertices: Vec<Vec3>,
        (e1, e2): (Vec3, Vec3),
        props: RopeProps,
        t: f64,
    ) -> Wrap {
        let chords = vertices.len().saturating_sub(1);
        Wrap {
            mesh: Arc::new(mesh),
            vertices,
            e1,
            e2,
            strand: 2.0,
            nodes: 3,
            props,
            t_init: vec![t; chords + 2],
            end_mass: 50.0,
            f1: Profile::constant(t),
            f2: Profile::constant(t),
            hold: Hold::Fixed,
            gravity: None,
            mode: SlipMode::SlipForward,
            grad: [0.0; 2],
            contact_mass: 1.0,
        }
    }

    /// The structure: block 0, loads 0 (end 1) and 1 (end 2), one rope.
    pub fn structure(&self) -> Structure {
        let ea = self.props.ea;
        let rho = self.props.mass_per_length;
        let k = self.vertices.len();
        let p1 = self.vertices[0] + self.e1 * self.strand;
        let p2 = self.vertices[k - 1] + self.e2 * self.strand;
        // geometric points of the rope from P1 to P2 with segment tensions
        let mut pts: Vec<(Vec3, Option<usize>)> = Vec::new();
        let mut tens = Vec::new();
        let seg = self.strand / (self.nodes + 1) as f64;
        for i in 0..=self.nodes {
            let f = i as f64 / (self.nodes + 1) as f64;
            pts.push((p1 + (self.vertices[0] - p1) * f, None));
            let d = self.strand - (i as f64 + 0.5) * seg;
            tens.push(self.t_init[0] - self.grad[0] * d);
        }
        for (j, v) in self.vertices.iter().enumerate() {
            pts.push((*v, Some(edge_at(&self.mesh, v))));
            if j + 1 < k {
                tens.push(self.t_init[j + 1]);
            }
        }
        for i in 1..=self.nodes + 1 {
            let f = i as f64 / (self.nodes + 1) as f64;
            pts.push((self.vertices[k - 1] + (p2 - self.vertices[k - 1]) * f, None));
            if i <= self.nodes {
                let d = (i as f64 - 0.5) * seg;
                tens.push(self.t_init[k] - self.grad[1] * d);
            } else {
                tens.push(self.t_init[k] - self.grad[1] * (self.strand - 0.5 * seg));
            }
        }
        // rest lengths from the initial tensions
        let mut sigma = vec![0.0];
        for j in 0..pts.len() - 1 {
            let l = (pts[j + 1].0 - pts[j].0).norm();
            sigma.push(sigma[j] + l / (1.0 + tens[j] / ea));
        }
        let n = pts.len();
        let mut mass: Vec<f64> = (0..n)
            .map(|i| {
                if i == 0 || i == n - 1 {
                    return 0.0;
                }
                let mut m = 0.5 * rho * (sigma[i + 1] - sigma[i - 1]);
                if i == 1 {
                    m += 0.5 * rho * sigma[1];
                }
                if i == n - 2 {
                    m += 0.5 * rho * (sigma[n - 1] - sigma[n - 2]);
                }
                m
            })
            .collect();
        for i in 1..n - 1 {
            if pts[i].1.is_some() && pts[i - 1].1.is_none() && pts[i + 1].1.is_none() {
                let give = (1.0 - self.contact_mass) * mass[i];
                mass[i] -= give;
                mass[i - 1] += 0.5 * give;
                mass[i + 1] += 0.5 * give;
            }
        }
        let mut nodes = Vec::new();
        for i in 1..n - 1 {
            nodes.push(NodeSpec {
                mass: mass[i],
                sigma: sigma[i],
                position: pts[i].0,
                velocity: Vec3::zeros(),
                contact: pts[i].1.map(|e| NodeContact {
                    block: 0,
                    edge: e,
                    anchor: pts[i].0,
                    mode: self.mode,
                    mu_rope: self.props.friction,
                    cap: mbcosim::scene::rope_block::structure::INITIAL_EDGE_CAPACITY,
                }),
            });
        }
        let (mass, fixed) = match self.hold {
            Hold::Fixed => (1000.0, true),
            Hold::Free(m) => (m, false),
        };
        let mut forces = vec![
            ForceSpec {
                body: BodyRef::Load(0),
                local: Vec3::zeros(),
                direction: self.e1,
                magnitude: self.f1,
            },
            ForceSpec {
                body: BodyRef::Load(1),
                local: Vec3::zeros(),
                direction: self.e2,
                magnitude: self.f2,
            },
        ];
        if let Hold::Free(_) = self.hold {
            forces.push(ForceSpec {
                body: BodyRef::Block(0),
                local: self.vertices[0],
                direction: -self.e1,
                magnitude: self.f1,
            });
            forces.push(ForceSpec {
                body: BodyRef::Block(0),
                local: self.vertices[k - 1],
                direction: -self.e2,
                magnitude: self.f2,
            });
        }
        let r2 = mass * 0.5;
        Structure {
            gravity: self.gravity,
            blocks: vec![BlockSpec {
                name: "block".into(),
                mass,
                inertia: Mat3::from_diagonal(&Vec3::new(r2, r2, r2)),
                mesh: Some(self.mesh.clone()),
                position: Vec3::zeros(),
                velocity: Vec3::zeros(),
                orientation: Quat::identity(),
                omega: Vec3::zeros(),
                fixed,
            }],
            loads: vec![
                LoadSpec {
                    name: "end1".into(),
                    mass: self.end_mass,
                    position: p1,
                    velocity: Vec3::zeros(),
                },
                LoadSpec {
                    name: "end2".into(),
                    mass: self.end_mass,
                    position: p2,
                    velocity: Vec3::zeros(),
                },
            ],
            hooks: vec![],
            ropes: vec![RopeSpec {
                name: "rope".into(),
                props: self.props,
                nominal_segment: self.strand / (self.nodes + 1) as f64,
                start: EndSpec::Load(0),
                end: EndSpec::Load(1),
                sigma_start: 0.0,
                sigma_end: sigma[n - 1],
                nodes,
            }],
            forces,
            dampers: vec![],
            ground: None,
        }
    }

    /// A rope wrapped 180 degrees around a `k`-edge half of a regular `2k`-gon of circumradius
    /// `r` [m] (one contact node per edge), both strands hanging along -y, 1.5 m long with 2
    /// nodes, 100 kg end loads pulled by `f1`, `f2` [N], every node sticking at `t1` [N] at first.
    pub fn drum(
        k: usize,
        r: f64,
        t1: f64,
        props: RopeProps,
        f: (Profile, Profile),
        hold: Hold,
    ) -> Self {
        let d = std::f64::consts::PI / k as f64;
        let vertices = (1..=k)
            .map(|j| {
                let a = 0.5 * std::f64::consts::PI + (k as f64 + 1.0 - 2.0 * j as f64) * 0.5 * d;
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        Wrap {
            mesh: Arc::new(polygon(2 * k, r)),
            vertices,
            e1: Vec3::new(0.0, -1.0, 0.0),
            e2: Vec3::new(0.0, -1.0, 0.0),
            strand: 1.5,
            nodes: 2,
            props,
            t_init: vec![t1; k + 1],
            end_mass: 100.0,
            f1: f.0,
            f2: f.1,
            hold,
            gravity: None,
            mode: SlipMode::Stick,
            grad: [0.0; 2],
            contact_mass: 1.0,
        }
    }

    /// A simulation of the rig (no detection of new crossings).
    pub fn sim(&self, settings: Settings) -> RopeBlockSim {
        RopeBlockSim::new(
            self.structure(),
            IntegratorKind::GenAlpha,
            settings,
            ContactSettings {
                detect: false,
                ..ContactSettings::default()
            },
            0.0,
        )
        .unwrap()
    }
}

/// The sliding drum of the report and cost checks, with `k` edges: an
/// undamped steel rope (EA 7.5e7 N, 6.4 kg/m, mu 0.2), circumradius 0.52 m, pulled at 9.81 kN and
/// 2.2 times that.
pub fn sliding_drum(k: usize) -> Wrap {
    let t1 = 9.81e3;
    let props = RopeProps {
        mass_per_length: 6.4,
        ea: 7.5e7,
        axial_damping: 0.0,
        friction: 0.2,
        ..RopeProps::default()
    };
    let pulls = (Profile::constant(t1), Profile::constant(2.2 * t1));
    Wrap::drum(k, 0.52, t1, props, pulls, Hold::Fixed)
}

/// Settings for quasi-static rope tests.
pub fn settings(h_max: f64) -> Settings {
    Settings {
        rtol: 1e-6,
        atol: 1e-7,
        h_max,
        ..Settings::default()
    }
}
