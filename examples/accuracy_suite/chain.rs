//! Planar pendulum chains: N uniform rods (1 m, 1 kg, I = m l^2 / 12 about z) joined by revolute
//! joints about z, the first hinged at the origin, released at rest from horizontal (along +x),
//! gravity 9.81 m/s^2 along -y. Measured: the position of the chain's free end at the end time.
//!
//! Reference: the same chain in absolute rod angles theta_i (from the downward vertical),
//! `sum_j mu_ij cos(theta_i - theta_j) theta_j'' = -sum_j mu_ij sin(theta_i - theta_j) theta_j'^2
//! - g m l (N - i - 1/2) sin theta_i`, with `mu_ii = m l^2 (N - 1 - i + 1/4) + I` and
//! `mu_ij = m l^2 (N - 1 - max(i, j) + 1/2)`, integrated by order-16 extrapolation.

use crate::ode;
use crate::suite::{G, Problem, Reference, Trajectory};
use mbcosim::math::{Mat3, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder, kinematics};
use nalgebra::{DMatrix, DVector};

const M: f64 = 1.0;
const L: f64 = 1.0;
/// Rod inertia about its centre: the thin-rod value about y and z, a small one about the axis.
const I_Z: f64 = M * L * L / 12.0;
const I_X: f64 = 1e-4;

/// Duration [s] for a chain of `n` rods: 2 s for the double pendulum, 1 s for longer chains.
pub fn duration(n: usize) -> f64 {
    if n <= 2 { 2.0 } else { 1.0 }
}

/// The suite problem for a chain of `n` rods.
pub fn problem(n: usize, samples: usize) -> Result<Problem, String> {
    let t_end = duration(n);
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0)))?;
    let inertia = Mat3::from_diagonal(&Vec3::new(I_X, I_Z, I_Z));
    let half = Vec3::new(0.5 * L, 0.0, 0.0);
    let mut prev = (BodyId::GROUND, Vec3::zeros());
    let mut last = BodyId::GROUND;
    for k in 0..n {
        let id = b.add_rigid_body(
            &format!("rod{k}"),
            M,
            inertia,
            BodyInit::at(Vec3::new((k as f64 + 0.5) * L, 0.0, 0.0)),
        )?;
        b.add_joint(
            &format!("hinge{k}"),
            JointKind::Revolute,
            Frame::new(prev.0, prev.1),
            Frame::new(id, -half),
        )?;
        prev = (id, half);
        last = id;
    }
    let model = b.build()?;
    let body = model.body(last).ok_or("chain: last rod missing")?.q_offset;
    let reference = reference(n, t_end);
    let trajectory = Trajectory {
        uniform: samples,
        ..trajectory(n, &crate::suite::grid(t_end, samples))
    };
    Ok(Problem {
        h_max: None,
        name: format!("chain{n}"),
        title: format!(
            "{n} rods (1 m, 1 kg) hinged about z, released from horizontal, {t_end} s: tip position"
        ),
        t_end,
        quantity: "tip position error [m]",
        aux_name: None,
        approach_speed: None,
        model,
        measure: Box::new(move |sim| {
            let q = &sim.state.q;
            let r = Vec3::new(q[body], q[body + 1], q[body + 2]);
            let tip = r + kinematics::quat_at(q, body + 3) * Vec3::new(0.5 * L, 0.0, 0.0);
            vec![tip.x, tip.y]
        }),
        primary: 2,
        reference,
        trajectory,
    })
}

/// Right-hand side of the minimal-coordinate chain: `y = [theta, theta']`.
fn rhs(n: usize) -> impl Fn(f64, &[f64], &mut [f64]) {
    let mu = DMatrix::from_fn(n, n, |i, j| {
        if i == j {
            M * L * L * ((n - 1 - i) as f64 + 0.25) + I_Z
        } else {
            M * L * L * ((n - 1 - i.max(j)) as f64 + 0.5)
        }
    });
    move |_t, y, dy| {
        let (th, w) = (&y[..n], &y[n..]);
        let mut mass = DMatrix::zeros(n, n);
        let mut f = DVector::zeros(n);
        for i in 0..n {
            let mut fi = -G * M * L * ((n - i) as f64 - 0.5) * th[i].sin();
            for j in 0..n {
                let d = th[i] - th[j];
                mass[(i, j)] = mu[(i, j)] * d.cos();
                fi -= mu[(i, j)] * d.sin() * w[j] * w[j];
            }
            f[i] = fi;
        }
        let acc = mass
            .cholesky()
            .expect("the chain's mass matrix is positive definite")
            .solve(&f);
        dy[..n].copy_from_slice(w);
        dy[n..].copy_from_slice(acc.as_slice());
    }
}

/// Tip position of the chain for absolute angles `theta` (from the downward vertical).
pub fn tip(theta: &[f64]) -> Vec<f64> {
    let x: f64 = theta.iter().map(|t| L * t.sin()).sum();
    let y: f64 = theta.iter().map(|t| -L * t.cos()).sum();
    vec![x, y]
}

fn initial(n: usize) -> Vec<f64> {
    let mut y0 = vec![std::f64::consts::FRAC_PI_2; n];
    y0.extend(std::iter::repeat_n(0.0, n));
    y0
}

/// The same ODE converged at every sample time (the state carried from one to the next).
pub fn trajectory(n: usize, times: &[f64]) -> Trajectory {
    let t_end = *times.last().expect("sample times");
    let c = ode::converge_samples(
        &rhs(n),
        &initial(n),
        times,
        (25.0 * t_end).ceil() as usize,
        1e-13,
        8,
        &|y| tip(&y[..n]),
    );
    Trajectory {
        uniform: times.len(),
        times: times.to_vec(),
        values: c.outputs,
        estimated_error: c.estimated_error,
        method: format!(
            "the joint-angle ODE converged at each sample time, {} macro steps, checked against half as many",
            c.macro_steps
        ),
    }
}

/// The converged minimal-coordinate solution at `t_end`.
pub fn reference(n: usize, t_end: f64) -> Reference {
    let mut y0 = vec![std::f64::consts::FRAC_PI_2; n];
    y0.extend(std::iter::repeat_n(0.0, n));
    let f = rhs(n);
    let c = ode::converge(
        &f,
        &y0,
        t_end,
        (25.0 * t_end).ceil() as usize,
        1e-13,
        8,
        &|y| tip(&y[..n]),
    );
    Reference {
        value: c.output,
        estimated_error: c.estimated_error,
        method: format!(
            "joint-angle ODE (N = {n}), extrapolated midpoint rule of order 16, {} macro steps, checked against half as many",
            c.macro_steps
        ),
    }
}
