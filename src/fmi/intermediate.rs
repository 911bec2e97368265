//! FMI 3.0 early return and intermediate updates: what the importer asked for at
//! `fmi3InstantiateCoSimulation`, and the [`StepWatch`] that `fmi3DoStep` runs the model under.
//!
//! The intermediate-update callback is called after every accepted internal step of the
//! model's integrator before the end of the communication step, with
//! `intermediateVariableSetRequested` and `intermediateVariableGetAllowed` false (the FMUs
//! declare no intermediate variables), `intermediateStepFinished` true and `canReturnEarly`
//! equal to `earlyReturnAllowed`. An early return it requests ends the step at
//! `earlyReturnTime` when that lies ahead, at once otherwise. While the callback runs, calls back
//! into the same instance are refused, as from every other callback of the instance
//! ([`super::handle`]: `fmi3DoStep` holds the instance until it returns).

use super::types3::{fmi3InstanceEnvironment, fmi3IntermediateUpdateCallback};
use crate::scene::watch::StepWatch;

/// The importer's choices at instantiation (FMI 3.0 only; FMI 2.0 instances keep the default:
/// no early return, no callback).
#[derive(Debug, Clone, Copy, Default)]
pub struct ImporterOptions {
    /// `earlyReturnAllowed`: `fmi3DoStep` ends at the model's events.
    pub early_return: bool,
    /// The intermediate-update callback, if any.
    pub callback: fmi3IntermediateUpdateCallback,
    /// The importer's `instanceEnvironment`, passed back to the callback (kept as an address).
    pub environment: usize,
}

/// The watch of one `fmi3DoStep`.
pub struct ImporterWatch {
    pub options: ImporterOptions,
}

impl StepWatch for ImporterWatch {
    fn stop_at_events(&self) -> bool {
        self.options.early_return
    }

    fn wants_internal_steps(&self) -> bool {
        self.options.callback.is_some()
    }

    fn internal_step(&mut self, t: f64) -> Option<f64> {
        let callback = self.options.callback?;
        let (mut requested, mut at) = (0u8, t);
        // SAFETY: the importer gave this callback and environment at instantiation for exactly
        // this call; the out-pointers are valid locals. Calls back into this instance are refused
        // while it runs (`super::handle::enter`).
        unsafe {
            callback(
                self.options.environment as fmi3InstanceEnvironment,
                t,
                0,
                0,
                1,
                u8::from(self.options.early_return),
                &mut requested,
                &mut at,
            );
        }
        if requested == 0 || !self.options.early_return {
            return None;
        }
        // a time that is not a number means "as soon as possible"
        Some(if at.is_finite() { at } else { t })
    }
}
