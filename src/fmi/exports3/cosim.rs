//! Co-simulation functions: stepping.

use crate::fmi::boundary::{guard, out_ref};
use crate::fmi::machine::{DO_STEP, GET_OUTPUT_DERIVATIVES};
use crate::fmi::types3::*;
use crate::scene::watch::StepEnd;

/// Advances from `currentCommunicationPoint` over `communicationStepSize` [s]. With
/// `earlyReturnAllowed` at instantiation the step ends at the model's first event (located in
/// time, see [`crate::scene::watch`]), or where the intermediate-update callback asks; then
/// `earlyReturn` is true and `lastSuccessfulTime` is where the model stopped (the importer's next
/// step starts there). Otherwise the step completes and `lastSuccessfulTime` is its end.
/// `eventHandlingNeeded` and `terminateSimulation` are always false (no event mode). A model
/// failure returns `fmi3Error` with the reason logged and `lastSuccessfulTime` the start of the
/// step.
///
/// # Safety
/// `instance` NULL or a live handle; the four output pointers NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3DoStep", DO_STEP, |i| {
            let mut flags = [
                out_ref(eventHandlingNeeded, "eventHandlingNeeded")?,
                out_ref(terminateSimulation, "terminateSimulation")?,
                out_ref(earlyReturn, "earlyReturn")?,
            ];
            let last = out_ref(lastSuccessfulTime, "lastSuccessfulTime")?;
            for f in flags.iter_mut() {
                **f = 0;
            }
            let mut watch = i.importer_watch();
            let result = i.step(currentCommunicationPoint, communicationStepSize, &mut watch);
            *last = i.last_successful_time();
            let early = matches!(result?, StepEnd::Early { .. });
            *flags[2] = u8::from(early);
            Ok(crate::fmi::types::fmi2OK)
        })
    }
}

/// Step mode is entered by `fmi3ExitInitializationMode` (`hasEventMode="false"`): accepted in
/// step mode as a no-op, refused elsewhere.
///
/// # Safety
/// `instance` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3EnterStepMode", DO_STEP, |_| {
            Ok(crate::fmi::types::fmi2OK)
        })
    }
}

/// Not provided (`maxOutputDerivativeOrder="0"`): `fmi3Error`.
///
/// # Safety
/// `instance` NULL or a live handle; the arrays are not touched.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _orders: *const fmi3Int32,
    _values: *mut fmi3Float64,
    _nValues: usize,
) -> fmi3Status {
    unsafe {
        guard(
            instance,
            "fmi3GetOutputDerivatives",
            GET_OUTPUT_DERIVATIVES,
            |_| Err("not supported: maxOutputDerivativeOrder=\"0\"".into()),
        )
    }
}
