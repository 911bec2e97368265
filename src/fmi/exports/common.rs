//! Life cycle: platform queries, instantiation, logging control, initialization, reset.

use std::os::raw::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr::null_mut;

use crate::fmi::boundary::{c_str, guard, in_slice, panic_message};
use crate::fmi::handle;
use crate::fmi::instance::Instance;
use crate::fmi::intermediate::ImporterOptions;
use crate::fmi::logger::{CATEGORIES, Category, Logger};
use crate::fmi::machine::{ALIVE, INIT_MODE, INSTANTIATED, TERMINATE};
use crate::fmi::resource_location::{Location, resource_folder};
use crate::fmi::types::*;
use crate::scene;

/// Returns `"default"`: the standard FMI 2.0 type definitions.
///
/// # Safety
/// None: a static string, callable at any time.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    TYPES_PLATFORM.as_ptr()
}

/// Returns `"2.0"`.
///
/// # Safety
/// None: a static string, callable at any time.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetVersion() -> *const c_char {
    VERSION.as_ptr()
}

/// Creates an instance of the model with GUID `fmuGUID`; NULL (with the reason logged) for an
/// unknown GUID, a Model-Exchange request, or missing arguments.
///
/// # Safety
/// Pointers must be NULL or valid C strings / a valid callback struct, per FMI 2.0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let run = AssertUnwindSafe(|| unsafe {
        instantiate(
            instanceName,
            fmuType,
            fmuGUID,
            fmuResourceLocation,
            functions,
            loggingOn,
        )
    });
    catch_unwind(run).unwrap_or_else(|p| {
        eprintln!(
            "mbcosim: fmi2Instantiate: internal error: {}",
            panic_message(p.as_ref())
        );
        null_mut()
    })
}

unsafe fn instantiate(
    name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    if functions.is_null() {
        eprintln!(
            "mbcosim: fmi2Instantiate: functions (the callback struct) is NULL; instance not created"
        );
        return null_mut();
    }
    // SAFETY: non-NULL and, per FMI 2.0, a valid fmi2CallbackFunctions; copied once.
    let callbacks = unsafe { *functions };
    let name = unsafe { c_str(name, "instanceName") };
    let logger = Logger::new(
        callbacks.logger,
        callbacks.componentEnvironment,
        name.as_ref().map_or("(unnamed)", |s| s),
        logging_on != 0,
    );
    let fail = |reason: String| {
        logger.log(
            fmi2Error,
            Category::StatusError,
            &format!("fmi2Instantiate: {reason}; instance not created"),
        );
        null_mut()
    };
    if let Err(e) = name {
        return fail(e);
    }
    if fmu_type != fmi2CoSimulation {
        let kind = if fmu_type == fmi2ModelExchange {
            "Model Exchange"
        } else {
            "an unknown interface type"
        };
        return fail(format!(
            "fmuType = {fmu_type} requests {kind}; only Co-Simulation (1) is provided"
        ));
    }
    let guid = match unsafe { c_str(guid, "fmuGUID") } {
        Ok(g) => g,
        Err(e) => return fail(e),
    };
    let folder = resource_folder(
        (!resource_location.is_null())
            .then(|| unsafe { c_str(resource_location, "fmuResourceLocation") }),
    );
    create(
        "fmi2Instantiate",
        "GUID",
        logger,
        guid,
        folder,
        ImporterOptions::default(),
    )
}

/// The instance of the model whose GUID is `guid`, with its logger, resources folder and the
/// importer's FMI 3.0 options, or NULL with the reason logged. Shared by `fmi2Instantiate` and
/// `fmi3InstantiateCoSimulation`: `func` names the caller in messages, `token` the GUID argument.
pub(crate) fn create(
    func: &str,
    token: &str,
    logger: Logger,
    guid: &str,
    folder: Result<Location, String>,
    importer: ImporterOptions,
) -> fmi2Component {
    let Some(entry) = scene::find_by_guid(guid) else {
        let known: Vec<String> = scene::registry()
            .iter()
            .map(|e| format!("{} {}", (e.info)().identifier, (e.info)().guid))
            .collect();
        logger.log(
            fmi2Error,
            Category::StatusError,
            &format!(
                "{func}: unknown {token} `{}`: the modelDescription.xml does not match this binary (known: {}); instance not created",
                guid.escape_debug(),
                known.join(", ")
            ),
        );
        return null_mut();
    };
    let mut inst = Instance::new(&entry, logger);
    let dir = match folder {
        Ok(Location::Folder(dir, note)) => {
            if let Some(note) = note {
                inst.log.log(
                    fmi2Warning,
                    Category::StatusWarning,
                    &format!("{func}: {note}"),
                );
            }
            Some(dir)
        }
        Ok(Location::Absent(reason)) if entry.resources.is_empty() => {
            inst.log.log(
                fmi2Warning,
                Category::StatusWarning,
                &format!(
                    "{func}: {reason}; the FMU's scene.toml is not read, the model starts from its built-in defaults"
                ),
            );
            None
        }
        Ok(Location::Absent(reason)) => {
            inst.log.log(
                fmi2Error,
                Category::StatusError,
                &format!(
                    "{func}: {reason}; model `{}` needs its resources folder (its data files); instance not created",
                    (entry.info)().identifier
                ),
            );
            return null_mut();
        }
        Err(reason) => {
            inst.log.log(
                fmi2Error,
                Category::StatusError,
                &format!(
                    "{func}: {reason}; the FMU's resources (its scene.toml) cannot be read from there, so the instance is not created rather than run with other parameters (pass the file: URI of the unpacked FMU's resources folder, or NULL for the built-in defaults)"
                ),
            );
            return null_mut();
        }
    };
    if let Err(reason) = inst.attach_resources(&entry, dir.as_deref()) {
        inst.log.log(
            fmi2Error,
            Category::StatusError,
            &format!("{func}: {reason}; instance not created"),
        );
        return null_mut();
    }
    inst.importer = importer;
    handle::into_component(inst)
}

/// Frees the instance and every FMU state it owns; NULL is ignored, and so (with a message) are
/// a handle already freed, a pointer that is not an instance, and a call from inside one of the
/// instance's own callbacks ([`handle::free`]).
///
/// # Safety
/// `c` must be NULL or a handle from `fmi2Instantiate`; it is invalid afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    unsafe { free_instance(c, "fmi2FreeInstance") }
}

/// The body of `fmi2FreeInstance` and `fmi3FreeInstance` (`func`).
///
/// # Safety
/// As for `fmi2FreeInstance`.
pub(crate) unsafe fn free_instance(c: fmi2Component, func: &'static str) {
    let res = catch_unwind(AssertUnwindSafe(|| unsafe { handle::free(c, func) }));
    if let Err(p) = res {
        eprintln!(
            "mbcosim: {func}: internal error: {}",
            panic_message(p.as_ref())
        );
    }
}

/// Switches debug logging on or off, for all or the named categories.
///
/// # Safety
/// `c` as for every function; `categories` NULL or `nCategories` valid C strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        set_debug_logging(
            "fmi2SetDebugLogging",
            c,
            loggingOn != 0,
            nCategories,
            categories,
        )
    }
}

/// The body of `fmi2SetDebugLogging` and `fmi3SetDebugLogging` (`func`).
///
/// # Safety
/// As for `fmi2SetDebugLogging`.
pub(crate) unsafe fn set_debug_logging(
    func: &'static str,
    c: fmi2Component,
    on: bool,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        guard(c, func, ALIVE, |inst| {
            let names = in_slice(categories, nCategories, "categories[]")?;
            let mut parsed = Vec::with_capacity(names.len());
            for (k, p) in names.iter().enumerate() {
                let name = c_str(*p, &format!("categories[{k}]"))?;
                let cat = Category::from_name(name.as_bytes()).ok_or_else(|| {
                    let known: Vec<_> = CATEGORIES
                        .iter()
                        .map(|(_, n, _)| n.to_string_lossy())
                        .collect();
                    format!(
                        "unknown log category `{}` (known: {})",
                        name.escape_debug(),
                        known.join(", ")
                    )
                })?;
                parsed.push(cat);
            }
            inst.log.set_debug_logging(on, &parsed);
            Ok(fmi2OK)
        })
    }
}

/// Records tolerance, start and stop time [s].
///
/// # Safety
/// `c` must be NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    let tol = (toleranceDefined != 0).then_some(tolerance);
    let stop = (stopTimeDefined != 0).then_some(stopTime);
    unsafe {
        guard(c, "fmi2SetupExperiment", INSTANTIATED, |i| {
            i.setup_experiment(tol, startTime, stop)
        })
    }
}

/// Enters initialization mode.
///
/// # Safety
/// `c` must be NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        guard(c, "fmi2EnterInitializationMode", INSTANTIATED, |i| {
            i.enter_initialization_mode()
        })
    }
}

/// Initializes the model at the start time and enters `stepComplete`.
///
/// # Safety
/// `c` must be NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        guard(c, "fmi2ExitInitializationMode", INIT_MODE, |i| {
            i.exit_initialization_mode()
        })
    }
}

/// Ends the simulation; values stay readable.
///
/// # Safety
/// `c` must be NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    unsafe { guard(c, "fmi2Terminate", TERMINATE, |i| i.terminate()) }
}

/// Back to `instantiated` with default parameters.
///
/// # Safety
/// `c` must be NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    unsafe { guard(c, "fmi2Reset", ALIVE, |i| i.reset()) }
}
