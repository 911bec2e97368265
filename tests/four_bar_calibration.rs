//! Error control on a closed loop (issue #17): the planar four-bar of the accuracy suite at every
//! tolerance from 1e-2 to 1e-10, with each adaptive integrator (BDF, DOPRI5, generalized-alpha),
//! either ends within 100 x rtol of an independent reference or fails with a message, and the
//! error falls as rtol is tightened. Per step, BDF was 33-17,464 x rtol off and DOPRI5 31-730 x
//! (not monotone); both now hold their error per unit step.
//!
//! Mechanism: Grashof crank-rocker, ground pivots O2 = (0, 0) m and O4 = (1, 0) m, crank 0.3 m,
//! coupler 1 m, rocker 0.8 m, uniform rods of 1 kg/m (inertia m L^2 / 12 about z), released at
//! rest at crank angle 90 deg in the open assembly, gravity 9.81 m/s^2 along -y, 2 s. Measured:
//! the coupler point 0.3 m off the coupler's centre, perpendicular to it [m].
//!
//! Reference: the same mechanism in planar redundant coordinates (x, y, angle of each link, 8
//! loop equations), accelerations from the KKT system `[M G^T; G 0] [a; lambda] = [f; gamma]`,
//! classical RK4 at 100,000 steps, checked against 50,000. It shares no code with the library
//! (which works in 3D with quaternions and 20 joint rows, 3 of them dropped as redundant).

mod common;
use common::{planar_distance, simulated_planar_point};
use mbcosim::integrator::IntegratorKind;
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder};
use nalgebra::{DMatrix, DVector};

const G: f64 = 9.81;
/// Ground link, crank, coupler, rocker [m].
const D: f64 = 1.0;
const A: f64 = 0.3;
const B: f64 = 1.0;
const C: f64 = 0.8;
/// Mass per length [kg/m].
const RHO: f64 = 1.0;
/// Offset of the measured point from the coupler's centre, perpendicular to the coupler [m].
const P_OFF: f64 = 0.3;
const T_END: f64 = 2.0;
const LENGTHS: [f64; 3] = [A, B, C];

/// Link angles (crank, coupler, rocker) [rad] at crank angle `phi` in the open assembly: the
/// coupler-rocker pin lies to the left of the line from the crank pin to O4.
fn assembly(phi: f64) -> [f64; 3] {
    let pin = [A * phi.cos(), A * phi.sin()];
    let to = [D - pin[0], -pin[1]];
    let dist = to[0].hypot(to[1]);
    let u = [to[0] / dist, to[1] / dist];
    let along = (B * B - C * C + dist * dist) / (2.0 * dist);
    let across = (B * B - along * along).sqrt();
    let pb = [
        pin[0] + along * u[0] - across * u[1],
        pin[1] + along * u[1] + across * u[0],
    ];
    let beta = (pb[1] - pin[1]).atan2(pb[0] - pin[0]);
    let gamma = pb[1].atan2(pb[0] - D);
    [phi, beta, gamma]
}

/// Planar state `[x, y, angle]` per link from the link angles (centres from the pivots).
fn planar_positions(th: [f64; 3]) -> [f64; 9] {
    let e = |a: f64| [a.cos(), a.sin()];
    let (e1, e2, e3) = (e(th[0]), e(th[1]), e(th[2]));
    let pin = [A * e1[0], A * e1[1]];
    [
        0.5 * A * e1[0],
        0.5 * A * e1[1],
        th[0],
        pin[0] + 0.5 * B * e2[0],
        pin[1] + 0.5 * B * e2[1],
        th[1],
        D + 0.5 * C * e3[0],
        0.5 * C * e3[1],
        th[2],
    ]
}

/// A term `(link, local x of the point [m], sign)` of a loop equation.
type Term = (usize, f64, f64);

/// The loop's four pin equations `sum sign (r_link + R(angle) (s, 0)) = ground point` (2 rows
/// each; the ground points do not enter the accelerations; sign 0 marks an unused term).
const PINS: [[Term; 2]; 4] = [
    [(0, -0.5 * A, 1.0), (0, 0.0, 0.0)],
    [(0, 0.5 * A, 1.0), (1, -0.5 * B, -1.0)],
    [(1, 0.5 * B, 1.0), (2, 0.5 * C, -1.0)],
    [(2, -0.5 * C, 1.0), (2, 0.0, 0.0)],
];

/// Accelerations of the planar coordinates `z` with rates `w` (KKT solve).
fn planar_accelerations(z: &[f64], w: &[f64]) -> DVector<f64> {
    let mut k = DMatrix::zeros(17, 17);
    let mut rhs = DVector::zeros(17);
    for (l, len) in LENGTHS.iter().enumerate() {
        let m = RHO * len;
        k[(3 * l, 3 * l)] = m;
        k[(3 * l + 1, 3 * l + 1)] = m;
        k[(3 * l + 2, 3 * l + 2)] = m * len * len / 12.0;
        rhs[3 * l + 1] = -m * G;
    }
    for (e, terms) in PINS.iter().enumerate() {
        for &(l, s, sign) in terms {
            if sign == 0.0 {
                continue;
            }
            let (th, om) = (z[3 * l + 2], w[3 * l + 2]);
            // d/dangle of R(angle) (s, 0) = s (-sin, cos); second time derivative gives -R s om^2
            let d = [-s * th.sin(), s * th.cos()];
            for r in 0..2 {
                let row = 9 + 2 * e + r;
                k[(row, 3 * l + r)] += sign;
                k[(row, 3 * l + 2)] += sign * d[r];
                k[(3 * l + r, row)] += sign;
                k[(3 * l + 2, row)] += sign * d[r];
            }
            rhs[9 + 2 * e] += sign * s * th.cos() * om * om;
            rhs[9 + 2 * e + 1] += sign * s * th.sin() * om * om;
        }
    }
    let sol = k
        .lu()
        .solve(&rhs)
        .expect("no singular configuration on a crank-rocker");
    sol.rows(0, 9).into_owned()
}

/// Coupler point [m] from planar coordinates.
fn planar_coupler_point(z: &[f64]) -> [f64; 2] {
    let th = z[5];
    [z[3] - P_OFF * th.sin(), z[4] + P_OFF * th.cos()]
}

/// Coupler point at `T_END` by RK4 with `steps` steps.
fn reference_point(steps: usize) -> [f64; 2] {
    let h = T_END / steps as f64;
    let f = |y: &DVector<f64>| {
        let a = planar_accelerations(&y.as_slice()[..9], &y.as_slice()[9..]);
        let mut d = DVector::zeros(18);
        d.rows_mut(0, 9).copy_from(&y.rows(9, 9));
        d.rows_mut(9, 9).copy_from(&a);
        d
    };
    let mut y = DVector::zeros(18);
    y.rows_mut(0, 9)
        .copy_from_slice(&planar_positions(assembly(std::f64::consts::FRAC_PI_2)));
    for _ in 0..steps {
        let k1 = f(&y);
        let k2 = f(&(&y + 0.5 * h * &k1));
        let k3 = f(&(&y + 0.5 * h * &k2));
        let k4 = f(&(&y + h * &k3));
        y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    planar_coupler_point(&y.as_slice()[..9])
}

/// The four-bar in the library: three rigid bodies, four revolute joints about z. Returns the
/// model and the position offset of the coupler in `q`.
fn four_bar() -> (Model, usize) {
    let th = assembly(std::f64::consts::FRAC_PI_2);
    let z = planar_positions(th);
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let mut ids = Vec::new();
    for (l, (len, name)) in LENGTHS
        .iter()
        .zip(["crank", "coupler", "rocker"])
        .enumerate()
    {
        let m = RHO * len;
        let i = m * len * len / 12.0;
        let init = BodyInit::at(Vec3::new(z[3 * l], z[3 * l + 1], 0.0))
            .oriented(Quat::from_axis_angle(&Vec3::z_axis(), th[l]));
        let inertia = Mat3::from_diagonal(&Vec3::new(1e-4 * m, i, i));
        ids.push(b.add_rigid_body(name, m, inertia, init).unwrap());
    }
    let x = |v: f64| Vec3::new(v, 0.0, 0.0);
    let joints = [
        (
            "O2",
            Frame::new(BodyId::GROUND, Vec3::zeros()),
            Frame::new(ids[0], x(-0.5 * A)),
        ),
        (
            "A",
            Frame::new(ids[0], x(0.5 * A)),
            Frame::new(ids[1], x(-0.5 * B)),
        ),
        (
            "B",
            Frame::new(ids[1], x(0.5 * B)),
            Frame::new(ids[2], x(0.5 * C)),
        ),
        (
            "O4",
            Frame::new(BodyId::GROUND, x(D)),
            Frame::new(ids[2], x(-0.5 * C)),
        ),
    ];
    for (name, fi, fj) in joints {
        b.add_joint(name, JointKind::Revolute, fi, fj).unwrap();
    }
    let model = b.build().unwrap();
    let off = model.body(ids[1]).unwrap().q_offset;
    (model, off)
}

#[test]
fn four_bar_reference_is_converged() {
    let (fine, coarse) = (reference_point(100_000), reference_point(50_000));
    let d = planar_distance(fine, coarse);
    assert!(
        d < 1e-11,
        "RK4 reference not converged: {d:e} m between 50k and 100k steps"
    );
    // the accuracy suite's reference (one-DOF crank-angle ODE, extrapolation) at 6.5e-13 m
    let suite = [0.343161881112, 0.555922057376];
    assert!(
        planar_distance(fine, suite) < 1e-11,
        "two independent references differ: {fine:?} against {suite:?}"
    );
}

#[test]
fn bdf_on_the_four_bar_is_within_100_rtol_and_monotone() {
    within_100_rtol_and_monotone(IntegratorKind::Bdf, 1e-10, "");
}

#[test]
fn dopri5_on_the_four_bar_is_within_100_rtol_and_monotone() {
    within_100_rtol_and_monotone(IntegratorKind::Dopri5, 1e-10, "");
}

/// Generalized-alpha, second order on the index-3 form, runs down to rtol 1e-10 here: its error
/// estimate's round-off along the constraint normals no longer stops it (issue #49 item 1; it
/// stopped from 1e-9 on before, docs/integrator_error_control.md).
#[test]
fn gen_alpha_on_the_four_bar_is_within_100_rtol_and_monotone() {
    within_100_rtol_and_monotone(
        IntegratorKind::GenAlpha,
        0.0,
        "tighter than generalized-alpha resolves",
    );
}

/// Runs `kind` at rtol 1e-2 .. 1e-10: failures are allowed only at or below `fail_from`, with a
/// message containing `message`.
fn within_100_rtol_and_monotone(kind: IntegratorKind, fail_from: f64, message: &str) {
    let reference = reference_point(100_000);
    let (model, off) = four_bar();
    let rtols = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];
    let mut errors: Vec<Option<f64>> = Vec::new();
    let mut report = String::new();
    let mut too_large = Vec::new();
    for &rtol in &rtols {
        match simulated_planar_point(&model, (off, Vec3::new(0.0, P_OFF, 0.0)), kind, rtol, T_END) {
            Ok(p) => {
                let e = planar_distance(p, reference);
                report.push_str(&format!(
                    "rtol {rtol:.0e}: error {e:.2e} m ({:.3} rtol)\n",
                    e / rtol
                ));
                if e > 100.0 * rtol {
                    too_large.push(rtol);
                }
                errors.push(Some(e));
            }
            Err(msg) => {
                assert!(
                    !msg.is_empty() && msg.contains(message),
                    "{} rtol {rtol:e}: a failure without the expected message: {msg}",
                    kind.name()
                );
                report.push_str(&format!("rtol {rtol:.0e}: failed: {msg}\n"));
                errors.push(None);
            }
        }
    }
    println!("{}:\n{report}", kind.name());
    assert!(
        too_large.is_empty(),
        "status OK with an error above 100 x rtol at rtol {too_large:?}:\n{report}"
    );
    // a failure with a message is allowed only at the tightest setting (round-off)
    let failed: Vec<f64> = rtols
        .iter()
        .zip(&errors)
        .filter(|(_, e)| e.is_none())
        .map(|(r, _)| *r)
        .collect();
    assert!(
        failed.iter().all(|&r| r <= fail_from),
        "failed at rtol {failed:?}:\n{report}"
    );
    let done: Vec<(f64, f64)> = rtols
        .iter()
        .zip(&errors)
        .filter_map(|(r, e)| e.map(|e| (*r, e)))
        .collect();
    for w in done.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "error does not fall from rtol {:e} to {:e}:\n{report}",
            w[0].0,
            w[1].0
        );
    }
}
