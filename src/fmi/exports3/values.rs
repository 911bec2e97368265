//! Getting and setting values: Float64, Int32, Int64 (enumerations), Boolean and String serve
//! the variable table; the other types have no variables in these models, so any value reference
//! is unknown (`fmi3Error`, logged) and an empty call is `fmi3OK`.
//!
//! `nValues` counts values, not references: an array variable takes as many as it has elements
//! (FMI 3.0, "Getting and Setting Variable Values"); the instance checks the count.

use super::common::refs;
use crate::fmi::boundary::{c_str, guard, in_slice, out_slice};
use crate::fmi::machine::{GET_VALUES, SET_VALUES};
use crate::fmi::types::fmi2OK;
use crate::fmi::types3::*;

macro_rules! getter {
    ($(#[$doc:meta])* $name:ident, $ty:ty, $method:ident) => {
        $(#[$doc])*
        ///
        /// # Safety
        /// `instance` NULL or a live handle; `valueReferences` and `values` NULL or arrays of
        /// `nValueReferences` and `nValues` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut $ty,
            nValues: usize,
        ) -> fmi3Status {
            unsafe {
                guard(instance, stringify!($name), GET_VALUES, |i| {
                    let vrs = refs(valueReferences, nValueReferences)?;
                    i.$method(vrs, out_slice(values, nValues, "values[]")?)
                })
            }
        }
    };
}

macro_rules! setter {
    ($(#[$doc:meta])* $name:ident, $ty:ty, $method:ident) => {
        $(#[$doc])*
        ///
        /// # Safety
        /// `instance` NULL or a live handle; `valueReferences` and `values` NULL or arrays of
        /// `nValueReferences` and `nValues` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const $ty,
            nValues: usize,
        ) -> fmi3Status {
            unsafe {
                guard(instance, stringify!($name), SET_VALUES, |i| {
                    let vrs = refs(valueReferences, nValueReferences)?;
                    i.$method(vrs, in_slice(values, nValues, "values[]")?)
                })
            }
        }
    };
}

getter!(
    /// Reads Float64 variables (FMI 2.0 Reals) and the independent variable `time`.
    fmi3GetFloat64, fmi3Float64, get_float64
);
getter!(
    /// Reads Int32 variables (FMI 2.0 Integers).
    fmi3GetInt32, fmi3Int32, get_int32
);
getter!(
    /// Reads enumeration variables (item numbers).
    fmi3GetInt64, fmi3Int64, get_int64
);
getter!(
    /// Reads Boolean variables (1 or 0).
    fmi3GetBoolean, fmi3Boolean, get_boolean3
);
getter!(
    /// Reads String variables; the strings stay valid until the next call on this instance.
    fmi3GetString, fmi3String, get_string3
);
setter!(
    /// Writes Float64 parameters and inputs; NaN, infinities and out-of-range values are refused.
    fmi3SetFloat64, fmi3Float64, set_float64
);
setter!(
    /// Writes Int32 parameters and inputs.
    fmi3SetInt32, fmi3Int32, set_int32
);
setter!(
    /// Writes enumeration parameters and inputs (item numbers).
    fmi3SetInt64, fmi3Int64, set_int64
);
setter!(
    /// Writes Boolean parameters and inputs (non-zero is true).
    fmi3SetBoolean, fmi3Boolean, set_boolean3
);

/// Writes String parameters and inputs (UTF-8).
///
/// # Safety
/// As for [`fmi3SetFloat64`]; each string NULL or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3String,
    nValues: usize,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3SetString", SET_VALUES, |i| {
            let vrs = refs(valueReferences, nValueReferences)?;
            let ptrs = in_slice(values, nValues, "values[]")?;
            let strs = ptrs
                .iter()
                .enumerate()
                .map(|(k, p)| c_str(*p, &format!("values[{k}]")))
                .collect::<Result<Vec<_>, _>>()?;
            i.set_string3(vrs, &strs)
        })
    }
}

/// `fmi3OK` for an empty call; otherwise the first value reference is unknown: the model has no
/// variable of type `kind`.
fn no_variables(
    i: &crate::fmi::instance::Instance,
    vrs: Result<&[fmi3ValueReference], String>,
    kind: &str,
) -> Result<fmi3Status, String> {
    match vrs?.first() {
        None => Ok(fmi2OK),
        Some(vr) => Err(format!(
            "unknown value reference {vr}: `{}` has no {kind} variables (see modelDescription.xml)",
            i.info().identifier
        )),
    }
}

macro_rules! no_type {
    ($name:ident, $mask:ident, $values:ty, $kind:literal $(, $extra:ident : $extra_ty:ty)*) => {
        #[doc = concat!("No ", $kind, " variables: `fmi3Error` for any value reference.")]
        ///
        /// # Safety
        /// `instance` NULL or a live handle; `valueReferences` NULL or `nValueReferences`
        /// elements; the values are not touched.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            $($extra: $extra_ty,)*
            _values: $values,
        ) -> fmi3Status {
            unsafe {
                guard(instance, stringify!($name), $mask, |i| {
                    no_variables(i, refs(valueReferences, nValueReferences), $kind)
                })
            }
        }
    };
}

macro_rules! no_type_n {
    ($name:ident, $mask:ident, $values:ty, $kind:literal $(, $extra:ident : $extra_ty:ty)*) => {
        #[doc = concat!("No ", $kind, " variables: `fmi3Error` for any value reference.")]
        ///
        /// # Safety
        /// `instance` NULL or a live handle; `valueReferences` NULL or `nValueReferences`
        /// elements; the values are not touched.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            $($extra: $extra_ty,)*
            _values: $values,
            _nValues: usize,
        ) -> fmi3Status {
            unsafe {
                guard(instance, stringify!($name), $mask, |i| {
                    no_variables(i, refs(valueReferences, nValueReferences), $kind)
                })
            }
        }
    };
}

no_type_n!(fmi3GetFloat32, GET_VALUES, *mut fmi3Float32, "Float32");
no_type_n!(fmi3GetInt8, GET_VALUES, *mut fmi3Int8, "Int8");
no_type_n!(fmi3GetUInt8, GET_VALUES, *mut fmi3UInt8, "UInt8");
no_type_n!(fmi3GetInt16, GET_VALUES, *mut fmi3Int16, "Int16");
no_type_n!(fmi3GetUInt16, GET_VALUES, *mut fmi3UInt16, "UInt16");
no_type_n!(fmi3GetUInt32, GET_VALUES, *mut fmi3UInt32, "UInt32");
no_type_n!(fmi3GetUInt64, GET_VALUES, *mut fmi3UInt64, "UInt64");
no_type_n!(fmi3GetBinary, GET_VALUES, *mut fmi3Binary, "Binary", _valueSizes: *mut usize);
no_type!(fmi3GetClock, GET_VALUES, *mut fmi3Clock, "Clock");
no_type_n!(fmi3SetFloat32, SET_VALUES, *const fmi3Float32, "Float32");
no_type_n!(fmi3SetInt8, SET_VALUES, *const fmi3Int8, "Int8");
no_type_n!(fmi3SetUInt8, SET_VALUES, *const fmi3UInt8, "UInt8");
no_type_n!(fmi3SetInt16, SET_VALUES, *const fmi3Int16, "Int16");
no_type_n!(fmi3SetUInt16, SET_VALUES, *const fmi3UInt16, "UInt16");
no_type_n!(fmi3SetUInt32, SET_VALUES, *const fmi3UInt32, "UInt32");
no_type_n!(fmi3SetUInt64, SET_VALUES, *const fmi3UInt64, "UInt64");
no_type_n!(fmi3SetBinary, SET_VALUES, *const fmi3Binary, "Binary", _valueSizes: *const usize);
no_type!(fmi3SetClock, SET_VALUES, *const fmi3Clock, "Clock");
