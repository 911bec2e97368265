//! Cost of each effect on each model's default scene (reported figures, no timed tests):
//! `cargo run --release --example bench_effects [-- out.md]`.
//!
//! Each row runs the model through its co-simulation interface (what the FMU runs: initialization
//! included, every output read at every communication point) with one effect switched relative to
//! the default, plus an all-off and an all-on scene. Time = best of 3 runs. A second argument
//! `rope` runs the RopeBlock table only.

use mbcosim::scene::{find_by_identifier, native};
use std::fmt::Write as _;
use std::time::Instant;

struct Variant {
    label: &'static str,
    adds: &'static str,
    values: Vec<(&'static str, f64)>,
}

fn v(label: &'static str, adds: &'static str, values: &[(&'static str, f64)]) -> Variant {
    Variant {
        label,
        adds,
        values: values.to_vec(),
    }
}

/// Best-of-3 wall time [s] of `model` with `values` over `stop` [s], and the final value of the
/// output `check` (to show the scenes do the same job).
fn measure(
    model: &str,
    values: &[(&str, f64)],
    stop: f64,
    step: f64,
    check: &str,
) -> Result<(f64, f64), String> {
    let entry = find_by_identifier(model).ok_or("unknown model")?;
    let values: Vec<(String, f64)> = values.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let mut best = f64::INFINITY;
    let mut last = f64::NAN;
    for _ in 0..3 {
        let mut m = (entry.create)();
        let t0 = Instant::now();
        let table = native::simulate(m.as_mut(), &values, stop, step).map_err(|e| e.to_string())?;
        best = best.min(t0.elapsed().as_secs_f64());
        if let Some(col) = table.column(check) {
            last = *col.last().unwrap_or(&f64::NAN);
        }
    }
    Ok((best, last))
}

/// One markdown table: a row per variant, with the output `check` at `stop` in `check_unit`.
fn table(
    model: &str,
    (stop, step): (f64, f64),
    (check, check_unit): (&str, &str),
    variants: &[Variant],
    md: &mut String,
) {
    let _ = writeln!(
        md,
        "\n### {model}: {stop} s simulated, communication step {step} s\n\n| scene | what it adds | parameters set | CPU [ms] | real-time factor | vs default | {check} at {stop} s [{check_unit}] |\n|---|---|---|---|---|---|---|"
    );
    let mut base = f64::NAN;
    for var in variants {
        let params: Vec<String> = var.values.iter().map(|(k, x)| format!("{k}={x}")).collect();
        match measure(model, &var.values, stop, step, check) {
            Ok((t, last)) => {
                if var.label == "default" {
                    base = t;
                }
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {:.1} | {:.0} | {:.2}x | {last:.6e} |",
                    var.label,
                    var.adds,
                    params.join(", "),
                    1e3 * t,
                    stop / t,
                    t / base
                );
            }
            Err(e) => {
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | failed: {e} | - | - | - |",
                    var.label,
                    var.adds,
                    params.join(", ")
                );
            }
        }
        eprintln!("{model}: {} done", var.label);
    }
}

fn main() {
    let mut md = String::from("## Effect costs (examples/bench_effects.rs)\n");
    let panel = [
        v(
            "default",
            "latches on, rigid panels, fixed satellite, no gravity, no cable loops",
            &[],
        ),
        v(
            "all off",
            "springs, stops and hinges only",
            &[("latches", 0.0)],
        ),
        v(
            "latches off",
            "removes the pin/groove contact (no lock-up)",
            &[("latches", 0.0)],
        ),
        v(
            "+ cable loops",
            "closed cable loops synchronizing the hinges",
            &[("cable_loop", 1.0)],
        ),
        v(
            "+ gravity",
            "gravity along -z (ground test)",
            &[("gravity_on", 1.0)],
        ),
        v(
            "+ free satellite",
            "6 more DOFs, momentum exchange with the bus",
            &[("free_satellite", 1.0)],
        ),
        v(
            "+ flexible panels",
            "10 Craig-Bampton modes per panel (30 modal coordinates)",
            &[("flexible_panels", 1.0), ("n_modes", 10.0)],
        ),
        v(
            "all on (rigid)",
            "latches, cable loops, gravity, free satellite",
            &[
                ("cable_loop", 1.0),
                ("gravity_on", 1.0),
                ("free_satellite", 1.0),
            ],
        ),
        v(
            "all on",
            "latches, cable loops, gravity, free satellite, flexible panels (10 modes)",
            &[
                ("cable_loop", 1.0),
                ("gravity_on", 1.0),
                ("free_satellite", 1.0),
                ("flexible_panels", 1.0),
                ("n_modes", 10.0),
            ],
        ),
    ];
    let only = std::env::args().nth(2);
    if only.as_deref() != Some("rope") {
        table(
            "PanelLock",
            (20.0, 0.05),
            ("hinge0_angle", "rad"),
            &panel,
            &mut md,
        );
    }
    let rope = [
        v(
            "default",
            "contact with friction, gravity, 100 segments per sling, no bending, no drag",
            &[],
        ),
        v(
            "all off",
            "no contact, no friction, no bending, no drag",
            &[("contact", 0.0), ("friction", 0.0)],
        ),
        v(
            "all off, 2 segments",
            "as all off, and the slings as 2 segments each (rope resolution at its minimum)",
            &[("contact", 0.0), ("friction", 0.0), ("segments", 2.0)],
        ),
        v(
            "contact off",
            "slings pass through the block (no detection, no nodes)",
            &[("contact", 0.0)],
        ),
        v("friction off", "frictionless edges", &[("friction", 0.0)]),
        v(
            "+ bending",
            "bending hinges at every node (EI 2e3 N m^2)",
            &[("bending", 1.0)],
        ),
        v(
            "+ drag",
            "quadratic air drag on every node",
            &[("drag", 1.0)],
        ),
        v(
            "all on",
            "contact, friction, bending, drag",
            &[("bending", 1.0), ("drag", 1.0)],
        ),
    ];
    // every RopeBlock row hoists: the hook rises at 0.25 m/s (reached over 0.5 s), so the slings
    // take up the block's weight and the contact nodes load, stick and slide
    let rope: Vec<Variant> = rope
        .into_iter()
        .map(|mut var| {
            var.values.push(("hook0_vz", 0.25));
            var
        })
        .collect();
    table(
        "RopeBlock",
        (4.0, 0.05),
        ("hook0_load", "N"),
        &rope,
        &mut md,
    );
    println!("{md}");
    if let Some(path) = std::env::args().nth(1) {
        std::fs::write(&path, &md).expect("write the table");
    }
}
