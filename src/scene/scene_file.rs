//! Scene files: a model's parameters as data, so a variant needs no recompiling.
//!
//! A scene file is a small TOML document (the subset below), read when an FMU is instantiated
//! (`resources/scene.toml` inside the FMU) and by `mbcosim simulate --scene FILE`:
//!
//! ```toml
//! # comments run to the end of the line
//! model = "PanelLock"          # optional; when present it must name the model
//!
//! [parameters]
//! n_panels = 3                 # integers
//! contact_stiffness = 1.0e7    # reals (an integer literal is accepted for a real)
//! latches = true               # booleans
//! integrator = "bdf"           # enumerations: item name, any case (or its number)
//! "some.dotted[name]" = 0.5    # names outside [A-Za-z0-9_-] are quoted
//! ```
//!
//! Every key of `[parameters]` is a parameter of the model's variable table (the names in
//! `modelDescription.xml`); units are those of the table (SI). Unknown names, outputs, wrong types,
//! out-of-range values, NaN/Inf and duplicate keys are refused with the file and line. The default
//! scene of each model is rendered from its variable table by [`render`] (the files under
//! `resources/scenes/` of the repository, checked against the table by a test), so the defaults
//! exist once, in the table.

use super::CoSimModel;
use super::port::{Causality, ModelInfo, PortSpec, PortType};

/// Name of the scene file inside an FMU's `resources/` folder.
pub const FMU_SCENE: &str = "scene.toml";

/// A value written in a scene file.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneValue {
    /// An integer literal.
    Integer(i64),
    /// A floating-point literal.
    Real(f64),
    /// `true` or `false`.
    Boolean(bool),
    /// A basic string.
    String(String),
}

/// One `name = value` line of the `[parameters]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneEntry {
    /// Variable name.
    pub name: String,
    /// Value as written.
    pub value: SceneValue,
    /// Line number (1-based), for messages.
    pub line: usize,
}

/// A parsed scene file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneFile {
    /// The `model` key, when given.
    pub model: Option<String>,
    /// The parameter values in file order.
    pub entries: Vec<SceneEntry>,
}

/// Parses `text`; `origin` (a file name) prefixes every message.
pub fn parse(text: &str, origin: &str) -> Result<SceneFile, String> {
    let mut file = SceneFile::default();
    let mut in_parameters = false;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let at = |msg: String| format!("{origin}:{line}: {msg}");
        let s = strip_comment(raw).trim();
        if s.is_empty() {
            continue;
        }
        if let Some(header) = s.strip_prefix('[') {
            let name = header
                .strip_suffix(']')
                .ok_or_else(|| at(format!("unterminated table header `{s}`")))?
                .trim();
            if name != "parameters" {
                return Err(at(format!(
                    "unknown table `[{name}]`: a scene file has only `[parameters]`"
                )));
            }
            if in_parameters {
                return Err(at("`[parameters]` appears twice".into()));
            }
            in_parameters = true;
            continue;
        }
        let (key, rest) = split_key(s).map_err(at)?;
        let value = parse_value(rest.trim()).map_err(|e| at(format!("`{key}`: {e}")))?;
        if !in_parameters {
            match (key.as_str(), value) {
                ("model", SceneValue::String(m)) if file.model.is_none() => file.model = Some(m),
                ("model", _) => return Err(at("`model` must be given once, as a string".into())),
                _ => {
                    return Err(at(format!(
                        "`{key}` is outside `[parameters]` (only `model` may stand there)"
                    )));
                }
            }
            continue;
        }
        if let Some(prev) = file.entries.iter().find(|e| e.name == key) {
            return Err(at(format!(
                "`{key}` is set twice (first on line {})",
                prev.line
            )));
        }
        file.entries.push(SceneEntry {
            name: key,
            value,
            line,
        });
    }
    Ok(file)
}

/// `s` without a `#` comment (a `#` inside a string is kept).
fn strip_comment(s: &str) -> &str {
    let mut in_string = false;
    let mut escaped = false;
    for (i, c) in s.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if in_string => escaped = true,
            '"' => in_string = !in_string,
            '#' if !in_string => return &s[..i],
            _ => {}
        }
    }
    s
}

/// Splits `key = value` into the key (bare or quoted) and the text after `=`.
fn split_key(s: &str) -> Result<(String, &str), String> {
    if s.starts_with('"') {
        let (key, used) = parse_string(s)?;
        let rest = s[used..].trim_start();
        let rest = rest
            .strip_prefix('=')
            .ok_or_else(|| format!("expected `=` after the key \"{key}\""))?;
        return Ok((key, rest));
    }
    let (key, rest) = s
        .split_once('=')
        .ok_or_else(|| format!("expected `name = value`, got `{s}`"))?;
    let key = key.trim();
    if key.is_empty()
        || !key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(format!(
            "bad key `{key}`: bare keys use A-Z a-z 0-9 _ - only; quote other names"
        ));
    }
    Ok((key.to_string(), rest))
}

/// A basic string at the start of `s`; returns it and the number of bytes used.
fn parse_string(s: &str) -> Result<(String, usize), String> {
    let mut out = String::new();
    let mut chars = s.char_indices().skip(1);
    while let Some((i, c)) = chars.next() {
        match c {
            '"' => return Ok((out, i + 1)),
            '\\' => match chars.next().map(|(_, c)| c) {
                Some('"') => out.push('"'),
                Some('\\') => out.push('\\'),
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                other => return Err(format!("unsupported escape `\\{}`", other.unwrap_or(' '))),
            },
            c => out.push(c),
        }
    }
    Err("unterminated string".into())
}

fn parse_value(s: &str) -> Result<SceneValue, String> {
    match s {
        "" => return Err("missing value".into()),
        "true" => return Ok(SceneValue::Boolean(true)),
        "false" => return Ok(SceneValue::Boolean(false)),
        _ => {}
    }
    if s.starts_with('"') {
        let (v, used) = parse_string(s)?;
        if !s[used..].trim().is_empty() {
            return Err(format!(
                "unexpected text after the string: `{}`",
                &s[used..]
            ));
        }
        return Ok(SceneValue::String(v));
    }
    let digits: String = s.chars().filter(|&c| c != '_').collect();
    if let Ok(i) = digits.parse::<i64>() {
        return Ok(SceneValue::Integer(i));
    }
    let lower = digits.to_ascii_lowercase();
    if lower.contains("inf") || lower.contains("nan") {
        return Err(format!("`{s}` refused: values must be finite"));
    }
    match digits.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(SceneValue::Real(v)),
        Ok(_) => Err(format!("`{s}` refused: values must be finite")),
        Err(_) => Err(format!(
            "cannot read `{s}` (expected a number, true/false or a \"string\")"
        )),
    }
}

/// Applies `file` to `model` (before initialization): every entry goes through the model's own
/// setter, so range checks and messages are the same as for an importer's `fmi2Set*`. Returns
/// the number of values set.
pub fn apply(model: &mut dyn CoSimModel, file: &SceneFile, origin: &str) -> Result<usize, String> {
    let info = model.info();
    if let Some(m) = &file.model
        && m != info.identifier
    {
        return Err(format!(
            "{origin}: the scene is for model `{m}`, not `{}`",
            info.identifier
        ));
    }
    for e in &file.entries {
        let at = |msg: String| format!("{origin}:{}: {msg}", e.line);
        let port = info.port_by_name(&e.name).ok_or_else(|| {
            at(format!(
                "`{}` has no parameter named `{}`",
                info.identifier, e.name
            ))
        })?;
        if port.causality != Causality::Parameter {
            return Err(at(format!(
                "`{}` has causality {}; a scene file sets parameters only",
                e.name,
                port.causality.name()
            )));
        }
        set_one(model, port, &e.value).map_err(at)?;
    }
    Ok(file.entries.len())
}

fn set_one(model: &mut dyn CoSimModel, port: &PortSpec, value: &SceneValue) -> Result<(), String> {
    let wrong = |want: &str| {
        format!(
            "`{}` needs {want}, got {}",
            port.name,
            match value {
                SceneValue::Integer(_) => "an integer",
                SceneValue::Real(_) => "a real",
                SceneValue::Boolean(_) => "a boolean",
                SceneValue::String(_) => "a string",
            }
        )
    };
    let int32 = |i: i64| {
        i32::try_from(i).map_err(|_| format!("`{}` = {i} does not fit in 32 bits", port.name))
    };
    let r = match (&port.ty, value) {
        (PortType::Real { .. }, SceneValue::Real(v)) => model.set_real(port.vr, *v),
        (PortType::Real { .. }, SceneValue::Integer(i)) => model.set_real(port.vr, *i as f64),
        (PortType::Real { .. }, _) => return Err(wrong("a number")),
        (PortType::Integer { .. }, SceneValue::Integer(i)) => {
            model.set_integer(port.vr, int32(*i)?)
        }
        (PortType::Integer { .. }, _) => return Err(wrong("an integer")),
        (PortType::Boolean { .. }, SceneValue::Boolean(b)) => model.set_boolean(port.vr, *b),
        (PortType::Boolean { .. }, _) => return Err(wrong("true or false")),
        (PortType::String { .. }, SceneValue::String(s)) => model.set_string(port.vr, s),
        (PortType::String { .. }, _) => return Err(wrong("a string")),
        (PortType::Enumeration { items, .. }, SceneValue::String(s)) => {
            let k = items
                .iter()
                .position(|(n, _)| n.eq_ignore_ascii_case(s))
                .ok_or_else(|| {
                    let names: Vec<&str> = items.iter().map(|(n, _)| *n).collect();
                    format!(
                        "`{}` = \"{s}\" is not one of {}",
                        port.name,
                        names.join(", ")
                    )
                })?;
            model.set_integer(port.vr, k as i32 + 1)
        }
        (PortType::Enumeration { .. }, SceneValue::Integer(i)) => {
            model.set_integer(port.vr, int32(*i)?)
        }
        (PortType::Enumeration { .. }, _) => return Err(wrong("an item name")),
    };
    r.map_err(|e| e.to_string())
}

/// The default scene of a model: every parameter at its start value, with its description,
/// unit and (for enumerations) the item names as comments.
pub fn render(info: &ModelInfo) -> String {
    let mut out = format!(
        "# Default scene of {id}: every parameter at its start value.\n\
         # Generated from the variable table by `mbcosim model-descriptions`; copy it, change\n\
         # values and load the copy (`mbcosim simulate {id} --scene FILE`, or replace\n\
         # resources/scene.toml inside the FMU). Units are SI, as in modelDescription.xml.\n\n\
         model = \"{id}\"\n\n[parameters]\n",
        id = info.identifier
    );
    for p in info
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Parameter)
    {
        let unit = p.unit.map(|u| format!(" [{u}]")).unwrap_or_default();
        out.push_str(&format!("\n# {}{unit}\n", p.description));
        let value = match &p.ty {
            PortType::Real { start, .. } => start.map(|v| format!("{v:?}")),
            PortType::Integer { start, .. } => start.map(|v| v.to_string()),
            PortType::Boolean { start } => start.map(|v| v.to_string()),
            PortType::String { start } => start.map(quote),
            PortType::Enumeration { items, start, .. } => {
                let names: Vec<&str> = items.iter().map(|(n, _)| *n).collect();
                out.push_str(&format!("# one of: {}\n", names.join(", ")));
                start.and_then(|k| items.get(k as usize - 1).map(|(n, _)| quote(n)))
            }
        };
        if let Some(v) = value {
            out.push_str(&format!("{} = {v}\n", key_text(&p.name)));
        }
    }
    out
}

fn key_text(name: &str) -> String {
    if !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        name.to_string()
    } else {
        quote(name)
    }
}

fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Reads and applies the scene file at `path`.
pub fn apply_file(model: &mut dyn CoSimModel, path: &std::path::Path) -> Result<usize, String> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {origin}: {e}"))?;
    apply(model, &parse(&text, &origin)?, &origin)
}

#[cfg(test)]
#[path = "scene_file_tests.rs"]
mod tests;
