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
//! Run: `cargo run --release --example rope_pull_speed [-- capstan | tilted [T1 tilt]]
//! [pseudo_coefficient]` (both by default; `tilted 9.81e5 20` runs that one case at the three
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
use pulled::hooked;
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
            let mut sim = hooked(&rig, 0.2);
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
            println!(
                "T1 {t1:.3e} N, tilt {tilt:4.1} deg, v {v:.2} m/s: steps {}, rejected {}, Newton {} (failed {}), edge slides {}; T2/T1 over 1-2 s mean {:.4}, least {:.4}, largest {:.4}; {:.2} s CPU",
                r.steps,
                r.rejected,
                r.newton,
                r.newton_failed,
                r.edge_slides,
                r.mean,
                r.least,
                r.largest,
                cpu_seconds() - start
            );
        }
    }
}

fn main() {
    let what: Vec<String> = std::env::args().skip(1).collect();
    let law = what
        .iter()
        .find_map(|w| FrictionLaw::from_name(w))
        .unwrap_or_default();
    let all = !what.iter().any(|w| w == "capstan" || w == "tilted");
    if all || what.iter().any(|w| w == "capstan") {
        capstan(law);
    }
    if all || what.iter().any(|w| w == "tilted") {
        tilted(&what, law);
    }
}
