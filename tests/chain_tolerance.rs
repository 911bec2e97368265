//! The 8-link pendulum at every tolerance from 1e-1 to 1e-10 (issue #17): each adaptive run either
//! ends within 100 x rtol of an independent reference or fails with a message; never status OK
//! with a larger error. From rtol 1e-2 on each decade lowers the error at least 3x. Reference:
//! the chain in absolute joint angles (closed-form mass matrix), classical RK4 at 40,000 steps,
//! checked against 20,000. The second test measures the trajectory error: the largest tip error
//! at t_k = k T / 8, k = 1..8, on a run that stops at each t_k in turn (like an FMU
//! communication grid), against the same RK4 reference at t_k.

mod common;
use common::{planar_distance, simulated_planar_point};
use mbcosim::integrator::IntegratorKind;
use mbcosim::math::{Mat3, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder};
use nalgebra::{DMatrix, DVector};

const N: usize = 8;
const G: f64 = 9.81;
/// Rod mass [kg], length [m], inertia about the centre across the rod and along it [kg m^2].
const MASS: f64 = 1.0;
const LEN: f64 = 1.0;
const I_ACROSS: f64 = MASS * LEN * LEN / 12.0;
const I_ALONG: f64 = 1e-4;
const T_END: f64 = 1.0;

/// `N` rods hinged about z at the origin and to each other, horizontal along +x at rest; gravity
/// along -y.
fn chain() -> (Model, usize) {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let inertia = Mat3::from_diagonal(&Vec3::new(I_ALONG, I_ACROSS, I_ACROSS));
    let half = Vec3::new(0.5 * LEN, 0.0, 0.0);
    let (mut parent, mut at) = (BodyId::GROUND, Vec3::zeros());
    for k in 0..N {
        let rod = b
            .add_rigid_body(
                &format!("rod{k}"),
                MASS,
                inertia,
                BodyInit::at(Vec3::new((k as f64 + 0.5) * LEN, 0.0, 0.0)),
            )
            .unwrap();
        b.add_joint(
            &format!("hinge{k}"),
            JointKind::Revolute,
            Frame::new(parent, at),
            Frame::new(rod, -half),
        )
        .unwrap();
        (parent, at) = (rod, half);
    }
    let model = b.build().unwrap();
    let offset = model.body(parent).unwrap().q_offset;
    (model, offset)
}

/// Angular accelerations of the chain in absolute angles `th` (from the downward vertical) with
/// rates `w`: Lagrange's equations with `M_ij = m L^2 c_ij cos(th_i - th_j) + I delta_ij`,
/// `c_ii = (N - 1 - i) + 1/4`, `c_ij = (N - 1 - max(i, j)) + 1/2`.
fn accelerations(th: &[f64], w: &[f64]) -> DVector<f64> {
    let c = |i: usize, j: usize| {
        if i == j {
            (N - 1 - i) as f64 + 0.25
        } else {
            (N - 1 - i.max(j)) as f64 + 0.5
        }
    };
    let mut mass = DMatrix::zeros(N, N);
    let mut rhs = DVector::zeros(N);
    for i in 0..N {
        rhs[i] = -G * MASS * LEN * ((N - i) as f64 - 0.5) * th[i].sin();
        for j in 0..N {
            let d = th[i] - th[j];
            let mij = MASS * LEN * LEN * c(i, j);
            mass[(i, j)] = mij * d.cos() + if i == j { I_ACROSS } else { 0.0 };
            rhs[i] -= mij * d.sin() * w[j] * w[j];
        }
    }
    mass.cholesky().unwrap().solve(&rhs)
}

/// Tip of the last rod at `T_END` [m] by RK4 with `steps` steps.
fn reference_tip(steps: usize) -> [f64; 2] {
    *reference_tips(steps).last().unwrap()
}

/// Sample times of the trajectory error: `t_k = k T_END / SAMPLES`, k = 1..SAMPLES.
const SAMPLES: usize = 8;

/// Tip of the last rod [m] at each sample time by RK4 with `steps` steps over `T_END` (a
/// multiple of `SAMPLES`).
fn reference_tips(steps: usize) -> Vec<[f64; 2]> {
    assert!(steps.is_multiple_of(SAMPLES));
    let h = T_END / steps as f64;
    let f = |y: &DVector<f64>| {
        let (th, w) = (y.rows(0, N), y.rows(N, N));
        let a = accelerations(th.as_slice(), w.as_slice());
        let mut d = DVector::zeros(2 * N);
        d.rows_mut(0, N).copy_from(&w);
        d.rows_mut(N, N).copy_from(&a);
        d
    };
    let mut y = DVector::zeros(2 * N);
    y.rows_mut(0, N).fill(std::f64::consts::FRAC_PI_2);
    let mut tips = Vec::with_capacity(SAMPLES);
    for step in 1..=steps {
        let k1 = f(&y);
        let k2 = f(&(&y + 0.5 * h * &k1));
        let k3 = f(&(&y + 0.5 * h * &k2));
        let k4 = f(&(&y + h * &k3));
        y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        if step.is_multiple_of(steps / SAMPLES) {
            let x: f64 = (0..N).map(|i| LEN * y[i].sin()).sum();
            let z: f64 = (0..N).map(|i| -LEN * y[i].cos()).sum();
            tips.push([x, z]);
        }
    }
    tips
}

/// Tip of the last rod [m] at each sample time, simulated by `kind` at `rtol` (atol = rtol,
/// defaults otherwise, as `simulated_planar_point`), advancing to each sample time in turn; or
/// the failure's message.
fn simulated_tips(
    model: &Model,
    offset: usize,
    kind: IntegratorKind,
    rtol: f64,
) -> Result<Vec<[f64; 2]>, String> {
    let s = mbcosim::integrator::Settings {
        rtol,
        atol: rtol,
        max_steps: 10_000_000,
        ..mbcosim::integrator::Settings::default()
    };
    let mut sim =
        mbcosim::sim::Simulation::new(model.clone(), kind, s, 0.0).map_err(|e| format!("{e:?}"))?;
    (1..=SAMPLES)
        .map(|k| {
            sim.advance_to(T_END * k as f64 / SAMPLES as f64)
                .map_err(|e| format!("{e:?}"))?;
            let q = &sim.state.q;
            let p = Vec3::new(q[offset], q[offset + 1], q[offset + 2])
                + mbcosim::model::kinematics::quat_at(q, offset + 3)
                    * Vec3::new(0.5 * LEN, 0.0, 0.0);
            Ok([p.x, p.y])
        })
        .collect()
}

/// Every integrator; generalized-alpha with its default error per unit step (per step it
/// returned OK with 8.7 m at rtol 7e-3 here).
#[test]
fn eight_link_pendulum_meets_every_tolerance_or_says_why() {
    let reference = reference_tip(40_000);
    let check = reference_tip(20_000);
    let ref_err = planar_distance(reference, check);
    assert!(ref_err < 1e-11, "reference not converged: {ref_err:.2e}");
    let (model, offset) = chain();
    for kind in IntegratorKind::ALL {
        let mut errors = Vec::new();
        for k in 1..=10 {
            let rtol = 10f64.powi(-k);
            match simulated_planar_point(
                &model,
                (offset, Vec3::new(0.5 * LEN, 0.0, 0.0)),
                kind,
                rtol,
                T_END,
            ) {
                Ok(tip) => {
                    let e = planar_distance(tip, reference);
                    println!(
                        "{:8} rtol {rtol:.0e}: tip error {e:.2e} m ({:.2} rtol)",
                        kind.name(),
                        e / rtol
                    );
                    assert!(
                        e <= 100.0 * rtol,
                        "{} at rtol {rtol:e}: status OK with tip error {e:.3e} m (> 100 rtol)",
                        kind.name()
                    );
                    errors.push((rtol, e));
                }
                Err(msg) => {
                    println!("{:8} rtol {rtol:.0e}: failed: {msg}", kind.name());
                    assert!(msg.len() > 20, "{}: failure without a message", kind.name());
                }
            }
        }
        // from rtol 1e-2 on, each decade of rtol lowers the error at least 3x until it is below
        // 1e-10 m (measured: 5.9x .. 103x); a decade whose tighter run failed with a message is
        // not judged
        assert_decades_fall_3x(kind, "error", &errors, 0.0);
        assert!(errors.len() >= 8, "{}: too few runs succeeded", kind.name());
    }
}

/// The trajectory error (largest tip error over t_k = k T / 8) of every integrator from rtol 1e-1
/// to 1e-10 (generalized-alpha to 1e-6: its runs at 1e-7 and 1e-8 cost most of the first test's
/// time): within 100 x rtol or a failure with a message, and from rtol 1e-2 on each decade lowers
/// it at least 3x until it is at or below 1e-10 m (measured: smallest factor 6.3x dopri5, 7.5x
/// bdf, 8.6x gen-alpha; about 2.5 s).
#[test]
fn eight_link_pendulum_trajectory_error_falls_with_rtol() {
    let reference = reference_tips(40_000);
    let check = reference_tips(20_000);
    let ref_err = reference
        .iter()
        .zip(&check)
        .map(|(a, b)| planar_distance(*a, *b))
        .fold(0.0, f64::max);
    assert!(ref_err < 1e-11, "reference not converged: {ref_err:.2e}");
    let (model, offset) = chain();
    for kind in IntegratorKind::ALL {
        let tightest = if kind == IntegratorKind::GenAlpha {
            6
        } else {
            10
        };
        let mut errors = Vec::new();
        for k in 1..=tightest {
            let rtol = 10f64.powi(-k);
            match simulated_tips(&model, offset, kind, rtol) {
                Ok(tips) => {
                    let e = tips
                        .iter()
                        .zip(&reference)
                        .map(|(a, b)| planar_distance(*a, *b))
                        .fold(0.0, f64::max);
                    println!(
                        "{:8} rtol {rtol:.0e}: trajectory tip error {e:.2e} m ({:.2} rtol)",
                        kind.name(),
                        e / rtol
                    );
                    assert!(
                        e <= 100.0 * rtol,
                        "{} at rtol {rtol:e}: status OK with trajectory tip error {e:.3e} m (> 100 rtol)",
                        kind.name()
                    );
                    errors.push((rtol, e));
                }
                Err(msg) => {
                    println!("{:8} rtol {rtol:.0e}: failed: {msg}", kind.name());
                    assert!(msg.len() > 20, "{}: failure without a message", kind.name());
                }
            }
        }
        assert_decades_fall_3x(kind, "trajectory error", &errors, 1e-10);
        assert!(
            errors.len() + 2 >= tightest as usize,
            "{}: too few runs succeeded",
            kind.name()
        );
    }
}

/// From rtol 1e-2 on, each decade of rtol in `errors` (rtol, error; loose to tight, failed runs
/// left out) lowers the error at least 3x while the looser error is above 1e-10 m, unless the
/// tighter error is at or below `floor` [m]; a decade with a failed run between is not judged.
fn assert_decades_fall_3x(kind: IntegratorKind, what: &str, errors: &[(f64, f64)], floor: f64) {
    for w in errors.windows(2) {
        let ((r0, e0), (r1, e1)) = (w[0], w[1]);
        if r0 <= 1e-2 && e0 > 1e-10 && (r0 / r1 - 10.0).abs() < 1e-6 {
            assert!(
                e1 <= e0 / 3.0 || e1 <= floor,
                "{}: {what} {e0:.2e} at rtol {r0:e} fell only to {e1:.2e} a decade tighter",
                kind.name()
            );
        }
    }
}
