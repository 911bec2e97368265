//! Latch geometry against hand-computed formulas: with the seated pin centre on a circle of radius
//! `r_s = R_c - d_g + r_p` at polar angle `phi = theta - theta_L`, its distance from the groove
//! centreline is `r_s sin(phi)`, so the penetrations into the flat side walls are
//! `delta_front = r_s sin(phi) + r_p - w_g/2` and `delta_rear = -r_s sin(phi) + r_p - w_g/2`,
//! with `d delta / d theta = +-r_s cos(phi)`. The library computes them in closed form where a
//! flat face is nearest (its unit test checks that against parry3d-f64) and with parry3d-f64
//! elsewhere.

use mbcosim::contact::{
    ContactError, ContactLaw, LatchContact, LatchGeometry, LatchParams, LawKind, Wall,
};
use mbcosim::math::Vec3;

const R_C: f64 = 0.030;
const W_G: f64 = 0.010;
const D_G: f64 = 0.006;
const R_P: f64 = 0.004;
const THETA_L: f64 = 1.2;

fn params() -> LatchParams {
    LatchParams {
        cam_radius: R_C,
        groove_width: W_G,
        groove_depth: D_G,
        pin_radius: R_P,
        lock_angle: THETA_L,
    }
}

fn latch() -> LatchGeometry {
    LatchGeometry::new(params()).unwrap()
}

fn engaged_at(l: &LatchGeometry, theta: f64) -> LatchContact {
    l.query(theta, true)
        .unwrap()
        .expect("engaged latch reports both walls")
}

const R_S: f64 = R_C - D_G + R_P;

/// Tolerance on lengths [m] against the hand formula: rounding only (1e-10 of the pin radius).
const TOL: f64 = 4e-13;

#[test]
fn penetration_matches_hand_formula() {
    let l = latch();
    let mut worst: f64 = 0.0;
    assert!((l.seat_radius() - R_S).abs() < TOL);
    // Angles from before engagement to deep in the front wall (phi in rad).
    for phi in [
        -0.05, -0.036, -0.02, -0.003, 0.0, 0.004, 0.0357, 0.0358, 0.036, 0.04,
    ] {
        let c = engaged_at(&l, THETA_L + phi);
        let s = R_S * f64::sin(phi);
        let front = s + R_P - 0.5 * W_G;
        let rear = -s + R_P - 0.5 * W_G;
        worst = worst
            .max((c.front.penetration - front).abs())
            .max((c.rear.penetration - rear).abs());
        assert!((c.front.penetration - front).abs() < TOL, "phi {phi}");
        assert!((c.rear.penetration - rear).abs() < TOL, "phi {phi}");
        let slope = R_S * f64::cos(phi);
        assert!((c.front.d_penetration_d_theta - slope).abs() < TOL);
        assert!((c.rear.d_penetration_d_theta + slope).abs() < TOL);
        assert!((c.front.moment_arm + slope).abs() < TOL);
        assert!((c.rear.moment_arm - slope).abs() < TOL);
        assert!((c.front.d2_penetration_d_theta2 + s).abs() < TOL);
        assert!((c.rear.d2_penetration_d_theta2 - s).abs() < TOL);
        // Flat faces: the wall pushes the pin along -y (front) or +y (rear) in the latch frame.
        assert!((c.front.normal - Vec3::new(0.0, -1.0, 0.0)).norm() < TOL);
        assert!((c.rear.normal - Vec3::new(0.0, 1.0, 0.0)).norm() < TOL);
        // The contact point is the pin's surface point facing the wall.
        let centre = l.pin_centre(THETA_L + phi);
        assert!((c.front.point - centre - Vec3::new(0.0, R_P, 0.0)).norm() < TOL);
        assert!((c.wall(Wall::Rear).point.y - (centre.y - R_P)).abs() < TOL);
    }
    eprintln!("largest |penetration - hand formula|: {worst:.1e} m");
}

#[test]
fn derivatives_match_finite_differences() {
    let l = latch();
    let h = 1e-6;
    for phi in [-0.03, 0.0, 0.02, 0.037] {
        let t = THETA_L + phi;
        let (m, c, p) = (
            engaged_at(&l, t - h),
            engaged_at(&l, t),
            engaged_at(&l, t + h),
        );
        for w in [Wall::Front, Wall::Rear] {
            let d1 = (p.wall(w).penetration - m.wall(w).penetration) / (2.0 * h);
            assert!((d1 - c.wall(w).d_penetration_d_theta).abs() < 1e-9, "{w:?}");
            let d2 =
                (p.wall(w).d_penetration_d_theta - m.wall(w).d_penetration_d_theta) / (2.0 * h);
            assert!(
                (d2 - c.wall(w).d2_penetration_d_theta2).abs() < 1e-9,
                "{w:?}"
            );
        }
    }
}

#[test]
fn engagement_drops_the_pin_without_penetration() {
    let l = latch();
    let theta_e = l.engagement_angle();
    let by_hand = THETA_L - f64::asin((0.5 * W_G - R_P) / R_S);
    assert!((theta_e - by_hand).abs() < 1e-15);
    assert!(!l.engages(theta_e - 1e-9));
    assert!(l.engages(theta_e));
    assert!(!l.engages(f64::NAN));
    let c = engaged_at(&l, theta_e);
    // Just clear of the rear wall, and the front wall a full clearance w_g - 2 r_p away.
    assert!(c.rear.penetration.abs() < 1e-15);
    assert!((c.front.penetration + (W_G - 2.0 * R_P)).abs() < 1e-15);
    // Not engaged: the pin rides on the rim and the walls are not reported.
    assert_eq!(l.query(theta_e, false).unwrap(), None);
    assert_eq!(l.query(THETA_L - 1.0, false).unwrap(), None);
}

#[test]
fn wall_torque_opposes_motion_both_ways() {
    let l = latch();
    let law = ContactLaw::new(LawKind::LankaraniNikravesh, 1e7, 1.5, 0.8).unwrap();
    let hinge_torque = |theta: f64, theta_dot: f64| -> f64 {
        let c = engaged_at(&l, theta);
        [c.front, c.rear]
            .iter()
            .map(|w| {
                let rate = w.d_penetration_d_theta * theta_dot;
                law.evaluate(w.penetration, rate, 0.05).force * w.moment_arm
            })
            .sum()
    };
    // Front wall touches where r_s sin(phi) = w_g/2 - r_p, the rear wall at the opposite angle.
    let phi_touch = f64::asin((0.5 * W_G - R_P) / R_S);
    for pen_angle in [1e-6, 1e-4, 1e-3] {
        // Driven past the front wall while opening: the torque on B closes the hinge.
        assert!(hinge_torque(THETA_L + phi_touch + pen_angle, 0.3) < 0.0);
        assert!(hinge_torque(THETA_L + phi_touch + pen_angle, 0.0) < 0.0);
        // Driven past the rear wall while closing: the torque on B opens it again.
        assert!(hinge_torque(THETA_L - phi_touch - pen_angle, -0.3) > 0.0);
        assert!(hinge_torque(THETA_L - phi_touch - pen_angle, 0.0) > 0.0);
    }
    // In the clearance between the walls there is no torque.
    assert_eq!(hinge_torque(THETA_L, 0.3), 0.0);
    // Virtual work: the static torque is minus the derivative of the contact energy in theta.
    let theta = THETA_L + phi_touch + 2e-4;
    let energy = |t: f64| law.potential_energy(engaged_at(&l, t).front.penetration);
    let h = 1e-7;
    let dv = (energy(theta + h) - energy(theta - h)) / (2.0 * h);
    let tq = hinge_torque(theta, 0.0);
    assert!((tq + dv).abs() < 1e-6 * tq.abs(), "{tq} vs {}", -dv);
}

#[test]
fn bad_geometry_is_refused() {
    let check = |p: LatchParams, needle: &str| match LatchGeometry::new(p) {
        Err(e @ ContactError::InvalidParameter { .. }) => {
            let m = e.to_string();
            assert!(m.contains(needle), "{m}");
        }
        other => panic!("expected an error naming {needle}, got {other:?}"),
    };
    let p = params();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        check(
            LatchParams {
                cam_radius: bad,
                ..p
            },
            "cam radius R_c",
        );
        check(
            LatchParams {
                groove_width: bad,
                ..p
            },
            "groove width w_g",
        );
        check(
            LatchParams {
                groove_depth: bad,
                ..p
            },
            "groove depth d_g",
        );
        check(
            LatchParams {
                pin_radius: bad,
                ..p
            },
            "pin radius r_p",
        );
    }
    check(
        LatchParams {
            lock_angle: f64::NAN,
            ..p
        },
        "lock angle",
    );
    check(
        LatchParams {
            groove_width: 0.0079,
            ..p
        },
        ">= 2 r_p",
    );
    check(
        LatchParams {
            groove_depth: 0.0039,
            ..p
        },
        ">= r_p",
    );
    check(
        LatchParams {
            groove_depth: 0.03,
            ..p
        },
        "< cam radius",
    );
    check(
        LatchParams {
            groove_width: 0.05,
            ..p
        },
        "2 (R_c - d_g)",
    );
    // A pin exactly as wide as the groove is admissible: no clearance, locked at once.
    let tight = LatchGeometry::new(LatchParams {
        groove_width: 2.0 * R_P,
        ..p
    })
    .unwrap();
    assert_eq!(tight.engagement_angle(), THETA_L);
    assert!(matches!(
        latch().query(f64::NAN, true),
        Err(ContactError::InvalidArgument { .. })
    ));
}
