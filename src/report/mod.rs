//! Plain-file reports: CSV tables and SVG line plots, written by hand (docs/plots.md says why
//! not with a plotting crate).

pub mod loglog;
pub mod plot_style;
pub mod readme_figures;
pub mod spectrum;
pub mod svg;
pub mod svg_check;
pub mod workprec;

use std::io::Write;
use std::path::Path;

/// Writes a CSV file with a header row and one row per record.
pub fn write_csv(path: &Path, header: &[&str], rows: &[Vec<f64>]) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "{}", header.join(","))?;
    for r in rows {
        let line: Vec<String> = r.iter().map(|x| format!("{x:.9e}")).collect();
        writeln!(f, "{}", line.join(","))?;
    }
    f.flush()
}
