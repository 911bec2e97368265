//! Tests of the exported functions on a test model that uses every variable type, fails on
//! request and panics on request; messages are captured in memory.

use std::ffi::CString;
use std::os::raw::c_char;
use std::ptr::{null, null_mut};
use std::sync::{Arc, Mutex};

use super::*;
use crate::fmi::exports::*;
use crate::fmi::logger::Captured;
use crate::fmi::test_probe::*;
use crate::scene::pid;

/// An instance handle plus its captured log.
struct H {
    c: fmi2Component,
    log: Arc<Mutex<Vec<Captured>>>,
}

impl H {
    fn new(entry: ModelEntry, logging_on: bool) -> H {
        let (logger, log) = Logger::capture("t", logging_on);
        let inst = Instance::new(&entry, logger);
        H {
            c: crate::fmi::handle::into_component(inst),
            log,
        }
    }
    fn probe() -> H {
        H::new(probe_entry(), false)
    }
    fn inst(&self) -> &Instance {
        unsafe { crate::fmi::handle::peek(self.c) }
    }
    fn state(&self) -> State {
        self.inst().state()
    }
    fn take_log(&self) -> Vec<Captured> {
        std::mem::take(&mut *self.log.lock().unwrap())
    }
    fn last_error(&self) -> String {
        self.take_log()
            .into_iter()
            .rev()
            .find(|m| m.0 >= fmi2Discard)
            .map(|m| m.2)
            .unwrap_or_default()
    }
    fn set_r(&self, vr: u32, v: f64) -> fmi2Status {
        unsafe { fmi2SetReal(self.c, &vr, 1, &v) }
    }
    fn get_r(&self, vr: u32) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { fmi2GetReal(self.c, &vr, 1, &mut v) };
        (s, v)
    }
    fn setup(&self, stop: Option<f64>) -> fmi2Status {
        unsafe {
            fmi2SetupExperiment(
                self.c,
                0,
                0.0,
                0.0,
                i32::from(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        }
    }
    fn init(&self) {
        assert_eq!(self.setup(Some(10.0)), fmi2OK);
        assert_eq!(unsafe { fmi2EnterInitializationMode(self.c) }, fmi2OK);
        assert_eq!(unsafe { fmi2ExitInitializationMode(self.c) }, fmi2OK);
    }
    fn step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { fmi2DoStep(self.c, t, h, 0) }
    }
}

impl Drop for H {
    fn drop(&mut self) {
        unsafe { fmi2FreeInstance(self.c) }
    }
}

#[test]
fn happy_path_with_all_types() {
    let h = H::probe();
    assert_eq!(h.set_r(MASS, 2.0), fmi2OK);
    assert_eq!(h.set_r(FORCE, 3.0), fmi2OK);
    let (vr, mode) = (0u32, 2);
    assert_eq!(unsafe { fmi2SetInteger(h.c, &vr, 1, &mode) }, fmi2OK);
    let label = CString::new("hello").unwrap();
    let p = label.as_ptr();
    assert_eq!(unsafe { fmi2SetString(h.c, &vr, 1, &p) }, fmi2OK);
    h.init();
    assert_eq!(h.get_r(X), (fmi2OK, 6.0));
    assert_eq!(h.step(0.0, 0.5), fmi2OK);
    assert_eq!(h.get_r(X), (fmi2OK, 7.5));
    let mut m = 0;
    assert_eq!(unsafe { fmi2GetInteger(h.c, &vr, 1, &mut m) }, fmi2OK);
    assert_eq!(m, 2);
    let mut s: fmi2String = null();
    assert_eq!(unsafe { fmi2GetString(h.c, &vr, 1, &mut s) }, fmi2OK);
    assert_eq!(
        unsafe { std::ffi::CStr::from_ptr(s) }.to_str().unwrap(),
        "hello"
    );
    let mut b = 7;
    assert_eq!(
        unsafe { fmi2GetBoolean(h.c, &PANIC_NOW, 1, &mut b) },
        fmi2OK
    );
    assert_eq!(b, 0);
    let mut t = 0.0;
    assert_eq!(
        unsafe { fmi2GetRealStatus(h.c, fmi2LastSuccessfulTime, &mut t) },
        fmi2OK
    );
    assert_eq!(t, 0.5);
    let mut term = 1;
    assert_eq!(
        unsafe { fmi2GetBooleanStatus(h.c, fmi2Terminated, &mut term) },
        fmi2OK
    );
    assert_eq!(term, 0);
    assert_eq!(unsafe { fmi2Terminate(h.c) }, fmi2OK);
    assert_eq!(h.get_r(X), (fmi2OK, 7.5));
    assert!(h.take_log().iter().all(|m| m.0 < fmi2Discard));
}

/// Drives a fresh instance into `target`.
fn in_state(target: State) -> H {
    let h = H::probe();
    match target {
        State::Instantiated => {}
        State::InitializationMode => {
            h.setup(None);
            unsafe { fmi2EnterInitializationMode(h.c) };
        }
        State::StepComplete => h.init(),
        State::Terminated => {
            h.init();
            unsafe { fmi2Terminate(h.c) };
        }
        State::Error => {
            h.set_r(X, 1.0);
        }
        State::Fatal => {
            h.init();
            let on = 1;
            unsafe { fmi2SetBoolean(h.c, &PANIC_NOW, 1, &on) };
            h.step(0.0, 0.1);
        }
        State::StepFailed => unreachable!(),
    }
    assert_eq!(h.state(), target);
    h.take_log();
    h
}

type Call = fn(&H) -> fmi2Status;

/// Every function with a harmless valid call, and the states where the standard allows it.
fn calls() -> Vec<(&'static str, Call, Mask)> {
    use crate::fmi::machine::*;
    vec![
        (
            "fmi2SetDebugLogging",
            |h| unsafe { fmi2SetDebugLogging(h.c, 1, 0, null()) },
            ALIVE,
        ),
        ("fmi2SetupExperiment", |h| h.setup(None), INSTANTIATED),
        (
            "fmi2EnterInitializationMode",
            |h| unsafe { fmi2EnterInitializationMode(h.c) },
            INSTANTIATED,
        ),
        (
            "fmi2ExitInitializationMode",
            |h| unsafe { fmi2ExitInitializationMode(h.c) },
            INIT_MODE,
        ),
        (
            "fmi2Terminate",
            |h| unsafe { fmi2Terminate(h.c) },
            TERMINATE,
        ),
        ("fmi2Reset", |h| unsafe { fmi2Reset(h.c) }, ALIVE),
        ("fmi2GetReal", |h| h.get_r(X).0, GET_VALUES),
        ("fmi2SetReal", |h| h.set_r(FORCE, 1.0), SET_VALUES),
        (
            "fmi2GetFMUstate",
            |h| {
                let mut s = null_mut();
                unsafe { fmi2GetFMUstate(h.c, &mut s) }
            },
            ALIVE,
        ),
        ("fmi2DoStep", |h| h.step(0.0, 0.1), DO_STEP),
        (
            "fmi2GetRealStatus",
            |h| {
                let mut t = 0.0;
                unsafe { fmi2GetRealStatus(h.c, fmi2LastSuccessfulTime, &mut t) }
            },
            GET_STATUS,
        ),
    ]
}

#[test]
fn every_function_checks_its_state_mask() {
    let states = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::Terminated,
        State::Error,
        State::Fatal,
    ];
    for (name, call, mask) in calls() {
        for s in states {
            let h = in_state(s);
            let status = call(&h);
            if mask.contains(s) {
                assert!(
                    status <= fmi2Warning,
                    "{name} in {s:?} gave {status}: {}",
                    h.last_error()
                );
            } else {
                assert_eq!(status, fmi2Error, "{name} in {s:?}");
                let msg = h.last_error();
                assert!(
                    msg.starts_with(name) && msg.contains("illegal call sequence"),
                    "{name} in {s:?}: {msg}"
                );
                let expected = if s == State::Fatal {
                    State::Fatal
                } else {
                    State::Error
                };
                assert_eq!(h.state(), expected, "{name} in {s:?}");
            }
        }
    }
}

#[test]
fn set_rules_null_arrays_and_unknown_references() {
    let cases: Vec<(Call, &str)> = vec![
        (|h| h.set_r(X, 1.0), "`x` is an output"),
        (|h| h.set_r(FORCE, f64::NAN), "must be finite"),
        (|h| h.set_r(FORCE, f64::NEG_INFINITY), "must be finite"),
        (|h| h.set_r(MASS, -1.0), "below its minimum 0"),
        (|h| h.set_r(77, 1.0), "unknown value reference 77"),
        (|h| h.get_r(77).0, "unknown value reference 77"),
        (
            |h| unsafe { fmi2SetReal(h.c, null(), 2, null()) },
            "vr[] is NULL",
        ),
        (
            |h| unsafe { fmi2GetReal(h.c, &X, 1, null_mut()) },
            "value[] is NULL",
        ),
        (
            |h| {
                let (vr, v) = (0u32, 3);
                unsafe { fmi2SetInteger(h.c, &vr, 1, &v) }
            },
            "not an item of enumeration Mode",
        ),
        (
            |h| {
                let p: fmi2String = null();
                unsafe { fmi2SetString(h.c, &0, 1, &p) }
            },
            "value[0] is NULL",
        ),
        (|h| h.set_r(MASS, 5.0), "fixed parameter"),
    ];
    for (k, (call, expected)) in cases.into_iter().enumerate() {
        let h = in_state(if k == 5 || k == 7 || k == 10 {
            State::StepComplete
        } else {
            State::Instantiated
        });
        assert_eq!(call(&h), fmi2Error, "case {k}");
        let msg = h.last_error();
        assert!(msg.contains(expected), "case {k}: {msg}");
        assert_eq!(h.state(), State::Error);
    }
    // n = 0 with NULL arrays is fine; tunable parameters and inputs after initialization too
    let h = in_state(State::StepComplete);
    assert_eq!(unsafe { fmi2SetReal(h.c, null(), 0, null()) }, fmi2OK);
    assert_eq!(unsafe { fmi2GetReal(h.c, null(), 0, null_mut()) }, fmi2OK);
    assert_eq!(h.set_r(GAIN, 4.0), fmi2OK);
    assert_eq!(h.set_r(FORCE, 4.0), fmi2OK);
}

#[test]
fn initialization_mode_getters_see_current_inputs() {
    let h = in_state(State::InitializationMode);
    h.set_r(MASS, 2.0);
    h.set_r(FORCE, 1.5);
    assert_eq!(h.get_r(X), (fmi2OK, 3.0));
    h.set_r(FORCE, 2.0);
    assert_eq!(h.get_r(X), (fmi2OK, 4.0));
    assert_eq!(
        h.set_r(MASS, 1.0),
        fmi2OK,
        "fixed parameters are settable until exit"
    );
    assert_eq!(unsafe { fmi2ExitInitializationMode(h.c) }, fmi2OK);
    assert_eq!(h.get_r(X), (fmi2OK, 2.0));
}

#[test]
fn do_step_checks_times_and_reports_model_failures() {
    let h = in_state(State::StepComplete);
    assert_eq!(h.step(0.0, 0.01), fmi2OK);
    assert_eq!(
        h.step(0.009999999999999998, 0.01),
        fmi2OK,
        "rounding jitter is accepted"
    );
    for (t, step, expected) in [
        (0.5, 0.1, "does not match the model time"),
        (0.02, 0.0, "must be positive"),
        (0.02, -0.1, "must be positive"),
        (0.02, f64::NAN, "must be positive"),
        (f64::NAN, 0.1, "must be finite"),
        (0.02, 20.0, "past the stop time 10 s"),
    ] {
        let h = in_state(State::StepComplete);
        h.step(0.0, 0.01);
        h.step(0.01, 0.01);
        assert_eq!(h.step(t, step), fmi2Error, "{t} {step}");
        let msg = h.last_error();
        assert!(
            msg.starts_with("fmi2DoStep") && msg.contains(expected),
            "{msg}"
        );
        assert_eq!(h.state(), State::Error);
    }
    let h = in_state(State::StepComplete);
    h.set_r(FORCE, 1e7);
    assert_eq!(h.step(0.0, 0.1), fmi2Error);
    assert!(h.last_error().contains("the probe diverged"));
    assert_eq!(unsafe { fmi2Reset(h.c) }, fmi2OK);
    assert_eq!(h.state(), State::Instantiated);
}

#[test]
fn a_panic_becomes_fatal_and_only_free_is_allowed() {
    let h = in_state(State::Fatal);
    let _ = h.take_log();
    assert_eq!(h.step(0.1, 0.1), fmi2Error);
    assert_eq!(unsafe { fmi2Reset(h.c) }, fmi2Error);
    let h2 = in_state(State::StepComplete);
    let on = 1;
    unsafe { fmi2SetBoolean(h2.c, &PANIC_NOW, 1, &on) };
    assert_eq!(h2.step(0.0, 0.1), fmi2Fatal);
    let log = h2.take_log();
    let fatal = log
        .iter()
        .find(|m| m.0 == fmi2Fatal)
        .expect("fatal message");
    assert_eq!(fatal.1, Category::StatusFatal);
    assert!(fatal.2.contains("probe asked to panic"), "{}", fatal.2);
}

#[test]
fn model_messages_follow_debug_logging() {
    let h = in_state(State::StepComplete);
    h.step(0.0, 0.1);
    assert!(
        h.take_log().is_empty(),
        "events are debug messages: off by default"
    );
    assert_eq!(unsafe { fmi2SetDebugLogging(h.c, 1, 0, null()) }, fmi2OK);
    h.set_r(FORCE, -1.0);
    assert_eq!(
        h.step(0.1, 0.1),
        fmi2Warning,
        "a model warning escalates the status"
    );
    let log = h.take_log();
    assert!(
        log.iter()
            .any(|m| m.1 == Category::Events && m.2.contains("stepped to"))
    );
    assert!(
        log.iter()
            .any(|m| m.0 == fmi2Warning && m.1 == Category::StatusWarning)
    );
    let cats = [c"logEvents".as_ptr()];
    assert_eq!(
        unsafe { fmi2SetDebugLogging(h.c, 0, 1, cats.as_ptr()) },
        fmi2OK
    );
    h.set_r(FORCE, 1.0);
    h.step(0.2, 0.1);
    assert!(h.take_log().is_empty());
    let bad = [c"logEverything".as_ptr()];
    assert_eq!(
        unsafe { fmi2SetDebugLogging(h.c, 1, 1, bad.as_ptr()) },
        fmi2Error
    );
    assert!(
        h.last_error()
            .contains("unknown log category `logEverything`")
    );
    let null_cat: [*const c_char; 1] = [null()];
    let h = in_state(State::Instantiated);
    assert_eq!(
        unsafe { fmi2SetDebugLogging(h.c, 1, 1, null_cat.as_ptr()) },
        fmi2Error
    );
}

#[test]
fn fmu_states_replay_bit_identically_and_refuse_bad_input() {
    let h = in_state(State::StepComplete);
    h.set_r(FORCE, 0.3);
    h.step(0.0, 0.1);
    let mut s = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(h.c, &mut s) }, fmi2OK);
    let run = |h: &H| {
        let mut out = vec![];
        for k in 1..6 {
            h.set_r(FORCE, 0.1 * k as f64);
            assert_eq!(h.step(0.1 * k as f64, 0.1), fmi2OK);
            out.push(h.get_r(X).1.to_bits());
        }
        out
    };
    let first = run(&h);
    assert_eq!(unsafe { fmi2SetFMUstate(h.c, s) }, fmi2OK);
    assert_eq!(run(&h), first);
    // serialize, restore into a second instance
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(h.c, s, &mut size) },
        fmi2OK
    );
    let mut buf = vec![0 as c_char; size];
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(h.c, s, buf.as_mut_ptr(), size) },
        fmi2OK
    );
    let h2 = H::probe();
    let mut s2 = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(h2.c, buf.as_ptr(), size, &mut s2) },
        fmi2OK
    );
    assert_eq!(unsafe { fmi2SetFMUstate(h2.c, s2) }, fmi2OK);
    assert_eq!(h2.state(), State::StepComplete);
    assert_eq!(run(&h2), first);
    // overwrite an existing state in place; a restored state leaves the error state
    let mut again = s2;
    assert_eq!(unsafe { fmi2GetFMUstate(h2.c, &mut again) }, fmi2OK);
    assert_eq!(again, s2);
    h2.set_r(X, 0.0);
    assert_eq!(h2.state(), State::Error);
    assert_eq!(unsafe { fmi2SetFMUstate(h2.c, s2) }, fmi2OK);
    assert_eq!(h2.state(), State::StepComplete);
    // refusals
    let foreign = 0x1234 as fmi2FMUstate;
    type Case = (&'static str, Box<dyn Fn(&H) -> fmi2Status>);
    let bad: Vec<Case> = vec![
        (
            "not created by this instance",
            Box::new(move |h| unsafe { fmi2SetFMUstate(h.c, foreign) }),
        ),
        (
            "FMUstate is NULL",
            Box::new(|h| unsafe { fmi2SetFMUstate(h.c, null_mut()) }),
        ),
        (
            "too small",
            Box::new(move |h| {
                let mut small = vec![0 as c_char; 10];
                unsafe { fmi2SerializeFMUstate(h.c, s, small.as_mut_ptr(), 10) }
            }),
        ),
        ("checksum", {
            let mut b = buf.clone();
            b[30] ^= 4;
            Box::new(move |h| {
                let mut t = null_mut();
                unsafe { fmi2DeSerializeFMUstate(h.c, b.as_ptr(), b.len(), &mut t) }
            })
        }),
        ("truncated", {
            let b = buf.clone();
            Box::new(move |h| {
                let mut t = null_mut();
                unsafe { fmi2DeSerializeFMUstate(h.c, b.as_ptr(), 5, &mut t) }
            })
        }),
        ("belongs to model `Probe`", {
            let b = buf.clone();
            Box::new(move |_| {
                let p = H::new(ModelEntry::new(pid::info, pid::create), false);
                let mut t = null_mut();
                let st = unsafe { fmi2DeSerializeFMUstate(p.c, b.as_ptr(), b.len(), &mut t) };
                assert!(p.last_error().contains("belongs to model `Probe`"));
                st
            })
        }),
    ];
    for (expected, call) in bad {
        let h3 = in_state(State::StepComplete);
        let mut own = null_mut();
        unsafe { fmi2GetFMUstate(h3.c, &mut own) };
        if expected == "too small" {
            // the handle `s` belongs to `h`, so use h itself
            assert_eq!(call(&h), fmi2Error);
            assert!(h.last_error().contains(expected));
            continue;
        }
        assert_eq!(call(&h3), fmi2Error, "{expected}");
        if !expected.starts_with("belongs") {
            let msg = h3.last_error();
            assert!(msg.contains(expected), "{expected}: {msg}");
        }
    }
    // free: sets the handle to NULL; a second free of the old value is refused
    let old = s;
    assert_eq!(unsafe { fmi2FreeFMUstate(h.c, &mut s) }, fmi2OK);
    assert!(s.is_null());
    let mut o = old;
    assert_eq!(unsafe { fmi2FreeFMUstate(h.c, &mut o) }, fmi2Error);
    let mut n = null_mut();
    let h4 = H::probe();
    assert_eq!(unsafe { fmi2FreeFMUstate(h4.c, &mut n) }, fmi2OK);
}

#[test]
fn reset_then_rerun_reproduces_the_first_run() {
    let h = H::probe();
    let run = |h: &H| {
        h.set_r(MASS, 3.0);
        h.init();
        let mut out = vec![];
        for k in 0..4 {
            h.set_r(FORCE, k as f64);
            h.step(0.25 * k as f64, 0.25);
            out.push(h.get_r(X).1.to_bits());
        }
        out
    };
    let first = run(&h);
    assert_eq!(unsafe { fmi2Reset(h.c) }, fmi2OK);
    assert_eq!(h.get_r(MASS).0, fmi2Error, "no getter in instantiated");
    assert_eq!(unsafe { fmi2Reset(h.c) }, fmi2OK);
    assert_eq!(run(&h), first);
}

#[test]
fn optional_functions_and_status_queries_explain_themselves() {
    let h = in_state(State::StepComplete);
    let mut st = 0;
    assert_eq!(
        unsafe { fmi2GetStatus(h.c, fmi2DoStepStatus, &mut st) },
        fmi2Discard
    );
    assert!(h.last_error().contains("fmi2DoStepStatus"));
    let mut i = 0;
    assert_eq!(
        unsafe { fmi2GetIntegerStatus(h.c, fmi2DoStepStatus, &mut i) },
        fmi2Discard
    );
    let mut sp: fmi2String = null();
    assert_eq!(
        unsafe { fmi2GetStringStatus(h.c, fmi2PendingStatus, &mut sp) },
        fmi2Discard
    );
    let mut r = 0.0;
    assert_eq!(unsafe { fmi2GetRealStatus(h.c, 99, &mut r) }, fmi2Discard);
    assert!(h.last_error().contains("unknown status kind 99"));
    assert_eq!(
        h.state(),
        State::StepComplete,
        "a discard leaves the state alone"
    );
    assert_eq!(
        unsafe { fmi2GetRealStatus(h.c, fmi2LastSuccessfulTime, null_mut()) },
        fmi2Error
    );
    for (name, call) in [
        (
            "fmi2GetDirectionalDerivative",
            (|h: &H| unsafe {
                fmi2GetDirectionalDerivative(h.c, null(), 0, null(), 0, null(), null_mut())
            }) as Call,
        ),
        ("fmi2SetRealInputDerivatives", |h| unsafe {
            fmi2SetRealInputDerivatives(h.c, null(), 0, null(), null())
        }),
        ("fmi2GetRealOutputDerivatives", |h| unsafe {
            fmi2GetRealOutputDerivatives(h.c, null(), 0, null(), null_mut())
        }),
        ("fmi2CancelStep", |h| unsafe { fmi2CancelStep(h.c) }),
    ] {
        let h = in_state(State::StepComplete);
        assert_eq!(call(&h), fmi2Error, "{name}");
        let msg = h.last_error();
        assert!(
            msg.starts_with(name) && (msg.contains("not supported") || msg.contains("no step")),
            "{msg}"
        );
    }
}

#[test]
fn null_instance_and_instantiate_refusals() {
    unsafe {
        assert_eq!(fmi2DoStep(null_mut(), 0.0, 0.1, 0), fmi2Error);
        assert_eq!(fmi2Reset(null_mut()), fmi2Error);
        fmi2FreeInstance(null_mut());
        let cb = fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: null_mut(),
        };
        let guid = CString::new(pid::info().guid).unwrap();
        let name = c"pid".as_ptr();
        let ok = fmi2Instantiate(name, fmi2CoSimulation, guid.as_ptr(), null(), &cb, 0, 0);
        assert!(!ok.is_null());
        fmi2FreeInstance(ok);
        assert!(
            fmi2Instantiate(name, fmi2ModelExchange, guid.as_ptr(), null(), &cb, 0, 0).is_null()
        );
        assert!(fmi2Instantiate(name, 7, guid.as_ptr(), null(), &cb, 0, 0).is_null());
        assert!(
            fmi2Instantiate(
                name,
                fmi2CoSimulation,
                c"{wrong}".as_ptr(),
                null(),
                &cb,
                0,
                0
            )
            .is_null()
        );
        assert!(fmi2Instantiate(name, fmi2CoSimulation, null(), null(), &cb, 0, 0).is_null());
        assert!(
            fmi2Instantiate(null(), fmi2CoSimulation, guid.as_ptr(), null(), &cb, 0, 0).is_null()
        );
        assert!(
            fmi2Instantiate(name, fmi2CoSimulation, guid.as_ptr(), null(), null(), 0, 0).is_null()
        );
        assert_eq!(
            std::ffi::CStr::from_ptr(fmi2GetVersion()).to_str().unwrap(),
            "2.0"
        );
        assert_eq!(
            std::ffi::CStr::from_ptr(fmi2GetTypesPlatform())
                .to_str()
                .unwrap(),
            "default"
        );
    }
}

#[test]
fn instances_move_between_threads() {
    let h = in_state(State::StepComplete);
    let c = h.c as usize;
    std::thread::spawn(move || {
        let c = c as fmi2Component;
        assert_eq!(unsafe { fmi2DoStep(c, 0.0, 0.1, 0) }, fmi2OK);
    })
    .join()
    .unwrap();
    assert_eq!(h.step(0.1, 0.1), fmi2OK);
}

#[test]
fn panel_lock_logs_solver_statistics_at_terminate() {
    use crate::scene::panel_lock;
    let h = H::new(ModelEntry::new(panel_lock::info, panel_lock::create), true);
    h.init();
    assert_eq!(h.step(0.0, 0.05), fmi2OK);
    let vr = panel_lock::ports::ivr::STEPS;
    let mut steps = -1;
    assert_eq!(unsafe { fmi2GetInteger(h.c, &vr, 1, &mut steps) }, fmi2OK);
    assert!(steps > 0, "{steps}");
    h.take_log();
    assert_eq!(unsafe { fmi2Terminate(h.c) }, fmi2OK);
    let log = h.take_log();
    let stats = log
        .iter()
        .find(|m| m.1 == Category::Solver && m.2.contains("solver statistics at fmi2Terminate"))
        .unwrap_or_else(|| panic!("no logSolver statistics in {log:?}"));
    assert!(
        stats.2.contains(&format!(": {steps} accepted steps, ")),
        "{}",
        stats.2
    );
    assert!(stats.2.contains("Newton iterations"), "{}", stats.2);
    // a model without an integrator promises none
    let h = H::new(ModelEntry::new(pid::info, pid::create), true);
    h.init();
    h.take_log();
    assert_eq!(unsafe { fmi2Terminate(h.c) }, fmi2OK);
    assert!(h.take_log().iter().all(|m| m.1 != Category::Solver));
}

/// The FMI 3.0 functions drive the same instance: typed value references, `time`, the step's
/// output flags, refusals with messages, and a panic that becomes `fmi3Fatal`.
#[test]
fn fmi3_functions_drive_the_same_instance() {
    use crate::fmi::exports3::*;
    use crate::fmi::types3::*;
    use crate::fmi::variables3::{TIME_VR, VR_BLOCK};
    let h = H::probe();
    let (mode, label, panic) = (VR_BLOCK, 3 * VR_BLOCK, 2 * VR_BLOCK + PANIC_NOW);
    let vals = [2.0, 3.0];
    assert_eq!(
        unsafe { fmi3SetFloat64(h.c, [MASS, FORCE].as_ptr(), 2, vals.as_ptr(), 2) },
        fmi3OK
    );
    assert_eq!(unsafe { fmi3SetInt64(h.c, &mode, 1, &2, 1) }, fmi3OK);
    let text = CString::new("hi").unwrap();
    let p = text.as_ptr();
    assert_eq!(unsafe { fmi3SetString(h.c, &label, 1, &p, 1) }, fmi3OK);
    assert_eq!(
        unsafe { fmi3EnterInitializationMode(h.c, 0, 0.0, 1.0, 1, 10.0) },
        fmi3OK
    );
    let mut t = f64::NAN;
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, &TIME_VR, 1, &mut t, 1) },
        fmi3OK
    );
    assert_eq!(t, 1.0, "time is the start time in initialization mode");
    assert_eq!(unsafe { fmi3ExitInitializationMode(h.c) }, fmi3OK);
    let (mut ev, mut term, mut early, mut last) = (9u8, 9u8, 9u8, f64::NAN);
    let step = |t0: f64, h0: f64, ev: &mut u8, term: &mut u8, early: &mut u8, last: &mut f64| unsafe {
        fmi3DoStep(h.c, t0, h0, 1, ev, term, early, last)
    };
    assert_eq!(
        step(1.0, 0.5, &mut ev, &mut term, &mut early, &mut last),
        fmi3OK
    );
    assert_eq!((ev, term, early, last), (0, 0, 0, 1.5));
    let mut out = [0.0; 2];
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, [X, TIME_VR].as_ptr(), 2, out.as_mut_ptr(), 2) },
        fmi3OK
    );
    assert_eq!(out, [7.5, 1.5]);
    let mut m = 0i64;
    assert_eq!(unsafe { fmi3GetInt64(h.c, &mode, 1, &mut m, 1) }, fmi3OK);
    assert_eq!(m, 2);
    let mut s: fmi3String = null();
    assert_eq!(unsafe { fmi3GetString(h.c, &label, 1, &mut s, 1) }, fmi3OK);
    assert_eq!(
        unsafe { std::ffi::CStr::from_ptr(s) }.to_str().unwrap(),
        "hi"
    );
    assert!(h.take_log().iter().all(|m| m.0 < fmi2Discard));

    // refusals: wrong family, unknown reference, mismatched lengths, an unused type
    let mut i = 0i32;
    assert_eq!(unsafe { fmi3GetInt32(h.c, &mode, 1, &mut i, 1) }, fmi3Error);
    let e = h.last_error();
    assert!(
        e.contains("fmi3GetInt32") && e.contains("Enumeration"),
        "{e}"
    );
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, &TIME_VR, 1, &mut t, 1) },
        fmi3Error
    );
    assert!(h.last_error().contains("illegal call sequence"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(unsafe { fmi3SetFloat64(h.c, &77, 1, &1.0, 1) }, fmi3Error);
    assert!(h.last_error().contains("unknown value reference 77"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(
        unsafe { fmi3SetFloat64(h.c, &TIME_VR, 1, &1.0, 1) },
        fmi3Error
    );
    assert!(h.last_error().contains("cannot be set"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(unsafe { fmi3SetFloat64(h.c, &MASS, 1, &1.0, 2) }, fmi3Error);
    assert!(h.last_error().contains("nValues = 2"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(
        unsafe { fmi3SetInt64(h.c, &mode, 1, &(1 << 40), 1) },
        fmi3Error
    );
    assert!(h.last_error().contains("enumeration items"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    let mut i8v = 0i8;
    assert_eq!(
        unsafe { fmi3GetInt8(h.c, null(), 0, &mut i8v, 0) },
        fmi3Error,
        "illegal in instantiated"
    );
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(unsafe { fmi3SetInt8(h.c, null(), 0, null(), 0) }, fmi3OK);
    assert_eq!(unsafe { fmi3SetInt8(h.c, &5, 1, &1, 1) }, fmi3Error);
    assert!(h.last_error().contains("no Int8 variables"));
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(unsafe { fmi3EnterEventMode(h.c) }, fmi3Error);
    assert!(h.last_error().contains("not supported"));

    // a panic in the model becomes fmi3Fatal, and only freeing is allowed then
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    assert_eq!(
        unsafe { fmi3EnterInitializationMode(h.c, 0, 0.0, 0.0, 0, 0.0) },
        fmi3OK
    );
    assert_eq!(unsafe { fmi3ExitInitializationMode(h.c) }, fmi3OK);
    assert_eq!(unsafe { fmi3SetBoolean(h.c, &panic, 1, &1, 1) }, fmi3OK);
    assert_eq!(
        step(0.0, 0.1, &mut ev, &mut term, &mut early, &mut last),
        fmi3Fatal
    );
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3Error);
}

/// An FMI 3.0 array (the probe's `arm0_x`..`arm2_x` as `arm_x`) reads its elements in order,
/// counts them in `nValues`, and refuses a wrong count, a folded member's old reference and
/// being set, each with a message; the instance works again after a reset.
#[test]
fn fmi3_array_variables_count_their_elements() {
    use crate::fmi::exports3::*;
    use crate::fmi::types3::*;
    use crate::fmi::variables3::TIME_VR;
    let h = H::probe();
    let vals = [2.0, 3.0];
    assert_eq!(
        unsafe { fmi3SetFloat64(h.c, [MASS, FORCE].as_ptr(), 2, vals.as_ptr(), 2) },
        fmi3OK
    );
    let init = || unsafe {
        assert_eq!(
            fmi3EnterInitializationMode(h.c, 0, 0.0, 0.0, 0, 0.0),
            fmi3OK
        );
        assert_eq!(fmi3ExitInitializationMode(h.c), fmi3OK);
    };
    init();
    let arm = ARM_X[0];
    let mut out = [f64::NAN; 5];
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, &arm, 1, out.as_mut_ptr(), 3) },
        fmi3OK
    );
    assert_eq!(out[..3], [6.0, 12.0, 18.0]);
    let vrs = [X, arm, TIME_VR];
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, vrs.as_ptr(), 3, out.as_mut_ptr(), 5) },
        fmi3OK
    );
    assert_eq!(out, [6.0, 6.0, 12.0, 18.0, 0.0]);
    assert!(h.take_log().iter().all(|m| m.0 < fmi2Discard));

    for n in [1, 4] {
        assert_eq!(
            unsafe { fmi3GetFloat64(h.c, &arm, 1, out.as_mut_ptr(), n) },
            fmi3Error
        );
        let e = h.last_error();
        assert!(
            e.contains(&format!("nValues = {n}")) && e.contains("`arm_x` (4) has 3"),
            "{e}"
        );
        assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
        init();
    }
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, &ARM_X[1], 1, out.as_mut_ptr(), 1) },
        fmi3Error
    );
    let e = h.last_error();
    assert!(
        e.contains("unknown value reference 5") && e.contains("element 1 of the array `arm_x`"),
        "{e}"
    );
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    init();
    let three = [1.0; 3];
    assert_eq!(
        unsafe { fmi3SetFloat64(h.c, &arm, 1, three.as_ptr(), 3) },
        fmi3Error
    );
    let e = h.last_error();
    assert!(e.contains("cannot be set") && e.contains("`arm_x`"), "{e}");
    assert_eq!(unsafe { fmi3Reset(h.c) }, fmi3OK);
    init();
    assert_eq!(
        unsafe { fmi3GetFloat64(h.c, &arm, 1, out.as_mut_ptr(), 3) },
        fmi3OK
    );
    assert_eq!(
        out[..3],
        [0.0, 0.0, 0.0],
        "mass and force back to their defaults"
    );
}

#[test]
fn one_step_request_check_per_do_step_for_every_model() {
    // the check of a step request runs once per fmi2DoStep, for the test model and every
    // registered one (a second check in a model's clock or the wrapper would count 2)
    let mut counted = Vec::new();
    let entries = std::iter::once(probe_entry()).chain(crate::scene::registry());
    for entry in entries {
        let name = (entry.info)().identifier;
        let h = H::new(entry, false);
        h.init();
        crate::scene::check_counter::take();
        assert_eq!(h.step(0.0, 0.01), fmi2OK, "{name}: {}", h.last_error());
        assert_eq!(h.step(0.01, 0.01), fmi2OK, "{name}: {}", h.last_error());
        assert_eq!(crate::scene::check_counter::take(), 2, "{name}: 2 steps");
        assert_eq!(h.step(0.5, 0.01), fmi2Error, "{name}");
        assert_eq!(
            crate::scene::check_counter::take(),
            1,
            "{name}: refused step"
        );
        counted.push(name);
    }
    assert!(counted.len() >= 4, "{counted:?}");
}

#[test]
fn one_step_request_check_per_direct_do_step() {
    // a model driven without the FMI layer (CLI, tests) checks through the trait's do_step
    let mut m = (probe_entry().create)();
    m.initialize(0.0).unwrap();
    crate::scene::check_counter::take();
    m.do_step(0.0, 0.01).unwrap();
    assert_eq!(crate::scene::check_counter::take(), 1);
    assert!(m.do_step(0.5, 0.01).is_err());
    assert_eq!(crate::scene::check_counter::take(), 1);
}
