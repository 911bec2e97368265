//! Lankarani-Nikravesh hysteresis damping (1990):
//! `F = k delta^n [1 + 3(1 - e^2)/4 * delta_dot / delta_dot_minus]`.
//!
//! Derived from the energy lost in an impact under the assumption that little energy is lost, so
//! it is accurate for a restitution coefficient `e >= 0.9`; for smaller `e` the effective
//! restitution of an impact is markedly larger than the nominal `e` (e.g. nominal 0.2 gives about
//! 0.67 for `n = 1.5`). This is the law of the solar-array paper (its eq. 15).

/// Hysteresis factor `chi(e) = 3 (1 - e^2) / 4` [-] for restitution `e` [-] in (0, 1].
pub fn hysteresis_factor(restitution: f64) -> f64 {
    0.75 * (1.0 - restitution * restitution)
}
