//! The mutable state of a simulation: a plain `Clone`, so snapshots and rollback are exact copies.

/// Time, coordinates, speeds, accelerations, multipliers and energy accumulators.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time [s].
    pub t: f64,
    /// Position coordinates (length `n_q`): positions [m], unit quaternions.
    pub q: Vec<f64>,
    /// Generalized speeds (length `n_v`) [m/s, rad/s (body frame)].
    pub v: Vec<f64>,
    /// Generalized accelerations (length `n_v`) [m/s^2, rad/s^2].
    pub vdot: Vec<f64>,
    /// Constraint multipliers (length `n_c`) [N, N m]; `-G^T lambda` is the reaction.
    pub lambda: Vec<f64>,
    /// Energy dissipated since the start [J].
    pub energy_dissipated: f64,
    /// Work done by inputs and prescribed loads since the start [J].
    pub work_input: f64,
    /// Discrete memory of the force effects (contact onset speeds, latch flags), changed only
    /// between steps.
    pub memory: Vec<f64>,
}
