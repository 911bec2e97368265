//! A force and a torque on one body's frame origin (the centre of mass of a rigid body), their
//! components read from six model inputs, in the world frame or in the body frame (a follower
//! load: thrusters and reaction wheels fixed to a satellite).
//!
//! With `R` the body's rotation (body to world) and the inputs `F`, `T`:
//! - world frame: force `F` on the translations, torque `R^T T` on the rotations (body frame);
//! - body frame: force `R F` on the translations, torque `T` on the rotations.
//!
//! Jacobians `K = -df/dx` (body-frame rotation increment `dtheta`, `R' = R (I + dtheta~)`):
//! world frame `K_rot,rot = -(R^T T)~`; body frame `K_trans,rot = R F~`. No `D` blocks.

use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::{Mat3, Matrix6, Vec3, skew};
use crate::model::BodyId;
use crate::model::kinematics::{BodyKin, kin_of};

/// Frame in which the components of an input-driven load are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum LoadFrame {
    /// Components along the world (inertial) axes.
    World,
    /// Components along the body axes: the load turns with the body.
    #[default]
    Body,
}

/// One body's input-driven force and torque.
#[derive(Debug, Clone, PartialEq)]
pub struct InputLoad {
    pub name: String,
    pub body: BodyId,
    /// Model input indices of the force components x, y, z [N].
    pub force_inputs: [usize; 3],
    /// Model input indices of the torque components x, y, z [N m].
    pub torque_inputs: [usize; 3],
    /// Frame of both the force and the torque components.
    pub frame: LoadFrame,
}

impl InputLoad {
    /// Force [N] and torque [N m] as given, in [`InputLoad::frame`].
    fn components(&self, inputs: &[f64]) -> (Vec3, Vec3) {
        let read =
            |idx: &[usize; 3]| Vec3::from_fn(|i, _| inputs.get(idx[i]).copied().unwrap_or(0.0));
        (read(&self.force_inputs), read(&self.torque_inputs))
    }

    /// Force in the world frame [N] and torque in the body frame [N m].
    fn world_force_body_torque(&self, k: &BodyKin, inputs: &[f64]) -> (Vec3, Vec3) {
        let (f, t) = self.components(inputs);
        match self.frame {
            LoadFrame::World => (f, k.rot.transpose() * t),
            LoadFrame::Body => (k.rot * f, t),
        }
    }
}

/// All input-driven body loads of a model.
#[derive(Debug, Clone)]
pub struct InputLoads {
    pub elements: Vec<InputLoad>,
}

impl ForceEffect for InputLoads {
    fn name(&self) -> &str {
        "input-load"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let k = kin_of(ctx.kins, e.body);
            if !k.is_free() {
                continue;
            }
            let (force, torque) = e.world_force_body_torque(k, ctx.inputs);
            for i in 0..3 {
                f[k.col + i] += force[i];
            }
            if k.rotational {
                for i in 0..3 {
                    f[k.col + 3 + i] += torque[i];
                }
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let k = kin_of(ctx.kins, e.body);
            let (force, torque) = e.components(ctx.inputs);
            let mut k6 = Matrix6::zeros();
            if k.rotational {
                match e.frame {
                    LoadFrame::World => k6
                        .fixed_view_mut::<3, 3>(3, 3)
                        .copy_from(&(-skew(&(k.rot.transpose() * torque)))),
                    LoadFrame::Body => {
                        let block: Mat3 = k.rot * skew(&force);
                        k6.fixed_view_mut::<3, 3>(0, 3).copy_from(&block);
                    }
                }
            }
            sink.add(k, k, &k6, &Matrix6::zeros());
        }
    }

    fn input_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let k = kin_of(ctx.kins, e.body);
                let (force, torque) = e.world_force_body_torque(k, ctx.inputs);
                force.dot(&k.v) + torque.dot(&k.omega)
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;

    struct Capture(Matrix6<f64>);
    impl JacobianSink for Capture {
        fn add(&mut self, _: &BodyKin, _: &BodyKin, k: &Matrix6<f64>, _: &Matrix6<f64>) {
            self.0 += k;
        }
    }

    /// The analytic `K` against central differences of the forces in the rotation increment.
    #[test]
    fn jacobian_matches_finite_differences() {
        let inputs = [0.0, 3.0, -1.0, 2.0, 0.5, -4.0, 1.5];
        for frame in [LoadFrame::World, LoadFrame::Body] {
            let loads = InputLoads {
                elements: vec![InputLoad {
                    name: "load".into(),
                    body: BodyId(0),
                    force_inputs: [1, 2, 3],
                    torque_inputs: [4, 5, 6],
                    frame,
                }],
            };
            let rot = Quat::from_euler_angles(0.3, -0.7, 1.1)
                .to_rotation_matrix()
                .into_inner();
            let kin = |rot: Mat3| BodyKin {
                r: Vec3::new(1.0, 2.0, 3.0),
                rot,
                v: Vec3::zeros(),
                omega: Vec3::zeros(),
                col: 0,
                rotational: true,
            };
            let forces = |rot: Mat3| {
                let kins = [kin(rot)];
                let ctx = EvalCtx {
                    t: 0.0,
                    kins: &kins,
                    inputs: &inputs,
                    memory: &[],
                    frozen: &[],
                };
                let mut f = [0.0; 6];
                loads.add_forces(&ctx, &mut f);
                f
            };
            let kins = [kin(rot)];
            let ctx = EvalCtx {
                t: 0.0,
                kins: &kins,
                inputs: &inputs,
                memory: &[],
                frozen: &[],
            };
            let mut cap = Capture(Matrix6::zeros());
            loads.add_jacobian(&ctx, &mut cap);
            let h = 1e-6;
            for j in 0..3 {
                let mut d = Vec3::zeros();
                d[j] = h;
                let turn = |s: f64| {
                    rot * crate::math::exp_so3(&(s * d))
                        .to_rotation_matrix()
                        .into_inner()
                };
                let (fp, fm) = (forces(turn(1.0)), forces(turn(-1.0)));
                for i in 0..6 {
                    let fd = -(fp[i] - fm[i]) / (2.0 * h);
                    assert!(
                        (fd - cap.0[(i, 3 + j)]).abs() < 1e-7,
                        "{frame:?} K[{i},{}] = {} vs finite difference {fd}",
                        3 + j,
                        cap.0[(i, 3 + j)]
                    );
                }
            }
        }
    }
}
