//! Hertz law: the purely elastic contact force `F = k delta^n`.
//!
//! No energy is lost: an impact under this law is perfectly elastic whatever the restitution
//! parameter says (it is ignored). For two elastic bodies with a point contact the Hertz theory
//! gives `n = 3/2`; the lock contact of the solar-array hinge uses `n = 1.5` as well.

/// Hysteresis factor `chi(e)` in `F = k delta^n (1 + chi delta_dot / delta_dot_minus)`: always 0.
///
/// `_restitution` [-] is ignored; it is taken so that every law has the same signature.
pub fn hysteresis_factor(_restitution: f64) -> f64 {
    0.0
}
