//! Ropes pulled by a hook at a constant speed (issue #42, the RopeBlock items still open): end 2
//! of the rope is on a hook that reaches `v` [m/s] along the strand's direction over 0.1 s and
//! keeps it; end 1 is a load of 100 kg per 9.81 kN pulled by a constant T1 along its strand. No
//! gravity, block welded, no detection of new crossings, generalized-alpha with the quasi-static
//! rope tests' settings (rtol 1e-6, atol 1e-7 m, h_max 1 ms); steel rope of `tests/rope/rig.rs`
//! (EA 7.5e7 N, 6.4 kg/m, axial damping 7.5e3 N s, mu 0.2).
//!
//! - Capstan: the 180 degree drum of k = 32 and 64 edges (circumradius 0.52 m), T1 9.81 kN and
//!   981 kN, v = 0.2 m/s, 2 s, sampled every 1 ms: the largest segment tension over the larger
//!   of the two end segments' (`over ends`), and the largest excess of a segment over both its
//!   neighbours (`local`), both relative.
//! - Tilted sharp edge: the 90 degree edge of `tests/rope/cone.rs`, strand 2 tilted along the
//!   edge by 0, 10 and 20 degrees, T1 9.81 kN and 981 kN, v = 0.05, 0.1, 0.2 m/s, 2 s: steps,
//!   rejections, Newton work, edge slides, CPU time of the thread, and T2/T1 across the node
//!   (its two segments) sampled every 1 ms, mean over 1-2 s, least and largest.
//!
//! - `quasi`: the 981 kN, 20 deg tilted edge with its end load's swing critically damped
//!   ([`pulled::PullOptions`]), pulled at 0.025, 0.05, 0.1, 0.2 m/s until the hook has pulled
//!   0.4 m, T2/T1 sampled every 0.2 mm of pulled length and compared at equal pulled length
//!   (`quasi strands`: the strands' material nodes damped across their strand too; `contact`:
//!   the contact node along its edge too, at the strand nodes' damping; a number scales every
//!   damping, critical by default; `coarse` samples every 10 mm instead).
//! - `tolerance`: the undamped 981 kN, 20 deg rig at 0.2 m/s with rtol/atol scaled by 0.01, 0.1,
//!   1, 10, 100 (a work-precision view).
//!
//! Run: `cargo run --release --example rope_pull_speed [-- capstan | tilted [T1 tilt] | quasi |
//! tolerance] [pseudo_coefficient]` (both by default; `tilted 9.81e5 20` runs that one case at the three
//! speeds; a friction law's name, `edge_first` (the default) or `pseudo_coefficient`, runs the
//! rigs under that law).
//! The figures are in docs/rope_friction.md ("Pulled at a speed").

#[allow(dead_code)]
#[path = "../tests/rope/pulled.rs"]
mod pulled;
#[allow(dead_code)]
#[path = "../tests/rope/rig.rs"]
mod rig;

use mbcosim::model::Profile;
use mbcosim::rope::friction::FrictionLaw;
use pulled::{PullOptions, hooked_with};
use rig::{Hold, Wrap};

fn capstan(law: FrictionLaw) {
    println!(
        "capstan pulled at 0.2 m/s, 2 s, samples every 1 ms, friction law {}",
        law.name()
    );
    for k in [32, 64] {
        for t1 in [9.81e3, 9.81e5] {
            let pull = (Profile::constant(t1), Profile::constant(t1));
            let props = mbcosim::rope::RopeProps {
                friction_law: law,
                ..rig::steel_rope()
            };
            let rig = Wrap {
                end_mass: 100.0 * t1 / 9.81e3,
                ..Wrap::drum(k, 0.52, t1, props, pull, Hold::Fixed)
            };
            let mut sim = hooked_with(&rig, 0.2, PullOptions::default());
            let (mut over_ends, mut local) = (0.0f64, 0.0f64);
            let mut at = (0.0, 0, 0.0, 0.0);
            for s in 1..=2000 {
                let t = 1e-3 * s as f64;
                sim.advance_to(t).unwrap();
                let ten: Vec<f64> = sim.rope_tensions(0).iter().map(|x| x.0).collect();
                let ends = ten[0].max(ten[ten.len() - 1]);
                let top = ten.iter().fold(0.0f64, |a, x| a.max(*x));
                over_ends = over_ends.max(top / ends - 1.0);
                for j in 1..ten.len() - 1 {
                    let e = ten[j] / ten[j - 1].max(ten[j + 1]) - 1.0;
                    if e > local {
                        local = e;
                        at = (t, j, ten[j], ten[j - 1].max(ten[j + 1]));
                    }
                }
            }
            let st = sim.sim.stats();
            println!(
                "k {k:3}, T1 {t1:.3e} N: over ends {over_ends:.3e}, local {local:.3e} (t {:.3} s, segment {} of {}: {:.1} N, neighbours up to {:.1} N), steps {}, rejected {}, Newton {}, {:?}",
                at.0,
                at.1,
                sim.rope_tensions(0).len(),
                at.2,
                at.3,
                st.steps,
                st.rejected,
                st.newton_iterations,
                sim.counters
            );
        }
    }
}

/// CPU time of this thread [s] (wall time since the first call where the kernel does not tell).
fn cpu_seconds() -> f64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .map(|ns| ns * 1e-9)
        .unwrap_or_else(|| {
            START
                .get_or_init(std::time::Instant::now)
                .elapsed()
                .as_secs_f64()
        })
}

/// The tilted-edge cases `(T1 [N], tilt [deg])`: all, or the one named on the command line.
fn tilted_cases(args: &[String]) -> Vec<(f64, f64)> {
    let named: Vec<f64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if let [t1, tilt] = named[..] {
        return vec![(t1, tilt)];
    }
    let mut out = Vec::new();
    for t1 in [9.81e3, 9.81e5] {
        for tilt in [0.0, 10.0, 20.0] {
            out.push((t1, tilt));
        }
    }
    out
}

fn tilted(args: &[String], law: FrictionLaw) {
    println!(
        "tilted sharp edge pulled by the hook, 2 s; T2/T1 across the node every 1 ms; friction law {}",
        law.name()
    );
    for (t1, tilt) in tilted_cases(args) {
        for v in [0.05, 0.1, 0.2] {
            let start = cpu_seconds();
            let r = pulled::run_tilted_under(law, t1, tilt, v);
            let label = format!("T1 {t1:.3e} N, tilt {tilt:4.1} deg, v {v:.2} m/s");
            print_tilted(&label, &r, cpu_seconds() - start);
        }
    }
}

/// One tilted-edge run's line: its work counters, T2/T1 over 1-2 s and the thread's CPU [s].
fn print_tilted(label: &str, r: &pulled::TiltedRun, cpu: f64) {
    println!(
        "{label}: steps {}, rejected {}, Newton {} (failed {}), edge slides {}; T2/T1 over 1-2 s mean {:.4}, least {:.4}, largest {:.4}; {cpu:.2} s CPU",
        r.steps, r.rejected, r.newton, r.newton_failed, r.edge_slides, r.mean, r.least, r.largest,
    );
}

/// The damped (quasi-static) tilted edge at four speeds, compared at equal pulled length.
fn quasi(strands: bool, contact: bool, factor: f64, ds: f64) {
    let (t1, tilt) = (9.81e5, 20.0);
    let rig = pulled::tilted_rig(t1, tilt);
    let c = factor * pulled::swing_critical_damping(&rig, t1);
    let cs = if strands {
        factor * pulled::strand_critical_damping(&rig, t1)
    } else {
        0.0
    };
    let cc = if contact {
        factor * pulled::strand_critical_damping(&rig, t1)
    } else {
        0.0
    };
    let opt = pulled::PullOptions {
        damping: c,
        strand_damping: cs,
        contact_damping: cc,
        ..Default::default()
    };
    println!(
        "tilted edge {t1:.3e} N, {tilt} deg, end load damped across its strand by {c:.4e} N s/m, strand nodes by {cs:.4e} N s/m, the contact node along its edge by {cc:.4e} N s/m; pulled 0.4 m, T2/T1 every {ds} m of pulled length"
    );
    let mut runs = Vec::new();
    for v in [0.025, 0.05, 0.1, 0.2] {
        let start = cpu_seconds();
        let r = pulled::run_tilted_by_length(t1, tilt, v, opt, ds, 0.4);
        let cpu = cpu_seconds() - start;
        let per_s = r.steps as f64 / r.t_end;
        for from in [0.1, 0.2] {
            let (mean, least, largest) = r.stats_from(from);
            println!(
                "v {v:.3} m/s: to {:.2} s: steps {} ({per_s:.0} per s), rejected {}, Newton {} (failed {}), edge slides {}; {cpu:.2} s CPU; T2/T1 from {from} m pulled: mean {mean:.5}, least {least:.5}, largest {largest:.5}",
                r.t_end, r.steps, r.rejected, r.newton, r.newton_failed, r.edge_slides
            );
        }
        runs.push((v, r));
    }
    let slow = &runs[0].1;
    for (v, r) in &runs[1..] {
        let worst = r
            .ratios
            .iter()
            .zip(&slow.ratios)
            .zip(&r.lengths)
            .filter(|(_, s)| **s >= 0.2 - 1e-12)
            .map(|((q, q0), _)| (q / q0 - 1.0).abs())
            .fold(0.0f64, f64::max);
        println!(
            "v {v:.3} m/s against 0.025 m/s at equal pulled length 0.2-0.4 m: largest |ratio / ratio_0.025 - 1| {worst:.3e}"
        );
    }
    // means over bins of 0.05 m of pulled length
    for k in 0..6 {
        let (a, b) = (0.1 + 0.05 * k as f64, 0.15 + 0.05 * k as f64);
        let row: Vec<String> = runs
            .iter()
            .map(|(v, r)| {
                let q: Vec<f64> = r
                    .lengths
                    .iter()
                    .zip(&r.ratios)
                    .filter(|(s, _)| **s > a + 1e-12 && **s <= b + 1e-12)
                    .map(|(_, q)| *q)
                    .collect();
                format!("{v}: {:.5}", q.iter().sum::<f64>() / q.len() as f64)
            })
            .collect();
        println!("mean over pulled ({a:.2}, {b:.2}] m: {}", row.join(", "));
    }
    // the samples at a few pulled lengths, for the table
    for s in [0.05, 0.1, 0.2, 0.3, 0.4] {
        let row: Vec<String> = runs
            .iter()
            .map(|(v, r)| {
                let i = r.lengths.iter().position(|x| (x - s).abs() < 1e-9);
                format!(
                    "{v}: {}",
                    i.map_or("-".into(), |i| format!("{:.5}", r.ratios[i]))
                )
            })
            .collect();
        println!("pulled {s} m: {}", row.join(", "));
    }
}

/// The undamped 981 kN, 20 deg rig at 0.2 m/s over 2 s with the tolerances scaled.
fn tolerance(law: FrictionLaw) {
    let (t1, tilt, v) = (9.81e5, 20.0, 0.2);
    println!(
        "tilted edge {t1:.3e} N, {tilt} deg, {v} m/s, undamped, 2 s, samples every 1 ms; rtol 1e-6 and atol 1e-7 m times:"
    );
    for scale in [0.01, 0.1, 1.0, 10.0, 100.0] {
        let opt = pulled::PullOptions {
            tol_scale: scale,
            ..Default::default()
        };
        let start = cpu_seconds();
        let r = pulled::run_tilted_with(law, t1, tilt, v, opt);
        print_tilted(&format!("x{scale}"), &r, cpu_seconds() - start);
    }
}

fn main() {
    let what: Vec<String> = std::env::args().skip(1).collect();
    let law = what
        .iter()
        .find_map(|w| FrictionLaw::from_name(w))
        .unwrap_or_default();
    if what.iter().any(|w| w == "quasi") {
        let factor = what.iter().find_map(|w| w.parse().ok()).unwrap_or(1.0);
        let ds = if what.iter().any(|w| w == "coarse") {
            1e-2
        } else {
            2e-4
        };
        quasi(
            what.iter().any(|w| w == "strands"),
            what.iter().any(|w| w == "contact"),
            factor,
            ds,
        );
    }
    if what.iter().any(|w| w == "tolerance") {
        tolerance(law);
    }
    let all = !what
        .iter()
        .any(|w| ["capstan", "tilted", "quasi", "tolerance"].contains(&w.as_str()));
    if all || what.iter().any(|w| w == "capstan") {
        capstan(law);
    }
    if all || what.iter().any(|w| w == "tilted") {
        tilted(&what, law);
    }
}
