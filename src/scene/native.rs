//! Native runs of a model, without any importer: set values by name, initialize, step with a
//! fixed communication step, record every output.
//!
//! This is the reference the packaged FMUs are compared against (same code path, so results
//! must agree to the last bit when the importer makes the same calls).

use super::port::{Causality, PortType};
use super::{CoSimModel, ModelError};

/// Outputs over time: one row per communication point, `time` [s] first.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names: `time`, then every output in table order.
    pub names: Vec<String>,
    /// One row per communication point (booleans as 0/1).
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// Comma-separated values with a header line; numbers in shortest round-trip form.
    pub fn to_csv(&self) -> String {
        let mut out = self.names.join(",");
        out.push('\n');
        for row in &self.rows {
            let cells: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }

    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.names.iter().position(|n| n == name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }
}

/// Sets the port `name` from a number (integers and enumerations rounded, booleans non-zero).
pub fn set_by_name(model: &mut dyn CoSimModel, name: &str, value: f64) -> Result<(), ModelError> {
    let info = model.info();
    let p = info.port_by_name(name).ok_or_else(|| {
        ModelError::InvalidValue(format!(
            "`{}` has no variable named `{name}`",
            info.identifier
        ))
    })?;
    match &p.ty {
        PortType::Real { .. } => model.set_real(p.vr, value),
        PortType::Integer { .. } | PortType::Enumeration { .. } => {
            model.set_integer(p.vr, value.round() as i32)
        }
        PortType::Boolean { .. } => model.set_boolean(p.vr, value != 0.0),
        PortType::String { .. } => Err(ModelError::InvalidValue(format!("`{name}` is a string"))),
    }
}

/// Every output of `model` now, in table order (booleans as 0/1, strings skipped).
pub fn outputs(model: &dyn CoSimModel) -> Result<Vec<f64>, ModelError> {
    let mut row = Vec::new();
    for p in model
        .info()
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Output)
    {
        row.push(match &p.ty {
            PortType::Real { .. } => model.get_real(p.vr)?,
            PortType::Integer { .. } | PortType::Enumeration { .. } => {
                f64::from(model.get_integer(p.vr)?)
            }
            PortType::Boolean { .. } => f64::from(u8::from(model.get_boolean(p.vr)?)),
            PortType::String { .. } => continue,
        });
    }
    Ok(row)
}

/// `a` and `b` equal within a relative tolerance of 1e-9 (Python's `math.isclose`).
fn isclose(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// Sets `values` by name, initializes at `t = 0` and steps with `step` [s] until `stop` [s].
///
/// Communication point `k` is `k * step`, and the last step is shortened to land on `stop` unless
/// it already ends within 1e-9 (relative) of it: the same time grid fmpy's `simulate_fmu` uses,
/// so both runs make bit-identical calls.
pub fn simulate(
    model: &mut dyn CoSimModel,
    values: &[(String, f64)],
    stop: f64,
    step: f64,
) -> Result<Table, ModelError> {
    if !(step.is_finite() && step > 0.0 && stop.is_finite() && stop >= 0.0) {
        return Err(ModelError::InvalidValue(format!(
            "stop time {stop} s and step {step} s must be finite, step > 0"
        )));
    }
    for (name, v) in values {
        set_by_name(model, name, *v)?;
    }
    let mut names = vec!["time".to_string()];
    names.extend(
        model
            .info()
            .ports
            .iter()
            .filter(|p| {
                p.causality == Causality::Output && !matches!(p.ty, PortType::String { .. })
            })
            .map(|p| p.name.clone()),
    );
    model.initialize(0.0)?;
    let mut rows = vec![[vec![0.0], outputs(model)?].concat()];
    let mut t = 0.0;
    let mut k = 0u64;
    while !(t > stop || isclose(t, stop)) {
        k += 1;
        let mut next = k as f64 * step;
        if next > stop && !isclose(next, stop) {
            next = stop;
        }
        model.do_step(t, next - t)?;
        t = next;
        rows.push([vec![t], outputs(model)?].concat());
    }
    Ok(Table { names, rows })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::pid;

    #[test]
    fn pid_run_with_constant_error_is_a_ramp() {
        let mut m = pid::create();
        let values = [("setpoint".to_string(), 2.0), ("ki".to_string(), 0.5)];
        let t = simulate(m.as_mut(), &values, 1.05, 0.1).unwrap();
        assert_eq!(t.names, ["time", "u", "error", "saturated"]);
        assert_eq!(t.rows.len(), 12);
        let last = t.rows.last().unwrap();
        assert_eq!(last[0], 1.05);
        assert!((last[1] - (2.0 + 0.5 * 2.0 * 1.05)).abs() < 1e-12);
        assert!(
            t.to_csv()
                .starts_with("time,u,error,saturated\n0.0,2.0,2.0,0.0\n")
        );
        assert!(simulate(pid::create().as_mut(), &[("nope".into(), 1.0)], 1.0, 0.1).is_err());
    }
}
