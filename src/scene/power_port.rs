//! Power ports: the coupling points of a model as an importer can connect them, an effort (force,
//! torque) beside the flow it is conjugate to (velocity, angular velocity), so that a master can
//! join two models port to port and check that a force meets a velocity (docs/power_bonds.md,
//! docs/osp_ports.md). The FMI layer writes them as OSP-IS variable groups
//! (`<Model>_OspModelDescription.xml`); here they are plain names of the model's variables.

use super::port::{Causality, ModelInfo};

/// The physical domain of a port, which fixes what its effort and flow are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PortDomain {
    /// Effort a force [N], flow a linear velocity [m/s], components in the same axes.
    LinearMechanical,
    /// Effort a torque [N m], flow an angular velocity [rad/s], components in the same axes.
    AngularMechanical,
}

impl PortDomain {
    /// SI units of the effort and the flow, as the variables must declare them.
    pub fn units(self) -> (&'static str, &'static str) {
        match self {
            PortDomain::LinearMechanical => ("N", "m/s"),
            PortDomain::AngularMechanical => ("N.m", "rad/s"),
        }
    }
}

/// One power port: effort and flow variables component by component (1 to 3 of each, the same
/// number), one of the two an input and the other an output, so that two models joined at the
/// port exchange an effort for a flow. Power into the model is `-(effort . flow)` for an effort
/// the model outputs (its load on the other side), `effort . flow` for an effort it takes in.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerPort {
    /// Port name, unique in the model (e.g. `hook0`).
    pub name: String,
    pub domain: PortDomain,
    /// Effort variables (force or torque components).
    pub effort: Vec<String>,
    /// Flow variables (velocity or angular velocity components), in the effort's axes.
    pub flow: Vec<String>,
}

impl PowerPort {
    /// A port over `effort` and `flow` variable names.
    pub fn new(
        name: impl Into<String>,
        domain: PortDomain,
        effort: &[&str],
        flow: &[&str],
    ) -> Self {
        Self {
            name: name.into(),
            domain,
            effort: effort.iter().map(|s| s.to_string()).collect(),
            flow: flow.iter().map(|s| s.to_string()).collect(),
        }
    }

    /// Checks the port against the model's variable table: 1-3 components, as many efforts as
    /// flows, every name a variable with the domain's unit, all efforts of one causality and all
    /// flows of the other (input against output).
    pub fn check(&self, info: &ModelInfo) -> Result<(), String> {
        let at = || format!("{}: power port `{}`", info.identifier, self.name);
        let n = self.effort.len();
        if !(1..=3).contains(&n) || self.flow.len() != n {
            return Err(format!(
                "{}: {n} effort and {} flow components (1 to 3 of each, as many of both)",
                at(),
                self.flow.len()
            ));
        }
        let (effort_unit, flow_unit) = self.domain.units();
        let mut causalities = [None, None];
        for (k, (names, unit)) in [(&self.effort, effort_unit), (&self.flow, flow_unit)]
            .into_iter()
            .enumerate()
        {
            for name in names {
                let port = info
                    .port_by_name(name)
                    .ok_or_else(|| format!("{}: no variable `{name}`", at()))?;
                if port.unit != Some(unit) {
                    return Err(format!(
                        "{}: `{name}` has unit {:?}, the port needs {unit}",
                        at(),
                        port.unit
                    ));
                }
                if !matches!(port.causality, Causality::Input | Causality::Output) {
                    return Err(format!("{}: `{name}` is neither input nor output", at()));
                }
                match causalities[k] {
                    None => causalities[k] = Some(port.causality),
                    Some(c) if c != port.causality => {
                        return Err(format!(
                            "{}: `{name}` differs in causality from the others",
                            at()
                        ));
                    }
                    Some(_) => {}
                }
            }
        }
        if causalities[0] == causalities[1] {
            return Err(format!(
                "{}: effort and flow are both {:?}; one must be an input, the other an output",
                at(),
                causalities[0]
            ));
        }
        Ok(())
    }
}

/// A model without power ports.
pub fn none() -> Vec<PowerPort> {
    Vec::new()
}
