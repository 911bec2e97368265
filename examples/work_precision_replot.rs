//! Redraws the work-precision plots of a written report from its `work_precision.csv` and
//! `report.md`, without running the studies:
//! `cargo run --release --example work_precision_replot -- [dir]` (default `docs/report`; also
//! `docs/report/rope`).

fn main() -> Result<(), String> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/report".into());
    for f in mbcosim::report::workprec::replot::replot(std::path::Path::new(&dir))? {
        println!("wrote {f}");
    }
    Ok(())
}
