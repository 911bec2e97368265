//! FMU states: get, set, free, serialize, deserialize: the FMI 2.0 implementation and byte
//! format (a state serialized through either API can be restored through the other).

use crate::fmi::boundary::{guard, in_slice, out_ref, out_slice};
use crate::fmi::machine::ALIVE;
use crate::fmi::types::fmi2OK;
use crate::fmi::types3::*;

/// Saves the model and state machine into a new state (`*FMUState == NULL`) or overwrites the
/// given one.
///
/// # Safety
/// `instance` NULL or a live handle; `FMUState` NULL or a valid pointer to a handle or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3GetFMUState", ALIVE, |i| {
            let slot = out_ref(FMUState, "FMUState")?;
            *slot = i.get_fmu_state(*slot as usize)? as fmi3FMUState;
            Ok(fmi2OK)
        })
    }
}

/// Restores a saved state (model and state machine).
///
/// # Safety
/// `instance` NULL or a live handle; `FMUState` any value (it is looked up, not dereferenced).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3SetFMUState", ALIVE, |i| {
            if FMUState.is_null() {
                return Err("FMUState is NULL".into());
            }
            i.set_fmu_state(FMUState as usize)
        })
    }
}

/// Frees a saved state and sets `*FMUState` to NULL (a NULL state is ignored).
///
/// # Safety
/// `instance` NULL or a live handle; `FMUState` NULL or a valid pointer to a handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3FreeFMUState", ALIVE, |i| {
            let slot = out_ref(FMUState, "FMUState")?;
            i.free_fmu_state(*slot as usize)?;
            *slot = std::ptr::null_mut();
            Ok(fmi2OK)
        })
    }
}

/// Size [bytes] of the serialized state.
///
/// # Safety
/// `instance` NULL or a live handle; `size` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3SerializedFMUStateSize", ALIVE, |i| {
            let out = out_ref(size, "size")?;
            *out = i.serialized_size(FMUState as usize)?;
            Ok(fmi2OK)
        })
    }
}

/// Writes the serialized state into `serializedState` (`size` bytes available).
///
/// # Safety
/// `instance` NULL or a live handle; `serializedState` NULL or `size` writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3SerializeFMUState", ALIVE, |i| {
            let buf = out_slice(serializedState, size, "serializedState[]")?;
            i.serialize_fmu_state(FMUState as usize, buf)
        })
    }
}

/// Rebuilds a state from bytes written by `fmi3SerializeFMUState` or `fmi2SerializeFMUstate`
/// (this or another process).
///
/// # Safety
/// `instance` NULL or a live handle; `serializedState` NULL or `size` readable bytes;
/// `FMUState` NULL or a valid pointer to a handle or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3DeserializeFMUState", ALIVE, |i| {
            let bytes = in_slice(serializedState, size, "serializedState[]")?;
            let slot = out_ref(FMUState, "FMUState")?;
            *slot = i.deserialize_fmu_state(bytes, *slot as usize)? as fmi3FMUState;
            Ok(fmi2OK)
        })
    }
}
