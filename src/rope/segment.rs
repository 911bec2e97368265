//! The tension-only axial law of one rope segment.
//!
//! A segment of unstretched length `L` [m] between two points at distance `l` [m], lengthening at
//! `l_dot` [m/s], carries the tension
//!
//! ```text
//! T = EA (l - L) / L + c (l_dot / L - l L_dot / L^2)   if l > L and that value is > 0,
//! T = 0                                                 otherwise (slack: no compression),
//! ```
//!
//! with `EA` [N] the axial stiffness, `c` [N s] the axial (Kelvin-Voigt) damping on the strain
//! rate, and `L_dot` [m/s] the rate at which the rest length changes (winch pay-out; 0 for a
//! material segment). The derivatives returned are those of the clamped function (zero where it
//! is clamped).

/// Tension and its partial derivatives for one segment.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tension {
    /// Tension [N], `>= 0`.
    pub t: f64,
    /// `dT/dl` [N/m].
    pub dt_dl: f64,
    /// `dT/dl_dot` [N s/m].
    pub dt_dldot: f64,
    /// `dT/dL` [N/m] (used for pay-out and the slip groups).
    pub dt_drest: f64,
}

/// Evaluates the axial law for stretched length `l`, rate `l_dot`, rest length `rest` and its
/// rate `rest_rate`.
#[inline]
pub fn tension(ea: f64, damping: f64, l: f64, l_dot: f64, rest: f64, rest_rate: f64) -> Tension {
    if l <= rest {
        return Tension::default();
    }
    let inv = 1.0 / rest;
    let t = ea * (l - rest) * inv + damping * (l_dot - l * rest_rate * inv) * inv;
    if t <= 0.0 {
        return Tension::default();
    }
    Tension {
        t,
        dt_dl: (ea - damping * rest_rate * inv) * inv,
        dt_dldot: damping * inv,
        dt_drest: -(ea * l + damping * l_dot) * inv * inv
            + 2.0 * damping * l * rest_rate * inv * inv * inv,
    }
}

/// Elastic energy [J] of a segment: `EA (l - L)^2 / (2 L)` when stretched, else 0.
#[inline]
pub fn strain_energy(ea: f64, l: f64, rest: f64) -> f64 {
    if l <= rest {
        0.0
    } else {
        0.5 * ea * (l - rest) * (l - rest) / rest
    }
}

/// `dV/dL` [N] of the strain energy at fixed `l` (work rate of a changing rest length).
#[inline]
pub fn strain_energy_drest(ea: f64, l: f64, rest: f64) -> f64 {
    if l <= rest {
        0.0
    } else {
        let e = (l - rest) / rest;
        -ea * (e + 0.5 * e * e)
    }
}
