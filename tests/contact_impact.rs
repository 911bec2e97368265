//! Independent check of the contact laws on an isolated 1-DOF impact: a mass `m` hits a fixed
//! wall at `v0` and the contact force is the only force. The test integrates
//! `m delta_ddot = -F(delta, delta_dot)` itself with classical RK4 at a fixed tiny step, starting
//! exactly at contact onset, and locates the two events (maximum compression `delta_dot = 0`,
//! separation `delta = 0`) by bisection on the length of the last RK4 step. This integrator is the
//! test's own and is not the product's.
//!
//! References: the closed-form Hertz impact (peak force and duration) and the nominal-to-effective
//! restitution table for `n = 1.5`.

use mbcosim::contact::{ContactLaw, LawKind};

/// State: penetration [m], penetration rate [m/s], dissipated energy [J].
type State = [f64; 3];

/// Outcome of one simulated impact.
struct Impact {
    /// Maximum penetration [m].
    delta_max: f64,
    /// Largest contact force seen at the RK4 nodes and at maximum compression [N].
    force_max: f64,
    /// Contact duration [s].
    duration: f64,
    /// Rebound speed [m/s] (positive).
    rebound_speed: f64,
    /// Energy dissipated by the contact [J].
    dissipated: f64,
    /// Whether the no-adhesion clamp was ever active.
    clamped: bool,
    /// Smallest force seen [N].
    force_min: f64,
}

/// The impact problem: law, mass `m` [kg], impact speed `v0` [m/s] (also the approach speed given
/// to the law) and a constant force `pull` [N] pulling the mass away from the wall.
struct Problem<'a> {
    law: &'a ContactLaw,
    m: f64,
    v0: f64,
    pull: f64,
}

fn rhs(p: &Problem, s: &State) -> State {
    let f = p.law.evaluate(s[0], s[1], p.v0);
    [s[1], -(f.force + p.pull) / p.m, f.dissipated_power]
}

fn rk4(p: &Problem, s: &State, h: f64) -> State {
    let add = |a: &State, b: &State, c: f64| [a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2]];
    let k1 = rhs(p, s);
    let k2 = rhs(p, &add(s, &k1, 0.5 * h));
    let k3 = rhs(p, &add(s, &k2, 0.5 * h));
    let k4 = rhs(p, &add(s, &k3, h));
    let mut out = *s;
    for i in 0..3 {
        out[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    out
}

/// Step length in (0, h] at which component `i` of an RK4 step from `s` crosses zero (bisection).
fn locate(p: &Problem, s: &State, h: f64, i: usize) -> f64 {
    let (mut lo, mut hi) = (0.0, h);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if rk4(p, s, mid)[i] > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Impact of mass `m` [kg] at `v0` [m/s]; `steps` RK4 steps per Hertz contact duration.
fn impact(law: &ContactLaw, m: f64, v0: f64, steps: f64) -> Impact {
    impact_pulled(law, m, v0, 0.0, steps)
}

/// As [`impact`], with a constant force `pull` [N] pulling the mass away from the wall.
fn impact_pulled(law: &ContactLaw, m: f64, v0: f64, pull: f64, steps: f64) -> Impact {
    let p = Problem { law, m, v0, pull };
    let (k, n) = (law.stiffness(), law.exponent());
    // Duration scale from the closed form (only used to size the step).
    let d_ref = (5.0 * m * v0 * v0 / (4.0 * k)).powf(1.0 / (n + 1.0));
    let h = 3.0 * d_ref / v0 / steps;
    let mut s: State = [0.0, v0, 0.0];
    let mut t = 0.0;
    let mut out = Impact {
        delta_max: 0.0,
        force_max: 0.0,
        duration: 0.0,
        rebound_speed: 0.0,
        dissipated: 0.0,
        clamped: false,
        force_min: 0.0,
    };
    let mut compressing = true;
    for _ in 0..(100.0 * steps) as usize {
        let next = rk4(&p, &s, h);
        if compressing && next[1] <= 0.0 {
            let tau = locate(&p, &s, h, 1);
            let at_max = rk4(&p, &s, tau);
            out.delta_max = at_max[0];
            out.force_max = out.force_max.max(law.evaluate(at_max[0], 0.0, v0).force);
            compressing = false;
        }
        if !compressing && next[0] <= 0.0 {
            let tau = locate(&p, &s, h, 0);
            let end = rk4(&p, &s, tau);
            out.duration = t + tau;
            out.rebound_speed = -end[1];
            out.dissipated = end[2];
            return out;
        }
        s = next;
        t += h;
        let f = law.evaluate(s[0], s[1], v0);
        out.force_max = out.force_max.max(f.force);
        out.force_min = out.force_min.min(f.force);
        out.clamped |= f.clamped;
    }
    panic!("impact did not end within {} steps", 100.0 * steps);
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn hertz_impact_matches_closed_form_peak_force_and_duration() {
    let (m, v0) = (1.0, 1.0);
    // (k [N/m^1.5], published F_max [N], published t_c [s])
    let cases = [(1e7, 721.350, 5.10029e-3), (1e8, 1811.949, 2.03046e-3)];
    for (k, f_pub, t_pub) in cases {
        let law = ContactLaw::hertz(k, 1.5).unwrap();
        let r = impact(&law, m, v0, 4000.0);
        let d_max = (5.0 * m * v0 * v0 / (4.0 * k)).powf(0.4);
        let f_max = k * d_max.powf(1.5);
        let t_c = 2.943275 * d_max / v0;
        let errs = [
            rel(r.delta_max, d_max),
            rel(r.force_max, f_max),
            rel(r.duration, t_c),
            rel(r.force_max, f_pub),
            rel(r.duration, t_pub),
        ];
        eprintln!(
            "Hertz k={k:e}: F_max={:.6} N, t_c={:.8} s; rel. errors vs closed form: delta_max {:.1e}, \
             F_max {:.1e}, t_c {:.1e}; vs published: F_max {:.1e}, t_c {:.1e}",
            r.force_max, r.duration, errs[0], errs[1], errs[2], errs[3], errs[4]
        );
        for e in errs {
            assert!(e < 1e-4, "relative error {e:e} for k = {k}");
        }
        // Elastic: the rebound speed equals the impact speed, nothing is dissipated.
        assert!((r.rebound_speed - v0).abs() < 1e-9);
        assert!(r.dissipated.abs() < 1e-12);
    }
}

#[test]
fn integrator_is_converged() {
    // The test's integrator is far more accurate than the tolerances it checks.
    let law = ContactLaw::new(LawKind::Flores, 1e7, 1.5, 0.4).unwrap();
    let a = impact(&law, 1.0, 1.0, 2000.0);
    let b = impact(&law, 1.0, 1.0, 4000.0);
    assert!((a.rebound_speed - b.rebound_speed).abs() < 1e-9);
    assert!(rel(a.duration, b.duration) < 1e-9);
    assert!(rel(a.force_max, b.force_max) < 1e-6);
}

#[test]
fn damped_laws_reproduce_the_effective_restitution_table() {
    let nominal = [0.95, 0.9, 0.8, 0.6, 0.4, 0.2];
    let table = [
        (
            LawKind::LankaraniNikravesh,
            [0.9535, 0.9132, 0.8471, 0.7561, 0.7016, 0.6723],
        ),
        (
            LawKind::HuntCrossley,
            [0.9524, 0.909, 0.8329, 0.712, 0.6197, 0.5469],
        ),
        (
            LawKind::Flores,
            [0.9468, 0.8939, 0.7885, 0.5773, 0.3629, 0.1555],
        ),
    ];
    let (m, v0) = (1.0, 1.0);
    let mut worst: f64 = 0.0;
    for (kind, expected) in table {
        for (e, want) in nominal.iter().zip(expected) {
            let law = ContactLaw::new(kind, 1e7, 1.5, *e).unwrap();
            let r = impact(&law, m, v0, 2000.0);
            let got = r.rebound_speed / v0;
            let err = (got - want).abs();
            worst = worst.max(err);
            eprintln!("{kind:?} e={e}: effective {got:.6} (table {want}), |error| {err:.1e}");
            assert!(err < 1e-3, "{kind:?} e = {e}: {got} vs {want}");
            // The table holds without the no-adhesion clamp ever acting.
            assert!(!r.clamped, "{kind:?} e = {e}: clamp active");
            // Energy: kinetic energy lost = energy dissipated by the law.
            let lost = 0.5 * m * (v0 * v0 - r.rebound_speed * r.rebound_speed);
            assert!(rel(r.dissipated, lost) < 1e-8, "{kind:?} e = {e}");
        }
    }
    eprintln!("worst |error| vs table: {worst:.1e}");
}

#[test]
fn no_adhesion_clamp_acts_only_when_other_forces_pull_the_bodies_apart() {
    let law = ContactLaw::new(LawKind::Flores, 1e7, 1.5, 0.2).unwrap();
    let (m, v0) = (1.0, 1.0);
    // Isolated impact: the bracket 1 + chi rate / v0 only tends to zero (where the deceleration
    // vanishes, rate -> -v0/chi), so the clamp never acts, even for very strong damping.
    for e in [0.2, 0.05, 0.01] {
        let strong = ContactLaw::new(LawKind::Flores, 1e7, 1.5, e).unwrap();
        let r = impact(&strong, m, v0, 4000.0);
        assert!(!r.clamped && r.force_min >= 0.0);
        assert!(r.rebound_speed < v0 / strong.hysteresis_factor());
    }
    // A constant 100 N pulling the mass off the wall drives the rate past -v0/chi in contact:
    // the clamp acts, the force never pulls, and the energy balance still closes (the pull does
    // no net work between onset and separation, both at delta = 0).
    let r = impact_pulled(&law, m, v0, 100.0, 4000.0);
    assert!(r.clamped);
    assert!(r.force_min >= 0.0);
    assert!(r.rebound_speed > v0 / law.hysteresis_factor());
    let lost = 0.5 * m * (v0 * v0 - r.rebound_speed * r.rebound_speed);
    assert!(rel(r.dissipated, lost) < 1e-8, "{} vs {lost}", r.dissipated);
}
