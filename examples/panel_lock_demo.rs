//! Runs the PanelLock demo natively: `cargo run --release --example panel_lock_demo [out_dir]`.
fn main() {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "out".into());
    match mbcosim::scene::panel_lock::run_demo(std::path::Path::new(&dir), 60.0, 0.01) {
        Ok(s) => print!("{s}"),
        Err(e) => {
            eprintln!("demo failed: {e}");
            std::process::exit(1);
        }
    }
}
