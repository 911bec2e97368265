//! One FMU instance in safe Rust: the model, the state machine, the FMU states.
//!
//! Every exported function runs its body between [`Instance::admit`], which checks the state
//! mask, and [`Instance::settle`], which turns an `Err(reason)` into `fmi2Error` with the reason
//! logged, forwards the model's own messages, escalates the status to the worst one seen, and moves the instance to the `error`
//! state whenever the result is `fmi2Error` or worse. The bodies below never see raw pointers.

use std::collections::HashMap;
use std::ffi::CString;
use std::os::raw::{c_char, c_int};
use std::path::Path;

use super::intermediate::{ImporterOptions, ImporterWatch};
use super::logger::{Category, Logger, to_cstring};
use super::machine::{Machine, Mask, State, past_initialization};
use super::snapshot::{self, Snapshot};
use super::types::*;
use crate::scene::port::{BaseType, Causality, ModelInfo, PortSpec, ValueRef};
use crate::scene::store::{PortIndex, check_integer, check_real, check_writable};
use crate::scene::watch::{StepEnd, StepWatch};
use crate::scene::{CoSimModel, LogLevel, ModelEntry, TIME_RTOL, scene_file};

/// Result of a function body: the status to return, or the reason for an `fmi2Error`.
pub type Outcome<T = fmi2Status> = Result<T, String>;

/// An FMU instance (what an `fmi2Component` points to).
pub struct Instance {
    /// The importer's logger and the debug-logging filters.
    pub log: Logger,
    info: &'static ModelInfo,
    create: fn() -> Box<dyn CoSimModel>,
    model: Box<dyn CoSimModel>,
    /// Initialized copy of the model answering getters in initialization mode.
    preview: Option<Box<dyn CoSimModel>>,
    machine: Machine,
    index: PortIndex,
    /// The FMI 3.0 variables (arrays folded), built at the first FMI 3.0 access.
    view3: std::cell::OnceCell<Result<super::arrays3::View3, String>>,
    /// FMU states owned by this instance, keyed by the handle given to the importer.
    states: HashMap<usize, Box<Snapshot>>,
    /// Strings returned by the last `fmi2GetString` (valid until the next call).
    strings: Vec<CString>,
    /// The scene file read at instantiation and where it came from (applied again on reset).
    scene: Option<(scene_file::SceneFile, String)>,
    /// The model's relative-tolerance parameter (the real parameter named [`TOLERANCE_PORT`]).
    rtol_port: Option<ValueRef>,
    /// True once the importer set that parameter with `fmi2SetReal` (it then takes precedence
    /// over the tolerance of `fmi2SetupExperiment`).
    rtol_set_by_importer: bool,
    /// The resources folder given at instantiation (models restored from serialized states get
    /// it too).
    resource_dir: Option<std::path::PathBuf>,
    /// FMI 3.0: early return and the intermediate-update callback (none for FMI 2.0).
    pub importer: ImporterOptions,
}

/// Name of the real parameter that `fmi2SetupExperiment`'s tolerance sets (when the importer
/// gives one and has not set the parameter itself).
pub const TOLERANCE_PORT: &str = "rtol";

const _: () = {
    const fn assert_send<T: Send>() {}
    assert_send::<Instance>();
};

impl Instance {
    /// A new instance of `entry`'s model, in state `instantiated`.
    pub fn new(entry: &ModelEntry, log: Logger) -> Self {
        let info = (entry.info)();
        Self {
            log,
            info,
            create: entry.create,
            model: (entry.create)(),
            preview: None,
            machine: Machine::default(),
            index: PortIndex::new(info),
            view3: std::cell::OnceCell::new(),
            states: HashMap::new(),
            strings: Vec::new(),
            scene: None,
            rtol_port: info
                .ports
                .iter()
                .find(|p| {
                    p.name == TOLERANCE_PORT
                        && p.causality == Causality::Parameter
                        && p.ty.base() == BaseType::Real
                })
                .map(|p| p.vr),
            rtol_set_by_importer: false,
            resource_dir: None,
            importer: ImporterOptions::default(),
        }
    }

    /// Tells the model where its resources were unpacked; fails when a model that ships data
    /// files gets no folder.
    /// A scene file `scene.toml` in the folder sets parameter values (the packed default scene,
    /// or a user's edit of it). It is read here only: `fmi2Reset` applies the values read now
    /// again (FMI: reset returns to the state after instantiation), so a file changed on disk
    /// later takes effect in a new instance, not after a reset.
    pub fn attach_resources(&mut self, entry: &ModelEntry, dir: Option<&Path>) -> Outcome<()> {
        match dir {
            Some(dir) => {
                self.model
                    .set_resource_dir(dir)
                    .map_err(|e| e.to_string())?;
                self.resource_dir = Some(dir.to_path_buf());
                let path = dir.join(scene_file::FMU_SCENE);
                let text = super::resource_location::read_scene_text(&path).map_err(|e| {
                    format!(
                        "{e}; fix or remove it (without a {} the model starts from its built-in defaults)",
                        scene_file::FMU_SCENE
                    )
                })?;
                if let Some(text) = text {
                    let origin = path.display().to_string();
                    let scene = scene_file::parse(&text, &origin)?;
                    scene_file::apply(self.model.as_mut(), &scene, &origin)?;
                    self.model.take_log();
                    self.scene = Some((scene, origin));
                } else {
                    self.log.log(
                        fmi2Warning,
                        super::logger::Category::StatusWarning,
                        &format!(
                            "fmi2Instantiate: the resources folder {} has no {}; the model starts from its built-in defaults",
                            dir.display(),
                            scene_file::FMU_SCENE
                        ),
                    );
                }
                Ok(())
            }
            None if !entry.resources.is_empty() => Err(format!(
                "model `{}` needs its resources folder, but fmuResourceLocation is missing or not a file:// URI of an existing folder",
                self.info.identifier
            )),
            None => Ok(()),
        }
    }

    /// Current state.
    pub fn state(&self) -> State {
        self.machine.state
    }

    /// The model's variable table.
    pub fn info(&self) -> &'static ModelInfo {
        self.info
    }

    /// Whether a function allowed in `mask` may run in the current state; the reason when not.
    /// The first half of running a function body ([`super::boundary::guard`]).
    pub fn admit(&self, mask: Mask) -> Outcome<()> {
        if mask.contains(self.machine.state) {
            Ok(())
        } else {
            Err(format!(
                "illegal call sequence: not allowed in state {} (allowed in: {})",
                self.machine.state.name(),
                mask.names()
            ))
        }
    }

    /// The second half (see the module documentation): the status of `func`'s `result`, with an
    /// error's reason and the model's messages logged and the state moved to `error` when the
    /// status is `fmi2Error` or worse.
    pub fn settle(&mut self, func: &str, result: Outcome) -> fmi2Status {
        let mut status = match result {
            Ok(s) => s,
            Err(reason) => {
                self.log.log(
                    fmi2Error,
                    Category::StatusError,
                    &format!("{func}: {reason}"),
                );
                fmi2Error
            }
        };
        status = status.max(self.forward_model_log());
        if status >= fmi2Error && self.machine.state != State::Fatal {
            self.machine.state = State::Error;
        }
        status
    }

    /// Marks the instance unusable after an internal error and logs why.
    pub fn set_fatal(&mut self, func: &str, reason: &str) {
        self.machine.state = State::Fatal;
        self.log.log(
            fmi2Fatal,
            Category::StatusFatal,
            &format!("{func}: internal error: {reason}. The instance is unusable; free it."),
        );
    }

    /// Logs a refusal that leaves the instance unchanged (`fmi2Discard`).
    fn discard(&self, func: &str, reason: &str) -> Outcome {
        self.log.log(
            fmi2Discard,
            Category::StatusDiscard,
            &format!("{func}: {reason}"),
        );
        Ok(fmi2Discard)
    }

    /// Sends the model's pending messages to the logger; returns the worst status among them.
    fn forward_model_log(&mut self) -> fmi2Status {
        let mut worst = fmi2OK;
        for rec in self.model.take_log() {
            let (status, category) = match rec.level {
                LogLevel::Event => (fmi2OK, Category::Events),
                LogLevel::Solver => (fmi2OK, Category::Solver),
                LogLevel::Warning => (fmi2Warning, Category::StatusWarning),
                LogLevel::Error => (fmi2Error, Category::StatusError),
            };
            self.log.log(status, category, &rec.message);
            worst = worst.max(status);
        }
        worst
    }

    fn spec(&self, base: BaseType, vr: ValueRef) -> Outcome<&'static PortSpec> {
        let info = self.info;
        self.index
            .get(base, vr)
            .map(|i| &info.ports[i])
            .ok_or_else(|| {
                format!(
                    "unknown value reference {vr}: `{}` has no {} variable with it",
                    info.identifier,
                    base.name()
                )
            })
    }

    /// The model that answers getters: an initialized preview in initialization mode.
    fn reader(&mut self) -> Outcome<&dyn CoSimModel> {
        if self.machine.state != State::InitializationMode {
            return Ok(self.model.as_ref());
        }
        let preview = match self.preview.take() {
            Some(p) => p,
            None => {
                let mut p = self.model.clone_box();
                let res = p.initialize(self.machine.start_time);
                p.take_log();
                res.map_err(|e| format!("initial values cannot be computed: {e}"))?;
                p
            }
        };
        Ok(&**self.preview.insert(preview))
    }

    fn check_get(&self, base: BaseType, vrs: &[ValueRef]) -> Outcome<()> {
        vrs.iter()
            .try_for_each(|vr| self.spec(base, *vr).map(|_| ()))
    }

    /// `fmi2GetReal`.
    pub fn get_reals(&mut self, vrs: &[ValueRef], out: &mut [f64]) -> Outcome {
        self.check_get(BaseType::Real, vrs)?;
        let m = self.reader()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = m.get_real(*vr).map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    }

    /// `fmi2GetInteger`.
    pub fn get_integers(&mut self, vrs: &[ValueRef], out: &mut [c_int]) -> Outcome {
        self.check_get(BaseType::Integer, vrs)?;
        let m = self.reader()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = m.get_integer(*vr).map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    }

    /// `fmi2GetBoolean`.
    pub fn get_booleans(&mut self, vrs: &[ValueRef], out: &mut [c_int]) -> Outcome {
        self.check_get(BaseType::Boolean, vrs)?;
        let m = self.reader()?;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = c_int::from(m.get_boolean(*vr).map_err(|e| e.to_string())?);
        }
        Ok(fmi2OK)
    }

    /// `fmi2GetString`: the pointers stay valid until the next call on this instance.
    pub fn get_strings(&mut self, vrs: &[ValueRef], out: &mut [*const c_char]) -> Outcome {
        self.check_get(BaseType::String, vrs)?;
        let m = self.reader()?;
        let values = vrs
            .iter()
            .map(|vr| m.get_string(*vr).map_err(|e| e.to_string()))
            .collect::<Outcome<Vec<_>>>()?;
        self.strings = values.iter().map(|s| to_cstring(s)).collect();
        for (o, s) in out.iter_mut().zip(&self.strings) {
            *o = s.as_ptr();
        }
        Ok(fmi2OK)
    }

    /// Checks that the port may be written in the current state.
    fn writable(&self, base: BaseType, vr: ValueRef) -> Outcome<&'static PortSpec> {
        let spec = self.spec(base, vr)?;
        check_writable(spec, past_initialization(self.machine.state)).map_err(|e| e.to_string())?;
        Ok(spec)
    }

    /// `fmi2SetReal`: NaN, infinities and values outside `[min, max]` are refused.
    pub fn set_reals(&mut self, vrs: &[ValueRef], values: &[f64]) -> Outcome {
        self.preview = None;
        for (vr, v) in vrs.iter().zip(values) {
            let spec = self.writable(BaseType::Real, *vr)?;
            check_real(spec, *v).map_err(|e| e.to_string())?;
            self.model.set_real(*vr, *v).map_err(|e| e.to_string())?;
            if Some(*vr) == self.rtol_port {
                self.rtol_set_by_importer = true;
            }
        }
        Ok(fmi2OK)
    }

    /// `fmi2SetInteger` (also enumerations).
    pub fn set_integers(&mut self, vrs: &[ValueRef], values: &[c_int]) -> Outcome {
        self.preview = None;
        for (vr, v) in vrs.iter().zip(values) {
            let spec = self.writable(BaseType::Integer, *vr)?;
            check_integer(spec, *v).map_err(|e| e.to_string())?;
            self.model.set_integer(*vr, *v).map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    }

    /// `fmi2SetBoolean`: any non-zero value is true.
    pub fn set_booleans(&mut self, vrs: &[ValueRef], values: &[c_int]) -> Outcome {
        self.preview = None;
        for (vr, v) in vrs.iter().zip(values) {
            self.writable(BaseType::Boolean, *vr)?;
            self.model
                .set_boolean(*vr, *v != 0)
                .map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    }

    /// `fmi2SetString`.
    pub fn set_strings(&mut self, vrs: &[ValueRef], values: &[&str]) -> Outcome {
        self.preview = None;
        for (vr, v) in vrs.iter().zip(values) {
            self.writable(BaseType::String, *vr)?;
            self.model.set_string(*vr, v).map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Outcome {
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(format!("tolerance {tol} must be positive and finite"));
            }
            if let Some(vr) = self.rtol_port {
                let spec = self.spec(BaseType::Real, vr)?;
                check_real(spec, tol).map_err(|e| {
                    format!("tolerance {tol} cannot be used as `{TOLERANCE_PORT}`: {e}")
                })?;
            }
        }
        if !start.is_finite() {
            return Err(format!("startTime {start} s must be finite"));
        }
        if let Some(stop) = stop
            && !(stop.is_finite() && stop >= start)
        {
            return Err(format!(
                "stopTime {stop} s must be finite and not before startTime {start} s"
            ));
        }
        self.machine.tolerance = tolerance;
        self.machine.start_time = start;
        self.machine.stop_time = stop;
        self.machine.last_successful_time = start;
        Ok(fmi2OK)
    }

    /// `fmi2EnterInitializationMode`: applies the experiment's tolerance (see
    /// [`Instance::apply_experiment_tolerance`]).
    pub fn enter_initialization_mode(&mut self) -> Outcome {
        self.apply_experiment_tolerance()?;
        self.machine.state = State::InitializationMode;
        self.preview = None;
        Ok(fmi2OK)
    }

    /// The tolerance of `fmi2SetupExperiment`, when given, becomes the model's relative tolerance
    /// [`TOLERANCE_PORT`] unless the importer set that parameter itself with `fmi2SetReal`
    /// (before or during initialization mode), which takes precedence. Precedence, highest
    /// first: `fmi2SetReal`, the experiment's tolerance, the FMU's `scene.toml`, the start value.
    /// Every decision is logged (category logSolver).
    fn apply_experiment_tolerance(&mut self) -> Outcome<()> {
        let Some(tol) = self.machine.tolerance else {
            return Ok(());
        };
        let message = match self.rtol_port {
            None => format!(
                "tolerance {tol} of fmi2SetupExperiment not used: `{}` has no error-controlled solver",
                self.info.identifier
            ),
            Some(vr) if self.rtol_set_by_importer => format!(
                "tolerance {tol} of fmi2SetupExperiment not used: `{TOLERANCE_PORT}` = {} was set with fmi2SetReal, which takes precedence",
                self.model.get_real(vr).map_err(|e| e.to_string())?
            ),
            Some(vr) => {
                self.model
                    .set_real(vr, tol)
                    .map_err(|e| format!("tolerance {tol} cannot be used: {e}"))?;
                format!("tolerance {tol} of fmi2SetupExperiment used as `{TOLERANCE_PORT}`")
            }
        };
        self.log.log(fmi2OK, Category::Solver, &message);
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: initializes the model at the start time.
    pub fn exit_initialization_mode(&mut self) -> Outcome {
        self.preview = None;
        self.model
            .initialize(self.machine.start_time)
            .map_err(|e| {
                format!(
                    "initialization at t = {} s failed: {e}",
                    self.machine.start_time
                )
            })?;
        finite_outputs(self.model.as_ref())
            .map_err(|e| format!("initialization at t = {} s {e}", self.machine.start_time))?;
        self.machine.state = State::StepComplete;
        self.machine.last_successful_time = self.model.time();
        Ok(fmi2OK)
    }

    /// `fmi2Terminate`: logs the solver statistics (category logSolver).
    pub fn terminate(&mut self) -> Outcome {
        self.log_solver_stats("at fmi2Terminate");
        self.machine.state = State::Terminated;
        Ok(fmi2OK)
    }

    /// Logs the model's integrator counters since the start (category logSolver); nothing for
    /// models without an integrator or before initialization.
    fn log_solver_stats(&self, when: &str) {
        if let Some(stats) = self.model.solver_stats() {
            self.log.log(
                fmi2OK,
                Category::Solver,
                &format!(
                    "solver statistics {when}, t = {} s: {}",
                    self.model.time(),
                    stats.summary()
                ),
            );
        }
    }

    /// `fmi2Reset`: back to `instantiated` with default parameters; FMU states stay valid.
    pub fn reset(&mut self) -> Outcome {
        self.model.reset();
        if let Some((scene, origin)) = &self.scene {
            scene_file::apply(self.model.as_mut(), scene, origin)?;
        }
        self.model.take_log();
        self.preview = None;
        self.machine = Machine::default();
        self.rtol_set_by_importer = false;
        self.strings.clear();
        Ok(fmi2OK)
    }

    /// `fmi2DoStep` and `fmi3DoStep` from `t` over `h` [s] under `watch` (`NoWatch` for FMI
    /// 2.0, [`Instance::importer_watch`] for FMI 3.0): the one request check of the step
    /// ([`CoSimModel::step_request`]), the
    /// stop time, the model's step, finite outputs.
    pub fn step(&mut self, t: f64, h: f64, watch: &mut dyn StepWatch) -> Outcome<StepEnd> {
        let request = self.model.step_request(t, h).map_err(|e| e.to_string())?;
        if let Some(stop) = self.machine.stop_time {
            let end = t + h;
            if end > stop + TIME_RTOL * 1f64.max(stop.abs()) {
                return Err(format!(
                    "the step from t = {t} s with h = {h} s ends at {end} s, past the stop time {stop} s"
                ));
            }
        }
        let end = match self.model.do_step_watched(request, watch) {
            Ok(end) => end,
            Err(e) => {
                self.log_solver_stats(&format!("after the failed step from t = {t} s"));
                return Err(format!("step from t = {t} s with h = {h} s failed: {e}"));
            }
        };
        finite_outputs(self.model.as_ref())
            .map_err(|e| format!("the step from t = {t} s with h = {h} s {e}"))?;
        self.machine.last_successful_time = self.model.time();
        if let StepEnd::Early { reason } = &end {
            self.log.log(
                fmi2OK,
                Category::Events,
                &format!(
                    "early return from the step from t = {t} s with h = {h} s at t = {} s: {reason}",
                    self.model.time()
                ),
            );
        }
        Ok(end)
    }

    /// The FMI 3.0 importer's early-return and intermediate-update choices as a step watcher
    /// ([`ImporterOptions`]).
    pub fn importer_watch(&self) -> ImporterWatch {
        ImporterWatch {
            options: self.importer,
        }
    }

    /// `fmi2GetFMUstate`: a new handle, or `existing` overwritten (0 means none).
    pub fn get_fmu_state(&mut self, existing: usize) -> Outcome<usize> {
        let snap = Snapshot::new(self.machine, self.model.clone_box());
        if existing != 0 {
            let slot = self
                .states
                .get_mut(&existing)
                .ok_or_else(|| not_ours(existing))?;
            **slot = snap;
            return Ok(existing);
        }
        Ok(self.keep(snap))
    }

    fn keep(&mut self, snap: Snapshot) -> usize {
        let boxed = Box::new(snap);
        let handle = &*boxed as *const Snapshot as usize;
        self.states.insert(handle, boxed);
        handle
    }

    fn snapshot(&mut self, handle: usize) -> Outcome<&mut Snapshot> {
        self.states
            .get_mut(&handle)
            .map(|b| &mut **b)
            .ok_or_else(|| not_ours(handle))
    }

    /// `fmi2SetFMUstate`: model and state machine back to the saved ones.
    pub fn set_fmu_state(&mut self, handle: usize) -> Outcome {
        let snap = self.snapshot(handle)?;
        let (machine, model) = (snap.machine, snap.model.clone_box());
        if has_outputs(machine.state) {
            finite_outputs(model.as_ref())
                .map_err(|e| format!("state refused: the restored FMU state {e}"))?;
        }
        self.machine = machine;
        self.model = model;
        self.preview = None;
        Ok(fmi2OK)
    }

    /// `fmi2FreeFMUstate` (0 is accepted and ignored).
    pub fn free_fmu_state(&mut self, handle: usize) -> Outcome {
        if handle != 0 {
            self.states
                .remove(&handle)
                .ok_or_else(|| not_ours(handle))?;
        }
        Ok(fmi2OK)
    }

    /// Number of FMU states this instance owns.
    pub fn fmu_state_count(&self) -> usize {
        self.states.len()
    }

    /// `fmi2SerializedFMUstateSize` [bytes].
    pub fn serialized_size(&mut self, handle: usize) -> Outcome<usize> {
        Ok(self.snapshot(handle)?.bytes().len())
    }

    /// `fmi2SerializeFMUstate` into `buf` (at least the serialized size).
    pub fn serialize_fmu_state(&mut self, handle: usize, buf: &mut [u8]) -> Outcome {
        let bytes = self.snapshot(handle)?.bytes();
        if buf.len() < bytes.len() {
            return Err(format!(
                "buffer of {} bytes is too small: the state needs {} (see fmi2SerializedFMUstateSize)",
                buf.len(),
                bytes.len()
            ));
        }
        buf[..bytes.len()].copy_from_slice(bytes);
        Ok(fmi2OK)
    }

    /// `fmi2DeSerializeFMUstate`: a new handle, or `existing` overwritten (0 means none).
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8], existing: usize) -> Outcome<usize> {
        if existing != 0 && !self.states.contains_key(&existing) {
            return Err(not_ours(existing));
        }
        let (create, dir) = (self.create, self.resource_dir.clone());
        let scene = self.scene.clone();
        let make = move || {
            let mut m = create();
            if let Some(dir) = &dir {
                // the folder was accepted for this model at instantiation
                let _ = m.set_resource_dir(dir);
            }
            // the scene file's tables (a PanelLock array, a RopeBlock rig) belong to the
            // instance, as at fmi2Reset: the state is decoded into a model made like it (it was
            // accepted at instantiation; the state's own values then replace the parameters)
            if let Some((scene, origin)) = &scene {
                let _ = scene_file::apply(m.as_mut(), scene, origin);
            }
            m
        };
        let snap = snapshot::decode(bytes, &make).map_err(|e| format!("state refused: {e}"))?;
        if has_outputs(snap.machine.state) {
            finite_outputs(snap.model.as_ref())
                .map_err(|e| format!("state refused: the serialized FMU state {e}"))?;
        }
        if existing != 0 {
            *self.snapshot(existing)? = snap;
            return Ok(existing);
        }
        Ok(self.keep(snap))
    }

    /// `fmi2GetStatus`: no status kind applies (no asynchronous steps).
    pub fn get_status(&mut self, kind: fmi2StatusKind) -> Outcome {
        self.discard("fmi2GetStatus", &unavailable_status(kind))
    }

    /// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` [s].
    pub fn get_real_status(&mut self, kind: fmi2StatusKind, out: &mut f64) -> Outcome {
        if kind == fmi2LastSuccessfulTime {
            *out = self.machine.last_successful_time;
            return Ok(fmi2OK);
        }
        self.discard("fmi2GetRealStatus", &unavailable_status(kind))
    }

    /// `fmi2GetIntegerStatus`: FMI 2.0 defines no integer status.
    pub fn get_integer_status(&mut self, kind: fmi2StatusKind) -> Outcome {
        self.discard("fmi2GetIntegerStatus", &unavailable_status(kind))
    }

    /// `fmi2GetBooleanStatus`: `fmi2Terminated` is always false (the model never asks to stop;
    /// a failing step returns `fmi2Error`, never `fmi2Discard`).
    pub fn get_boolean_status(&mut self, kind: fmi2StatusKind, out: &mut c_int) -> Outcome {
        if kind == fmi2Terminated {
            *out = 0;
            return Ok(fmi2OK);
        }
        self.discard("fmi2GetBooleanStatus", &unavailable_status(kind))
    }

    /// `fmi2GetStringStatus`: no pending step, so no text.
    pub fn get_string_status(&mut self, kind: fmi2StatusKind) -> Outcome {
        self.discard("fmi2GetStringStatus", &unavailable_status(kind))
    }
}

/// True when the model's outputs have been computed in this instance state (after
/// initialization; in initialization mode the getters answer from a preview).
fn has_outputs(state: State) -> bool {
    !matches!(
        state,
        State::Instantiated | State::InitializationMode | State::Fatal
    )
}

/// Every real output of `model` is finite; otherwise the outputs that are not, by name (a call
/// that would return OK with NaN or infinite outputs returns fmi2Error instead, issue #25).
/// Allocates nothing when every output is finite (the step loop stays allocation-free).
fn finite_outputs(model: &dyn CoSimModel) -> Outcome<()> {
    let bad: Vec<String> = model
        .info()
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Output && p.ty.base() == BaseType::Real)
        .filter_map(|p| match model.get_real(p.vr) {
            Ok(v) if v.is_finite() => None,
            Ok(v) => Some(format!("`{}` = {v}", p.name)),
            Err(e) => Some(format!("`{}` unreadable ({e})", p.name)),
        })
        .collect();
    if bad.is_empty() {
        return Ok(());
    }
    Err(format!("gives non-finite outputs: {}", bad.join(", ")))
}

fn not_ours(handle: usize) -> String {
    format!("FMU state {handle:#x} was not created by this instance or was already freed")
}

fn unavailable_status(kind: fmi2StatusKind) -> String {
    let name = match kind {
        fmi2DoStepStatus => "fmi2DoStepStatus",
        fmi2PendingStatus => "fmi2PendingStatus",
        fmi2LastSuccessfulTime => "fmi2LastSuccessfulTime",
        fmi2Terminated => "fmi2Terminated",
        _ => return format!("unknown status kind {kind}"),
    };
    format!(
        "status kind {name} is not available from this function (no asynchronous steps: canRunAsynchronuously=false)"
    )
}

#[path = "instance3.rs"]
mod fmi3;

#[cfg(test)]
#[path = "instance_tests.rs"]
mod tests;
