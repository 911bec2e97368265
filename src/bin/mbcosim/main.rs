//! `mbcosim`: packs the FMUs, regenerates model descriptions, runs models natively, reproduces the
//! studies. `mbcosim --help` and `mbcosim <command> --help` describe every command; docs/cli.md
//! gives the decisions behind the options (value syntax, input schedules, CSV format, paths).
//!
//! Output paths (`--out`, `dist/`, `out/`, `docs/`) resolve against the current directory.
//! `pack`, `demo` and `model-descriptions` also need the source tree (the build script and the
//! checked-in descriptions): they find it in the current directory or above it, or at
//! `MBCOSIM_REPO`.
//!
//! Packing needs a fresh cdylib: `pack` and `demo` first run `scripts/build_portable.sh` for the
//! same profile and target directory as this executable. For x86_64 Linux that is the cdylib of
//! the same host build (`cargo run --release --bin mbcosim` built it; .cargo/config.toml links it
//! with zig against glibc 2.17 through scripts/link_host.sh, the toolchain installed into `.venv`
//! on first use), stripped, its debug info in `dist/debug/` (docs/portable_binary.md). Set
//! `MBCOSIM_NO_BUILD=1` to skip that and pack the last stripped library as it is. `demo` also
//! installs three.js for `simulate --replay` (`npm ci` in tools/replay, docs/replay.md).
#![forbid(unsafe_code)]

mod models;
mod pack;
mod progress;
mod replay;
mod schedule;
mod simulate;
mod state_fields;
mod study;
mod values;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Multibody co-simulation models (PanelLock, RopeBlock, PidController, SpringMassDamper) as FMI
/// 2.0 and FMI 3.0 co-simulation FMUs: pack them, run them natively, reproduce the studies.
#[derive(Parser)]
#[command(name = "mbcosim", version, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build <DIR>/<Model>.fmu (FMI 2.0) and <DIR>/fmi3/<Model>.fmu (FMI 3.0) for every
    /// registered model (needs the source tree).
    Pack(pack::PackArgs),
    /// Rewrite modelDescription/<Model>.xml and resources/scenes/<Model>.toml from the variable
    /// tables (needs the source tree).
    ModelDescriptions(pack::DescriptionArgs),
    /// Pack the FMUs, install three.js for --replay (npm), then run the demos and print their
    /// tables (needs the source tree).
    Demo(pack::DemoArgs),
    /// Regenerate the figures README.md embeds (the PanelLock demo's plots, the work-precision
    /// plots from docs/report/refresh/'s results) in docs/ (needs the source tree).
    ReadmeFigures,
    /// Run one model natively and write its outputs as CSV (stdout or --out).
    Simulate(simulate::SimulateArgs),
    /// List the registered models.
    Models,
    /// List a model's variables: causality, type, unit, range, start value, description.
    Variables(models::VariablesArgs),
    /// Work-precision report: CSV, log-log plots and report.md.
    Report(study::ReportArgs),
    /// The paper's Table 1 / Figs. 4-5 with flexible PanelLock panels: CSV, SVG plots and a
    /// markdown table.
    Table1(study::Table1Args),
    /// Calibrate the paper's unstated latch and spring parameters against Table 1: a grid over
    /// restitution, preload scale and cam radius, ranked by the worst residual.
    Calibrate(study::CalibrateArgs),
    /// Every field of a serialized FMU state, one JSON object a line (offset, len, kind, what).
    StateFields(state_fields::StateFieldsArgs),
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Pack(a) => pack::pack(&a),
        Command::ModelDescriptions(a) => pack::model_descriptions(&a),
        Command::Demo(a) => pack::demo(&a),
        Command::ReadmeFigures => {
            let repo = pack::repo_root("readme-figures")?;
            for f in mbcosim::report::readme_figures::regenerate(&repo, &repo)? {
                println!("wrote {}", f.display());
            }
            Ok(())
        }
        Command::Simulate(a) => simulate::simulate(&a),
        Command::Models => {
            models::list_models();
            Ok(())
        }
        Command::Variables(a) => models::list_variables(&a),
        Command::Report(a) => study::report(&a),
        Command::Table1(a) => study::table1(&a),
        Command::Calibrate(a) => study::calibrate(&a),
        Command::StateFields(a) => state_fields::state_fields(&a),
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mbcosim: {e}");
            ExitCode::FAILURE
        }
    }
}
