//! A [`Simulation`]'s running state inside a model's serialized state: what a model built on the
//! multibody solver needs to restore a run bit for bit (state, inputs, integrator history,
//! work counters, monitors), written and read in one place.
//!
//! PanelLock and RopeBlock write their own sequence (their formats predate this one and carry
//! model data in between) around the shared solver state ([`write_state`], [`read_state`]); a
//! new model calls [`write`] and [`read`].

use super::ModelError;
use super::bytes::{ByteReader, ByteWriter};
use super::clock::same_time;
use crate::integrator::Stats;
use crate::sim::Simulation;
use crate::state::State;

/// Writes the solver state `st` (time, coordinates, multipliers, work counters, effect
/// memory): the part of every model's serialized state that [`read_state`] reads back.
pub fn write_state(w: &mut ByteWriter, st: &State) {
    w.f64(st.t);
    w.f64s(&st.q);
    w.f64s(&st.v);
    w.f64s(&st.vdot);
    w.f64s(&st.lambda);
    w.f64(st.energy_dissipated);
    w.f64(st.work_input);
    w.f64s(&st.memory);
}

/// Reads what [`write_state`] wrote; with `elapsed` [s] (the model clock's elapsed time) the
/// state's time must match it ([`same_time`]), checked before anything else is read.
pub fn read_state(r: &mut ByteReader, elapsed: Option<f64>) -> Result<State, ModelError> {
    let t = r.finite_f64("state time")?;
    if let Some(elapsed) = elapsed
        && !same_time(t, elapsed)
    {
        return Err(ModelError::BadState(format!(
            "corrupt state: scene time {t} s does not match the clock's elapsed time {elapsed} s"
        )));
    }
    Ok(State {
        t,
        q: r.f64s("positions")?,
        v: r.f64s("speeds")?,
        vdot: r.f64s("accelerations")?,
        lambda: r.f64s("multipliers")?,
        energy_dissipated: r.f64("dissipated energy")?,
        work_input: r.f64("input work")?,
        memory: r.f64s("effect memory")?,
    })
}

/// Writes `sim`'s running state.
pub fn write(w: &mut ByteWriter, sim: &Simulation) {
    write_state(w, &sim.state);
    w.f64s(&sim.system.inputs);
    w.f64s(&sim.integrator_memory());
    w.f64s(&sim.stats().to_numbers());
    w.f64s(&sim.integrator_monitors());
}

/// Reads what [`write`] wrote into `sim`, a simulation of the same model (freshly built from
/// the same parameters); `elapsed` [s] is the model clock's elapsed time, which the state's
/// time must match ([`same_time`]).
pub fn read(r: &mut ByteReader, sim: &mut Simulation, elapsed: f64) -> Result<(), ModelError> {
    let state = read_state(r, Some(elapsed))?;
    let bad = |e: String| ModelError::BadState(format!("corrupt state: {e}"));
    let inputs = r.f64s("inputs")?;
    if inputs.len() != sim.system.inputs.len() || inputs.iter().any(|u| !u.is_finite()) {
        return Err(bad(format!(
            "{} inputs where the model has {} finite ones",
            inputs.len(),
            sim.system.inputs.len()
        )));
    }
    let memory = r.f64s("integrator memory")?;
    let stats = Stats::from_numbers(&r.f64s("solver counters")?).map_err(bad)?;
    let monitors = r.f64s("integrator monitors")?;
    sim.system.inputs = inputs;
    sim.restore(state, &memory).map_err(bad)?;
    sim.set_stats(stats);
    sim.restore_integrator_monitors(&monitors).map_err(bad)
}
