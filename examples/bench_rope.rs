//! RopeBlock speed figures (reported, not asserted):
//!
//! - (a) the default lift (demo schedule, 12 s): wall time, real-time factor, peak hook load and
//!   sling tension errors against a tight-tolerance reference run, steps, Newton iterations, for
//!   a few `rtol` values;
//! - (b) cost per step against the number of rope nodes: the block hanging straight below the
//!   hook from one sling (no contact) with 50 .. 5000 segments, hoisted; fitted log-log exponent;
//! - (c) cost per step of the default lift against the size of the block mesh (more bilge facets:
//!   more triangles and plate edges, all far from the slings).
//!
//! `cargo run --release --example bench_rope -- [csv_dir]` prints markdown tables and writes
//! `bench_rope_{accuracy,nodes,mesh}.csv` to `csv_dir` (default: the current directory).
//! `BENCH_ROPE_LONG=1` runs a longer sweep (more rtol values, more node counts, longer runs).
//! A lift run that has not finished after `BENCH_ROPE_BUDGET` seconds of wall time (default 60)
//! is abandoned and reported as not finished, with the simulated time it reached.

use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::rope::shell::parametric::BlockShape;
use mbcosim::scene::rope_block::demo::{Demo, hoist, run};
use mbcosim::scene::rope_block::{BlockGeometry, RopeBlockParams, RopeBlockScene};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One run of the lift demo: summary, wall time [s], integrator counters.
struct LiftRun {
    peak_load: f64,
    peak_tension: f64,
    wall: f64,
    simulated: f64,
    steps: u64,
    newton: u64,
    factorizations: u64,
    /// Wall time of construction and static settling [s].
    setup: f64,
    /// Whether the 12 s were reached within the wall-time budget.
    finished: bool,
}

/// Wall-time budget of one lift run [s].
fn budget() -> f64 {
    std::env::var("BENCH_ROPE_BUDGET")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60.0)
}

/// Runs the lift demo (settled, hoisted 8 s at 0.2 m/s, held) with `params`, giving up after
/// [`budget`] seconds of wall time.
fn lift(params: RopeBlockParams) -> Result<LiftRun, String> {
    // driven as demo::run drives it, keeping the scene to read the integrator counters
    let start = Instant::now();
    let mut scene = RopeBlockScene::new(params.clone())?;
    let setup = start.elapsed().as_secs_f64();
    let limit = budget();
    let peaks = hoist(&mut scene, 12.0, 0.05, |_| {
        start.elapsed().as_secs_f64() <= limit
    })?;
    let st = scene.sim.sim.stats();
    Ok(LiftRun {
        setup,
        finished: peaks.finished,
        peak_load: peaks.hook_load,
        peak_tension: peaks.sling_tension,
        wall: start.elapsed().as_secs_f64(),
        simulated: scene.sim.time(),
        steps: st.steps,
        newton: st.newton_iterations,
        factorizations: st.factorizations,
    })
}

/// Integration cost per step [s] of `params` over `duration` [s] of hoisting at 0.2 m/s
/// (construction and settling excluded), and the steps taken.
fn cost_per_step(params: RopeBlockParams, duration: f64) -> Result<(f64, u64), String> {
    let mut scene = RopeBlockScene::new(params)?;
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0)?;
    let s0 = scene.sim.sim.stats().steps;
    let start = Instant::now();
    let n = (duration / 0.05).round() as usize;
    for _ in 0..n {
        scene.step(0.05)?;
    }
    let wall = start.elapsed().as_secs_f64();
    let steps = scene.sim.sim.stats().steps - s0;
    Ok((wall / steps.max(1) as f64, steps))
}

/// Least-squares slope of `ln y` over `ln x`.
fn loglog_slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, y) in pts {
        let (lx, ly) = (x.ln(), y.ln());
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

fn write_csv(dir: &Path, name: &str, header: &str, rows: &[String]) -> Result<(), String> {
    let path = dir.join(name);
    let mut f = std::fs::File::create(&path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    writeln!(f, "{header}").map_err(|e| e.to_string())?;
    for r in rows {
        writeln!(f, "{r}").map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn main() -> Result<(), String> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let long = std::env::var_os("BENCH_ROPE_LONG").is_some();

    // (a) accuracy and speed of the default lift
    let base = RopeBlockParams::default();
    println!(
        "## (a) default lift: 12 s, 4 slings x {} segments, {:?}, h_max {} s\n",
        base.segments, base.integrator, base.h_max
    );
    let reference = lift(RopeBlockParams {
        rtol: 1e-7,
        atol: 1e-9,
        h_max: 0.002,
        integrator: IntegratorKind::GenAlpha,
        ..base.clone()
    })?;
    if !reference.finished {
        return Err("the reference run did not finish within the budget".into());
    }
    println!(
        "reference (gen-alpha, rtol 1e-7, atol 1e-9, h_max 2 ms): peak hook load {:.2} kN, peak sling tension {:.2} kN, {} steps, {:.1} s wall\n",
        reference.peak_load / 1e3,
        reference.peak_tension / 1e3,
        reference.steps,
        reference.wall
    );
    println!(
        "| integrator | rtol | wall [s] | set-up [s] | real-time factor | peak hook load error | peak sling tension error | steps | Newton iterations | factorizations |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let rtols: &[f64] = if long {
        &[1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6]
    } else {
        &[1e-3, 3e-4, 1e-4, 3e-5, 1e-5]
    };
    let mut rows = Vec::new();
    let mut rtol_list: Vec<f64> = rtols.to_vec();
    if !rtol_list.contains(&base.rtol) {
        rtol_list.push(base.rtol);
        rtol_list.sort_by(|a, b| b.total_cmp(a));
    }
    for kind in [IntegratorKind::GenAlpha, IntegratorKind::Bdf] {
        for &rtol in &rtol_list {
            let r = lift(RopeBlockParams {
                rtol,
                integrator: kind,
                ..base.clone()
            })?;
            let mark = if rtol == base.rtol && kind == base.integrator {
                " (default)"
            } else {
                ""
            };
            let (rtf, el, et) = if r.finished {
                (
                    r.simulated / r.wall,
                    (r.peak_load - reference.peak_load).abs() / reference.peak_load,
                    (r.peak_tension - reference.peak_tension).abs() / reference.peak_tension,
                )
            } else {
                (f64::NAN, f64::NAN, f64::NAN)
            };
            if r.finished {
                println!(
                    "| {} | {rtol:.0e}{mark} | {:.3} | {:.3} | {rtf:.0}x | {:.3} % | {:.3} % | {} | {} | {} |",
                    kind.name(),
                    r.wall,
                    r.setup,
                    100.0 * el,
                    100.0 * et,
                    r.steps,
                    r.newton,
                    r.factorizations
                );
            } else {
                println!(
                    "| {} | {rtol:.0e}{mark} | > {:.0} | {:.3} | not finished: t = {:.2} s reached | - | - | {} | {} | {} |",
                    kind.name(),
                    r.wall,
                    r.setup,
                    r.simulated,
                    r.steps,
                    r.newton,
                    r.factorizations
                );
            }
            rows.push(format!(
                "{},{rtol:e},{},{},{rtf},{el},{et},{},{},{},{}",
                kind.name(),
                r.wall,
                r.setup,
                r.steps,
                r.newton,
                r.factorizations,
                r.simulated
            ));
        }
    }
    write_csv(
        &dir,
        "bench_rope_accuracy.csv",
        "integrator,rtol,wall_s,setup_s,real_time_factor,peak_hook_load_rel_error,peak_sling_tension_rel_error,steps,newton_iterations,factorizations,simulated_s",
        &rows,
    )?;
    let demo_wall = {
        let mut sink = std::io::sink();
        run(Demo::Lift, None, 12.0, 0.05, &mut sink)?.wall
    };
    println!(
        "\nlift demo (`rope_block_demo`, default parameters, construction and settling included): {:.3} s wall = {:.0}x real time\n",
        demo_wall,
        12.0 / demo_wall
    );

    // (b) cost per step against rope nodes: one straight sling above the centre of mass
    println!("## (b) cost per step against rope nodes (one straight sling, no contact)\n");
    println!(
        "| segments | rope nodes | steps | cost per step [ms] | cost per node and step [us] |"
    );
    println!("|---|---|---|---|---|");
    let counts: &[usize] = if long {
        &[50, 100, 200, 500, 1000, 2000, 5000, 10000]
    } else {
        &[50, 100, 200, 500, 1000, 2000, 5000]
    };
    let duration = if long { 2.0 } else { 0.5 };
    let mut pts = Vec::new();
    let mut rows = Vec::new();
    for &seg in counts {
        let p = RopeBlockParams::single_sling(seg);
        let (c, steps) = cost_per_step(p, duration)?;
        let nodes = seg - 1;
        pts.push((nodes as f64, c));
        println!(
            "| {seg} | {nodes} | {steps} | {:.3} | {:.3} |",
            1e3 * c,
            1e6 * c / nodes as f64
        );
        rows.push(format!("{seg},{nodes},{steps},{c}"));
    }
    let slope = loglog_slope(&pts);
    let big: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.0 >= 199.0).collect();
    let slope_big = loglog_slope(&big);
    println!(
        "\nfitted exponent (cost per step ~ nodes^p): p = {slope:.3} over all, {slope_big:.3} from 200 segments on\n"
    );
    write_csv(
        &dir,
        "bench_rope_nodes.csv",
        "segments,rope_nodes,steps,cost_per_step_s",
        &rows,
    )?;

    // (c) cost per step against the block mesh
    println!(
        "## (c) cost per step of the lift against the block mesh (bilge facets on both sides)\n"
    );
    println!("| bilge facets | triangles | plate edges | steps | cost per step [ms] |");
    println!("|---|---|---|---|---|");
    let facets: &[usize] = if long {
        &[4, 8, 16, 32, 64, 128, 170]
    } else {
        &[4, 16, 64, 170]
    };
    let mut rows = Vec::new();
    for &nf in facets {
        let mut p = base.clone();
        p.rig.block.geometry = BlockGeometry::Shape(BlockShape {
            bilge_facets: nf,
            both_bilges: true,
            ..base.rig.shape().copied().unwrap_or_default()
        });
        let mesh = p.design_mesh()?;
        let (tri, edges) = (mesh.triangles.len(), mesh.edges.len());
        let (c, steps) = cost_per_step(p, duration)?;
        println!("| {nf} | {tri} | {edges} | {steps} | {:.3} |", 1e3 * c);
        rows.push(format!("{nf},{tri},{edges},{steps},{c}"));
    }
    write_csv(
        &dir,
        "bench_rope_mesh.csv",
        "bilge_facets,triangles,plate_edges,steps,cost_per_step_s",
        &rows,
    )?;
    println!("\nCSV written to {}", dir.display());
    Ok(())
}
