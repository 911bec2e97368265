//! `state-fields`: the field map of a serialized FMU state (the adversarial harness's map).

use std::path::PathBuf;

#[derive(clap::Args)]
pub struct StateFieldsArgs {
    /// A serialized FMU state (fmi2SerializeFMUstate bytes).
    state_file: PathBuf,
    /// The FMU's resources folder, for models that read data files.
    #[arg(long, value_name = "DIR")]
    resources: Option<PathBuf>,
}

pub fn state_fields(a: &StateFieldsArgs) -> Result<(), String> {
    let file = a.state_file.display();
    let bytes = std::fs::read(&a.state_file).map_err(|e| format!("cannot read {file}: {e}"))?;
    let spans = mbcosim::fmi::snapshot::field_map(&bytes, a.resources.as_deref())
        .map_err(|e| format!("{file}: {e}"))?;
    for s in spans {
        println!(
            "{{\"offset\": {}, \"len\": {}, \"kind\": \"{}\", \"what\": {:?}}}",
            s.offset, s.len, s.kind, s.what
        );
    }
    Ok(())
}
