//! Runs the RopeBlock demonstrations natively and writes CSV files and SVG plots:
//! `cargo run --release --example rope_block_demo -- [out_dir]` writes `rope_lift.csv`,
//! `rope_turnover.csv` and, for each, `*_tensions.svg` (hook loads and sling tensions) and
//! `*_contacts.svg` (normal and friction force of the contact nodes) (default directory: the
//! current one).

use mbcosim::report::svg::{Series, line_plot};
use mbcosim::scene::rope_block::demo::{Demo, run};
use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;

fn main() -> Result<(), String> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    for (demo, file, duration) in [
        (Demo::Lift, "rope_lift.csv", 12.0),
        (Demo::Turnover, "rope_turnover.csv", 40.0),
    ] {
        let path = dir.join(file);
        let f =
            File::create(&path).map_err(|e| format!("cannot create {}: {e}", path.display()))?;
        let s = run(demo, None, duration, 0.05, &mut BufWriter::new(f))?;
        plots(&path, &dir, file.trim_end_matches(".csv"))?;
        println!("{demo:?}: {}", s.describe(&path));
    }
    Ok(())
}

/// Columns of a CSV file written by the demo: names and values.
fn read_csv(path: &std::path::Path) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut lines = text.lines();
    let names: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::to_string)
        .collect();
    let mut cols = vec![Vec::new(); names.len()];
    for l in lines {
        for (c, x) in cols.iter_mut().zip(l.split(',')) {
            c.push(x.parse::<f64>().unwrap_or(f64::NAN));
        }
    }
    Ok((names, cols))
}

/// Legend name in words of a CSV column: `sling2.tension_lug` is "sling 2 tension at the lug".
fn words(column: &str) -> String {
    let (part, what) = column.split_once('.').unwrap_or((column, ""));
    let digits = part.trim_start_matches(|c: char| c.is_ascii_alphabetic());
    let kind = &part[..part.len() - digits.len()];
    let kind = if kind == "contact" {
        "contact node"
    } else {
        kind
    };
    let what = match what {
        "load" => "load",
        "tension_lug" => "tension at the lug",
        "tension_hook" => "tension at the hook",
        "normal" => "normal force",
        "friction" => "friction force",
        other => other,
    };
    format!("{kind} {digits} {what}")
}

/// Tension and contact-force plots [kN] over time [s] from a demo CSV.
fn plots(csv: &std::path::Path, dir: &std::path::Path, stem: &str) -> Result<(), String> {
    let (names, cols) = read_csv(csv)?;
    let col = |n: &str| names.iter().position(|x| x == n).map(|i| &cols[i]);
    let t = col("time").ok_or("no time column")?;
    let series = |pick: &dyn Fn(&str) -> bool| -> Vec<(String, Vec<(f64, f64)>)> {
        names
            .iter()
            .enumerate()
            .filter(|(_, n)| pick(n))
            .map(|(i, n)| {
                let pts = t.iter().zip(&cols[i]).map(|(a, b)| (*a, b / 1e3)).collect();
                (words(n), pts)
            })
            .filter(|(_, p): &(String, Vec<(f64, f64)>)| p.iter().any(|q| q.1 != 0.0))
            .collect()
    };
    let write = |name: &str, title: &str, data: Vec<(String, Vec<(f64, f64)>)>| {
        let s: Vec<Series> = data
            .iter()
            .map(|(n, p)| Series {
                name: n,
                points: p.clone(),
            })
            .collect();
        let path = dir.join(format!("{stem}_{name}.svg"));
        std::fs::write(&path, line_plot(title, "Time [s]", "Force [kN]", &s))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    let scene = if stem.contains("turnover") {
        "RopeBlock turnover"
    } else {
        "RopeBlock lift"
    };
    write(
        "tensions",
        &format!("{scene}: hook loads and sling tensions at the lugs"),
        series(&|n| n.ends_with(".load") || n.ends_with(".tension_lug")),
    )?;
    write(
        "contacts",
        &format!("{scene}: normal and friction forces of contact nodes 0 to 3"),
        series(&|n| {
            ["contact0.", "contact1.", "contact2.", "contact3."]
                .iter()
                .any(|p| n.starts_with(p))
                && (n.ends_with(".normal") || n.ends_with(".friction"))
        }),
    )?;
    Ok(())
}
