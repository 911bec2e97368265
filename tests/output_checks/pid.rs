//! PidController: `error` and `saturated` against the inputs and limits by hand.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::pid;

fn vr(m: &dyn CoSimModel, name: &str) -> u32 {
    m.info()
        .port_by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

fn set(m: &mut dyn CoSimModel, name: &str, v: f64) {
    let r = vr(m, name);
    m.set_real(r, v).unwrap();
}

fn get(m: &dyn CoSimModel, name: &str) -> f64 {
    m.get_real(vr(m, name)).unwrap()
}

/// Setpoint and measurement held over each of the steps.
const SAMPLES: [(f64, f64); 8] = [
    (1.0, 0.0),
    (1.0, 0.25),
    (-2.0, 0.5),
    (0.3, 0.3),
    (0.0, -0.7),
    (5.0, 4.9),
    (-0.1, 0.45),
    (2.5, -1.0),
];

#[test]
fn error_is_setpoint_minus_measurement_of_the_last_sample() {
    // proportional only (kp 2, ki = kd = 0) with limits +-1 and the anti-windup tracking all
    // but off (Tt 1e9 s: the integral it builds stays below 1e-9): u = clamp(2 e), saturated
    // exactly when |2 e| > 1, error = setpoint - measurement set before the step
    let mut m = pid::create();
    let gains = [("kp", 2.0), ("ki", 0.0), ("kd", 0.0), ("Tt", 1e9)];
    for (n, v) in gains.into_iter().chain([("u_min", -1.0), ("u_max", 1.0)]) {
        set(m.as_mut(), n, v);
    }
    set(m.as_mut(), "setpoint", 0.4);
    set(m.as_mut(), "measurement", 0.1);
    m.initialize(0.0).unwrap();
    let sat = vr(m.as_ref(), "saturated");
    assert!((get(m.as_ref(), "error") - 0.3).abs() < 1e-15);
    let (h, mut t) = (0.1, 0.0);
    for (sp, meas) in SAMPLES {
        set(m.as_mut(), "setpoint", sp);
        set(m.as_mut(), "measurement", meas);
        // outputs change only in the step: still the previous sample's
        let before = get(m.as_ref(), "error");
        assert_ne!(before, sp - meas);
        m.do_step(t, h).unwrap();
        t += h;
        let (e, u) = (get(m.as_ref(), "error"), get(m.as_ref(), "u"));
        let by_hand = sp - meas;
        assert!(
            (e - by_hand).abs() <= 1e-15 * by_hand.abs().max(1.0),
            "t {t}: error {e} vs {by_hand}"
        );
        let v = 2.0 * by_hand;
        assert!((u - v.clamp(-1.0, 1.0)).abs() < 1e-8, "t {t}: u {u} vs {v}");
        assert_eq!(
            m.get_boolean(sat).unwrap(),
            v.abs() > 1.0,
            "t {t}: saturated with u = {u}, unclamped {v}"
        );
    }
}
