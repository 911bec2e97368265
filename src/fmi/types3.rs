//! Hand-written FMI 3.0 C types (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h` of the FMI 3.0
//! standard headers).
//!
//! As for FMI 2.0 ([`super::types`]), C enums are plain `c_uint` aliases with constants, and
//! `fmi3Boolean` (C `bool`) is taken as a byte, so an out-of-range value coming from an importer
//! is a number to read (non-zero is true), never undefined behaviour. The status codes 0..4 are
//! the same numbers as FMI 2.0's, so the shared state machine's statuses pass through unchanged.

#![allow(non_camel_case_types, non_upper_case_globals)]

use std::os::raw::{c_char, c_uint, c_void};

/// Opaque instance handle (`fmi3Instance`).
pub type fmi3Instance = *mut c_void;
/// Opaque importer pointer passed back to the callbacks.
pub type fmi3InstanceEnvironment = *mut c_void;
/// Opaque FMU state handle (`fmi3FMUState`).
pub type fmi3FMUState = *mut c_void;
/// Value reference (unique over all variables of a model in FMI 3.0).
pub type fmi3ValueReference = u32;
/// 32-bit float (not used by the models: refused).
pub type fmi3Float32 = f32;
/// 64-bit float.
pub type fmi3Float64 = f64;
/// 8-bit signed integer (not used: refused).
pub type fmi3Int8 = i8;
/// 8-bit unsigned integer (not used: refused).
pub type fmi3UInt8 = u8;
/// 16-bit signed integer (not used: refused).
pub type fmi3Int16 = i16;
/// 16-bit unsigned integer (not used: refused).
pub type fmi3UInt16 = u16;
/// 32-bit signed integer (FMI 2.0 `Integer`).
pub type fmi3Int32 = i32;
/// 32-bit unsigned integer (not used: refused).
pub type fmi3UInt32 = u32;
/// 64-bit signed integer (FMI 3.0 enumerations).
pub type fmi3Int64 = i64;
/// 64-bit unsigned integer (not used: refused).
pub type fmi3UInt64 = u64;
/// C `bool`, read as a byte: 0 is false, anything else true.
pub type fmi3Boolean = u8;
/// Character.
pub type fmi3Char = c_char;
/// NUL-terminated string.
pub type fmi3String = *const fmi3Char;
/// Byte of a serialized FMU state.
pub type fmi3Byte = u8;
/// Binary value (not used: refused).
pub type fmi3Binary = *const fmi3Byte;
/// Clock value (C `bool`; no clocks: refused).
pub type fmi3Clock = u8;

/// Status returned by every function (`fmi3Status`).
pub type fmi3Status = c_uint;
/// All well.
pub const fmi3OK: fmi3Status = 0;
/// Something is not quite right; the computation continues.
pub const fmi3Warning: fmi3Status = 1;
/// The call was refused, the instance is unchanged.
pub const fmi3Discard: fmi3Status = 2;
/// The instance cannot continue; reset, restore a state, or free it.
pub const fmi3Error: fmi3Status = 3;
/// The instance is corrupt; only `fmi3FreeInstance` is allowed.
pub const fmi3Fatal: fmi3Status = 4;

/// Kind of a variable dependency (`fmi3DependencyKind`).
pub type fmi3DependencyKind = c_uint;
/// Kind of a clock interval (`fmi3IntervalQualifier`).
pub type fmi3IntervalQualifier = c_uint;

/// Importer's logger (not variadic in FMI 3.0; no instance name argument).
pub type fmi3LogMessageCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ),
>;
/// Clock update callback of Scheduled Execution (unused).
pub type fmi3ClockUpdateCallback =
    Option<unsafe extern "C" fn(instanceEnvironment: fmi3InstanceEnvironment)>;
/// Intermediate update callback of Co-Simulation (unused: `providesIntermediateUpdate="false"`).
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        intermediateUpdateTime: fmi3Float64,
        intermediateVariableSetRequested: fmi3Boolean,
        intermediateVariableGetAllowed: fmi3Boolean,
        intermediateStepFinished: fmi3Boolean,
        canReturnEarly: fmi3Boolean,
        earlyReturnRequested: *mut fmi3Boolean,
        earlyReturnTime: *mut fmi3Float64,
    ),
>;
/// Preemption lock callback of Scheduled Execution (unused).
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
/// Preemption unlock callback of Scheduled Execution (unused).
pub type fmi3UnlockPreemptionCallback = Option<unsafe extern "C" fn()>;

/// `fmi3GetVersion()` result.
pub const VERSION3: &std::ffi::CStr = c"3.0";
