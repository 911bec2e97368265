//! Instance handles: what `fmi2Instantiate` and `fmi3InstantiateCoSimulation` return, checked on
//! entry to every exported function that takes one.
//!
//! A handle points to a [`Handle`]: a magic number, the name of the exported function running on
//! the instance (if any), a copy of the importer's logger for refusals, and the [`Instance`].
//!
//! - **Freed or foreign handles.** The magic number is checked first: a handle already freed (its
//!   magic is [`FREED`]) or a pointer to anything else (another magic) gets `fmi2Error` with the
//!   reason on stderr (`fmi2FreeInstance`: ignored), never a dereference of the instance. The
//!   [`Handle`] block itself outlives `fmi2FreeInstance`: the instance inside is dropped at once,
//!   but the block is kept in a quarantine of the last [`QUARANTINE`] freed handles, so that a
//!   freed handle still reads [`FREED`]. Limits (docs/fmu_conformance.md): a handle freed more
//!   than [`QUARANTINE`] frees ago, or a garbage pointer into unmapped or unaligned memory, may
//!   still crash; a pointer whose first 8 bytes happen to be [`MAGIC`] is taken for an instance.
//! - **Re-entry.** While an exported function runs on an instance, any other call into the same
//!   instance (from inside one of its callbacks: the FMI 2.0 or 3.0 logger, the FMI 3.0
//!   intermediate update; or from another thread) is refused with `fmi2Error` and a logged
//!   message, and changes nothing; `fmi2FreeInstance` re-entered logs and does not free.

use std::cell::UnsafeCell;
use std::collections::VecDeque;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use super::instance::Instance;
use super::logger::{Category, Logger};
use super::types::*;

/// The first 8 bytes of a live handle (`"mbcosim!"` in ASCII).
pub const MAGIC: u64 = u64::from_be_bytes(*b"mbcosim!");
/// The first 8 bytes of a freed handle (`"mbfreed!"`).
pub const FREED: u64 = u64::from_be_bytes(*b"mbfreed!");
/// How many freed handle blocks are kept (a few hundred bytes each) so that their magic stays
/// readable; the oldest is released when one more is freed.
pub const QUARANTINE: usize = 4096;

/// The block an instance handle points to. `magic` must stay the first field.
#[repr(C)]
pub struct Handle {
    magic: AtomicU64,
    /// The exported function running on the instance now.
    running: Mutex<Option<&'static str>>,
    /// Set while a refusal is being logged: a logger that re-enters again is told on stderr
    /// instead of being called recursively.
    refusing: AtomicBool,
    /// The importer's logger, for refusals (which must not touch the instance).
    refusals: Logger,
    /// The instance; `None` once freed. Only the function named in `running` touches it.
    instance: UnsafeCell<Option<Box<Instance>>>,
}

/// Freed handle blocks, oldest first (addresses).
static FREED_BLOCKS: Mutex<VecDeque<usize>> = Mutex::new(VecDeque::new());

/// Why a pointer is not a live handle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bad {
    Null,
    Freed,
    NotAnInstance,
}

impl Bad {
    /// The message for `func` called with such a pointer.
    pub fn message(self, func: &str) -> String {
        match self {
            Bad::Null => format!("{func} called with a NULL instance (fmi2Component)"),
            Bad::Freed => format!(
                "{func} called with an instance that was already freed (fmi2FreeInstance/fmi3FreeInstance): refused"
            ),
            Bad::NotAnInstance => format!(
                "{func} called with a pointer that is not an instance of this FMU (wrong magic number: garbage, or a handle of another FMU): refused"
            ),
        }
    }
}

/// The handle of a new instance; the caller owns it until `fmi2FreeInstance`.
pub fn into_component(instance: Instance) -> fmi2Component {
    let handle = Handle {
        magic: AtomicU64::new(MAGIC),
        running: Mutex::new(None),
        refusing: AtomicBool::new(false),
        refusals: instance.log.clone(),
        instance: UnsafeCell::new(Some(Box::new(instance))),
    };
    Box::into_raw(Box::new(handle)).cast()
}

/// The handle behind `c` when it is one (live or freed).
///
/// # Safety
/// `c` must be NULL, a handle from [`into_component`], or a pointer to at least 8 readable
/// bytes; other pointers are the documented limit.
unsafe fn check<'a>(c: fmi2Component) -> Result<&'a Handle, Bad> {
    if c.is_null() {
        return Err(Bad::Null);
    }
    let p = c.cast::<Handle>();
    if !p.is_aligned() {
        return Err(Bad::NotAnInstance);
    }
    // SAFETY: aligned and, per the contract, 8 readable bytes: the `magic` field of a handle (the
    // first field of a repr(C) struct) or whatever else is there.
    let magic = unsafe { &*c.cast::<AtomicU64>() }.load(Ordering::Acquire);
    match magic {
        // SAFETY: the magic says this is a handle block made by `into_component`, live or
        // quarantined (never released while it reads MAGIC or FREED).
        MAGIC => Ok(unsafe { &*p }),
        FREED => Err(Bad::Freed),
        _ => Err(Bad::NotAnInstance),
    }
}

/// A running exported function's exclusive hold on an instance: cleared on drop.
pub struct Entered<'a> {
    handle: &'a Handle,
}

impl Entered<'_> {
    /// The instance. The hold makes this the only reference to it; `enter` checked that it is
    /// there (the magic was MAGIC after the hold was taken).
    pub fn instance(&mut self) -> Option<&mut Instance> {
        // SAFETY: `running` names this call, so no other call holds a reference into the
        // instance (every access goes through `enter` or `free`, which take the hold first).
        let slot = unsafe { &mut *self.handle.instance.get() };
        slot.as_deref_mut()
    }
}

impl Drop for Entered<'_> {
    fn drop(&mut self) {
        *lock(&self.handle.running) = None;
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Starts `func` on the instance behind `c`: `None` (the reason logged: on stderr for a pointer
/// that is not a live handle, to the importer's logger for a call made while another runs on the
/// instance).
///
/// # Safety
/// As for [`check`].
pub unsafe fn enter<'a>(c: fmi2Component, func: &'static str) -> Option<Entered<'a>> {
    let handle = match unsafe { check(c) } {
        Ok(h) => h,
        Err(bad) => {
            eprintln!("mbcosim: {}", bad.message(func));
            return None;
        }
    };
    if let Err(other) = claim(handle, func) {
        refuse(handle, func, other, "refused; the instance is unchanged");
        return None;
    }
    let entered = Entered { handle };
    // freed by another thread between the check and the hold (itself a misuse): refuse
    if handle.magic.load(Ordering::Acquire) != MAGIC {
        eprintln!("mbcosim: {}", Bad::Freed.message(func));
        return None;
    }
    Some(entered)
}

/// Marks `func` as running on `handle`; the function already running if there is one.
fn claim(handle: &Handle, func: &'static str) -> Result<(), &'static str> {
    let mut running = lock(&handle.running);
    match *running {
        Some(other) => Err(other),
        None => {
            *running = Some(func);
            Ok(())
        }
    }
}

/// Logs that `func` was called while `other` runs on the instance.
fn refuse(handle: &Handle, func: &str, other: &str, outcome: &str) {
    let text = format!(
        "{func} called while {other} is running on this instance (from inside one of the instance's own callbacks: logger or intermediate update, or from another thread): {outcome}"
    );
    if handle.refusing.swap(true, Ordering::AcqRel) {
        eprintln!("mbcosim: [{}] {text}", handle.refusals.instance_name());
        return;
    }
    handle.refusals.log(fmi2Error, Category::StatusError, &text);
    handle.refusing.store(false, Ordering::Release);
}

/// `fmi2FreeInstance`: drops the instance and quarantines the handle block. A freed or foreign
/// pointer, or a call from inside one of the instance's callbacks, is reported and ignored.
///
/// # Safety
/// As for [`check`].
pub unsafe fn free(c: fmi2Component, func: &'static str) {
    let handle = match unsafe { check(c) } {
        Ok(h) => h,
        Err(Bad::Null) => return,
        Err(bad) => {
            eprintln!("mbcosim: {}; ignored", bad.message(func));
            return;
        }
    };
    if let Err(other) = claim(handle, func) {
        refuse(handle, func, other, "refused: the instance is not freed");
        return;
    }
    if handle.magic.load(Ordering::Acquire) != MAGIC {
        // freed by another thread between the check and the hold (itself a misuse)
        *lock(&handle.running) = None;
        eprintln!("mbcosim: {}; ignored", Bad::Freed.message(func));
        return;
    }
    // From here every call with this handle is refused as freed, including calls made from the
    // importer's logger while the instance is dropped.
    handle.magic.store(FREED, Ordering::Release);
    // SAFETY: `running` names this call: nobody else holds a reference into the instance.
    let instance = unsafe { &mut *handle.instance.get() }.take();
    drop(instance);
    *lock(&handle.running) = None;
    let released = {
        let mut blocks = lock(&FREED_BLOCKS);
        blocks.push_back(c as usize);
        if blocks.len() > QUARANTINE {
            blocks.pop_front()
        } else {
            None
        }
    };
    if let Some(old) = released {
        // SAFETY: a block made by `into_component` (Box::into_raw), freed above some frees ago and
        // held only by this queue.
        drop(unsafe { Box::from_raw(old as *mut Handle) });
    }
}

/// The instance behind a live handle, for unit tests that inspect it between calls.
///
/// # Safety
/// `c` must be a live handle and no call may be running on it.
#[cfg(test)]
pub unsafe fn peek<'a>(c: fmi2Component) -> &'a Instance {
    let handle = unsafe { check(c) }.expect("a live handle");
    // SAFETY: per the contract, no call holds the instance.
    unsafe { &*handle.instance.get() }
        .as_deref()
        .expect("a live handle holds its instance")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::test_probe::probe_entry;

    fn live() -> (
        fmi2Component,
        std::sync::Arc<std::sync::Mutex<Vec<crate::fmi::logger::Captured>>>,
    ) {
        let (logger, log) = Logger::capture("h", false);
        (into_component(Instance::new(&probe_entry(), logger)), log)
    }

    #[test]
    fn freed_and_foreign_pointers_are_told_apart() {
        let (c, _) = live();
        assert!(unsafe { check(c) }.is_ok());
        unsafe { free(c, "fmi2FreeInstance") };
        assert_eq!(unsafe { check(c) }.err(), Some(Bad::Freed));
        unsafe { free(c, "fmi2FreeInstance") }; // ignored, no double free
        assert!(unsafe { enter(c, "fmi2Reset") }.is_none());
        let mut garbage = [0xabu64; 8];
        let g: fmi2Component = garbage.as_mut_ptr().cast();
        assert_eq!(unsafe { check(g) }.err(), Some(Bad::NotAnInstance));
        unsafe { free(g, "fmi2FreeInstance") };
        assert_eq!(garbage, [0xabu64; 8], "nothing was written");
        let odd: fmi2Component = garbage.as_mut_ptr().cast::<u8>().wrapping_add(1).cast();
        assert_eq!(unsafe { check(odd) }.err(), Some(Bad::NotAnInstance));
        assert_eq!(
            unsafe { check(std::ptr::null_mut()) }.err(),
            Some(Bad::Null)
        );
        assert!(Bad::Freed.message("f").contains("already freed"));
    }

    #[test]
    fn a_second_call_while_one_runs_is_refused_and_logged() {
        let (c, log) = live();
        {
            let _first = unsafe { enter(c, "fmi2DoStep") }.unwrap();
            assert!(unsafe { enter(c, "fmi2Reset") }.is_none());
            unsafe { free(c, "fmi2FreeInstance") };
            assert!(unsafe { check(c) }.is_ok(), "not freed while a call runs");
        }
        let texts: Vec<String> = log.lock().unwrap().iter().map(|m| m.2.clone()).collect();
        assert_eq!(texts.len(), 2, "{texts:?}");
        assert!(texts[0].contains("fmi2Reset called while fmi2DoStep is running"));
        assert!(texts[1].contains("the instance is not freed"), "{texts:?}");
        assert!(
            unsafe { enter(c, "fmi2Reset") }.is_some(),
            "free again after the call"
        );
        unsafe { free(c, "fmi2FreeInstance") };
    }
}
