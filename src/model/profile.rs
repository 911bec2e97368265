//! Prescribed time functions for driving constraints and applied loads.

/// A scalar function of time with its first two derivatives, or a value taken from a model input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// `c0 + c1 t + c2 t^2`.
    Polynomial { c0: f64, c1: f64, c2: f64 },
    /// `offset + amplitude sin(omega t + phase)` (omega [rad/s]).
    Sine {
        offset: f64,
        amplitude: f64,
        omega: f64,
        phase: f64,
    },
    /// `gain * inputs[index]`, constant over a communication step (zero derivatives).
    Input { index: usize, gain: f64 },
}

impl Profile {
    /// A constant value.
    pub fn constant(c: f64) -> Self {
        Profile::Polynomial {
            c0: c,
            c1: 0.0,
            c2: 0.0,
        }
    }

    /// `c0 + rate t`.
    pub fn linear(c0: f64, rate: f64) -> Self {
        Profile::Polynomial {
            c0,
            c1: rate,
            c2: 0.0,
        }
    }

    /// Value, first and second time derivative at time `t` [s] given the model inputs.
    pub fn eval(&self, t: f64, inputs: &[f64]) -> (f64, f64, f64) {
        match *self {
            Profile::Polynomial { c0, c1, c2 } => {
                (c0 + t * (c1 + t * c2), c1 + 2.0 * c2 * t, 2.0 * c2)
            }
            Profile::Sine {
                offset,
                amplitude,
                omega,
                phase,
            } => {
                let (s, c) = (omega * t + phase).sin_cos();
                (
                    offset + amplitude * s,
                    amplitude * omega * c,
                    -amplitude * omega * omega * s,
                )
            }
            Profile::Input { index, gain } => {
                (gain * inputs.get(index).copied().unwrap_or(0.0), 0.0, 0.0)
            }
        }
    }

    /// Input index the profile reads, if any.
    pub fn input(&self) -> Option<usize> {
        match self {
            Profile::Input { index, .. } => Some(*index),
            _ => None,
        }
    }

    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        match *self {
            Profile::Polynomial { c0, c1, c2 } => {
                c0.is_finite() && c1.is_finite() && c2.is_finite()
            }
            Profile::Sine {
                offset,
                amplitude,
                omega,
                phase,
            } => {
                offset.is_finite()
                    && amplitude.is_finite()
                    && omega.is_finite()
                    && phase.is_finite()
            }
            Profile::Input { gain, .. } => gain.is_finite(),
        }
    }
}
