//! Linear viscous dampers to the ground ([`DamperSpec`]): a test rig's element that makes a
//! quasi-static state of a pulled rig exist (an end load's swing and its strands' transverse
//! vibration damped, their motion along the strand free). Force on the body `F = -c P v` [N]
//! with the projector `P = I - a a^T` across the free axis `a`; dissipated power `c v^T P v` [W].

use super::structure::{DamperSpec, Structure};
use crate::effect::point_force::TwoPointForce;
use crate::effect::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::{Mat3, Vec3};
use crate::model::BodyId;
use crate::model::kinematics::{BodyKin, kin_of};

/// The dampers of a structure, each on its load's body.
#[derive(Debug, Clone)]
pub struct RigDampers {
    /// The load's body and its damper's matrix `c P` [N s/m].
    pub elements: Vec<(BodyId, Mat3)>,
}

impl RigDampers {
    /// The dampers of `s` on the bodies of its build: `loads` (by load number) and `nodes` (by
    /// rope, interior node).
    pub fn new(s: &Structure, loads: &[BodyId], nodes: &[Vec<BodyId>]) -> Self {
        let cp = |c: f64, a: &Vec3| c * (Mat3::identity() - a * a.transpose());
        let mut elements = Vec::new();
        for d in &s.dampers {
            match d {
                DamperSpec::Load {
                    load,
                    damping,
                    free_axis,
                } => elements.push((loads[*load], cp(*damping, free_axis))),
                DamperSpec::Strands {
                    rope,
                    damping,
                    free_axes,
                } => {
                    let spec = &s.ropes[*rope].nodes;
                    let first = spec.iter().position(|n| n.contact.is_some());
                    let last = spec.iter().rposition(|n| n.contact.is_some());
                    let (Some(first), Some(last)) = (first, last) else {
                        continue;
                    };
                    for (i, body) in nodes[*rope].iter().enumerate() {
                        if i < first {
                            elements.push((*body, cp(*damping, &free_axes[0])));
                        } else if i > last {
                            elements.push((*body, cp(*damping, &free_axes[1])));
                        }
                    }
                }
                DamperSpec::ContactNodes { rope, damping } => {
                    let spec = &s.ropes[*rope].nodes;
                    for (n, body) in spec.iter().zip(&nodes[*rope]) {
                        if n.contact.is_some() {
                            elements.push((*body, cp(*damping, &Vec3::zeros())));
                        }
                    }
                }
            }
        }
        RigDampers { elements }
    }

    /// The force of element `(body, cp)` as a two-point force from the ground (A) to the load
    /// (B): the load receives `-force`.
    fn evaluate<'a>(ctx: &'a EvalCtx, body: BodyId, cp: &Mat3) -> TwoPointForce<'a> {
        let load = kin_of(ctx.kins, body);
        TwoPointForce {
            a: &BodyKin::GROUND,
            s_a: Vec3::zeros(),
            b: load,
            s_b: Vec3::zeros(),
            force: cp * load.point_velocity(&Vec3::zeros()),
            kd: Mat3::zeros(),
            cd: *cp,
        }
    }
}

impl ForceEffect for RigDampers {
    fn name(&self) -> &str {
        "rig damper"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for (body, cp) in &self.elements {
            Self::evaluate(ctx, *body, cp).add_forces(f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for (body, cp) in &self.elements {
            Self::evaluate(ctx, *body, cp).add_jacobian(sink);
        }
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|(body, cp)| {
                let v = kin_of(ctx.kins, *body).point_velocity(&Vec3::zeros());
                v.dot(&(cp * v))
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effect::JacobianSink;
    use crate::math::Matrix6;

    /// Collects the load's own D block.
    struct Sink(Matrix6<f64>, usize);
    impl JacobianSink for Sink {
        fn add(&mut self, row: &BodyKin, col: &BodyKin, _k: &Matrix6<f64>, d: &Matrix6<f64>) {
            if row.is_free() && col.is_free() {
                self.0 += d;
                self.1 += 1;
            }
        }
    }

    /// A load moving at v = (1, 2, 3) m/s with c = 10 N s/m and the free axis x: force
    /// (0, -20, -30) N by hand, power 10 (4 + 9) = 130 W, D = c diag(0, 1, 1) on the speeds.
    #[test]
    fn damps_across_the_free_axis_only() {
        let s = Structure {
            loads: vec![super::super::structure::LoadSpec {
                name: "load".into(),
                mass: 1.0,
                position: Vec3::zeros(),
                velocity: Vec3::zeros(),
            }],
            dampers: vec![DamperSpec::Load {
                load: 0,
                damping: 10.0,
                free_axis: Vec3::x(),
            }],
            ..Structure::default()
        };
        let mut kin = BodyKin::GROUND;
        kin.col = 0;
        kin.v = Vec3::new(1.0, 2.0, 3.0);
        let kins = [kin];
        let ctx = EvalCtx {
            t: 0.0,
            kins: &kins,
            inputs: &[],
            memory: &[],
            frozen: &[],
        };
        let d = RigDampers::new(&s, &[BodyId(0)], &[]);
        let mut f = vec![0.0; 3];
        d.add_forces(&ctx, &mut f);
        assert_eq!(f, vec![0.0, -20.0, -30.0]);
        assert_eq!(d.dissipated_power(&ctx), 130.0);
        let mut sink = Sink(Matrix6::zeros(), 0);
        d.add_jacobian(&ctx, &mut sink);
        assert_eq!(sink.1, 1);
        let want = Matrix6::from_diagonal(&nalgebra::Vector6::new(0.0, 10.0, 10.0, 0.0, 0.0, 0.0));
        assert_eq!(sink.0, want);
    }

    /// A rope of five interior nodes, the third and fourth on edges: the strand damper takes
    /// nodes 0 and 1 across axis x and node 4 across axis y, nothing between the contact
    /// nodes; the contact-node damper takes nodes 2 and 3 in all directions.
    #[test]
    fn strand_and_contact_dampers_pick_their_nodes() {
        use super::super::structure::{NodeContact, NodeSpec, RopeSpec};
        let node = |contact: bool| NodeSpec {
            mass: 1.0,
            sigma: 0.0,
            position: Vec3::zeros(),
            velocity: Vec3::zeros(),
            contact: contact.then_some(NodeContact {
                block: 0,
                edge: 0,
                anchor: Vec3::zeros(),
                mode: crate::rope::SlipMode::Stick,
                mu_rope: 0.2,
                cap: 1.0,
            }),
        };
        let rope = RopeSpec {
            name: "rope".into(),
            props: crate::rope::RopeProps::default(),
            nominal_segment: 1.0,
            start: super::super::structure::EndSpec::Load(0),
            end: super::super::structure::EndSpec::Load(0),
            sigma_start: 0.0,
            sigma_end: 1.0,
            nodes: [false, false, true, true, false].map(node).to_vec(),
        };
        let s = Structure {
            ropes: vec![rope],
            dampers: vec![
                DamperSpec::Strands {
                    rope: 0,
                    damping: 2.0,
                    free_axes: [Vec3::x(), Vec3::y()],
                },
                DamperSpec::ContactNodes {
                    rope: 0,
                    damping: 3.0,
                },
            ],
            ..Structure::default()
        };
        let bodies: Vec<BodyId> = (10..15).map(BodyId).collect();
        let d = RigDampers::new(&s, &[], &[bodies]);
        let across = |a: Vec3| 2.0 * (Mat3::identity() - a * a.transpose());
        let want = vec![
            (BodyId(10), across(Vec3::x())),
            (BodyId(11), across(Vec3::x())),
            (BodyId(14), across(Vec3::y())),
            (BodyId(12), 3.0 * Mat3::identity()),
            (BodyId(13), 3.0 * Mat3::identity()),
        ];
        assert_eq!(d.elements, want);
    }
}
