//! Getting and setting variable values; directional derivatives (not provided).

use crate::fmi::boundary::{c_str, guard, in_slice, out_slice};
use crate::fmi::machine::{GET_VALUES, SET_VALUES};
use crate::fmi::types::*;

/// Reads real variables.
///
/// # Safety
/// `c` NULL or a live handle; `vr` and `value` NULL or arrays of `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetReal", GET_VALUES, |i| {
            let vrs = in_slice(vr, nvr, "vr[]")?;
            i.get_reals(vrs, out_slice(value, nvr, "value[]")?)
        })
    }
}

/// Reads integer and enumeration variables.
///
/// # Safety
/// As for [`fmi2GetReal`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetInteger", GET_VALUES, |i| {
            let vrs = in_slice(vr, nvr, "vr[]")?;
            i.get_integers(vrs, out_slice(value, nvr, "value[]")?)
        })
    }
}

/// Reads boolean variables (1 or 0).
///
/// # Safety
/// As for [`fmi2GetReal`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetBoolean", GET_VALUES, |i| {
            let vrs = in_slice(vr, nvr, "vr[]")?;
            i.get_booleans(vrs, out_slice(value, nvr, "value[]")?)
        })
    }
}

/// Reads string variables; the strings stay valid until the next call on this instance.
///
/// # Safety
/// As for [`fmi2GetReal`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetString", GET_VALUES, |i| {
            let vrs = in_slice(vr, nvr, "vr[]")?;
            i.get_strings(vrs, out_slice(value, nvr, "value[]")?)
        })
    }
}

/// Writes real parameters and inputs; NaN, infinities and out-of-range values are refused.
///
/// # Safety
/// `c` NULL or a live handle; `vr` and `value` NULL or arrays of `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SetReal", SET_VALUES, |i| {
            i.set_reals(in_slice(vr, nvr, "vr[]")?, in_slice(value, nvr, "value[]")?)
        })
    }
}

/// Writes integer and enumeration parameters and inputs.
///
/// # Safety
/// As for [`fmi2SetReal`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SetInteger", SET_VALUES, |i| {
            i.set_integers(in_slice(vr, nvr, "vr[]")?, in_slice(value, nvr, "value[]")?)
        })
    }
}

/// Writes boolean parameters and inputs (non-zero is true).
///
/// # Safety
/// As for [`fmi2SetReal`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SetBoolean", SET_VALUES, |i| {
            i.set_booleans(in_slice(vr, nvr, "vr[]")?, in_slice(value, nvr, "value[]")?)
        })
    }
}

/// Writes string parameters and inputs (UTF-8).
///
/// # Safety
/// As for [`fmi2SetReal`]; each string NULL or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SetString", SET_VALUES, |i| {
            let vrs = in_slice(vr, nvr, "vr[]")?;
            let ptrs = in_slice(value, nvr, "value[]")?;
            let strs = ptrs
                .iter()
                .enumerate()
                .map(|(k, p)| c_str(*p, &format!("value[{k}]")))
                .collect::<Result<Vec<_>, _>>()?;
            i.set_strings(vrs, &strs)
        })
    }
}

/// Not provided (`providesDirectionalDerivative="false"`): `fmi2Error`.
///
/// # Safety
/// `c` NULL or a live handle; the arrays are not read.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _vUnknown_ref: *const fmi2ValueReference,
    _nUnknown: usize,
    _vKnown_ref: *const fmi2ValueReference,
    _nKnown: usize,
    _dvKnown: *const fmi2Real,
    _dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetDirectionalDerivative", GET_VALUES, |_| {
            Err("not supported: the model description declares providesDirectionalDerivative=\"false\"".into())
        })
    }
}
