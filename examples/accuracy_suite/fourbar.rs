//! A closed loop: a planar four-bar under gravity (-y), released at rest, 2 s.
//!
//! Grashof crank-rocker: ground pivots O2 = (0, 0) and O4 = (1, 0) (ground link d = 1 m), crank
//! a = 0.3 m (the shortest link, so it can turn fully), coupler b = 1 m, rocker c = 0.8 m
//! (s + l = 1.3 <= p + q = 1.8); uniform rods of 1 kg/m, I = m L^2 / 12 about z. Released at
//! crank angle pi/2 in the open assembly (B above the line from the crank pin to O4). Measured:
//! a coupler point P, 0.3 m off the coupler's centre perpendicular to it, at the end.
//!
//! Reference: the one-DOF model in the crank angle phi. With the coupler and rocker angles
//! beta(phi), gamma(phi) from the loop closure (solved in closed form) and their derivatives
//! from the velocity and acceleration loop equations, Lagrange's equation is
//! `M(phi) phi'' + C(phi) phi'^2 = Q(phi)`, `M = sum m |r'|^2 + I theta'^2`,
//! `C = sum m r'.r'' + I theta' theta''`, `Q = -g sum m y'` (primes: d/dphi). A crank-rocker
//! driven from its crank has no dead centre, so the closure is smooth for every phi.

use crate::ode;
use crate::suite::{G, Problem, Reference, Trajectory};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder, kinematics};
use nalgebra::{Matrix2, Vector2};

const D: f64 = 1.0;
const A: f64 = 0.3;
const B: f64 = 1.0;
const C: f64 = 0.8;
/// Mass per length [kg/m].
const RHO: f64 = 1.0;
/// Coupler point offset from the coupler's centre, perpendicular to it [m].
const P_OFF: f64 = 0.3;
const PHI0: f64 = std::f64::consts::FRAC_PI_2;
const T_END: f64 = 2.0;

type V2 = Vector2<f64>;

fn e(a: f64) -> V2 {
    V2::new(a.cos(), a.sin())
}

fn e_perp(a: f64) -> V2 {
    V2::new(-a.sin(), a.cos())
}

/// Angles of coupler and rocker and their first and second derivatives with respect to phi.
struct Closure {
    beta: [f64; 3],
    gamma: [f64; 3],
}

fn closure(phi: f64) -> Closure {
    let pin = A * e(phi);
    let o4 = V2::new(D, 0.0);
    let to = o4 - pin;
    let dist = to.norm();
    let u = to / dist;
    let n = V2::new(-u.y, u.x);
    let x = (B * B - C * C + dist * dist) / (2.0 * dist);
    let h = (B * B - x * x).sqrt();
    let pb = pin + x * u + h * n;
    let beta = (pb - pin).y.atan2((pb - pin).x);
    let gamma = (pb - o4).y.atan2((pb - o4).x);
    // velocity loop: b beta' e_perp(beta) - c gamma' e_perp(gamma) = -a e_perp(phi)
    let m = Matrix2::from_columns(&[B * e_perp(beta), -C * e_perp(gamma)]);
    let lu = m.lu();
    let d1 = lu
        .solve(&(-A * e_perp(phi)))
        .expect("no dead centre in a crank-rocker");
    // acceleration loop: the same matrix times (beta'', gamma'')
    let rhs2 = A * e(phi) + B * d1.x * d1.x * e(beta) - C * d1.y * d1.y * e(gamma);
    let d2 = lu.solve(&rhs2).expect("no dead centre in a crank-rocker");
    Closure {
        beta: [beta, d1.x, d2.x],
        gamma: [gamma, d1.y, d2.y],
    }
}

/// Centre of mass of each link, its first and second derivative with respect to phi, the link
/// angle's first and second derivative, and the link's mass and inertia.
struct LinkKin {
    r: [V2; 3],
    th: [f64; 2],
    m: f64,
    i: f64,
}

fn links(phi: f64, c: &Closure) -> [LinkKin; 3] {
    let rod = |len: f64| (RHO * len, RHO * len * len * len / 12.0);
    let (m1, i1) = rod(A);
    let (m2, i2) = rod(B);
    let (m3, i3) = rod(C);
    let [b, b1, b2] = c.beta;
    let [g, g1, g2] = c.gamma;
    let crank = LinkKin {
        r: [0.5 * A * e(phi), 0.5 * A * e_perp(phi), -0.5 * A * e(phi)],
        th: [1.0, 0.0],
        m: m1,
        i: i1,
    };
    let coupler = LinkKin {
        r: [
            A * e(phi) + 0.5 * B * e(b),
            A * e_perp(phi) + 0.5 * B * b1 * e_perp(b),
            -A * e(phi) + 0.5 * B * (b2 * e_perp(b) - b1 * b1 * e(b)),
        ],
        th: [b1, b2],
        m: m2,
        i: i2,
    };
    let rocker = LinkKin {
        r: [
            V2::new(D, 0.0) + 0.5 * C * e(g),
            0.5 * C * g1 * e_perp(g),
            0.5 * C * (g2 * e_perp(g) - g1 * g1 * e(g)),
        ],
        th: [g1, g2],
        m: m3,
        i: i3,
    };
    [crank, coupler, rocker]
}

fn rhs(_t: f64, y: &[f64], dy: &mut [f64]) {
    let (phi, w) = (y[0], y[1]);
    let c = closure(phi);
    let (mut mass, mut coriolis, mut q) = (0.0, 0.0, 0.0);
    for l in links(phi, &c) {
        mass += l.m * l.r[1].norm_squared() + l.i * l.th[0] * l.th[0];
        coriolis += l.m * l.r[1].dot(&l.r[2]) + l.i * l.th[0] * l.th[1];
        q -= G * l.m * l.r[1].y;
    }
    dy[0] = w;
    dy[1] = (q - coriolis * w * w) / mass;
}

/// The coupler point for crank angle `phi`.
fn coupler_point(phi: f64) -> Vec<f64> {
    let c = closure(phi);
    let p = A * e(phi) + 0.5 * B * e(c.beta[0]) + P_OFF * e_perp(c.beta[0]);
    vec![p.x, p.y]
}

pub fn problem(samples: usize) -> Result<Problem, String> {
    let c = closure(PHI0);
    let (beta, gamma) = (c.beta[0], c.gamma[0]);
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0)))?;
    let rod = |len: f64| {
        let m = RHO * len;
        let i = m * len * len / 12.0;
        (m, Mat3::from_diagonal(&Vec3::new(1e-4 * m, i, i)))
    };
    let at = |p: V2, angle: f64| {
        BodyInit::at(Vec3::new(p.x, p.y, 0.0))
            .oriented(Quat::from_axis_angle(&Vec3::z_axis(), angle))
    };
    let pin = A * e(PHI0);
    let (m1, i1) = rod(A);
    let (m2, i2) = rod(B);
    let (m3, i3) = rod(C);
    let crank = b.add_rigid_body("crank", m1, i1, at(0.5 * pin, PHI0))?;
    let coupler = b.add_rigid_body("coupler", m2, i2, at(pin + 0.5 * B * e(beta), beta))?;
    let rocker = b.add_rigid_body(
        "rocker",
        m3,
        i3,
        at(V2::new(D, 0.0) + 0.5 * C * e(gamma), gamma),
    )?;
    let x = |v: f64| Vec3::new(v, 0.0, 0.0);
    b.add_joint(
        "O2",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, Vec3::zeros()),
        Frame::new(crank, x(-0.5 * A)),
    )?;
    b.add_joint(
        "A",
        JointKind::Revolute,
        Frame::new(crank, x(0.5 * A)),
        Frame::new(coupler, x(-0.5 * B)),
    )?;
    b.add_joint(
        "B",
        JointKind::Revolute,
        Frame::new(coupler, x(0.5 * B)),
        Frame::new(rocker, x(0.5 * C)),
    )?;
    b.add_joint(
        "O4",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, x(D)),
        Frame::new(rocker, x(-0.5 * C)),
    )?;
    let model = b.build()?;
    let off = model
        .body(coupler)
        .ok_or("four-bar: coupler missing")?
        .q_offset;
    let conv = ode::converge(&rhs, &[PHI0, 0.0], T_END, 50, 1e-13, 8, &|y| {
        coupler_point(y[0])
    });
    let times = crate::suite::grid(T_END, samples);
    let traj = ode::converge_samples(&rhs, &[PHI0, 0.0], &times, 50, 1e-13, 8, &|y| {
        coupler_point(y[0])
    });
    Ok(Problem {
        h_max: None,
        name: "fourbar".into(),
        title: format!(
            "planar four-bar crank-rocker (d {D}, a {A}, b {B}, c {C} m; 1 kg/m rods), released at crank angle 90 deg, {T_END} s: coupler point"
        ),
        t_end: T_END,
        quantity: "coupler point position error [m]",
        aux_name: None,
        approach_speed: None,
        model,
        measure: Box::new(move |sim| {
            let q = &sim.state.q;
            let r = Vec3::new(q[off], q[off + 1], q[off + 2]);
            let p = r + kinematics::quat_at(q, off + 3) * Vec3::new(0.0, P_OFF, 0.0);
            vec![p.x, p.y]
        }),
        primary: 2,
        reference: Reference {
            value: conv.output,
            estimated_error: conv.estimated_error,
            method: format!(
                "one-DOF crank-angle ODE with closed-form loop closure, extrapolated midpoint rule of order 16, {} macro steps, checked against half as many",
                conv.macro_steps
            ),
        },
        trajectory: Trajectory {
            uniform: samples,
            times,
            values: traj.outputs,
            estimated_error: traj.estimated_error,
            method: format!(
                "the crank-angle ODE converged at each sample time, {} macro steps, checked against half as many",
                traj.macro_steps
            ),
        },
    })
}
