//! Contact laws pointwise: finite-difference checks of both derivatives for every law, the
//! no-adhesion clamp, the approach-speed floor, energy functions, static quantities and input
//! validation.

use mbcosim::contact::{ContactError, ContactLaw, DEFAULT_MIN_APPROACH_SPEED, LawKind};

fn laws() -> Vec<ContactLaw> {
    let mut v = Vec::new();
    for kind in LawKind::ALL {
        for n in [0.9, 1.0, 1.5, 2.0] {
            for e in [0.2, 0.6, 0.95, 1.0] {
                v.push(ContactLaw::new(kind, 1e7, n, e).unwrap());
            }
        }
    }
    v
}

#[test]
fn derivatives_match_central_differences() {
    let v_minus = 0.8;
    for law in laws() {
        for delta in [1e-7, 3e-5, 2e-4, 1e-3] {
            for delta_dot in [0.5, 0.05, 0.0, -0.01, -0.2] {
                let f = law.evaluate(delta, delta_dot, v_minus);
                if f.clamped {
                    continue;
                }
                let hd = 1e-6 * delta;
                let fd_delta = (law.evaluate(delta + hd, delta_dot, v_minus).force
                    - law.evaluate(delta - hd, delta_dot, v_minus).force)
                    / (2.0 * hd);
                let hv = 1e-6;
                let fp = law.evaluate(delta, delta_dot + hv, v_minus);
                let fm = law.evaluate(delta, delta_dot - hv, v_minus);
                assert!(!fp.clamped && !fm.clamped);
                let fd_rate = (fp.force - fm.force) / (2.0 * hv);
                let scale = f.d_force_d_delta.abs().max(1e-9);
                assert!(
                    (f.d_force_d_delta - fd_delta).abs() < 1e-7 * scale,
                    "{law:?} delta={delta} rate={delta_dot}: {} vs {fd_delta}",
                    f.d_force_d_delta
                );
                let scale = f.d_force_d_delta_dot.abs().max(f.force * 1e-9).max(1e-12);
                assert!(
                    (f.d_force_d_delta_dot - fd_rate).abs() < 1e-6 * scale,
                    "{law:?} delta={delta} rate={delta_dot}: {} vs {fd_rate}",
                    f.d_force_d_delta_dot
                );
            }
        }
    }
}

#[test]
fn clamp_gives_zero_force_and_zero_derivatives() {
    let law = ContactLaw::new(LawKind::Flores, 1e7, 1.5, 0.2).unwrap();
    // chi = 6.4: the bracket 1 + 6.4 * rate / 1 turns negative below rate = -0.15625 m/s.
    let f = law.evaluate(1e-4, -0.2, 1.0);
    assert!(f.clamped);
    assert_eq!(
        (f.force, f.d_force_d_delta, f.d_force_d_delta_dot),
        (0.0, 0.0, 0.0)
    );
    assert_eq!(f.damping_force, -f.elastic_force);
    assert!(f.dissipated_power > 0.0);
    // Finite differences agree with the zero derivatives inside the clamped region.
    let g = law.evaluate(1e-4 * (1.0 + 1e-6), -0.2 - 1e-6, 1.0);
    assert_eq!(g.force, 0.0);
    // Just above the threshold the force is positive.
    assert!(law.evaluate(1e-4, -0.15, 1.0).force > 0.0);
}

#[test]
fn separated_contact_gives_nothing() {
    for law in laws() {
        for delta in [0.0, -1e-3] {
            let f = law.evaluate(delta, 1.0, 1.0);
            assert_eq!(f.force, 0.0);
            assert_eq!(f.d_force_d_delta, 0.0);
            assert_eq!(f.d_force_d_delta_dot, 0.0);
            assert_eq!(f.dissipated_power, 0.0);
            assert_eq!(law.potential_energy(delta), 0.0);
        }
        // n < 1: the stiffness is singular at 0 but stays finite for any positive delta.
        let f = law.evaluate(f64::MIN_POSITIVE, 0.0, 1.0);
        assert!(f.force.is_finite() && f.d_force_d_delta.is_finite());
    }
}

#[test]
fn approach_speed_floor_bounds_the_damping() {
    let law = ContactLaw::new(LawKind::HuntCrossley, 1e7, 1.5, 0.5).unwrap();
    assert_eq!(law.min_approach_speed(), DEFAULT_MIN_APPROACH_SPEED);
    let at_floor = law.evaluate(1e-4, 1e-3, DEFAULT_MIN_APPROACH_SPEED);
    for unknown in [0.0, 1e-30, -1.0, f64::NAN] {
        assert_eq!(law.evaluate(1e-4, 1e-3, unknown), at_floor);
    }
    // Damping coefficient dF/d delta_dot = chi k delta^n / v_floor.
    let expect = 0.75 * 1e7 * 1e-4_f64.powf(1.5) / DEFAULT_MIN_APPROACH_SPEED;
    assert!((at_floor.d_force_d_delta_dot - expect).abs() < 1e-12 * expect);
    let custom = law.with_min_approach_speed(1e-2).unwrap();
    assert_eq!(custom.effective_approach_speed(1e-3), 1e-2);
    assert_eq!(custom.effective_approach_speed(0.5), 0.5);
}

#[test]
fn potential_energy_is_the_integral_of_the_elastic_force() {
    for law in laws() {
        let d = 2e-4;
        let h = 1e-6 * d;
        let dpe = (law.potential_energy(d + h) - law.potential_energy(d - h)) / (2.0 * h);
        let el = law.evaluate(d, 0.0, 1.0).elastic_force;
        assert!((dpe - el).abs() < 1e-7 * el, "{law:?}");
    }
}

#[test]
fn dissipated_power_is_damping_force_times_rate() {
    let law = ContactLaw::new(LawKind::LankaraniNikravesh, 1e8, 1.5, 0.8).unwrap();
    for rate in [0.3, -0.3] {
        let f = law.evaluate(1e-4, rate, 1.0);
        assert!((f.force - f.elastic_force - f.damping_force).abs() < 1e-12 * f.force);
        assert_eq!(f.dissipated_power, f.damping_force * rate);
        assert!(f.dissipated_power > 0.0);
    }
}

#[test]
fn static_penetration_and_linearized_stiffness() {
    for law in laws() {
        for force in [0.1, 12.5, 931.0] {
            let d = law.static_penetration(force).unwrap();
            // At rest every law reduces to k delta^n.
            let f = law.evaluate(d, 0.0, 0.3);
            assert!((f.force - force).abs() < 1e-12 * force, "{law:?}");
            let kl = law.linearized_stiffness(d).unwrap();
            assert!((kl - f.d_force_d_delta).abs() < 1e-12 * kl);
            // Independent: dF_s/d delta_s by differencing the inverse map delta_s(F).
            let h = 1e-6 * force;
            let dd = law.static_penetration(force + h).unwrap()
                - law.static_penetration(force - h).unwrap();
            assert!((2.0 * h / dd - kl).abs() < 1e-6 * kl, "{law:?}");
        }
        assert_eq!(law.static_penetration(0.0).unwrap(), 0.0);
    }
    // Hand-checked values, k = 1e7 N/m^1.5: F = 1000 N -> delta = 1e-4^(2/3) m.
    let hz = ContactLaw::hertz(1e7, 1.5).unwrap();
    let d = hz.static_penetration(1000.0).unwrap();
    assert!((d - 2.154_434_690_031_884e-3).abs() < 1e-15);
    let kl = hz.linearized_stiffness(d).unwrap();
    assert!((kl - 1.5 * 1e7 * d.sqrt()).abs() < 1e-9 * kl);
    // Edges at zero penetration.
    assert_eq!(hz.linearized_stiffness(0.0).unwrap(), 0.0);
    let lin = ContactLaw::hertz(3e6, 1.0).unwrap();
    assert_eq!(lin.linearized_stiffness(0.0).unwrap(), 3e6);
    let soft = ContactLaw::hertz(1e8, 0.9).unwrap();
    assert!(soft.linearized_stiffness(0.0).is_err());
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(hz.static_penetration(bad).is_err());
        assert!(hz.linearized_stiffness(bad).is_err());
    }
}

fn param_error(r: Result<ContactLaw, ContactError>) -> String {
    match r {
        Err(e @ ContactError::InvalidParameter { .. }) => e.to_string(),
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

#[test]
fn bad_parameters_are_refused_with_precise_messages() {
    use LawKind::*;
    for k in [0.0, -1e7, f64::NAN, f64::INFINITY] {
        let m = param_error(ContactLaw::new(Hertz, k, 1.5, 1.0));
        assert!(m.contains("stiffness k") && m.contains("> 0"), "{m}");
    }
    for n in [0.0, -1.5, f64::NAN, f64::NEG_INFINITY] {
        let m = param_error(ContactLaw::new(Flores, 1e7, n, 0.5));
        assert!(m.contains("exponent n"), "{m}");
    }
    for e in [0.0, -0.1, 1.0 + 1e-12, f64::NAN, f64::INFINITY] {
        for kind in LawKind::ALL {
            let m = param_error(ContactLaw::new(kind, 1e7, 1.5, e));
            assert!(m.contains("restitution e") && m.contains("(0, 1]"), "{m}");
        }
    }
    let law = ContactLaw::hertz(1e7, 1.5).unwrap();
    for v in [0.0, -1.0, f64::NAN] {
        let m = param_error(law.with_min_approach_speed(v));
        assert!(m.contains("minimum approach speed"), "{m}");
    }
    assert_eq!(LawKind::from_code(3).unwrap(), LawKind::Flores);
    for code in [-1, 4, i32::MAX] {
        let m = LawKind::from_code(code).unwrap_err().to_string();
        assert!(m.contains("contact law code"), "{m}");
    }
    // e = 1 is admissible for every law and then no law dissipates.
    for kind in LawKind::ALL {
        let l = ContactLaw::new(kind, 1e7, 1.5, 1.0).unwrap();
        assert_eq!(l.hysteresis_factor(), 0.0);
    }
}
