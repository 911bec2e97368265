//! Compile-time proof that every exported `fmi3*` function has the C signature of the FMI 3.0
//! headers, as bindgen declares them in `fmi-sys` (feature `fmi3`, a dev-dependency only), with
//! one deliberate difference: `fmi3Boolean` and `fmi3Clock` (C `bool`) are Rust `bool` in
//! `fmi-sys` and `u8` here (`src/fmi/types3.rs` reads them as a byte, so that a value other than
//! 0 or 1 from an importer is a number, not undefined behaviour).
//!
//! The check does not hand-write a second copy of the signatures. [`Ours`] maps each type that
//! appears in a bindgen declaration to the type this library must use for it: itself, except
//! `bool` -> `u8`, applied through pointers and through callback function pointers. For each
//! function the `const` below only compiles if the export coerces to the mapped `fmi-sys`
//! typedef, i.e. if every argument and the result are the standard's, position by position, and
//! a `u8` stands exactly where the header has a `bool`. C `bool` and `u8` have the same size and
//! alignment (asserted below), so the two declarations are the same C ABI.

use std::os::raw::c_void;

use fmi_sys::fmi3 as sys;
use mbcosim::fmi as ours;
use mbcosim::fmi::types3 as t3;

/// The type this library uses for a type of the `fmi-sys` declarations.
trait Ours {
    type T;
}

macro_rules! itself {
    ($($t:ty),* $(,)?) => { $(impl Ours for $t { type T = $t; })* };
}
itself!(
    (),
    f32,
    f64,
    i8,
    u8,
    i16,
    u16,
    i32,
    u32,
    i64,
    u64,
    usize,
    c_void
);

/// C `bool` (`fmi3Boolean`, `fmi3Clock`): read as a byte.
impl Ours for bool {
    type T = u8;
}

impl<P: Ours> Ours for *const P {
    type T = *const P::T;
}

impl<P: Ours> Ours for *mut P {
    type T = *mut P::T;
}

/// Function pointers (bindgen wraps them in `Option`): arguments and result mapped.
macro_rules! function_pointer {
    ($($arg:ident),*) => {
        impl<R: Ours $(, $arg: Ours)*> Ours for Option<unsafe extern "C" fn($($arg),*) -> R> {
            type T = Option<unsafe extern "C" fn($($arg::T),*) -> R::T>;
        }
    };
}
function_pointer!();
function_pointer!(A1);
function_pointer!(A1, A2);
function_pointer!(A1, A2, A3);
function_pointer!(A1, A2, A3, A4);
function_pointer!(A1, A2, A3, A4, A5);
function_pointer!(A1, A2, A3, A4, A5, A6);
function_pointer!(A1, A2, A3, A4, A5, A6, A7);
function_pointer!(A1, A2, A3, A4, A5, A6, A7, A8);
function_pointer!(A1, A2, A3, A4, A5, A6, A7, A8, A9);
function_pointer!(A1, A2, A3, A4, A5, A6, A7, A8, A9, A10);
function_pointer!(A1, A2, A3, A4, A5, A6, A7, A8, A9, A10, A11);
function_pointer!(A1, A2, A3, A4, A5, A6, A7, A8, A9, A10, A11, A12);

/// The `fmi-sys` declaration `S` as this library must spell it.
type Mapped<S> = <S as Ours>::T;

/// Compiles only when `A` and `B` are the same type.
trait SameAs<B> {}
impl<T> SameAs<T> for T {}
const fn same_type<A: SameAs<B>, B>() {}

macro_rules! same_signature {
    ($($name:ident => $ty:ident),* $(,)?) => {
        $(const _: Mapped<sys::$ty> = Some(ours::$name);)*
        /// The functions checked by `same_signature!`.
        const CHECKED: &[&str] = &[$(stringify!($name)),*];
    };
}

same_signature! {
    // inquire version numbers, logging, instantiation, life cycle
    fmi3GetVersion => fmi3GetVersionTYPE,
    fmi3SetDebugLogging => fmi3SetDebugLoggingTYPE,
    fmi3InstantiateModelExchange => fmi3InstantiateModelExchangeTYPE,
    fmi3InstantiateCoSimulation => fmi3InstantiateCoSimulationTYPE,
    fmi3InstantiateScheduledExecution => fmi3InstantiateScheduledExecutionTYPE,
    fmi3FreeInstance => fmi3FreeInstanceTYPE,
    fmi3EnterInitializationMode => fmi3EnterInitializationModeTYPE,
    fmi3ExitInitializationMode => fmi3ExitInitializationModeTYPE,
    fmi3EnterEventMode => fmi3EnterEventModeTYPE,
    fmi3Terminate => fmi3TerminateTYPE,
    fmi3Reset => fmi3ResetTYPE,
    // getters
    fmi3GetFloat32 => fmi3GetFloat32TYPE,
    fmi3GetFloat64 => fmi3GetFloat64TYPE,
    fmi3GetInt8 => fmi3GetInt8TYPE,
    fmi3GetUInt8 => fmi3GetUInt8TYPE,
    fmi3GetInt16 => fmi3GetInt16TYPE,
    fmi3GetUInt16 => fmi3GetUInt16TYPE,
    fmi3GetInt32 => fmi3GetInt32TYPE,
    fmi3GetUInt32 => fmi3GetUInt32TYPE,
    fmi3GetInt64 => fmi3GetInt64TYPE,
    fmi3GetUInt64 => fmi3GetUInt64TYPE,
    fmi3GetBoolean => fmi3GetBooleanTYPE,
    fmi3GetString => fmi3GetStringTYPE,
    fmi3GetBinary => fmi3GetBinaryTYPE,
    fmi3GetClock => fmi3GetClockTYPE,
    // setters
    fmi3SetFloat32 => fmi3SetFloat32TYPE,
    fmi3SetFloat64 => fmi3SetFloat64TYPE,
    fmi3SetInt8 => fmi3SetInt8TYPE,
    fmi3SetUInt8 => fmi3SetUInt8TYPE,
    fmi3SetInt16 => fmi3SetInt16TYPE,
    fmi3SetUInt16 => fmi3SetUInt16TYPE,
    fmi3SetInt32 => fmi3SetInt32TYPE,
    fmi3SetUInt32 => fmi3SetUInt32TYPE,
    fmi3SetInt64 => fmi3SetInt64TYPE,
    fmi3SetUInt64 => fmi3SetUInt64TYPE,
    fmi3SetBoolean => fmi3SetBooleanTYPE,
    fmi3SetString => fmi3SetStringTYPE,
    fmi3SetBinary => fmi3SetBinaryTYPE,
    fmi3SetClock => fmi3SetClockTYPE,
    // variable dependencies
    fmi3GetNumberOfVariableDependencies => fmi3GetNumberOfVariableDependenciesTYPE,
    fmi3GetVariableDependencies => fmi3GetVariableDependenciesTYPE,
    // FMU states
    fmi3GetFMUState => fmi3GetFMUStateTYPE,
    fmi3SetFMUState => fmi3SetFMUStateTYPE,
    fmi3FreeFMUState => fmi3FreeFMUStateTYPE,
    fmi3SerializedFMUStateSize => fmi3SerializedFMUStateSizeTYPE,
    fmi3SerializeFMUState => fmi3SerializeFMUStateTYPE,
    fmi3DeserializeFMUState => fmi3DeserializeFMUStateTYPE,
    // partial derivatives
    fmi3GetDirectionalDerivative => fmi3GetDirectionalDerivativeTYPE,
    fmi3GetAdjointDerivative => fmi3GetAdjointDerivativeTYPE,
    // configuration mode
    fmi3EnterConfigurationMode => fmi3EnterConfigurationModeTYPE,
    fmi3ExitConfigurationMode => fmi3ExitConfigurationModeTYPE,
    // clocks
    fmi3GetIntervalDecimal => fmi3GetIntervalDecimalTYPE,
    fmi3GetIntervalFraction => fmi3GetIntervalFractionTYPE,
    fmi3GetShiftDecimal => fmi3GetShiftDecimalTYPE,
    fmi3GetShiftFraction => fmi3GetShiftFractionTYPE,
    fmi3SetIntervalDecimal => fmi3SetIntervalDecimalTYPE,
    fmi3SetIntervalFraction => fmi3SetIntervalFractionTYPE,
    fmi3SetShiftDecimal => fmi3SetShiftDecimalTYPE,
    fmi3SetShiftFraction => fmi3SetShiftFractionTYPE,
    fmi3EvaluateDiscreteStates => fmi3EvaluateDiscreteStatesTYPE,
    fmi3UpdateDiscreteStates => fmi3UpdateDiscreteStatesTYPE,
    // Model Exchange
    fmi3EnterContinuousTimeMode => fmi3EnterContinuousTimeModeTYPE,
    fmi3CompletedIntegratorStep => fmi3CompletedIntegratorStepTYPE,
    fmi3SetTime => fmi3SetTimeTYPE,
    fmi3SetContinuousStates => fmi3SetContinuousStatesTYPE,
    fmi3GetContinuousStateDerivatives => fmi3GetContinuousStateDerivativesTYPE,
    fmi3GetEventIndicators => fmi3GetEventIndicatorsTYPE,
    fmi3GetContinuousStates => fmi3GetContinuousStatesTYPE,
    fmi3GetNominalsOfContinuousStates => fmi3GetNominalsOfContinuousStatesTYPE,
    fmi3GetNumberOfEventIndicators => fmi3GetNumberOfEventIndicatorsTYPE,
    fmi3GetNumberOfContinuousStates => fmi3GetNumberOfContinuousStatesTYPE,
    // Co-Simulation
    fmi3EnterStepMode => fmi3EnterStepModeTYPE,
    fmi3GetOutputDerivatives => fmi3GetOutputDerivativesTYPE,
    fmi3DoStep => fmi3DoStepTYPE,
    // Scheduled Execution
    fmi3ActivateModelPartition => fmi3ActivateModelPartitionTYPE,
}

// C `bool` and the byte that stands for it: the same size and alignment.
const _: () = {
    use std::mem::{align_of, size_of};
    assert!(size_of::<bool>() == size_of::<u8>());
    assert!(align_of::<bool>() == align_of::<u8>());
};

// The hand-written platform and callback types of `src/fmi/types3.rs`, against the headers.
const _: () = {
    same_type::<t3::fmi3Instance, sys::fmi3Instance>();
    same_type::<t3::fmi3InstanceEnvironment, sys::fmi3InstanceEnvironment>();
    same_type::<t3::fmi3FMUState, sys::fmi3FMUState>();
    same_type::<t3::fmi3ValueReference, sys::fmi3ValueReference>();
    same_type::<t3::fmi3Float32, sys::fmi3Float32>();
    same_type::<t3::fmi3Float64, sys::fmi3Float64>();
    same_type::<t3::fmi3Int8, sys::fmi3Int8>();
    same_type::<t3::fmi3UInt8, sys::fmi3UInt8>();
    same_type::<t3::fmi3Int16, sys::fmi3Int16>();
    same_type::<t3::fmi3UInt16, sys::fmi3UInt16>();
    same_type::<t3::fmi3Int32, sys::fmi3Int32>();
    same_type::<t3::fmi3UInt32, sys::fmi3UInt32>();
    same_type::<t3::fmi3Int64, sys::fmi3Int64>();
    same_type::<t3::fmi3UInt64, sys::fmi3UInt64>();
    same_type::<t3::fmi3Char, sys::fmi3Char>();
    same_type::<t3::fmi3String, sys::fmi3String>();
    same_type::<t3::fmi3Byte, sys::fmi3Byte>();
    same_type::<t3::fmi3Binary, sys::fmi3Binary>();
    same_type::<t3::fmi3Status, sys::fmi3Status>();
    same_type::<t3::fmi3DependencyKind, sys::fmi3DependencyKind>();
    same_type::<t3::fmi3IntervalQualifier, sys::fmi3IntervalQualifier>();
    // the two C `bool` types, and the callbacks that take them
    same_type::<sys::fmi3Boolean, bool>();
    same_type::<sys::fmi3Clock, bool>();
    same_type::<t3::fmi3Boolean, Mapped<sys::fmi3Boolean>>();
    same_type::<t3::fmi3Clock, Mapped<sys::fmi3Clock>>();
    same_type::<t3::fmi3LogMessageCallback, Mapped<sys::fmi3LogMessageCallback>>();
    same_type::<t3::fmi3ClockUpdateCallback, Mapped<sys::fmi3ClockUpdateCallback>>();
    same_type::<t3::fmi3IntermediateUpdateCallback, Mapped<sys::fmi3IntermediateUpdateCallback>>();
    same_type::<t3::fmi3LockPreemptionCallback, Mapped<sys::fmi3LockPreemptionCallback>>();
    same_type::<t3::fmi3UnlockPreemptionCallback, Mapped<sys::fmi3UnlockPreemptionCallback>>();
};

#[test]
fn all_75_functions_are_checked_once() {
    assert_eq!(CHECKED.len(), 75);
    let mut names = CHECKED.to_vec();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), 75, "a function is listed twice");
}

#[test]
fn status_constants_match() {
    assert_eq!(t3::fmi3OK, sys::fmi3Status_fmi3OK);
    assert_eq!(t3::fmi3Warning, sys::fmi3Status_fmi3Warning);
    assert_eq!(t3::fmi3Discard, sys::fmi3Status_fmi3Discard);
    assert_eq!(t3::fmi3Error, sys::fmi3Status_fmi3Error);
    assert_eq!(t3::fmi3Fatal, sys::fmi3Status_fmi3Fatal);
}

#[test]
fn version_is_the_headers() {
    let ours = unsafe { std::ffi::CStr::from_ptr(ours::fmi3GetVersion()) };
    assert_eq!(ours.to_bytes_with_nul(), sys::fmi3Version);
}
