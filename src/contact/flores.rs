//! Flores et al. (2011) hysteresis damping:
//! `F = k delta^n [1 + 8(1 - e)/(5 e) * delta_dot / delta_dot_minus]`.
//!
//! Derived without the small-dissipation assumption, so it stays close to the nominal restitution
//! over the whole range (for `n = 1.5`: nominal 0.2 gives about 0.156, nominal 0.9 about 0.894).
//! The factor grows without bound as `e -> 0`, which is why `e` must be strictly positive.

/// Hysteresis factor `chi(e) = 8 (1 - e) / (5 e)` [-] for restitution `e` [-] in (0, 1].
pub fn hysteresis_factor(restitution: f64) -> f64 {
    8.0 * (1.0 - restitution) / (5.0 * restitution)
}
