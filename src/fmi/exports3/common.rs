//! Life cycle: version, instantiation, logging control, initialization, termination, reset.

use std::os::raw::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr::null_mut;

use crate::fmi::boundary::{c_str, guard, in_slice, panic_message};
use crate::fmi::exports::{create, free_instance, set_debug_logging};
use crate::fmi::intermediate::ImporterOptions;
use crate::fmi::logger::{Category, Logger};
use crate::fmi::machine::{ALIVE, INIT_MODE, INSTANTIATED, TERMINATE};
use crate::fmi::resource_location::resource_folder3;
use crate::fmi::types::{fmi2Error, fmi2Warning};
use crate::fmi::types3::*;

/// Returns `"3.0"`.
///
/// # Safety
/// None: a static string, callable at any time.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetVersion() -> *const c_char {
    VERSION3.as_ptr()
}

/// Switches debug logging on or off, for all or the named categories.
///
/// # Safety
/// `instance` NULL or a live handle; `categories` NULL or `nCategories` valid C strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    unsafe {
        set_debug_logging(
            "fmi3SetDebugLogging",
            instance,
            loggingOn != 0,
            nCategories,
            categories,
        )
    }
}

/// Creates a Co-Simulation instance of the model whose GUID is `instantiationToken`; NULL (with
/// the reason logged) for an unknown token or missing arguments. Event mode is not provided
/// (`eventModeUsed` is accepted with a warning and has no effect); `earlyReturnAllowed` and the
/// intermediate-update callback are kept for `fmi3DoStep` ([`crate::fmi::intermediate`]);
/// required intermediate variables are never offered (a warning says so).
///
/// # Safety
/// Pointers must be NULL or valid per FMI 3.0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let run = AssertUnwindSafe(|| unsafe {
        let name = c_str(instanceName, "instanceName");
        let logger = Logger::new3(
            logMessage,
            instanceEnvironment,
            name.as_ref().map_or("(unnamed)", |s| s),
            loggingOn != 0,
        );
        const F: &str = "fmi3InstantiateCoSimulation";
        let fail = |reason: String| {
            logger.log(
                fmi2Error,
                Category::StatusError,
                &format!("{F}: {reason}; instance not created"),
            );
            null_mut()
        };
        if let Err(e) = name {
            return fail(e);
        }
        let token = match c_str(instantiationToken, "instantiationToken") {
            Ok(t) => t,
            Err(e) => return fail(e),
        };
        for (on, what) in [
            (
                eventModeUsed != 0,
                "eventModeUsed = true: hasEventMode=\"false\", so the instance never enters event mode",
            ),
            (
                nRequiredIntermediateVariables > 0,
                "requiredIntermediateVariables given: providesIntermediateUpdate=\"false\", so they are never offered",
            ),
        ] {
            if on {
                logger.log(
                    fmi2Warning,
                    Category::StatusWarning,
                    &format!("{F}: {what}"),
                );
            }
        }
        let folder = resource_folder3(
            (!resourcePath.is_null()).then(|| c_str(resourcePath, "resourcePath")),
        );
        let importer = ImporterOptions {
            early_return: earlyReturnAllowed != 0,
            callback: intermediateUpdate,
            environment: instanceEnvironment as usize,
        };
        create(F, "instantiationToken", logger, token, folder, importer)
    });
    catch_unwind(run).unwrap_or_else(|p| {
        eprintln!(
            "mbcosim: fmi3InstantiateCoSimulation: internal error: {}",
            panic_message(p.as_ref())
        );
        null_mut()
    })
}

/// Model Exchange is not provided: NULL, with the reason logged.
///
/// # Safety
/// Pointers must be NULL or valid per FMI 3.0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    unsafe {
        refuse_interface(
            instanceName,
            instanceEnvironment,
            logMessage,
            "Model Exchange",
        )
    }
}

/// Scheduled Execution is not provided: NULL, with the reason logged.
///
/// # Safety
/// Pointers must be NULL or valid per FMI 3.0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _clockUpdate: fmi3ClockUpdateCallback,
    _lockPreemption: fmi3LockPreemptionCallback,
    _unlockPreemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    unsafe {
        refuse_interface(
            instanceName,
            instanceEnvironment,
            logMessage,
            "Scheduled Execution",
        )
    }
}

unsafe fn refuse_interface(
    name: fmi3String,
    env: fmi3InstanceEnvironment,
    log: fmi3LogMessageCallback,
    kind: &str,
) -> fmi3Instance {
    let run = AssertUnwindSafe(|| {
        let name = unsafe { c_str(name, "instanceName") }.unwrap_or("(unnamed)");
        Logger::new3(log, env, name, true).log(
            fmi2Error,
            Category::StatusError,
            &format!(
                "fmi3Instantiate{}: {kind} is not provided, only Co-Simulation (fmi3InstantiateCoSimulation); instance not created",
                kind.replace(' ', "")
            ),
        );
    });
    if catch_unwind(run).is_err() {
        eprintln!("mbcosim: {kind} instantiation refused");
    }
    null_mut()
}

/// Frees the instance and every FMU state it owns; NULL is ignored.
///
/// # Safety
/// `instance` must be NULL or a live handle; it is invalid afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    unsafe { free_instance(instance, "fmi3FreeInstance") }
}

/// Records tolerance, start and stop time [s] and enters initialization mode.
///
/// # Safety
/// `instance` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    toleranceDefined: fmi3Boolean,
    tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    let tol = (toleranceDefined != 0).then_some(tolerance);
    let stop = (stopTimeDefined != 0).then_some(stopTime);
    unsafe {
        guard(instance, "fmi3EnterInitializationMode", INSTANTIATED, |i| {
            i.enter_initialization_mode3(tol, startTime, stop)
        })
    }
}

/// Initializes the model at the start time and enters step mode.
///
/// # Safety
/// `instance` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    unsafe {
        guard(instance, "fmi3ExitInitializationMode", INIT_MODE, |i| {
            i.exit_initialization_mode()
        })
    }
}

/// Ends the simulation; values stay readable.
///
/// # Safety
/// `instance` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    unsafe { guard(instance, "fmi3Terminate", TERMINATE, |i| i.terminate()) }
}

/// Back to `instantiated` with default parameters.
///
/// # Safety
/// `instance` NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    unsafe { guard(instance, "fmi3Reset", ALIVE, |i| i.reset()) }
}

/// The value references of a call, as a slice.
///
/// # Safety
/// As for [`in_slice`].
pub(super) unsafe fn refs<'a>(
    vr: *const fmi3ValueReference,
    n: usize,
) -> Result<&'a [fmi3ValueReference], String> {
    unsafe { in_slice(vr, n, "valueReferences[]") }
}
