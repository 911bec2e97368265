//! Runs the RopeBlock demonstrations natively and writes CSV files and SVG plots:
//! `cargo run --release --example rope_block_demo -- [out_dir]` writes `rope_lift.csv`,
//! `rope_turnover.csv` and, for each, `*_tensions.svg` (hook loads and sling tensions) and
//! `*_contacts.svg` (normal and friction force of the contact nodes) (default directory: the
//! current one).

use mbcosim::scene::rope_block::demo::{Demo, run};
use mbcosim::scene::rope_block::demo_plots::write_plots;
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
        let scene = match demo {
            Demo::Lift => "RopeBlock lift",
            Demo::Turnover => "RopeBlock turnover",
        };
        write_plots(&path, &dir, file.trim_end_matches(".csv"), scene)?;
        println!("{demo:?}: {}", s.describe(&path));
    }
    Ok(())
}
