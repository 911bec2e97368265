//! An impact: a ball (sphere, 1 kg, radius 5 cm) dropped from 5 cm onto the half-space y <= 0
//! under gravity, point/half-space contact at its centre with the plane offset by the radius
//! (penetration = radius - height of the centre), Hertz k = 1e7 N/m^1.5, n = 1.5; or the damped
//! Lankarani-Nikravesh law with e = 0.8. 0.25 s: the ball hits at 0.101 s at 0.99 m/s, is in
//! contact for about 5 ms and is in the air again at the end. Measured: the height of the
//! centre at the end [m] (the error); its vertical speed (the auxiliary error [m/s]).
//!
//! Reference: the 1-DOF ODE `y'' = -g + F(delta, delta') / m`, `delta = r - y`, integrated in
//! phases by adaptive order-16 extrapolation (rtol 1e-15): free fall, the contact onset located
//! by bisection on the step, the contact phase with the approach speed of the onset, the
//! separation located the same way, free flight. Its error estimate is the difference to the
//! same computation at 10x looser tolerances. For Hertz it is also checked against energy
//! conservation and quadrature: contact time `t_c = 2 int_0^dmax d delta / sqrt(E(delta))`,
//! `E = v^2 + 2 g delta - 2 k delta^(n+1) / ((n+1) m)`, leaving at the impact speed.

use crate::ode;
use crate::suite::{G, Problem, Reference, Trajectory};
use mbcosim::contact::{ContactLaw, LawKind};
use mbcosim::effect::plane_contact::{PlaneContact, PlaneContacts};
use mbcosim::math::{Mat3, Vec3};
use mbcosim::model::{BodyInit, Frame, ModelBuilder};
use std::sync::Arc;

const MASS: f64 = 1.0;
const RADIUS: f64 = 0.05;
const DROP: f64 = 0.05;
const K_HERTZ: f64 = 1e7;
const EXPONENT: f64 = 1.5;
const T_END: f64 = 0.25;

/// Which contact law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    Hertz,
    /// Lankarani-Nikravesh with this restitution coefficient.
    LankaraniNikravesh(f64),
}

impl Law {
    /// Hysteresis factor of the damping bracket (written out here, not taken from the library).
    fn chi(self) -> f64 {
        match self {
            Law::Hertz => 0.0,
            Law::LankaraniNikravesh(e) => 0.75 * (1.0 - e * e),
        }
    }
}

/// Contact force for penetration `d`, its rate `dd` and the approach speed `v_minus`.
fn force(law: Law, d: f64, dd: f64, v_minus: f64) -> f64 {
    if d <= 0.0 {
        return 0.0;
    }
    (K_HERTZ * d.powf(EXPONENT) * (1.0 + law.chi() * dd / v_minus)).max(0.0)
}

/// The reference state `[y, v]` at `T_END` for ODE tolerance `rtol`, and the located onset time;
/// the damping divides by the onset speed times `v_scale` (1 for the reference; other values
/// measure how much the result depends on the recorded approach speed).
fn ode_reference(law: Law, rtol: f64, v_scale: f64) -> (Vec<f64>, f64) {
    let atol = 1e-3 * rtol;
    let free = |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -G;
    };
    let y0 = [RADIUS + DROP, 0.0];
    let (t_on, y_on, hit) =
        ode::adaptive_until(&free, 0.0, &y0, T_END, rtol, atol, &|y| y[0] - RADIUS);
    assert!(hit, "the ball reaches the floor");
    let v_minus = -y_on[1] * v_scale;
    let contact = move |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -G + force(law, RADIUS - y[0], -y[1], v_minus) / MASS;
    };
    let (t_off, y_off, left) =
        ode::adaptive_until(&contact, t_on, &y_on, T_END, rtol, atol, &|y| RADIUS - y[0]);
    assert!(left, "the ball leaves the floor before the end");
    let (t, y, _) = ode::adaptive_until(&free, t_off, &y_off, T_END, rtol, atol, &|_| 1.0);
    assert!((t - T_END).abs() < 1e-12);
    (y, t_on)
}

/// The reference states `[y, v]` at `times` (ascending) by the same phases as
/// [`ode_reference`], stopping at each time within its phase; also the located onset and
/// separation times.
fn ode_samples(law: Law, rtol: f64, times: &[f64]) -> (Vec<Vec<f64>>, f64, f64) {
    let atol = 1e-3 * rtol;
    let free = |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -G;
    };
    let contact = |v_minus: f64| {
        move |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -G + force(law, RADIUS - y[0], -y[1], v_minus) / MASS;
        }
    };
    let (mut t, mut y) = (0.0, vec![RADIUS + DROP, 0.0]);
    // 0: falling, 1: in contact, 2: in the air again
    let (mut phase, mut v_minus) = (0, 0.0);
    let (mut t_on, mut t_off) = (f64::NAN, f64::NAN);
    let mut out = Vec::with_capacity(times.len());
    for &tk in times {
        loop {
            let (t1, y1, hit) = match phase {
                0 => ode::adaptive_until(&free, t, &y, tk, rtol, atol, &|y| y[0] - RADIUS),
                1 => ode::adaptive_until(&contact(v_minus), t, &y, tk, rtol, atol, &|y| {
                    RADIUS - y[0]
                }),
                _ => ode::adaptive_until(&free, t, &y, tk, rtol, atol, &|_| 1.0),
            };
            (t, y) = (t1, y1);
            if !hit {
                break;
            }
            phase += 1;
            if phase == 1 {
                (t_on, v_minus) = (t, -y[1]);
            } else {
                t_off = t;
            }
        }
        assert!((t - tk).abs() < 1e-12, "the reference reaches {tk} s");
        out.push(y.clone());
    }
    (out, t_on, t_off)
}

/// Sample times: `k T / k_max`, k = 1..k_max, and (none of those falls in the ~5 ms contact)
/// three inside the contact, at 1/4, 1/2 and 3/4 of the reference's contact interval; also the
/// reference values there, their estimated error (largest difference in height to rtol 1e-14)
/// and how it was made.
fn trajectory(law: Law, samples: usize) -> Trajectory {
    let (_, t_on, t_off) = ode_samples(law, 1e-15, &[T_END]);
    let mut times = crate::suite::grid(T_END, samples);
    times.extend([0.25, 0.5, 0.75].map(|f| t_on + f * (t_off - t_on)));
    times.sort_by(f64::total_cmp);
    let (values, _, _) = ode_samples(law, 1e-15, &times);
    let (check, _, _) = ode_samples(law, 1e-14, &times);
    let estimated_error = values
        .iter()
        .zip(&check)
        .map(|(a, b)| (a[0] - b[0]).abs())
        .fold(0.0, f64::max);
    // free fall before the onset in closed form
    let fall = times
        .iter()
        .zip(&values)
        .filter(|(t, _)| **t < t_on)
        .map(|(t, v)| (v[0] - (RADIUS + DROP - 0.5 * G * t * t)).abs())
        .fold(0.0, f64::max);
    Trajectory {
        method: format!(
            "the phased ODE stopped at each sample time; contact {t_on:.6} .. {t_off:.6} s, samples there at 1/4, 1/2, 3/4 of it; vs rtol 1e-14: height {estimated_error:.1e} m; free fall vs closed form {fall:.1e} m"
        ),
        estimated_error: estimated_error.max(fall),
        uniform: samples,
        times,
        values,
    }
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the three-term recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Semi-analytic Hertz reference `[y, v]` at `T_END`: free fall in closed form, the contact
/// time by quadrature, rebound at the impact speed (energy conservation).
fn hertz_quadrature() -> Vec<f64> {
    let t_on = (2.0 * DROP / G).sqrt();
    let v = G * t_on;
    let c = 2.0 * K_HERTZ / ((EXPONENT + 1.0) * MASS);
    let energy = |d: f64| v * v + 2.0 * G * d - c * d.powf(EXPONENT + 1.0);
    let (mut lo, mut hi) = (0.0, 1.0);
    while energy(hi) > 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if energy(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let dm = 0.5 * (lo + hi);
    // delta = dm (1 - s^2): t_c / 2 = int_0^1 2 dm s / sqrt(E) ds, with E / s^2 written without
    // cancellation (E(dm) = 0): -2 g dm + c dm^(n+1) (1 - (1 - s^2)^(n+1)) / s^2
    let integrand = |s: f64| {
        let ratio = if s == 0.0 {
            EXPONENT + 1.0
        } else {
            -((EXPONENT + 1.0) * (-s * s).ln_1p()).exp_m1() / (s * s)
        };
        let e_over_s2 = -2.0 * G * dm + c * dm.powf(EXPONENT + 1.0) * ratio;
        2.0 * dm / e_over_s2.sqrt()
    };
    // graded toward s = 1, where (1 - s^2)^(n+1) is not smooth
    let rule = gauss_legendre(20);
    let mut edges = vec![0.0, 0.5];
    for k in 2..=45 {
        edges.push(1.0 - 0.5f64.powi(k));
    }
    edges.push(1.0);
    let mut half = 0.0;
    for w in edges.windows(2) {
        let (a, b) = (w[0], w[1]);
        half += rule
            .iter()
            .map(|(x, wt)| 0.5 * (b - a) * wt * integrand(0.5 * (a + b) + 0.5 * (b - a) * x))
            .sum::<f64>();
    }
    let t_off = t_on + 2.0 * half;
    let dt = T_END - t_off;
    vec![RADIUS + v * dt - 0.5 * G * dt * dt, v - G * dt]
}

pub fn problem(law: Law, samples: usize) -> Result<Problem, String> {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0)))?;
    let i = 0.4 * MASS * RADIUS * RADIUS;
    let ball = b.add_rigid_body(
        "ball",
        MASS,
        Mat3::from_diagonal(&Vec3::new(i, i, i)),
        BodyInit::at(Vec3::new(0.0, RADIUS + DROP, 0.0)),
    )?;
    let contact_law = match law {
        Law::Hertz => ContactLaw::hertz(K_HERTZ, EXPONENT),
        Law::LankaraniNikravesh(e) => {
            ContactLaw::new(LawKind::LankaraniNikravesh, K_HERTZ, EXPONENT, e)
        }
    }
    .map_err(|e| e.to_string())?;
    b.add_force_effect(Arc::new(PlaneContacts {
        elements: vec![PlaneContact {
            name: "floor".into(),
            point: Frame::new(ball, Vec3::zeros()),
            normal: Vec3::y(),
            offset: RADIUS,
            law: contact_law,
        }],
    }));
    let model = b.build()?;
    let (qo, vo) = {
        let body = model.body(ball).ok_or("impact: ball missing")?;
        (body.q_offset, body.v_offset)
    };
    let (value, t_on) = ode_reference(law, 1e-15, 1.0);
    let (check, _) = ode_reference(law, 1e-14, 1.0);
    let mut estimated_error = (value[0] - check[0]).abs();
    let (name, title, mut method) = match law {
        Law::Hertz => (
            "impact_hertz".to_string(),
            "ball (1 kg, r 5 cm) dropped 5 cm on a half-space, Hertz k 1e7 N/m^1.5, n 1.5, 0.25 s: height after the rebound".to_string(),
            String::new(),
        ),
        Law::LankaraniNikravesh(e) => (
            "impact_ln".to_string(),
            format!(
                "the same drop, Lankarani-Nikravesh e {e} (approach speed at onset), 0.25 s: height after the rebound"
            ),
            String::new(),
        ),
    };
    method.push_str(&format!(
        "1-DOF ODE in phases, adaptive order-16 extrapolation at rtol 1e-15, onset and separation by bisection (onset {:.1e} s from the closed form); vs rtol 1e-14: height {:.1e} m, speed {:.1e} m/s",
        (t_on - (2.0 * DROP / G).sqrt()).abs(),
        (value[0] - check[0]).abs(),
        (value[1] - check[1]).abs()
    ));
    if law != Law::Hertz {
        // the solver records the approach speed at the end of its first step in contact, after
        // gravity has sped the ball up by g times the time since onset
        let eps = 1e-6;
        let (perturbed, _) = ode_reference(law, 1e-15, 1.0 + eps);
        let v_on = (2.0 * G * DROP).sqrt();
        method.push_str(&format!(
            "; the height moves by {:.2e} m per m/s of error in the approach speed",
            (perturbed[0] - value[0]) / (eps * v_on)
        ));
    }
    if law == Law::Hertz {
        let q = hertz_quadrature();
        let d = (value[0] - q[0]).abs();
        estimated_error = estimated_error.max(d);
        method.push_str(&format!(
            "; vs quadrature of the contact time with energy conservation: height {d:.1e} m, speed {:.1e} m/s",
            (value[1] - q[1]).abs()
        ));
    }
    Ok(Problem {
        h_max: None,
        name,
        title,
        t_end: T_END,
        quantity: "height error after the rebound [m]",
        aux_name: Some("speed error [m/s]"),
        // Hertz ignores the approach speed
        approach_speed: (law != Law::Hertz).then(|| (2.0 * G * DROP).sqrt()),
        model,
        measure: Box::new(move |sim| vec![sim.state.q[qo + 1], sim.state.v[vo + 1]]),
        primary: 1,
        reference: Reference {
            value,
            estimated_error,
            method,
        },
        trajectory: trajectory(law, samples),
    })
}
