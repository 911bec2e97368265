//! The model argument (with clap's list of models and did-you-mean) and the listings `models`
//! and `variables`.

use clap::builder::PossibleValuesParser;
use mbcosim::scene::port::{Causality, PortSpec, PortType};
use mbcosim::scene::{self, ModelEntry};

/// Parser of a model identifier: clap refuses anything else, lists the models and suggests the
/// closest one. Matching ignores case (the argument sets `ignore_case`).
pub fn parser() -> PossibleValuesParser {
    PossibleValuesParser::new(
        scene::registry()
            .into_iter()
            .map(|e| (e.info)().identifier)
            .collect::<Vec<_>>(),
    )
}

/// The registered model named `name` (ASCII case ignored, as the parser accepts it).
pub fn entry(name: &str) -> Result<ModelEntry, String> {
    scene::registry()
        .into_iter()
        .find(|e| (e.info)().identifier.eq_ignore_ascii_case(name))
        .ok_or_else(|| {
            let ids: Vec<&str> = scene::registry()
                .iter()
                .map(|e| (e.info)().identifier)
                .collect();
            format!("unknown model `{name}`; models: {}", ids.join(", "))
        })
}

pub fn list_models() {
    for e in scene::registry() {
        let info = (e.info)();
        let first = info.description.split(". ").next().unwrap_or("");
        println!("{:<14} {}", info.identifier, first.trim_end_matches('.'));
    }
}

#[derive(clap::Args)]
pub struct VariablesArgs {
    /// Model identifier (`mbcosim models` lists them).
    #[arg(value_parser = parser(), ignore_case = true)]
    model: String,
    /// Only variables of this causality (parameter, input, output, ...).
    #[arg(long)]
    causality: Option<String>,
}

/// Type, start value and range of `p` in the words `--set` uses.
pub fn type_text(p: &PortSpec) -> String {
    let range = |lo: Option<String>, hi: Option<String>| match (lo, hi) {
        (None, None) => String::new(),
        (lo, hi) => format!(
            " in [{}, {}]",
            lo.unwrap_or_else(|| "-inf".into()),
            hi.unwrap_or_else(|| "inf".into())
        ),
    };
    let start = |s: Option<String>| s.map(|s| format!(" = {s}")).unwrap_or_default();
    match &p.ty {
        PortType::Real {
            start: s, min, max, ..
        } => format!(
            "Real{}{}",
            start(s.map(|v| format!("{v:?}"))),
            range(min.map(|v| format!("{v:?}")), max.map(|v| format!("{v:?}")))
        ),
        PortType::Integer { start: s, min, max } => format!(
            "Integer{}{}",
            start(s.map(|v| v.to_string())),
            range(min.map(|v| v.to_string()), max.map(|v| v.to_string()))
        ),
        PortType::Boolean { start: s } => format!("Boolean{}", start(s.map(|b| b.to_string()))),
        PortType::String { start: s } => format!("String{}", start(s.map(|s| format!("{s:?}")))),
        PortType::Enumeration {
            type_name,
            items,
            start: s,
        } => {
            let names: Vec<String> = items
                .iter()
                .enumerate()
                .map(|(k, (n, _))| format!("{}={n}", k + 1))
                .collect();
            let s = s.and_then(|k| items.get(usize::try_from(k - 1).ok()?).map(|(n, _)| *n));
            format!(
                "{type_name}{} ({})",
                start(s.map(str::to_string)),
                names.join(", ")
            )
        }
    }
}

pub fn list_variables(a: &VariablesArgs) -> Result<(), String> {
    let info = (entry(&a.model)?.info)();
    let wanted = a.causality.as_deref().map(str::to_ascii_lowercase);
    let mut shown = 0;
    for p in &info.ports {
        if wanted
            .as_deref()
            .is_some_and(|w| p.causality.name().to_ascii_lowercase() != w)
        {
            continue;
        }
        shown += 1;
        let unit = p.unit.map(|u| format!(" [{u}]")).unwrap_or_default();
        let how = match p.causality {
            Causality::Parameter => format!("{} parameter", p.variability.name()),
            c => c.name().to_string(),
        };
        println!("{}{unit}  ({how}) {}", p.name, type_text(p));
        println!("    {}", p.description);
    }
    if shown == 0 {
        return Err(format!(
            "{} has no {} variables (causalities: parameter, calculatedParameter, input, output, local)",
            info.identifier,
            a.causality.as_deref().unwrap_or("")
        ));
    }
    Ok(())
}
