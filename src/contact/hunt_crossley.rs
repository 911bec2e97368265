//! Hunt-Crossley damping (1975) with the factor of the restitution-velocity relation
//! `e = 1 - 2/3 chi`: `F = k delta^n [1 + 3(1 - e)/2 * delta_dot / delta_dot_minus]`.
//!
//! Like Lankarani-Nikravesh it is a small-dissipation approximation: accurate near `e = 1`, and
//! for small `e` the effective restitution overshoots the nominal one (nominal 0.2 gives about
//! 0.55 for `n = 1.5`).

/// Hysteresis factor `chi(e) = 3 (1 - e) / 2` [-] for restitution `e` [-] in (0, 1].
pub fn hysteresis_factor(restitution: f64) -> f64 {
    1.5 * (1.0 - restitution)
}
