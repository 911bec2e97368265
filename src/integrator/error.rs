//! Why an integrator stopped: the failure as a type ([`Failure`]: the integrator, the time and a
//! [`Cause`], itself holding the [`NewtonFailure`] it grew from where there is one), and the one
//! place where the message a user reads and its remedy are formatted from it
//! ([`Failure::what`], [`Failure::remedy`], `Display` of [`SolverError`]). Integrators decide what to do
//! after a failure from its type, never from its text. Remedies name integrators by the
//! spellings the FMUs' `integrator` parameter accepts ([`IntegratorKind::parameter_name`]).

use super::IntegratorKind;

/// Why integration stopped: the failure (boxed: the error travels in every `Result` of the step
/// loop). The message a user reads is formatted from it on demand ([`std::fmt::Display`]:
/// [`Failure::what`], then `"; "` and [`Failure::remedy`] when there is one); `String::from`
/// (or `to_string`) gives it as text for the callers that pass it on as such. `Debug` shows the
/// message beside the failure, as when the message was a field (tests match it in `{e:?}`).
#[derive(Clone, PartialEq)]
pub struct SolverError(Box<Failure>);

impl std::fmt::Debug for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("SolverError")
            .field(&self.to_string())
            .field(&self.0)
            .finish()
    }
}

impl SolverError {
    /// The error of `failure`.
    pub fn new(failure: Failure) -> Self {
        SolverError(Box::new(failure))
    }

    /// A failure of `kind` at `t` [s].
    pub fn at(kind: IntegratorKind, t: f64, cause: Cause) -> Self {
        Self::new(Failure {
            kind: Some(kind),
            t: Some(t),
            cause,
        })
    }

    /// A failure the causes above do not cover (set-up, consistency, a caller's misuse, a failed
    /// solve of an explicit stage), in its own words.
    pub fn other(detail: impl Into<String>) -> Self {
        Self::new(Failure {
            kind: None,
            t: None,
            cause: Cause::Other(detail.into()),
        })
    }

    /// The failure the message is formatted from.
    pub fn failure(&self) -> &Failure {
        &self.0
    }

    /// When it failed [s], where known.
    pub fn t(&self) -> Option<f64> {
        self.0.t
    }

    /// What failed.
    pub fn cause(&self) -> &Cause {
        &self.0.cause
    }
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0.what())?;
        if let Some(remedy) = self.0.remedy() {
            write!(f, "; {remedy}")?;
        }
        Ok(())
    }
}

/// The message, for callers whose errors are text.
impl From<SolverError> for String {
    fn from(e: SolverError) -> String {
        e.to_string()
    }
}

impl std::error::Error for SolverError {}

/// A failure: which integrator, when, why.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// The integrator that failed; `None` outside an integrator (set-up, the simulation's own
    /// checks).
    pub kind: Option<IntegratorKind>,
    /// Time of the state the integrator stood at [s]; `None` where none applies.
    pub t: Option<f64>,
    /// Why.
    pub cause: Cause,
}

/// Why a Newton iteration failed. The integrators retry a failed step with a fresh matrix, then
/// with a smaller step; only a failure that no retry cures is reported.
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonFailure {
    /// End of the step the iteration solved for [s].
    pub t: f64,
    /// Why.
    pub cause: NewtonCause,
}

/// The kinds of [`NewtonFailure`].
#[derive(Debug, Clone, PartialEq)]
pub enum NewtonCause {
    /// The Newton matrix could not be factorized, or its solve gave non-finite values; the
    /// linear solver's account.
    SingularMatrix(String),
    /// Non-finite values in what is named (the residual, the matrix's entries): a force law
    /// evaluated outside its range.
    NonFinite(&'static str),
    /// The corrections grew (at the contraction rate, where measured).
    Diverged(Option<f64>),
    /// The corrections did not fall below the tolerance within this many iterations.
    NoConvergence(usize),
    /// The effects' frozen decisions (a contact's stick or slip) kept changing at the converged
    /// iterate.
    SlipModes,
}

impl std::fmt::Display for NewtonFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let t = self.t;
        match &self.cause {
            NewtonCause::SingularMatrix(detail) => write!(f, "{detail} at t = {t:.9e} s"),
            NewtonCause::NonFinite(what) => write!(f, "non-finite {what} at t = {t:.9e} s"),
            NewtonCause::Diverged(Some(rate)) => {
                write!(
                    f,
                    "Newton iteration diverges at t = {t:.9e} s (rate {rate:.2})"
                )
            }
            NewtonCause::Diverged(None) => write!(f, "Newton iteration diverges at t = {t:.9e} s"),
            NewtonCause::NoConvergence(n) => write!(
                f,
                "Newton iteration did not converge in {n} iterations at t = {t:.9e} s"
            ),
            NewtonCause::SlipModes => write!(f, "slip modes not settled at t = {t:.9e} s"),
        }
    }
}

/// Why an integrator stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum Cause {
    /// Newton failed at a fixed step `h` [s], which no smaller step can retry.
    FixedStepTooLarge { h: f64, newton: NewtonFailure },
    /// The step size fell below `h` [s], where it no longer advances time.
    StepCollapse { h: f64, why: Collapse },
    /// A fixed step `h` [s] of an explicit method produced non-finite values.
    NonFinite { h: f64 },
    /// An explicit method is held at its stability boundary, not by the tolerance: `steps` steps
    /// in a row, `h_lambda` the largest `h |lambda|` among them, `h` [s] their size, `more` the
    /// steps still needed to reach `t_end` [s].
    Stiffness {
        steps: u64,
        h_lambda: f64,
        h: f64,
        more: f64,
        t_end: f64,
    },
    /// More than `max_steps` steps in one call.
    StepBudget { max_steps: u64 },
    /// The tolerance is tighter than the method resolves in double precision: the step it needs,
    /// `h` [s], leaves the round-off of positions `share` of the tolerance.
    Tolerance {
        rtol: f64,
        atol: f64,
        h: f64,
        share: f64,
    },
    /// An explicit method at a singular configuration of the joints named (`joints`).
    SingularConfiguration { joints: String, how: Passage },
    /// A failure the causes above do not cover (set-up, consistency, tree detection, a caller's
    /// misuse, a failed solve of an explicit stage), in its own words.
    Other(String),
}

/// Why a step size collapsed.
#[derive(Debug, Clone, PartialEq)]
pub enum Collapse {
    /// Newton failed at every step size; `singular` what a rank monitor saw, if it saw the
    /// mechanism at a singular configuration.
    Newton {
        newton: NewtonFailure,
        singular: Option<SingularPassage>,
    },
    /// The steps kept gaining energy: `gain` of the allowed 100 rtol of the energy in play.
    EnergyGain { gain: f64 },
    /// An explicit method's error estimate did not fall with the step.
    ErrorEstimate,
}

/// A singular configuration as a rank monitor measured it: the joints of the weakest loop
/// constraints, the smallest pivot against its value at the start (`ratio`), the relative
/// tolerance in force.
#[derive(Debug, Clone, PartialEq)]
pub struct SingularPassage {
    pub joints: String,
    pub ratio: f64,
    pub rtol: f64,
}

/// What an explicit method met at a singular configuration (`until` [s]: the end of the passage
/// seen so far).
#[derive(Debug, Clone, PartialEq)]
pub enum Passage {
    /// The solution left it on another branch: the direction of motion turned by `degrees`.
    Branch { degrees: f64, until: f64 },
    /// The energy balance changed by `change` [J] within it, `allowed` [J] allowed.
    Energy {
        change: f64,
        allowed: f64,
        until: f64,
    },
    /// The step size fell below `h` [s] there.
    StepCollapse { h: f64 },
}

/// `use integrator = a or b ...`, with the parameter spellings of `kinds` (library-only kinds
/// left out).
fn use_integrators(kinds: &[IntegratorKind]) -> String {
    let names: Vec<&str> = kinds.iter().filter_map(|k| k.parameter_name()).collect();
    format!("use integrator = {}", names.join(" or "))
}

impl Failure {
    /// The integrator's name for messages ("the integrator" when none is known).
    fn name(&self) -> &'static str {
        self.kind.map_or("the integrator", |k| k.name())
    }

    /// The time for messages [s] (NaN when unknown: never for the causes that print it).
    fn time(&self) -> f64 {
        self.t.unwrap_or(f64::NAN)
    }

    /// What happened, with the numbers that show it.
    pub fn what(&self) -> String {
        let t = self.time();
        let name = self.name();
        match &self.cause {
            Cause::FixedStepTooLarge { h, newton } => {
                format!("{newton} with the fixed step {h:.3e} s")
            }
            Cause::StepCollapse { h, why } => match why {
                Collapse::Newton { newton, .. } => {
                    format!("step size fell below {h:.1e} s at t = {t:.9e} s: {newton}")
                }
                Collapse::EnergyGain { gain } => format!(
                    "step size fell below {h:.1e} s at t = {t:.9e} s: the steps keep gaining energy ({gain:.2e} of the allowed 100 rtol of the energy in play) however small"
                ),
                Collapse::ErrorEstimate => format!(
                    "{name}: step size fell below {h:.1e} s at t = {t:.9e} s: the error estimate does not fall with the step"
                ),
            },
            Cause::NonFinite { h } => format!(
                "{name} step at t = {t:.9e} s produced non-finite values with the fixed step {h:.3e} s"
            ),
            Cause::Stiffness {
                steps,
                h_lambda,
                h,
                more,
                t_end,
            } => format!(
                "{name} is stiff here: {steps} steps in a row up to t = {t:.9e} s were held at its stability boundary (h |lambda| up to {h_lambda:.1}), not by the tolerance, and at their size ({h:.2e} s) this call needs {more:.1e} more steps to reach t = {t_end} s"
            ),
            Cause::StepBudget { max_steps } => {
                format!("more than {max_steps} steps in one call at t = {t:.9e} s")
            }
            Cause::Tolerance {
                rtol,
                atol,
                h,
                share,
            } => format!(
                "rtol {rtol:.1e} / atol {atol:.1e} is tighter than generalized-alpha resolves here in double precision: at t = {t:.9e} s the step this tolerance needs ({h:.1e} s) is so small that the round-off of positions takes {share:.2} of the tolerance"
            ),
            Cause::SingularConfiguration { joints, how } => {
                let head = format!("singular configuration at t = {t:.9e} s (joints {joints})");
                match how {
                    Passage::Branch { degrees, until } => format!(
                        "{head}: the solution left it on another branch of the mechanism (the direction of motion turned by {degrees:.0} degrees within the passage, up to t = {until:.9e} s)"
                    ),
                    Passage::Energy {
                        change,
                        allowed,
                        until,
                    } => format!(
                        "{head}: the energy balance changed by {change:.3e} J within the passage (up to t = {until:.9e} s; allowed {allowed:.3e} J, 100 rtol of the kinetic energy)"
                    ),
                    Passage::StepCollapse { h } => format!(
                        "{head}: the step size fell below {h:.1e} s because the constraints lose rank there"
                    ),
                }
            }
            Cause::Other(detail) => detail.clone(),
        }
    }

    /// What the user can do about it, naming the integrators it advises by the `integrator`
    /// parameter's spellings (never the failing one: the Verner pairs have no spelling);
    /// `None` for [`Cause::Other`], whose words carry their own advice.
    pub fn remedy(&self) -> Option<String> {
        use IntegratorKind::{Bdf, Dopri5, GenAlpha};
        let implicit = [Bdf, GenAlpha];
        Some(match &self.cause {
            Cause::FixedStepTooLarge { .. } => {
                "the fixed step is too large for this problem: reduce it or use adaptive steps"
                    .to_string()
            }
            Cause::StepCollapse { why, .. } => match why {
                Collapse::Newton {
                    singular: Some(p), ..
                } => format!(
                    "the mechanism is at a singular configuration (joints {}: the loop constraints' smallest pivot fell to {:.1e} of its value at the start), where the solve amplifies round-off {:.0e}-fold beyond what rtol = {:.0e} leaves room for; loosen rtol or {}, which passes singular configurations at tighter tolerances",
                    p.joints,
                    p.ratio,
                    1.0 / p.ratio.max(f64::MIN_POSITIVE),
                    p.rtol,
                    use_integrators(&[Dopri5])
                ),
                Collapse::Newton {
                    newton,
                    singular: None,
                } => newton_remedy(&newton.cause).to_string(),
                Collapse::EnergyGain { .. } => {
                    "a force whose potential energy disagrees with the force, or a force law too stiff for the solver (check stiffness and damping parameters)".to_string()
                }
                Collapse::ErrorEstimate => format!(
                    "non-finite or singular accelerations? (check the parameters, or {})",
                    use_integrators(&implicit)
                ),
            },
            Cause::NonFinite { .. } => "reduce the fixed step or use adaptive steps".to_string(),
            Cause::Stiffness { .. } => format!(
                "a stiff spring, damper or contact makes explicit steps this small: {}",
                use_integrators(&implicit)
            ),
            Cause::StepBudget { .. } => match self.kind {
                Some(GenAlpha | Bdf) | None => "raise h_max or loosen rtol/atol".to_string(),
                Some(_) => format!(
                    "the scene is too stiff for an explicit method: {}",
                    use_integrators(&implicit)
                ),
            },
            Cause::Tolerance { .. } => {
                format!("loosen rtol/atol or {}", use_integrators(&[Bdf, Dopri5]))
            }
            Cause::SingularConfiguration { how, .. } => match how {
                Passage::Branch { .. } => format!(
                    "the explicit method's projection onto the constraints cannot keep the branch there: {}, or loosen rtol so the steps pass the singular configuration",
                    use_integrators(&[GenAlpha])
                ),
                Passage::Energy { .. } => format!(
                    "the accelerations there are too ill-conditioned for an explicit method at this tolerance: {}, or loosen rtol",
                    use_integrators(&[GenAlpha])
                ),
                Passage::StepCollapse { .. } => format!(
                    "loosen rtol so the steps pass the singular configuration, or {}",
                    use_integrators(&[GenAlpha])
                ),
            },
            Cause::Other(_) => return None,
        })
    }
}

/// What a Newton failure that no step size cures says about the problem (the integrator does
/// not know whether the model has contacts).
fn newton_remedy(cause: &NewtonCause) -> &'static str {
    match cause {
        NewtonCause::SingularMatrix(_) => {
            "the Newton matrix is singular here: a singular configuration (joints whose constraints \
             lose rank, e.g. a closed loop at a dead point) or a body without mass or inertia"
        }
        NewtonCause::NonFinite(_) => {
            "the forces or constraints became non-finite: a force law evaluated outside its range \
             (check its parameters)"
        }
        NewtonCause::Diverged(_) | NewtonCause::NoConvergence(_) | NewtonCause::SlipModes => {
            "Newton does not converge however small the step: a force law too stiff or not smooth \
             enough for the solver (check stiffness and damping parameters) or a discontinuity in \
             the forces"
        }
    }
}

#[cfg(test)]
#[path = "error_tests.rs"]
mod tests;
