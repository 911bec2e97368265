//! Unit tests of the PID controller against analytic responses.

use super::*;

fn pid(params: &[(ValueRef, f64)]) -> Pid {
    let mut p = Pid::new();
    for (vr, v) in params {
        p.set_real(*vr, *v).unwrap();
    }
    p
}

fn u(p: &Pid) -> f64 {
    p.get_real(vr::U).unwrap()
}

#[test]
fn table_is_valid() {
    info().validate().unwrap();
}

#[test]
fn constant_error_gives_exact_ramp_for_any_step_sequence() {
    // u(t) = kp*e + ki*e*t for a constant error, at every communication point.
    let (kp, ki, e) = (2.0, 0.75, 0.4);
    let steps: [&[f64]; 3] = [&[0.01; 300], &[0.5; 6], &[0.3, 0.001, 1.2, 0.499, 0.7, 0.3]];
    for seq in steps {
        let mut p = pid(&[(vr::KP, kp), (vr::KI, ki), (vr::KD, 0.3), (vr::SETPOINT, e)]);
        p.initialize(0.0).unwrap();
        assert_eq!(u(&p), kp * e);
        let mut t = 0.0;
        for h in seq {
            p.do_step(t, *h).unwrap();
            t += h;
            let exact = kp * e + ki * e * t;
            assert!(
                (u(&p) - exact).abs() <= 1e-12 * exact.abs(),
                "t={t}: {} vs {exact}",
                u(&p)
            );
        }
        assert!((t - 3.0).abs() < 1e-12);
    }
}

#[test]
fn filtered_derivative_of_a_ramp_matches_the_discrete_and_continuous_solutions() {
    // Error ramp e = a*t sampled at the step starts, kp = ki = 0. The first step sees no change,
    // then every step a change a*h: D after k steps = kd*a*(1 - r^(k-1)), r = Tf/(Tf+h)
    // (backward Euler), which tends to the continuous kd*a*(1 - exp(-t/Tf)) as h -> 0.
    let (kd, tf, a) = (0.5, 0.2, 3.0);
    for h in [0.05, 0.001] {
        let mut p = pid(&[(vr::KP, 0.0), (vr::KI, 0.0), (vr::KD, kd), (vr::TF, tf)]);
        p.initialize(0.0).unwrap();
        let r = tf / (tf + h);
        let mut t = 0.0;
        for k in 1..=((1.0 / h).round() as i32) {
            p.set_real(vr::SETPOINT, a * t).unwrap();
            p.do_step(t, h).unwrap();
            t += h;
            let discrete = kd * a * (1.0 - r.powi(k - 1));
            assert!(
                (u(&p) - discrete).abs() < 1e-12,
                "k={k}: {} vs {discrete}",
                u(&p)
            );
        }
        let continuous = kd * a * (1.0 - (-1.0 / tf).exp());
        let err = (u(&p) - continuous).abs();
        assert!(err < 0.2 * h / tf * kd * a, "h={h}: {err}");
    }
}

#[test]
fn zero_filter_time_gives_a_difference_quotient() {
    let mut p = pid(&[(vr::KP, 0.0), (vr::KI, 0.0), (vr::KD, 2.0), (vr::TF, 0.0)]);
    p.initialize(0.0).unwrap();
    p.set_real(vr::SETPOINT, 1.0).unwrap();
    p.do_step(0.0, 0.1).unwrap();
    assert!((u(&p) - 2.0 * 1.0 / 0.1).abs() < 1e-12);
    p.do_step(0.1, 0.1).unwrap();
    assert_eq!(u(&p), 0.0);
}

#[test]
fn derivative_on_measurement_has_no_setpoint_kick() {
    let mut p = pid(&[(vr::KP, 0.0), (vr::KI, 0.0), (vr::KD, 1.0)]);
    p.set_boolean(vr::D_ON_MEASUREMENT, true).unwrap();
    p.initialize(0.0).unwrap();
    p.set_real(vr::SETPOINT, 5.0).unwrap();
    p.do_step(0.0, 0.01).unwrap();
    assert_eq!(u(&p), 0.0);
    p.set_real(vr::MEASUREMENT, 1.0).unwrap();
    p.do_step(0.01, 0.01).unwrap();
    assert!(u(&p) < 0.0);
    // fixed parameter: refused after initialization, with the reason
    let e = p
        .set_boolean(vr::D_ON_MEASUREMENT, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("fixed parameter"), "{e}");
}

#[test]
fn back_calculation_prevents_windup() {
    // e = 1 for 2 s with kp = 1, ki = 1, u_max = 1.5; then e = -0.2.
    // Tt = 0: the integral is reset so that v = u_max at each saturated sample, and the output
    // leaves saturation in the first step after the error reverses. Without anti-windup (huge
    // Tt) the integral winds up to ~2 and the output stays saturated for seconds.
    let run = |tt: f64| {
        let mut p = pid(&[(vr::KP, 1.0), (vr::KI, 1.0), (vr::U_MAX, 1.5), (vr::TT, tt)]);
        p.set_real(vr::SETPOINT, 1.0).unwrap();
        p.initialize(0.0).unwrap();
        let h = 0.01;
        let mut t = 0.0;
        for _ in 0..200 {
            p.do_step(t, h).unwrap();
            t += h;
        }
        assert!(p.get_boolean(vr::SATURATED).unwrap());
        assert_eq!(u(&p), 1.5);
        p.set_real(vr::SETPOINT, -0.2).unwrap();
        let mut n = 0;
        while p.get_boolean(vr::SATURATED).unwrap() && n < 10_000 {
            p.do_step(t, h).unwrap();
            t += h;
            n += 1;
        }
        (n, p)
    };
    let (n_aw, mut p) = run(0.0);
    assert_eq!(n_aw, 1);
    // analytic first unsaturated output: I = 1.5 - 1 (kp*e), then I + ki*h*e + kp*e
    assert!((u(&p) - (0.5 - 0.01 * 0.2 - 0.2)).abs() < 1e-12);
    assert!(
        p.take_log()
            .iter()
            .any(|r| r.message.contains("left saturation"))
    );
    let (n_windup, _) = run(1.0e9);
    assert!(n_windup > 100, "{n_windup}");
}

#[test]
fn pi_loop_on_a_first_order_plant_settles_at_the_setpoint() {
    // Plant tau*dy/dt = -y + K*u, exact zero-order-hold discretization.
    let (tau, gain, h): (f64, f64, f64) = (1.0, 2.0, 0.01);
    let mut p = pid(&[(vr::KP, 1.0), (vr::KI, 1.0), (vr::SETPOINT, 1.0)]);
    p.initialize(0.0).unwrap();
    let (mut y, mut t) = (0.0, 0.0);
    let decay = (-h / tau).exp();
    for _ in 0..2000 {
        p.set_real(vr::MEASUREMENT, y).unwrap();
        p.do_step(t, h).unwrap();
        y = decay * y + gain * (1.0 - decay) * u(&p);
        t += h;
    }
    assert!((y - 1.0).abs() < 1e-6, "{y}");
    assert!((u(&p) - 0.5).abs() < 1e-6);
}

#[test]
fn serialize_clone_reset_and_misuse() {
    let mut p = pid(&[(vr::KD, 0.1), (vr::SETPOINT, 1.0)]);
    p.initialize(0.0).unwrap();
    p.do_step(0.0, 0.1).unwrap();
    let bytes = p.serialize();
    let mut q = Pid::new();
    q.deserialize(&bytes).unwrap();
    let c = p.clone_box();
    for m in [&mut p as &mut dyn CoSimModel, &mut q] {
        m.set_real(vr::MEASUREMENT, 0.3).unwrap();
        m.do_step(0.1, 0.05).unwrap();
    }
    assert_eq!(u(&p).to_bits(), u(&q).to_bits());
    assert_eq!(c.time(), 0.1);
    for cut in 0..bytes.len() {
        assert!(q.deserialize(&bytes[..cut]).is_err());
    }
    assert!(
        (q.time() - 0.15).abs() < 1e-15,
        "a refused state leaves the model unchanged"
    );
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(q.deserialize(&longer).is_err());

    assert!(
        p.do_step(0.2, 0.1)
            .unwrap_err()
            .to_string()
            .contains("does not match")
    );
    assert!(p.do_step(0.15, 0.0).is_err());
    assert!(p.do_step(0.15, f64::NAN).is_err());
    p.set_real(vr::U_MIN, 3.0).unwrap();
    p.set_real(vr::U_MAX, 2.0).unwrap();
    assert!(
        p.do_step(0.15, 0.1)
            .unwrap_err()
            .to_string()
            .contains("u_min")
    );
    assert!(p.initialize(0.0).is_err());

    p.reset();
    assert_eq!(p.time(), 0.0);
    assert!(p.do_step(0.0, 0.1).is_err());
    p.initialize(1.0).unwrap();
    p.do_step(1.0, 0.1).unwrap();
}

#[test]
fn overflowing_signals_are_refused_instead_of_a_nan_output() {
    // issue #25 item 2: kp = 0 with setpoint 1e308 and measurement -1e308 gave u = NaN with OK
    let mut p = Pid::new();
    p.set_real(vr::KP, 0.0).unwrap();
    p.set_real(vr::SETPOINT, 1e308).unwrap();
    p.set_real(vr::MEASUREMENT, -1e308).unwrap();
    let e = p.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("overflows"), "{e}");
    assert!(!p.ports().is_initialized());
    let mut q = Pid::new();
    q.set_real(vr::KP, 1e300).unwrap();
    q.set_real(vr::SETPOINT, 1e10).unwrap();
    let e = q.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("not finite"), "{e}");
}
