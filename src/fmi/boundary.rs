//! The C boundary: panic guard, pointer-to-slice and string conversions.
//!
//! No panic may unwind into the importer (it would abort the host process): every export runs
//! under [`guard`] or [`catch_unwind`]. A panic inside an instance call becomes `fmi2Fatal` with a
//! logged message, and the instance then only accepts `fmi2FreeInstance`.

use std::any::Any;
use std::ffi::CStr;
use std::os::raw::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};

use super::handle;
use super::instance::{Instance, Outcome};
use super::machine::Mask;
use super::types::*;

/// The text of a panic payload.
pub fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-text payload".to_string()
    }
}

/// Runs `body` on the instance behind `c` under the handle check ([`handle::enter`]: freed and
/// foreign pointers, calls from inside the instance's own callbacks), the state machine and a
/// panic guard.
///
/// # Safety
/// `c` must be NULL, a handle returned by `fmi2Instantiate` (live or freed), or a pointer to at
/// least 8 readable bytes (see [`handle`] for the limits of the check).
pub unsafe fn guard(
    c: fmi2Component,
    func: &'static str,
    mask: Mask,
    body: impl FnOnce(&mut Instance) -> Outcome,
) -> fmi2Status {
    let Some(mut entered) = (unsafe { handle::enter(c, func) }) else {
        return fmi2Error;
    };
    let Some(inst) = entered.instance() else {
        return fmi2Error;
    };
    // the one panic boundary of the call: models and the layers below catch no panics
    let result = catch_unwind(AssertUnwindSafe(|| {
        let outcome = inst.admit(mask).and_then(|()| body(inst));
        inst.settle(func, outcome)
    }));
    match result {
        Ok(status) => status,
        Err(payload) => {
            let reason = panic_message(payload.as_ref());
            // The instance may be half-updated; marking it fatal only writes plain fields.
            let logged = catch_unwind(AssertUnwindSafe(|| inst.set_fatal(func, &reason)));
            if logged.is_err() {
                eprintln!("mbcosim: {func}: internal error: {reason}");
            }
            fmi2Fatal
        }
    }
}

/// A slice from an importer's array; `n = 0` gives an empty slice whatever the pointer.
///
/// # Safety
/// If `n > 0` and `p` is not NULL, `p` must point to `n` readable, initialized `T`.
pub unsafe fn in_slice<'a, T>(p: *const T, n: usize, what: &str) -> Outcome<&'a [T]> {
    if n == 0 {
        return Ok(&[]);
    }
    check_array(p, n, what)?;
    // SAFETY: non-NULL, aligned, length checked; validity is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice over an importer's output array; `n = 0` gives an empty slice.
///
/// # Safety
/// If `n > 0` and `p` is not NULL, `p` must point to `n` writable `T` not aliased elsewhere.
pub unsafe fn out_slice<'a, T>(p: *mut T, n: usize, what: &str) -> Outcome<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    check_array(p, n, what)?;
    // SAFETY: as for `in_slice`, plus exclusive access per the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

fn check_array<T>(p: *const T, n: usize, what: &str) -> Outcome<()> {
    if p.is_null() {
        return Err(format!("{what} is NULL but its length is {n}"));
    }
    if !p.is_aligned() {
        return Err(format!("{what} is not aligned for its element type"));
    }
    if n > isize::MAX as usize / size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    Ok(())
}

/// A mutable reference to an importer's output variable.
///
/// # Safety
/// If not NULL, `p` must point to a writable `T`.
pub unsafe fn out_ref<'a, T>(p: *mut T, what: &str) -> Outcome<&'a mut T> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !p.is_aligned() {
        return Err(format!("{what} is not aligned"));
    }
    // SAFETY: non-NULL and aligned; validity is the caller's contract.
    Ok(unsafe { &mut *p })
}

/// A UTF-8 string from an importer's C string.
///
/// # Safety
/// If not NULL, `p` must point to a NUL-terminated string.
pub unsafe fn c_str<'a>(p: *const c_char, what: &str) -> Outcome<&'a str> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated per the caller's contract.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|e| format!("{what} is not valid UTF-8 ({e})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_handle_null_and_zero_lengths() {
        let empty: &[f64] = unsafe { in_slice(std::ptr::null(), 0, "v") }.unwrap();
        assert!(empty.is_empty());
        let e = unsafe { in_slice::<f64>(std::ptr::null(), 3, "value[]") }.unwrap_err();
        assert!(e.contains("value[] is NULL"), "{e}");
        let e = unsafe { out_slice::<f64>(std::ptr::dangling_mut(), usize::MAX, "v") }.unwrap_err();
        assert!(e.contains("impossible"), "{e}");
        assert!(unsafe { c_str(std::ptr::null(), "name") }.is_err());
        assert_eq!(unsafe { c_str(c"abc".as_ptr(), "name") }.unwrap(), "abc");
        let payload: Box<dyn Any + Send> = Box::new("boom");
        assert_eq!(panic_message(payload.as_ref()), "boom");
    }
}
