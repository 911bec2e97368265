//! Plain-file reports: CSV tables and SVG line plots (no plotting dependency).

pub mod loglog;
pub mod spectrum;
pub mod svg;
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
