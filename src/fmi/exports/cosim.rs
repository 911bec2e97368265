//! Co-simulation functions: stepping and status queries.

use crate::fmi::boundary::{guard, out_ref};
use crate::fmi::machine::{
    ALIVE, DO_STEP, GET_OUTPUT_DERIVATIVES, GET_STATUS, SET_INPUT_DERIVATIVES,
};
use crate::fmi::types::*;
use crate::scene::watch::NoWatch;

/// Not provided (`canInterpolateInputs="false"`): `fmi2Error`.
///
/// # Safety
/// `c` NULL or a live handle; the arrays are not read.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(
            c,
            "fmi2SetRealInputDerivatives",
            SET_INPUT_DERIVATIVES,
            |_| {
                Err("not supported: canInterpolateInputs=\"false\" (inputs are held constant over a step)".into())
            },
        )
    }
}

/// Not provided (`maxOutputDerivativeOrder="0"`): `fmi2Error`.
///
/// # Safety
/// `c` NULL or a live handle; the arrays are not touched.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(
            c,
            "fmi2GetRealOutputDerivatives",
            GET_OUTPUT_DERIVATIVES,
            |_| Err("not supported: maxOutputDerivativeOrder=\"0\"".into()),
        )
    }
}

/// Advances from `currentCommunicationPoint` over `communicationStepSize` [s]; a model failure
/// returns `fmi2Error` with the reason logged (never `fmi2Discard`).
///
/// # Safety
/// `c` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2DoStep", DO_STEP, |i| {
            i.step(
                currentCommunicationPoint,
                communicationStepSize,
                &mut NoWatch,
            )
            .map(|_| fmi2OK)
        })
    }
}

/// No asynchronous step can be running (`canRunAsynchronuously="false"`): `fmi2Error`.
///
/// # Safety
/// `c` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsafe {
        guard(c, "fmi2CancelStep", ALIVE, |_| {
            Err("no step is in progress to cancel (canRunAsynchronuously=\"false\": fmi2DoStep always completes)".into())
        })
    }
}

/// No status kind is available here: `fmi2Discard` with the reason logged.
///
/// # Safety
/// `c` NULL or a live handle; `value` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetStatus", GET_STATUS, |i| {
            out_ref(value, "value")?;
            i.get_status(s)
        })
    }
}

/// `fmi2LastSuccessfulTime` [s]; other kinds `fmi2Discard`.
///
/// # Safety
/// `c` NULL or a live handle; `value` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetRealStatus", GET_STATUS, |i| {
            i.get_real_status(s, out_ref(value, "value")?)
        })
    }
}

/// FMI 2.0 defines no integer status: `fmi2Discard`.
///
/// # Safety
/// `c` NULL or a live handle; `value` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetIntegerStatus", GET_STATUS, |i| {
            out_ref(value, "value")?;
            i.get_integer_status(s)
        })
    }
}

/// `fmi2Terminated` (always false: the model never asks to stop); other kinds `fmi2Discard`.
///
/// # Safety
/// `c` NULL or a live handle; `value` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetBooleanStatus", GET_STATUS, |i| {
            i.get_boolean_status(s, out_ref(value, "value")?)
        })
    }
}

/// No pending step, so no text: `fmi2Discard`.
///
/// # Safety
/// `c` NULL or a live handle; `value` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetStringStatus", GET_STATUS, |i| {
            out_ref(value, "value")?;
            i.get_string_status(s)
        })
    }
}
