//! A minimal FMI 2.0 / FMI 3.0 Co-Simulation importer, cross-compiled for every platform the
//! FMUs ship (x86_64 Linux, x86_64 Windows under wine, aarch64 Linux under qemu) so that
//! `tests/python/test_platforms.py` can run each FMU's shipped binary where it runs.
//!
//! It knows nothing of mbcosim: it loads the shared library of an unpacked FMU by dynamic
//! loading, calls the exported C functions only, and takes everything else from its arguments
//! (which the test reads from the packed `modelDescription.xml`):
//!
//! ```text
//! platform_importer <2|3> <library> <token> <resources> <start> <stop> <step> <vr,vr,...>
//! ```
//!
//! `resources` is passed unchanged (FMI 2.0: a `file:` URI; FMI 3.0: a path). It runs the
//! experiment with fixed steps; at the middle step it saves the state, serializes it to bytes
//! and frees it, runs to the end, then deserializes the bytes, restores them and runs the second
//! half again. Every value goes to stdout as the hex of its IEEE bits, so runs compare bit for
//! bit:
//!
//! ```text
//! run <k> <t> <v...>       communication point k of the run (t and values as f64 bit patterns)
//! saved <k> <bytes>        the state serialized at point k: its size
//! end run <bytes> <fnv>    the final state serialized: size and FNV-1a 64 hash
//! replay <k> <t> <v...>    point k of the second half, after the deserialized state was restored
//! end replay <bytes> <fnv>
//! ```
//!
//! Then it terminates and frees the instance. Exit status 0 only when every call returned OK (or
//! Warning); otherwise the failing call is named on stderr. The FMU's own messages go to its
//! stderr sink (the logger is NULL).

use std::ffi::{CString, c_char, c_void};
use std::process::ExitCode;

use libloading::Library;

/// `fmi2Status` / `fmi3Status`: 0 OK, 1 Warning, anything else a failure.
type Status = u32;
type Handle = *mut c_void;

/// What the run needs from an instance, whichever FMI version it speaks.
trait Slave {
    /// The values of `vrs` (Real / Float64).
    fn get(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), String>;
    /// One communication step from `t` of length `h`.
    fn step(&self, t: f64, h: f64) -> Result<(), String>;
    /// The current state, saved and serialized (the saved state is freed again).
    fn save(&self) -> Result<Vec<u8>, String>;
    /// The state `bytes` deserialized and restored (the deserialized state is freed again).
    fn restore(&self, bytes: &[u8]) -> Result<(), String>;
    /// Terminates the instance and frees it.
    fn finish(&self) -> Result<(), String>;
}

/// Fails with the function's name unless `s` is OK or Warning.
fn check(what: &str, s: Status) -> Result<(), String> {
    if s <= 1 {
        Ok(())
    } else {
        Err(format!("{what} returned status {s}"))
    }
}

/// The exported function `name` of `lib` as a function pointer of type `T`.
fn symbol<T: Copy>(lib: &Library, name: &str) -> Result<T, String> {
    // SAFETY: T is the function type FMI declares for `name`; the pointer is only used while
    // `lib` stays loaded (it lives as long as the instance that holds the pointer).
    unsafe { lib.get::<T>(name.as_bytes()) }
        .map(|s| *s)
        .map_err(|e| format!("{name}: {e}"))
}

/// FMI 2.0's `fmi2CallbackFunctions`, all NULL (the FMU logs to stderr and allocates itself).
#[repr(C)]
struct Callbacks2 {
    logger: *const c_void,
    allocate_memory: *const c_void,
    free_memory: *const c_void,
    step_finished: *const c_void,
    component_environment: *mut c_void,
}

/// An FMI 2.0 Co-Simulation instance and the functions it is driven by.
struct Fmi2 {
    c: Handle,
    get_real: unsafe extern "C" fn(Handle, *const u32, usize, *mut f64) -> Status,
    do_step: unsafe extern "C" fn(Handle, f64, f64, i32) -> Status,
    get_state: unsafe extern "C" fn(Handle, *mut Handle) -> Status,
    set_state: unsafe extern "C" fn(Handle, Handle) -> Status,
    free_state: unsafe extern "C" fn(Handle, *mut Handle) -> Status,
    size: unsafe extern "C" fn(Handle, Handle, *mut usize) -> Status,
    serialize: unsafe extern "C" fn(Handle, Handle, *mut u8, usize) -> Status,
    deserialize: unsafe extern "C" fn(Handle, *const u8, usize, *mut Handle) -> Status,
    terminate: unsafe extern "C" fn(Handle) -> Status,
    free_instance: unsafe extern "C" fn(Handle),
}

impl Fmi2 {
    /// Instantiates, sets up and initializes the experiment `[start, stop]`.
    fn start(
        lib: &Library,
        token: &str,
        resources: &str,
        start: f64,
        stop: f64,
    ) -> Result<Self, String> {
        type Instantiate = unsafe extern "C" fn(
            *const c_char,
            i32,
            *const c_char,
            *const c_char,
            *const Callbacks2,
            i32,
            i32,
        ) -> Handle;
        let instantiate: Instantiate = symbol(lib, "fmi2Instantiate")?;
        let setup: unsafe extern "C" fn(Handle, i32, f64, f64, i32, f64) -> Status =
            symbol(lib, "fmi2SetupExperiment")?;
        let enter: unsafe extern "C" fn(Handle) -> Status =
            symbol(lib, "fmi2EnterInitializationMode")?;
        let exit: unsafe extern "C" fn(Handle) -> Status =
            symbol(lib, "fmi2ExitInitializationMode")?;
        let callbacks = Callbacks2 {
            logger: std::ptr::null(),
            allocate_memory: std::ptr::null(),
            free_memory: std::ptr::null(),
            step_finished: std::ptr::null(),
            component_environment: std::ptr::null_mut(),
        };
        let (name, token, resources) = (cstring("importer")?, cstring(token)?, cstring(resources)?);
        // SAFETY: NUL-terminated strings and a callback struct that outlive the call; the FMU
        // copies what it keeps. fmi2CoSimulation = 1, visible = loggingOn = false.
        let c = unsafe {
            instantiate(
                name.as_ptr(),
                1,
                token.as_ptr(),
                resources.as_ptr(),
                &callbacks,
                0,
                0,
            )
        };
        if c.is_null() {
            return Err("fmi2Instantiate returned NULL".into());
        }
        let me = Fmi2 {
            c,
            get_real: symbol(lib, "fmi2GetReal")?,
            do_step: symbol(lib, "fmi2DoStep")?,
            get_state: symbol(lib, "fmi2GetFMUstate")?,
            set_state: symbol(lib, "fmi2SetFMUstate")?,
            free_state: symbol(lib, "fmi2FreeFMUstate")?,
            size: symbol(lib, "fmi2SerializedFMUstateSize")?,
            serialize: symbol(lib, "fmi2SerializeFMUstate")?,
            deserialize: symbol(lib, "fmi2DeSerializeFMUstate")?,
            terminate: symbol(lib, "fmi2Terminate")?,
            free_instance: symbol(lib, "fmi2FreeInstance")?,
        };
        // SAFETY: `c` is the live instance just created.
        unsafe {
            check("fmi2SetupExperiment", setup(c, 0, 0.0, start, 1, stop))?;
            check("fmi2EnterInitializationMode", enter(c))?;
            check("fmi2ExitInitializationMode", exit(c))?;
        }
        Ok(me)
    }
}

impl Slave for Fmi2 {
    fn get(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        // SAFETY: both buffers hold vrs.len() elements.
        check("fmi2GetReal", unsafe {
            (self.get_real)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        })
    }

    fn step(&self, t: f64, h: f64) -> Result<(), String> {
        // SAFETY: live instance.
        check("fmi2DoStep", unsafe { (self.do_step)(self.c, t, h, 0) })
    }

    fn save(&self) -> Result<Vec<u8>, String> {
        let mut state: Handle = std::ptr::null_mut();
        let mut n = 0usize;
        // SAFETY: live instance; `state` is the FMU's own handle, freed below; the buffer holds
        // the size the FMU reported.
        unsafe {
            check("fmi2GetFMUstate", (self.get_state)(self.c, &mut state))?;
            check(
                "fmi2SerializedFMUstateSize",
                (self.size)(self.c, state, &mut n),
            )?;
            let mut bytes = vec![0u8; n];
            check(
                "fmi2SerializeFMUstate",
                (self.serialize)(self.c, state, bytes.as_mut_ptr(), n),
            )?;
            check("fmi2FreeFMUstate", (self.free_state)(self.c, &mut state))?;
            Ok(bytes)
        }
    }

    fn restore(&self, bytes: &[u8]) -> Result<(), String> {
        let mut state: Handle = std::ptr::null_mut();
        // SAFETY: live instance; `bytes` is what fmi2SerializeFMUstate wrote; the state the FMU
        // allocates is freed after use.
        unsafe {
            check(
                "fmi2DeSerializeFMUstate",
                (self.deserialize)(self.c, bytes.as_ptr(), bytes.len(), &mut state),
            )?;
            check("fmi2SetFMUstate", (self.set_state)(self.c, state))?;
            check("fmi2FreeFMUstate", (self.free_state)(self.c, &mut state))
        }
    }

    fn finish(&self) -> Result<(), String> {
        // SAFETY: live instance, not used after it is freed (the run ends here).
        unsafe {
            check("fmi2Terminate", (self.terminate)(self.c))?;
            (self.free_instance)(self.c);
        }
        Ok(())
    }
}

/// An FMI 3.0 Co-Simulation instance and the functions it is driven by.
struct Fmi3 {
    c: Handle,
    get_float64: unsafe extern "C" fn(Handle, *const u32, usize, *mut f64, usize) -> Status,
    #[allow(clippy::type_complexity)]
    do_step: unsafe extern "C" fn(
        Handle,
        f64,
        f64,
        bool,
        *mut bool,
        *mut bool,
        *mut bool,
        *mut f64,
    ) -> Status,
    get_state: unsafe extern "C" fn(Handle, *mut Handle) -> Status,
    set_state: unsafe extern "C" fn(Handle, Handle) -> Status,
    free_state: unsafe extern "C" fn(Handle, *mut Handle) -> Status,
    size: unsafe extern "C" fn(Handle, Handle, *mut usize) -> Status,
    serialize: unsafe extern "C" fn(Handle, Handle, *mut u8, usize) -> Status,
    deserialize: unsafe extern "C" fn(Handle, *const u8, usize, *mut Handle) -> Status,
    terminate: unsafe extern "C" fn(Handle) -> Status,
    free_instance: unsafe extern "C" fn(Handle),
}

impl Fmi3 {
    /// Instantiates and initializes the experiment `[start, stop]`.
    fn start(
        lib: &Library,
        token: &str,
        resources: &str,
        start: f64,
        stop: f64,
    ) -> Result<Self, String> {
        type Instantiate = unsafe extern "C" fn(
            *const c_char,
            *const c_char,
            *const c_char,
            bool,
            bool,
            bool,
            bool,
            *const u32,
            usize,
            *mut c_void,
            *const c_void,
            *const c_void,
        ) -> Handle;
        let instantiate: Instantiate = symbol(lib, "fmi3InstantiateCoSimulation")?;
        let enter: unsafe extern "C" fn(Handle, bool, f64, f64, bool, f64) -> Status =
            symbol(lib, "fmi3EnterInitializationMode")?;
        let exit: unsafe extern "C" fn(Handle) -> Status =
            symbol(lib, "fmi3ExitInitializationMode")?;
        let (name, token, resources) = (cstring("importer")?, cstring(token)?, cstring(resources)?);
        // SAFETY: NUL-terminated strings that outlive the call; no intermediate variables, no
        // callbacks (NULL logger and intermediate update).
        let c = unsafe {
            instantiate(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                std::ptr::null_mut(),
                std::ptr::null(),
                std::ptr::null(),
            )
        };
        if c.is_null() {
            return Err("fmi3InstantiateCoSimulation returned NULL".into());
        }
        let me = Fmi3 {
            c,
            get_float64: symbol(lib, "fmi3GetFloat64")?,
            do_step: symbol(lib, "fmi3DoStep")?,
            get_state: symbol(lib, "fmi3GetFMUState")?,
            set_state: symbol(lib, "fmi3SetFMUState")?,
            free_state: symbol(lib, "fmi3FreeFMUState")?,
            size: symbol(lib, "fmi3SerializedFMUStateSize")?,
            serialize: symbol(lib, "fmi3SerializeFMUState")?,
            deserialize: symbol(lib, "fmi3DeserializeFMUState")?,
            terminate: symbol(lib, "fmi3Terminate")?,
            free_instance: symbol(lib, "fmi3FreeInstance")?,
        };
        // SAFETY: `c` is the live instance just created.
        unsafe {
            check(
                "fmi3EnterInitializationMode",
                enter(c, false, 0.0, start, true, stop),
            )?;
            check("fmi3ExitInitializationMode", exit(c))?;
        }
        Ok(me)
    }
}

impl Slave for Fmi3 {
    fn get(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        // SAFETY: both buffers hold vrs.len() elements (scalars).
        check("fmi3GetFloat64", unsafe {
            (self.get_float64)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len())
        })
    }

    fn step(&self, t: f64, h: f64) -> Result<(), String> {
        let (mut event, mut terminate, mut early) = (false, false, false);
        let mut last = 0.0;
        // SAFETY: live instance; the out-pointers are valid locals.
        check("fmi3DoStep", unsafe {
            (self.do_step)(
                self.c,
                t,
                h,
                false,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        })?;
        if terminate || early {
            return Err(format!(
                "fmi3DoStep at t = {t}: terminate = {terminate}, early return = {early}"
            ));
        }
        Ok(())
    }

    fn save(&self) -> Result<Vec<u8>, String> {
        let mut state: Handle = std::ptr::null_mut();
        let mut n = 0usize;
        // SAFETY: as for FMI 2.0.
        unsafe {
            check("fmi3GetFMUState", (self.get_state)(self.c, &mut state))?;
            check(
                "fmi3SerializedFMUStateSize",
                (self.size)(self.c, state, &mut n),
            )?;
            let mut bytes = vec![0u8; n];
            check(
                "fmi3SerializeFMUState",
                (self.serialize)(self.c, state, bytes.as_mut_ptr(), n),
            )?;
            check("fmi3FreeFMUState", (self.free_state)(self.c, &mut state))?;
            Ok(bytes)
        }
    }

    fn restore(&self, bytes: &[u8]) -> Result<(), String> {
        let mut state: Handle = std::ptr::null_mut();
        // SAFETY: as for FMI 2.0.
        unsafe {
            check(
                "fmi3DeserializeFMUState",
                (self.deserialize)(self.c, bytes.as_ptr(), bytes.len(), &mut state),
            )?;
            check("fmi3SetFMUState", (self.set_state)(self.c, state))?;
            check("fmi3FreeFMUState", (self.free_state)(self.c, &mut state))
        }
    }

    fn finish(&self) -> Result<(), String> {
        // SAFETY: live instance, not used after it is freed (the run ends here).
        unsafe {
            check("fmi3Terminate", (self.terminate)(self.c))?;
            (self.free_instance)(self.c);
        }
        Ok(())
    }
}

fn cstring(s: &str) -> Result<CString, String> {
    CString::new(s).map_err(|_| format!("argument {s:?} holds a NUL character"))
}

/// FNV-1a 64 of `bytes` (to name a serialized state in one short field).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// One output line: `tag k t v...` with every f64 as the hex of its bits.
fn point(tag: &str, k: usize, t: f64, values: &[f64]) {
    let mut line = format!("{tag} {k} {:016x}", t.to_bits());
    for v in values {
        line.push_str(&format!(" {:016x}", v.to_bits()));
    }
    println!("{line}");
}

/// Runs points `from..=n` (stepping from each but the last), printing each under `tag`.
fn run_points(
    slave: &dyn Slave,
    tag: &str,
    vrs: &[u32],
    (start, step): (f64, f64),
    from: usize,
    n: usize,
    mut at: impl FnMut(usize) -> Result<(), String>,
) -> Result<(), String> {
    let mut values = vec![0.0; vrs.len()];
    for k in from..=n {
        let t = start + k as f64 * step;
        slave.get(vrs, &mut values)?;
        point(tag, k, t, &values);
        at(k)?;
        if k < n {
            slave.step(t, step)?;
        }
    }
    Ok(())
}

/// The experiment with a state saved, serialized and restored at its middle point.
fn experiment(
    slave: &dyn Slave,
    vrs: &[u32],
    start: f64,
    stop: f64,
    step: f64,
) -> Result<(), String> {
    let n = ((stop - start) / step).round() as usize;
    let mid = n / 2;
    let mut saved = None;
    run_points(slave, "run", vrs, (start, step), 0, n, |k| {
        if k == mid {
            let bytes = slave.save()?;
            println!("saved {k} {}", bytes.len());
            saved = Some(bytes);
        }
        Ok(())
    })?;
    let end = slave.save()?;
    println!("end run {} {:016x}", end.len(), fnv1a(&end));
    let saved = saved.ok_or("no state saved")?;
    slave.restore(&saved)?;
    run_points(slave, "replay", vrs, (start, step), mid, n, |_| Ok(()))?;
    let end = slave.save()?;
    println!("end replay {} {:016x}", end.len(), fnv1a(&end));
    slave.finish()
}

fn number(what: &str, s: &str) -> Result<f64, String> {
    s.parse().map_err(|e| format!("{what} {s:?}: {e}"))
}

fn main_inner(args: &[String]) -> Result<(), String> {
    let [version, library, token, resources, start, stop, step, vrs] = args else {
        return Err(
            "usage: platform_importer <2|3> <library> <token> <resources> <start> <stop> <step> <vr,vr,...>"
                .into(),
        );
    };
    let (start, stop, step) = (
        number("start", start)?,
        number("stop", stop)?,
        number("step", step)?,
    );
    let vrs = vrs
        .split(',')
        .map(|v| {
            v.parse::<u32>()
                .map_err(|e| format!("value reference {v:?}: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // SAFETY: loading the FMU's library runs its initializers; that is what an importer does.
    let lib = unsafe { Library::new(library) }.map_err(|e| format!("loading {library}: {e}"))?;
    match version.as_str() {
        "2" => experiment(
            &Fmi2::start(&lib, token, resources, start, stop)?,
            &vrs,
            start,
            stop,
            step,
        ),
        "3" => experiment(
            &Fmi3::start(&lib, token, resources, start, stop)?,
            &vrs,
            start,
            stop,
            step,
        ),
        v => Err(format!("FMI version {v:?}: 2 or 3")),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match main_inner(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("platform_importer: {e}");
            ExitCode::FAILURE
        }
    }
}
