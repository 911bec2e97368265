//! Typed values for `--set` and input schedules, read by the variable's declared type, and
//! did-you-mean suggestions for names.
//!
//! Rules (the scene files' where they overlap): Real a finite number within the declared
//! min/max; Integer a whole number (`10`, also written `10.0`; `10.5` refused) within min/max;
//! Boolean `true`/`false`/`1`/`0`; Enumeration an item name (case ignored) or its number;
//! String the text as is. `_` between digits is allowed in numbers, as in scene files.

use mbcosim::scene::CoSimModel;
use mbcosim::scene::port::{ModelInfo, PortSpec, PortType};
/// A value of the variable's own type: the model store's.
pub use mbcosim::scene::store::Value;

fn finite_number(name: &str, text: &str) -> Result<f64, String> {
    let digits: String = text.trim().chars().filter(|&c| c != '_').collect();
    let lower = digits.to_ascii_lowercase();
    match digits.parse::<f64>() {
        Ok(v) if v.is_finite() && !lower.contains("inf") && !lower.contains("nan") => Ok(v),
        Ok(_) => Err(format!(
            "`{name}` = `{text}` refused: values must be finite"
        )),
        Err(_) => Err(format!("`{name}` = `{text}` is not a number")),
    }
}

/// A whole number in `i32` range (`10` or `10.0`), for Integer and Enumeration variables.
fn whole_number(name: &str, text: &str, what: &str) -> Result<i32, String> {
    let digits: String = text.trim().chars().filter(|&c| c != '_').collect();
    if let Ok(i) = digits.parse::<i64>() {
        return i32::try_from(i)
            .map_err(|_| format!("`{name}` = {i} does not fit in a 32-bit {what}"));
    }
    let v = finite_number(name, text)
        .map_err(|_| format!("`{name}` is {what}: `{text}` is not a whole number"))?;
    if v.fract() != 0.0 {
        return Err(format!(
            "`{name}` is {what}: `{text}` is not a whole number (give e.g. {} or {})",
            v.floor(),
            v.ceil()
        ));
    }
    if v < f64::from(i32::MIN) || v > f64::from(i32::MAX) {
        return Err(format!("`{name}` = {text} does not fit in a 32-bit {what}"));
    }
    Ok(v as i32)
}

/// Reads `text` as a value of `port`'s type, checking the declared range.
pub fn parse_for(port: &PortSpec, text: &str) -> Result<Value, String> {
    let name = port.name.as_str();
    let unit = port.unit.map(|u| format!(" {u}")).unwrap_or_default();
    match &port.ty {
        PortType::Real { min, max, .. } => {
            let v = finite_number(name, text)?;
            if let Some(lo) = min
                && v < *lo
            {
                return Err(format!(
                    "`{name}` = {v:?}{unit} is below its minimum {lo:?}{unit}"
                ));
            }
            if let Some(hi) = max
                && v > *hi
            {
                return Err(format!(
                    "`{name}` = {v:?}{unit} is above its maximum {hi:?}{unit}"
                ));
            }
            Ok(Value::Real(v))
        }
        PortType::Integer { min, max, .. } => {
            let i = whole_number(name, text, "an Integer")?;
            if let Some(lo) = min
                && i < *lo
            {
                return Err(format!("`{name}` = {i} is below its minimum {lo}"));
            }
            if let Some(hi) = max
                && i > *hi
            {
                return Err(format!("`{name}` = {i} is above its maximum {hi}"));
            }
            Ok(Value::Integer(i))
        }
        PortType::Boolean { .. } => match text.trim().to_ascii_lowercase().as_str() {
            "true" | "1" => Ok(Value::Boolean(true)),
            "false" | "0" => Ok(Value::Boolean(false)),
            _ => Err(format!(
                "`{name}` is a Boolean: `{text}` is not true, false, 1 or 0"
            )),
        },
        PortType::String { .. } => Ok(Value::String(text.to_string())),
        PortType::Enumeration {
            type_name, items, ..
        } => {
            let listing = || {
                items
                    .iter()
                    .enumerate()
                    .map(|(k, (n, _))| format!("{} ({})", n, k + 1))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let t = text.trim();
            if let Some(k) = items.iter().position(|(n, _)| n.eq_ignore_ascii_case(t)) {
                return Ok(Value::Integer(k as i32 + 1));
            }
            let looks_numeric = t.starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c));
            if looks_numeric {
                let i = whole_number(name, t, &format!("an enumeration ({type_name})"))?;
                if i >= 1 && (i as usize) <= items.len() {
                    return Ok(Value::Integer(i));
                }
                return Err(format!(
                    "`{name}` = {i} is not an item number of {type_name}: {}",
                    listing()
                ));
            }
            let names: Vec<&str> = items.iter().map(|(n, _)| *n).collect();
            Err(format!(
                "`{name}` = `{t}` is not one of {type_name}: {}{}",
                listing(),
                did_you_mean(t, &names)
            ))
        }
    }
}

/// One `--set NAME=VALUE`: the writable port it names and the value read for its type; errors
/// start with `--set NAME=VALUE:`.
pub fn parse_set<'a>(info: &'a ModelInfo, kv: &str) -> Result<(&'a PortSpec, Value), String> {
    let (k, v) = kv
        .split_once('=')
        .ok_or_else(|| format!("--set {kv}: expected NAME=VALUE"))?;
    let port = writable(info, k.trim()).map_err(|e| format!("--set {kv}: {e}"))?;
    let value = parse_for(port, v).map_err(|e| format!("--set {kv}: {e}"))?;
    let value = match value {
        Value::String(s) if is_path(port) => {
            Value::String(from_current_dir(&s).map_err(|e| format!("--set {kv}: {e}"))?)
        }
        other => other,
    };
    Ok((port, value))
}

/// True for a String parameter that names a file (`*_file`, e.g. RopeBlock's `mesh_file`).
pub fn is_path(port: &PortSpec) -> bool {
    matches!(port.ty, PortType::String { .. }) && port.name.ends_with("_file")
}

/// A relative path given on the command line, resolved against the current directory (as
/// `--scene` and `--out` are); absolute paths and the empty string (no file) stay as they are.
fn from_current_dir(text: &str) -> Result<String, String> {
    if text.is_empty() || std::path::Path::new(text).is_absolute() {
        return Ok(text.to_string());
    }
    let abs = std::path::absolute(text).map_err(|e| format!("cannot resolve `{text}`: {e}"))?;
    abs.into_os_string()
        .into_string()
        .map_err(|p| format!("`{}` is not UTF-8", p.to_string_lossy()))
}

/// Sets `value` through the model's own setter (its rules and messages).
pub fn apply(model: &mut dyn CoSimModel, port: &PortSpec, value: &Value) -> Result<(), String> {
    let r = match value {
        Value::Real(v) => model.set_real(port.vr, *v),
        Value::Integer(i) => model.set_integer(port.vr, *i),
        Value::Boolean(b) => model.set_boolean(port.vr, *b),
        Value::String(s) => model.set_string(port.vr, s),
    };
    r.map_err(|e| e.to_string())
}

/// The port `name` of `info` that `--set` may write (a parameter or an input), or a message
/// that names the nearest writable names.
pub fn writable<'a>(info: &'a ModelInfo, name: &str) -> Result<&'a PortSpec, String> {
    let writable: Vec<&str> = info
        .ports
        .iter()
        .filter(|p| p.is_writable())
        .map(|p| p.name.as_str())
        .collect();
    match info.port_by_name(name) {
        Some(p) if p.is_writable() => Ok(p),
        Some(p) => {
            let what = p.causality.name();
            let article = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                "an"
            } else {
                "a"
            };
            Err(format!(
                "`{name}` is {article} {what} of {} (computed by the model) and cannot be set; --set takes parameters and inputs",
                info.identifier
            ))
        }
        None => Err(format!(
            "{} has no variable `{name}`{}",
            info.identifier,
            near_names(name, &writable, info.identifier)
        )),
    }
}

/// Levenshtein distance over chars, ASCII case ignored.
pub fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().map(|c| c.to_ascii_lowercase()).collect();
    let b: Vec<char> = b.chars().map(|c| c.to_ascii_lowercase()).collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// Up to five candidates close to `name`: edit distance at most a third of its length (at least
/// 2), or one containing the other; nearest first.
pub fn nearest<'a>(name: &str, candidates: &[&'a str]) -> Vec<&'a str> {
    let lname = name.to_ascii_lowercase();
    let limit = (name.chars().count() / 3).max(2);
    let mut scored: Vec<(usize, &str)> = candidates
        .iter()
        .filter_map(|c| {
            let d = distance(name, c);
            let lc = c.to_ascii_lowercase();
            let contains = lname.len() >= 3 && (lc.contains(&lname) || lname.contains(&lc));
            (d <= limit || contains).then_some((d, *c))
        })
        .collect();
    scored.sort();
    scored.into_iter().take(5).map(|(_, c)| c).collect()
}

/// `; did you mean `a`?` (or several), empty without a close candidate.
pub fn did_you_mean(name: &str, candidates: &[&str]) -> String {
    match nearest(name, candidates).as_slice() {
        [] => String::new(),
        [one] => format!("; did you mean `{one}`?"),
        many => format!(
            "; did you mean one of {}?",
            many.iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The did-you-mean hint, or the whole list when it is short, or where to find it.
pub fn near_names(name: &str, candidates: &[&str], model: &str) -> String {
    let hint = did_you_mean(name, candidates);
    if !hint.is_empty() {
        hint
    } else if candidates.len() <= 12 {
        format!("; names: {}", candidates.join(", "))
    } else {
        format!(
            "; `mbcosim variables {model}` lists all {}",
            candidates.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_and_suggestions() {
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("Setpoint", "setpoint"), 0);
        assert_eq!(
            nearest("setpont", &["setpoint", "measurement", "kp"]),
            ["setpoint"]
        );
        assert!(nearest("zzz", &["setpoint", "kp"]).is_empty());
    }
}
