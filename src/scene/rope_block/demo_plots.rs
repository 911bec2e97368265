//! SVG plots of a demo CSV written by [`super::demo::run`]: hook loads and sling tensions, and
//! the normal and friction forces of the first contact nodes, in kN over time in seconds.

use crate::report::svg::{Series, line_plot};
use std::path::{Path, PathBuf};

/// Columns of a demo CSV: names and values (a cell that does not parse is NaN).
fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
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
pub fn words(column: &str) -> String {
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

/// Writes `{stem}_tensions.svg` (hook loads and sling tensions at the lugs) and
/// `{stem}_contacts.svg` (normal and friction forces of contact nodes 0 to 3) into `dir` from
/// the demo CSV `csv`; `scene` opens the titles ("RopeBlock lift"). Series that stay zero are
/// left out. Returns the paths written.
pub fn write_plots(
    csv: &Path,
    dir: &Path,
    stem: &str,
    scene: &str,
) -> Result<Vec<PathBuf>, String> {
    let (names, cols) = read_csv(csv)?;
    let t = names
        .iter()
        .position(|x| x == "time")
        .map(|i| &cols[i])
        .ok_or_else(|| format!("{}: no time column", csv.display()))?;
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
    let mut written = Vec::new();
    let mut write = |name: &str, title: &str, data: Vec<(String, Vec<(f64, f64)>)>| {
        let s: Vec<Series> = data
            .iter()
            .map(|(n, p)| Series {
                name: n,
                points: p.clone(),
            })
            .collect();
        let path = dir.join(format!("{stem}_{name}.svg"));
        std::fs::write(&path, line_plot(title, "Time [s]", "Force [kN]", &s))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        written.push(path);
        Ok::<(), String>(())
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
    Ok(written)
}
