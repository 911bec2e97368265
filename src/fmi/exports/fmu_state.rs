//! FMU states: get, set, free, serialize, deserialize.
//!
//! A handle given to the importer is only ever looked up in the instance's own table, never
//! dereferenced, so a stale or foreign handle is refused with a message instead of crashing.

use crate::fmi::boundary::{guard, in_slice, out_ref, out_slice};
use crate::fmi::machine::ALIVE;
use crate::fmi::types::*;

/// Saves the model and state machine into a new state (`*FMUstate == NULL`) or overwrites the
/// given one.
///
/// # Safety
/// `c` NULL or a live handle; `FMUstate` NULL or a valid pointer to a handle or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2GetFMUstate", ALIVE, |i| {
            let slot = out_ref(FMUstate, "FMUstate")?;
            *slot = i.get_fmu_state(*slot as usize)? as fmi2FMUstate;
            Ok(fmi2OK)
        })
    }
}

/// Restores a saved state (model and state machine).
///
/// # Safety
/// `c` NULL or a live handle; `FMUstate` any value (it is looked up, not dereferenced).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SetFMUstate", ALIVE, |i| {
            if FMUstate.is_null() {
                return Err("FMUstate is NULL".into());
            }
            i.set_fmu_state(FMUstate as usize)
        })
    }
}

/// Frees a saved state and sets `*FMUstate` to NULL (a NULL state is ignored).
///
/// # Safety
/// `c` NULL or a live handle; `FMUstate` NULL or a valid pointer to a handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2FreeFMUstate", ALIVE, |i| {
            let slot = out_ref(FMUstate, "FMUstate")?;
            i.free_fmu_state(*slot as usize)?;
            *slot = std::ptr::null_mut();
            Ok(fmi2OK)
        })
    }
}

/// Size [bytes] of the serialized state.
///
/// # Safety
/// `c` NULL or a live handle; `size` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SerializedFMUstateSize", ALIVE, |i| {
            let out = out_ref(size, "size")?;
            *out = i.serialized_size(FMUstate as usize)?;
            Ok(fmi2OK)
        })
    }
}

/// Writes the serialized state into `serializedState` (`size` bytes available).
///
/// # Safety
/// `c` NULL or a live handle; `serializedState` NULL or `size` writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2SerializeFMUstate", ALIVE, |i| {
            let buf = out_slice(serializedState.cast::<u8>(), size, "serializedState[]")?;
            i.serialize_fmu_state(FMUstate as usize, buf)
        })
    }
}

/// Rebuilds a state from bytes written by `fmi2SerializeFMUstate` (this or another process).
///
/// # Safety
/// `c` NULL or a live handle; `serializedState` NULL or `size` readable bytes; `FMUstate` NULL
/// or a valid pointer to a handle or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        guard(c, "fmi2DeSerializeFMUstate", ALIVE, |i| {
            let bytes = in_slice(serializedState.cast::<u8>(), size, "serializedState[]")?;
            let slot = out_ref(FMUstate, "FMUstate")?;
            *slot = i.deserialize_fmu_state(bytes, *slot as usize)? as fmi2FMUstate;
            Ok(fmi2OK)
        })
    }
}
