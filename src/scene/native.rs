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
pub fn isclose(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The communication points of a run from `t = 0` to `stop` [s] with step `step` [s]: point `k`
/// is `k * step`, and the last step is shortened to land on `stop` unless it already ends within
/// 1e-9 (relative) of it: the same time grid fmpy's `simulate_fmu` uses, so both runs make
/// bit-identical calls. The first item is `0.0`.
#[derive(Debug, Clone)]
pub struct Grid {
    stop: f64,
    step: f64,
    k: u64,
    t: Option<f64>,
}

impl Grid {
    /// The grid for `stop` and `step`; both finite, `step > 0`, `stop >= 0`.
    pub fn new(stop: f64, step: f64) -> Result<Self, ModelError> {
        if !(step.is_finite() && step > 0.0 && stop.is_finite() && stop >= 0.0) {
            return Err(ModelError::InvalidValue(format!(
                "stop time {stop} s and step {step} s must be finite, step > 0"
            )));
        }
        Ok(Self {
            stop,
            step,
            k: 0,
            t: None,
        })
    }

    /// Number of communication steps (points after `t = 0`), counted without running the grid
    /// where the count is large; exact up to the 1e-9 end tolerance.
    pub fn steps_estimate(&self) -> u64 {
        let n = self.stop / self.step;
        if n > 1e15 {
            return u64::MAX;
        }
        let r = n.round();
        if isclose(r, n) || (r - n).abs() < 1e-9 {
            r as u64
        } else {
            n.ceil() as u64
        }
    }
}

impl Iterator for Grid {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        let Some(t) = self.t else {
            self.t = Some(0.0);
            return Some(0.0);
        };
        if t > self.stop || isclose(t, self.stop) {
            return None;
        }
        self.k += 1;
        let mut next = self.k as f64 * self.step;
        if next > self.stop && !isclose(next, self.stop) {
            next = self.stop;
        }
        self.t = Some(next);
        Some(next)
    }
}

/// Sets `values` by name, initializes at `t = 0` and steps with `step` [s] until `stop` [s] on
/// the [`Grid`] (fmpy's time grid, so both runs make bit-identical calls).
pub fn simulate(
    model: &mut dyn CoSimModel,
    values: &[(String, f64)],
    stop: f64,
    step: f64,
) -> Result<Table, ModelError> {
    let mut grid = Grid::new(stop, step)?;
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
    let mut t = grid.next().unwrap_or(0.0);
    for next in grid {
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

    #[test]
    fn grid_lands_on_stop_and_estimates_its_length() {
        let g: Vec<f64> = Grid::new(1.05, 0.1).unwrap().collect();
        assert_eq!(g.len(), 12);
        assert_eq!((g[0], g[1], g[11]), (0.0, 0.1, 1.05));
        assert_eq!(Grid::new(1.05, 0.1).unwrap().steps_estimate(), 11);
        assert_eq!(Grid::new(1.0, 0.1).unwrap().collect::<Vec<_>>().len(), 11);
        assert_eq!(Grid::new(1.0, 0.1).unwrap().steps_estimate(), 10);
        assert_eq!(Grid::new(0.0, 0.1).unwrap().collect::<Vec<_>>(), [0.0]);
        assert!(Grid::new(1.0, 0.0).is_err() && Grid::new(f64::NAN, 0.1).is_err());
    }
}
