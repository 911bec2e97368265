//! Many contact nodes at once (issue #19): a rope around a polygonal drum of 64 and 256 edges
//! (wrap 180 degrees, circumradius 0.52 m), and around a rounded 90 degree corner (a square block
//! whose corner is a 16-facet arc), pulled at one end slowly from T1 until the rope runs through
//! every contact node. The applied T2/T1 at gross slip must equal the polygon law, the product
//! of the sharp-edge ratios `(1 + mu tan(theta_i/2)) / (1 - mu tan(theta_i/2))` over the turns
//! `theta_i` of the rig's geometry, within 0.5 % (for the drums it also lies within 0.5 % of the
//! capstan law `exp(mu pi)`), both ways round the corner; and at every contact node and every
//! output point the friction (hold along the edge and the rope's pull along the rope) stays
//! inside the cone, `|(F_e, F_r)| <= mu N` to 1e-9 relative. Steel rope EA 7.5e7 N, 6.4 kg/m,
//! mu 0.2, at 9.81 kN and 981 kN (the 256-edge drum at 981 kN only, for run time). Before the
//! cone settlement slid sticking nodes again until none is left outside, the 64-edge drum at
//! 9.81 kN had a sticking node at friction / (mu N) = 1 + 4.4e-9.

use crate::rig::*;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::SlipMode;
use mbcosim::rope::friction::FrictionLaw;
use std::f64::consts::PI;
use std::sync::Arc;

const MU: f64 = STEEL_MU;

/// The polygon law of a rig: the product of the sharp-edge ratios over the turns at its
/// vertices (strand 1 in, chords, strand 2 out), from the geometry alone.
fn polygon_law(rig: &Wrap) -> f64 {
    let mut dirs = vec![-rig.e1];
    dirs.extend(rig.vertices.windows(2).map(|v| (v[1] - v[0]).normalize()));
    dirs.push(rig.e2);
    dirs.windows(2)
        .map(|d| {
            let theta = d[0].dot(&d[1]).clamp(-1.0, 1.0).acos();
            let x = MU * (0.5 * theta).tan();
            (1.0 + x) / (1.0 - x)
        })
        .product()
}

/// What a ramp to gross slip measured.
struct GrossSlip {
    /// Applied T2/T1 when every node first slid.
    ratio: f64,
    /// Largest friction / (mu N) at any node and output point.
    worst_cone: f64,
    /// First output point with friction outside the cone.
    first_bad: Option<String>,
}

/// Ramps the pull of end 2 (end 1 with `reverse`) of `rig` from `t1` [N] by `1.2 t1` over
/// `duration` [s], the other end held at `t1`, checking the cone at every contact node every
/// `dt` [s], until every node slides the way it is pulled.
fn ramp_to_gross_slip(mut rig: Wrap, t1: f64, reverse: bool, duration: f64, dt: f64) -> GrossSlip {
    let rate = 1.2 * t1 / duration;
    (rig.f1, rig.f2) = if reverse {
        (Profile::linear(t1, rate), Profile::constant(t1))
    } else {
        (Profile::constant(t1), Profile::linear(t1, rate))
    };
    let want = if reverse {
        SlipMode::SlipBackward
    } else {
        SlipMode::SlipForward
    };
    let mut sim = rig.sim(settings(1e-3));
    let mut out = GrossSlip {
        ratio: f64::NAN,
        worst_cone: 0.0,
        first_bad: None,
    };
    let steps = (duration / dt).round() as usize;
    for s in 1..=steps {
        let t = dt * s as f64;
        sim.advance_to(t).unwrap();
        let modes = sim.slip_modes();
        for rep in sim.contact_reports() {
            let n = rep.reaction.normal;
            let f = rep.reaction.friction();
            out.worst_cone = out.worst_cone.max(f / (MU * n));
            // Coulomb's other half: on the cone while the rope slides through the node
            let under = modes[rep.slot] != SlipMode::Stick && f < MU * n * (1.0 - 1e-9);
            if (!(n > 0.0 && f <= MU * n * (1.0 + 1e-9)) || under) && out.first_bad.is_none() {
                out.first_bad = Some(format!(
                    "t = {t:.3} s, node {} ({:?}): friction {f:.9e} N = {:.12} mu N (F_e {:.3e} N, F_r {:.6e} N), T {:.6e} / {:.6e} N, turn {:.3e} rad",
                    rep.node,
                    modes[rep.slot],
                    f / (MU * n),
                    rep.hold_force,
                    rep.pull.along_rope,
                    rep.segments.t_prev,
                    rep.segments.t_next,
                    rep.turn,
                ));
            }
        }
        if modes.iter().all(|m| *m == want) {
            let (a, b) = (rig.f1.eval(t, &[]).0, rig.f2.eval(t, &[]).0);
            out.ratio = b / a;
            return out;
        }
    }
    out
}

/// Checks one ramp against the polygon law; returns failures.
fn check(name: &str, rig: Wrap, t1: f64, reverse: bool, dt: f64) -> Vec<String> {
    let law = polygon_law(&rig);
    let want = if reverse { 1.0 / law } else { law };
    let start = std::time::Instant::now();
    let g = ramp_to_gross_slip(rig, t1, reverse, 2.0, dt);
    let rel = g.ratio / want - 1.0;
    println!(
        "{name}, T1 {t1:.3e} N, reverse {reverse}: T2/T1 at gross slip {:.5} (polygon law {want:.5}, {rel:+.1e}), max friction / (mu N) {:.12}, {:.1} s",
        g.ratio,
        g.worst_cone,
        start.elapsed().as_secs_f64()
    );
    let mut failures = Vec::new();
    if rel.is_nan() || rel.abs() >= 0.005 {
        failures.push(format!(
            "{name}, T1 {t1}, reverse {reverse}: {} vs {want}",
            g.ratio
        ));
    }
    failures.extend(
        g.first_bad
            .map(|b| format!("{name}, T1 {t1}, reverse {reverse}: {b}")),
    );
    failures
}

/// The drum of `k` edges with end loads of `end_mass` [kg].
fn drum(k: usize, t1: f64, end_mass: f64) -> Wrap {
    let pull = (Profile::constant(t1), Profile::constant(t1));
    Wrap {
        end_mass,
        ..Wrap::drum(k, 0.52, t1, steel_rope(), pull, Hold::Fixed)
    }
}

#[test]
fn drum_of_64_contact_nodes_follows_the_polygon_law_inside_the_cone() {
    let capstan = (MU * PI).exp();
    let law = polygon_law(&drum(64, 1.0, 1.0));
    println!("k = 64: polygon law {law:.6}, capstan {capstan:.6}");
    assert!((law / capstan - 1.0).abs() < 0.005);
    let mut failures = Vec::new();
    // end loads of 100 kg per 9.81 kN of T1
    for t1 in [9.81e3, 9.81e5] {
        for reverse in [false, true] {
            let rig = drum(64, t1, 100.0 * t1 / 9.81e3);
            failures.extend(check("drum k = 64", rig, t1, reverse, 1e-3));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The 64-edge drum under the rope paper's pseudo friction coefficient (issue #45 item 4): each
/// edge is across the rope, so no load acts along the edges and the polygon law holds to the
/// same 0.5 %, with every node inside its cone (on it while sliding) to 1e-9.
#[test]
fn drum_of_64_contact_nodes_follows_the_polygon_law_under_the_pseudo_coefficient() {
    let mut failures = Vec::new();
    for t1 in [9.81e3, 9.81e5] {
        let mut rig = drum(64, t1, 100.0 * t1 / 9.81e3);
        rig.props.friction_law = FrictionLaw::PseudoCoefficient;
        failures.extend(check(
            "drum k = 64, pseudo coefficient",
            rig,
            t1,
            false,
            1e-3,
        ));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The 256-edge drum's polygon law, checked against the capstan law it approaches.
fn drum_256_law() {
    let capstan = (MU * PI).exp();
    let law = polygon_law(&drum(256, 1.0, 1.0));
    println!("k = 256: polygon law {law:.6}, capstan {capstan:.6}");
    assert!((law / capstan - 1.0).abs() < 0.005);
}

#[test]
fn drum_of_256_contact_nodes_follows_the_polygon_law_inside_the_cone() {
    drum_256_law();
    let t1 = 9.81e5;
    let failures = check("drum k = 256", drum(256, t1, 1e4), t1, false, 1e-3);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// At 9.81 kN the stick band of a 0.7 degree turn (`2 mu tan(theta/2) T` = 24 N) is 2e-9 m of
/// stretch of a 6.4 mm segment, 50 times below the position tolerance, so the slip front's
/// stick/slip decisions take many steps: the slowest rope test (90 s on the idle machine,
/// 2026-11-29; over three minutes on a loaded one), kept in the suite because the issue's
/// targets name both load levels at 256 nodes.
#[test]
fn drum_of_256_contact_nodes_at_9_81_kn_follows_the_polygon_law_inside_the_cone() {
    drum_256_law();
    let t1 = 9.81e3;
    let failures = check("drum k = 256", drum(256, t1, 1e4), t1, false, 1e-3);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A 2 m square block (a prism along z) whose corner at (+1, +1) is rounded with radius 0.25 m
/// by `n` facets; the rope wraps the arc's `n + 1` vertices, both strands leaving 2 degrees off
/// the block's faces (strand 1 down along x = 1, strand 2 along y = 1 towards -x).
fn rounded_corner(n: usize, t1: f64) -> Wrap {
    let rho = 0.25;
    let c = (1.0 - rho, 1.0 - rho);
    let arc: Vec<(f64, f64)> = (0..=n)
        .map(|j| {
            let a = 0.5 * PI * j as f64 / n as f64;
            (c.0 + rho * a.cos(), c.1 + rho * a.sin())
        })
        .collect();
    let mut section = vec![(-1.0, -1.0), (1.0, -1.0)];
    section.extend(&arc);
    section.push((-1.0, 1.0));
    let off = 2f64.to_radians();
    let vertices = arc.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
    let pull = (Profile::constant(t1), Profile::constant(t1));
    let mut rig = Wrap {
        end_mass: 100.0 * t1 / 9.81e3,
        ..Wrap::drum(2, 0.5, t1, steel_rope(), pull, Hold::Fixed)
    };
    rig.mesh = Arc::new(prism(&section, 1.0));
    rig.vertices = vertices;
    rig.e1 = Vec3::new(off.sin(), -off.cos(), 0.0);
    rig.e2 = Vec3::new(-off.cos(), off.sin(), 0.0);
    rig.strand = 1.0;
    rig.t_init = vec![t1; n + 2];
    rig
}

#[test]
fn rope_pulled_around_a_rounded_corner_both_ways() {
    let n = 16;
    let turn = 0.5 * PI - 2.0 * 2f64.to_radians();
    let capstan = (MU * turn).exp();
    let law = polygon_law(&rounded_corner(n, 1.0));
    println!("rounded corner, {n} facets: polygon law {law:.6}, capstan {capstan:.6}");
    let mut failures = Vec::new();
    for t1 in [9.81e3, 9.81e5] {
        for reverse in [false, true] {
            let rig = rounded_corner(n, t1);
            failures.extend(check("rounded corner", rig, t1, reverse, 1e-3));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Issue #42's "no tension spike above the strand's load by more than 1e-6 relative" on the
/// 32-edge drum, at 9.81 kN and 981 kN. A rope pulled at a speed rings axially at about 1e-3
/// of its load (docs/rope_friction.md, "Pulled at a speed": 49-59 N between neighbours at
/// 18 kN is a strand node accelerating at 15-18 m/s^2, physics, not a report error), so the
/// check needs a quasi-static rig: end 1 held at T1, end 2's pull raised smoothly from T1 to
/// 1.015 T1 over 2 s along `T1 (1.015 - 0.015 cos(2 pi t / 8 s))` (zero rate at the start, so
/// no step excites the axial modes, whose periods are milliseconds; end loads of 10 kg, so the
/// inertia of the ends' motion under the rising load is below 1e-8 of it), which stays below
/// the per-edge slip ratio 1.0197: every node sticks, the drum's friction carries the
/// difference. At every sample (10 ms) no segment's tension may exceed the larger applied end
/// load, the load the strand carries (an input, not a reported tension), by more than 1e-6
/// relative; and the segment at end 2 carries that load to 1e-6 (the rig is quasi-static).
/// Raised to 1.15 T1 instead, the nodes near end 2 start sliding at about 0.7 s and from there
/// the strand rings at up to 3.4e-4 of its load (docs/rope_friction.md, 2026-12-07 "rope3"):
/// the stick-slip onset excites the axial modes, so that rig is not quasi-static.
#[test]
fn quasi_static_drum_of_32_edges_has_no_tension_above_the_strands_load() {
    use mbcosim::model::Profile;
    let period = 8.0;
    let omega = 2.0 * PI / period;
    for t1 in [9.81e3, 9.81e5] {
        let load = |t: f64| t1 * (1.015 - 0.015 * (omega * t).cos());
        let f2 = Profile::Sine {
            offset: 1.015 * t1,
            amplitude: 0.015 * t1,
            omega,
            phase: -0.5 * PI,
        };
        let rig = Wrap {
            end_mass: 10.0,
            ..Wrap::drum(
                32,
                0.52,
                t1,
                steel_rope(),
                (Profile::constant(t1), f2),
                Hold::Fixed,
            )
        };
        let mut sim = rig.sim(settings(1e-3));
        let (mut worst_over, mut worst_end, mut sliding) = (f64::NEG_INFINITY, 0.0f64, 0);
        for s in 1..=200 {
            let t = 1e-2 * s as f64;
            sim.advance_to(t).unwrap();
            let strand = load(t).max(t1);
            let ten: Vec<f64> = sim.rope_tensions(0).iter().map(|x| x.0).collect();
            let top = ten.iter().fold(f64::NEG_INFINITY, |a, x| a.max(*x));
            worst_over = worst_over.max(top / strand - 1.0);
            worst_end = worst_end.max((ten[ten.len() - 1] / strand - 1.0).abs());
            sliding += sim
                .slip_modes()
                .iter()
                .filter(|m| **m != SlipMode::Stick)
                .count();
        }
        println!(
            "quasi-static drum k = 32, T1 {t1:.3e} N: largest segment tension over the strand's load {worst_over:+.2e}, end-2 segment against its load {worst_end:.2e}, sliding node samples {sliding}"
        );
        assert!(worst_over <= 1e-6, "T1 {t1}: {worst_over:e}");
        assert!(worst_end <= 1e-6, "T1 {t1}: {worst_end:e}");
        assert!(sliding == 0, "T1 {t1}: {sliding} node samples slid");
    }
}
