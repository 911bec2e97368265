//! Hand-written FMI 2.0 C types (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`).
//!
//! C enums are plain `c_uint` aliases with constants, exactly as bindgen renders them, so that
//! an out-of-range value coming from an importer is just a number to refuse, never undefined
//! behaviour. `tests/fmi/fmi_signatures.rs` checks every export against the `fmi-sys` typedefs.

#![allow(non_camel_case_types, non_upper_case_globals)]

use std::os::raw::{c_char, c_int, c_uint, c_void};

/// Opaque instance handle (`fmi2Component`).
pub type fmi2Component = *mut c_void;
/// Opaque importer pointer passed back to the callbacks.
pub type fmi2ComponentEnvironment = *mut c_void;
/// Opaque FMU state handle.
pub type fmi2FMUstate = *mut c_void;
/// Value reference.
pub type fmi2ValueReference = c_uint;
/// Real value.
pub type fmi2Real = f64;
/// Integer value.
pub type fmi2Integer = c_int;
/// Boolean value: 0 is false, anything else true.
pub type fmi2Boolean = c_int;
/// Character.
pub type fmi2Char = c_char;
/// NUL-terminated string.
pub type fmi2String = *const fmi2Char;
/// Byte of a serialized FMU state.
pub type fmi2Byte = c_char;

/// Status returned by every function (`fmi2Status`).
pub type fmi2Status = c_uint;
/// All well.
pub const fmi2OK: fmi2Status = 0;
/// Something is not quite right; the computation continues.
pub const fmi2Warning: fmi2Status = 1;
/// The call was refused, the instance is unchanged (status queries only, here).
pub const fmi2Discard: fmi2Status = 2;
/// The instance cannot continue; reset, restore a state, or free it.
pub const fmi2Error: fmi2Status = 3;
/// The instance is corrupt; only `fmi2FreeInstance` is allowed.
pub const fmi2Fatal: fmi2Status = 4;
/// An asynchronous step is running (never returned: no asynchronous steps).
pub const fmi2Pending: fmi2Status = 5;

/// Interface type requested at instantiation (`fmi2Type`).
pub type fmi2Type = c_uint;
/// Model Exchange (not provided by this library).
pub const fmi2ModelExchange: fmi2Type = 0;
/// Co-Simulation.
pub const fmi2CoSimulation: fmi2Type = 1;

/// Kind of a co-simulation status query (`fmi2StatusKind`).
pub type fmi2StatusKind = c_uint;
/// Status of an asynchronous `fmi2DoStep`.
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
/// Text describing a pending step.
pub const fmi2PendingStatus: fmi2StatusKind = 1;
/// Time [s] reached by the last successful step.
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
/// Whether the slave wants the simulation to end.
pub const fmi2Terminated: fmi2StatusKind = 3;

/// Importer's logger: printf-style and variadic; always called as `(.., "%s", message)`.
pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        componentEnvironment: fmi2ComponentEnvironment,
        instanceName: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    ),
>;
/// Importer's `calloc` (unused: `canNotUseMemoryManagementFunctions="true"`).
pub type fmi2CallbackAllocateMemory =
    Option<unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void>;
/// Importer's `free` (unused).
pub type fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(obj: *mut c_void)>;
/// Completion callback of an asynchronous step (unused).
pub type fmi2StepFinished = Option<
    unsafe extern "C" fn(componentEnvironment: fmi2ComponentEnvironment, status: fmi2Status),
>;

/// Callbacks handed over by the importer at instantiation.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct fmi2CallbackFunctions {
    /// Message sink; may be NULL (messages then go to stderr for errors only).
    pub logger: fmi2CallbackLogger,
    /// Memory allocation (unused).
    pub allocateMemory: fmi2CallbackAllocateMemory,
    /// Memory release (unused).
    pub freeMemory: fmi2CallbackFreeMemory,
    /// Asynchronous step completion (unused).
    pub stepFinished: fmi2StepFinished,
    /// Passed back to `logger` unchanged.
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// `fmi2GetTypesPlatform()` result.
pub const TYPES_PLATFORM: &std::ffi::CStr = c"default";
/// `fmi2GetVersion()` result.
pub const VERSION: &std::ffi::CStr = c"2.0";

/// Human-readable name of a status.
pub fn status_name(s: fmi2Status) -> &'static str {
    match s {
        fmi2OK => "fmi2OK",
        fmi2Warning => "fmi2Warning",
        fmi2Discard => "fmi2Discard",
        fmi2Error => "fmi2Error",
        fmi2Fatal => "fmi2Fatal",
        fmi2Pending => "fmi2Pending",
        _ => "invalid status",
    }
}
