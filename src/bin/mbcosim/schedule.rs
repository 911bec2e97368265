//! Input schedules (`simulate --inputs file.csv`): a `time` column [s] and one column per input.
//!
//! Piecewise constant: at every communication point `t` (before the step that starts there, and
//! at `t = 0` before initialization) each scheduled input takes the value of the last row whose
//! time is `<= t` (within 1e-9 relative, the time grid's own tolerance). Before the first row's
//! time an input keeps its start, scene or `--set` value. Header cells may carry the unit as
//! written in mbcosim's own CSV (`setpoint`, `force [N]`); a unit that differs from the
//! variable's is refused. Blank lines and lines starting with `#` are skipped; cells are not
//! quoted.

use std::path::{Path, PathBuf};

use mbcosim::scene::CoSimModel;
use mbcosim::scene::native::isclose;
use mbcosim::scene::port::{Causality, ModelInfo, PortSpec};

use crate::values::{self, Value};

struct Row {
    line: usize,
    time: f64,
    values: Vec<Value>,
}

/// A loaded, validated schedule and how far it has been applied.
pub struct Schedule {
    path: PathBuf,
    columns: Vec<&'static PortSpec>,
    rows: Vec<Row>,
    /// Rows with time <= the last communication point seen.
    due: usize,
    /// Index + 1 of the row last applied (0: none yet).
    applied: usize,
}

/// Splits `name [unit]` into the name and the unit.
fn split_unit(cell: &str) -> (&str, Option<&str>) {
    let cell = cell.trim();
    if let Some(open) = cell.rfind(" [")
        && cell.ends_with(']')
    {
        return (cell[..open].trim(), Some(&cell[open + 2..cell.len() - 1]));
    }
    (cell, None)
}

impl Schedule {
    /// Reads `path` and checks it against `info`'s inputs.
    pub fn load(path: &Path, info: &'static ModelInfo) -> Result<Self, String> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--inputs {file}: cannot read: {e}"))?;
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim_start_matches('\u{feff}').trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hline, header) = lines
            .next()
            .ok_or_else(|| format!("{file}: empty; expected a header `time,<input>,...`"))?;
        let inputs: Vec<&str> = info
            .ports
            .iter()
            .filter(|p| p.causality == Causality::Input)
            .map(|p| p.name.as_str())
            .collect();
        let mut time_col = None;
        let mut columns: Vec<Option<&'static PortSpec>> = Vec::new();
        for (c, cell) in header.split(',').enumerate() {
            let at = format!("{file}:{hline}, column {}", c + 1);
            let (name, unit) = split_unit(cell);
            if name == "time" {
                if time_col.replace(c).is_some() {
                    return Err(format!("{at}: a second `time` column"));
                }
                if unit.is_some_and(|u| u != "s") {
                    return Err(format!("{at}: `time` is in s, not {}", unit.unwrap_or("")));
                }
                columns.push(None);
                continue;
            }
            let port = info.port_by_name(name).ok_or_else(|| {
                format!(
                    "{at}: `{name}` is not an input of {}{}",
                    info.identifier,
                    values::near_names(name, &inputs, info.identifier)
                )
            })?;
            if port.causality != Causality::Input {
                let what = port.causality.name();
                let article = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                };
                return Err(format!(
                    "{at}: `{name}` is {article} {what} of {}, not an input; a schedule sets inputs ({}){}",
                    info.identifier,
                    inputs.join(", "),
                    if port.causality == Causality::Parameter {
                        "; set parameters with --set"
                    } else {
                        ""
                    }
                ));
            }
            if unit != port.unit && unit.is_some() {
                return Err(match port.unit {
                    Some(u) => format!(
                        "{at}: `{name}` is in {u}, the header says {}",
                        unit.unwrap_or("")
                    ),
                    None => format!(
                        "{at}: `{name}` has no unit (dimensionless), the header says {}",
                        unit.unwrap_or("")
                    ),
                });
            }
            if columns.iter().flatten().any(|p| p.name == port.name) {
                return Err(format!("{at}: `{name}` appears twice"));
            }
            columns.push(Some(port));
        }
        let time_col = time_col
            .ok_or_else(|| format!("{file}:{hline}: no `time` column in the header `{header}`"))?;
        if columns.len() < 2 {
            return Err(format!(
                "{file}:{hline}: the header names no input (inputs of {}: {})",
                info.identifier,
                inputs.join(", ")
            ));
        }
        let names: Vec<&str> = header.split(',').map(|c| split_unit(c).0).collect();
        let mut rows: Vec<Row> = Vec::new();
        for (line, l) in lines {
            let cells: Vec<&str> = l.split(',').map(str::trim).collect();
            if cells.len() != columns.len() {
                return Err(format!(
                    "{file}:{line}: {} cells, the header has {}",
                    cells.len(),
                    columns.len()
                ));
            }
            let at = |c: usize| format!("{file}:{line}, column {} (`{}`)", c + 1, names[c]);
            let time: f64 = cells[time_col]
                .parse()
                .ok()
                .filter(|t: &f64| t.is_finite() && *t >= 0.0)
                .ok_or_else(|| format!("{}: time must be a finite number >= 0 s", at(time_col)))?;
            if let Some(prev) = rows.last()
                && time <= prev.time
            {
                return Err(format!(
                    "{}: time {time:?} s is not after the previous row's {:?} s (line {}); times must increase",
                    at(time_col),
                    prev.time,
                    prev.line
                ));
            }
            let mut vals = Vec::new();
            for (c, port) in columns.iter().enumerate() {
                if let Some(port) = port {
                    vals.push(
                        values::parse_for(port, cells[c]).map_err(|e| format!("{}: {e}", at(c)))?,
                    );
                }
            }
            rows.push(Row {
                line,
                time,
                values: vals,
            });
        }
        if rows.is_empty() {
            return Err(format!("{file}: a header and no rows"));
        }
        Ok(Self {
            path: path.to_path_buf(),
            columns: columns.into_iter().flatten().collect(),
            rows,
            due: 0,
            applied: 0,
        })
    }

    /// Sets the inputs of the last row with time <= `t`, when that row is not the one already
    /// set; `t` must not decrease between calls.
    pub fn apply_at(&mut self, t: f64, model: &mut dyn CoSimModel) -> Result<(), String> {
        while let Some(r) = self.rows.get(self.due) {
            if r.time <= t || isclose(r.time, t) {
                self.due += 1;
            } else {
                break;
            }
        }
        if self.due == 0 || self.due == self.applied {
            return Ok(());
        }
        let row = &self.rows[self.due - 1];
        for (port, v) in self.columns.iter().zip(&row.values) {
            values::apply(model, port, v).map_err(|e| {
                format!(
                    "{}:{} (`{}` at t = {t} s): {e}",
                    self.path.display(),
                    row.line,
                    port.name
                )
            })?;
        }
        self.applied = self.due;
        Ok(())
    }
}
