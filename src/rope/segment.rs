//! The tension-only axial law of one rope segment.
//!
//! A segment of unstretched length `L` [m] between two points at distance `l` [m], lengthening at
//! `l_dot` [m/s], carries the tension
//!
//! ```text
//! T = EA (l - L) / L + c (l_dot / L - l L_dot / L^2)   if l > L (stretched),
//! T = 0                                                 otherwise (slack: no compression),
//! ```
//!
//! with `EA` [N] the axial stiffness, `c` [N s] the axial (Kelvin-Voigt) damping on the strain
//! rate, and `L_dot` [m/s] the rate at which the rest length changes (winch pay-out; 0 for a
//! material segment). The derivatives returned are those of that piecewise function.
//!
//! Spring and dashpot act in parallel while the segment is stretched, so a stretched segment that
//! shortens fast can push by at most its damping force; whether it carries anything at all is
//! decided by its length alone. Decision and reason: the law clamped on the total (`T = max(0,
//! ...)`, tried first) switches on the speeds. A sling hanging slack under its own weight
//! (strains of 1e-6, where the damping of the kHz axial modes outweighs the spring) then flips
//! segments between the two branches inside every Newton iteration: the default lift set down on
//! the ground fell to steps of tens of microseconds, and the trapezoidal damping work of those
//! flips grew the energy balance by 110 kJ in 0.7 s, until the energy guard stopped it. With the
//! length alone deciding, the same set-down runs 8 s in 1,146 steps within 14 J
//! (tests/rope_ground.rs), and the damper's power `c (l_dot/L)^2 L` is dissipative either way.

/// Tension and its partial derivatives for one segment.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tension {
    /// Tension [N]; negative only while a stretched segment shortens fast (its damping).
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
