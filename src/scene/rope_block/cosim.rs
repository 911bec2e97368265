//! RopeBlock as a co-simulation model: the variable table of [`super::ports`] in, the native
//! [`RopeBlockScene`] inside, its outputs published after initialization and every step.
//!
//! # Effect switches and their value parameters
//! Each optional effect has a boolean switch and value parameters. **Rule:** a value parameter
//! is ignored while its switch is off (the effect is then not assembled at all: no bending
//! hinges, no drag nodes, no friction, no gravity, no contact detection, so no per-step work),
//! but a negative, NaN or out-of-range value is always refused, switch on or off (at `set`
//! already, and again at initialization). A switch on with a zero value is the same as off
//! (the rope model assembles bending and drag only for positive coefficients).
//!
//! # Hook inputs
//! Per hook: velocity x/y/z [m/s] (world) and winch pay-out rate [m/s]. A changed command is
//! applied at the start of the next step (no direct feedthrough) and reached linearly over
//! `hook_ramp_time` (default 0.5 s) from the previous one, so hook position and velocity stay
//! continuous and the integrator keeps its history; with `hook_ramp_time` = 0 the velocity jumps
//! and the integrator restarts. Unchanged values cost nothing. In the lift scenario hook 1
//! does not exist: its inputs are accepted and ignored.
//!
//! # Start
//! The scene starts hanging at rest in static equilibrium (settled with the rope sliding freely
//! over the edges, then every contact node sticking) at the importer's start time, any finite
//! value: the scene's time axis begins at 0 and the model's time is start time + elapsed time
//! ([`crate::scene::clock::Clock`]), so a run started at 1000 s gives the outputs of a run
//! started at 0 s.

use super::persist::{read_sim, write_sim};
use super::ports::*;
use super::rig::BlockGeometry;
use super::rig_checks::check_rig;
use super::rig_digest::RigDigest;
use super::rig_file::{RigOverride, read_rig};
use super::scene::solver_settings;
use super::{RopeBlockParams, RopeBlockScene};
use crate::math::Vec3;
use crate::rope::shell::import::MESH_FILE;
use crate::scene::bytes::{ByteReader, ByteWriter, checksum64};
use crate::scene::clock::Clock;
use crate::scene::port::{PortType, ValueRef};
use crate::scene::scene_file::SceneTable;
use crate::scene::store::PortStore;
use crate::scene::view::Snapshot;
use crate::scene::watch::{StepEnd, StepWatch, advance_watched};
use crate::scene::{CoSimModel, LogLevel, LogRecord, ModelError, StepRequest};

/// Version of the serialized FMU state (2 adds the friction-slide dissipation and the energy
/// guard's reference; 3 the clock, start time and elapsed time, in place of the time; 4 the
/// digest of the mesh file; 5 the digest of the rig ([`RigDigest`]); 6 the integrator's
/// monitors ([`crate::integrator::Integrator::monitors`], after the hook ramp); 7 the power
/// bonds' work ([`super::bonds::BondBooks`]).
/// Version 1 states are still read, with none booked and
/// the guard's reference taken anew; versions 1 and 2 start at 0 s; versions before 5 restore
/// without a rig check, as before).
const STATE_FORMAT: u32 = 7;
use std::path::{Path, PathBuf};

/// A new RopeBlock instance at default parameters.
pub fn create() -> Box<dyn CoSimModel> {
    Box::new(RopeBlockModel::new())
}

/// Where one scene output goes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Target {
    Real(ValueRef),
    Integer(ValueRef),
}

/// The co-simulation model.
#[derive(Debug)]
pub struct RopeBlockModel {
    ports: PortStore,
    scene: Option<RopeBlockScene>,
    /// Port of each scene output (derived from the names; `None`: not a port, e.g. `time`).
    targets: Vec<Option<Target>>,
    /// Hook commands in effect, as [`HOOK_INPUTS`]: velocity x/y/z [m/s], pay-out rate [m/s],
    /// displacement x/y/z [m].
    applied: [[f64; N_HOOK_INPUTS]; MAX_HOOKS],
    /// Start time and time since the start (the scene's own time axis begins at 0).
    clock: Clock,
    /// Digest of the mesh file's bytes the scene was built from (none for the parametric
    /// block); kept in serialized states, which refuse to restore with a changed file.
    mesh_digest: Option<u64>,
    /// Digest of the rig the scene was built from (none before initialization); kept in
    /// serialized states, which refuse to restore into an instance with another rig.
    rig_digest: Option<RigDigest>,
    resource_dir: Option<PathBuf>,
    /// The rig tables of the scene file read at instantiation (replacing parts of the
    /// scenario's rig).
    rig_file: Option<RigOverride>,
    log: Vec<LogRecord>,
}

impl Clone for RopeBlockModel {
    fn clone(&self) -> Self {
        RopeBlockModel {
            ports: self.ports.clone(),
            scene: self.scene.as_ref().map(|s| s.with_sim(s.sim.clone())),
            targets: self.targets.clone(),
            applied: self.applied,
            clock: self.clock,
            mesh_digest: self.mesh_digest,
            rig_digest: self.rig_digest,
            resource_dir: self.resource_dir.clone(),
            rig_file: self.rig_file.clone(),
            log: self.log.clone(),
        }
    }
}

impl Default for RopeBlockModel {
    fn default() -> Self {
        Self::new()
    }
}

impl RopeBlockModel {
    /// Default parameters, not initialized.
    pub fn new() -> Self {
        RopeBlockModel {
            ports: PortStore::new(info()),
            scene: None,
            targets: Vec::new(),
            applied: [[0.0; N_HOOK_INPUTS]; MAX_HOOKS],
            clock: Clock::default(),
            mesh_digest: None,
            rig_digest: None,
            resource_dir: None,
            rig_file: None,
            log: Vec::new(),
        }
    }

    fn mesh_path(&self, file: &str) -> Result<PathBuf, ModelError> {
        let p = Path::new(file);
        if p.is_absolute() {
            return Ok(p.to_path_buf());
        }
        match &self.resource_dir {
            Some(dir) => Ok(dir.join(p)),
            None => Err(ModelError::InvalidValue(format!(
                "mesh_file `{file}` is relative, but no FMU resources folder is known; give an absolute path"
            ))),
        }
    }

    /// The scene parameters from the current port values (see the module doc for the rule on
    /// switches and values).
    pub fn params(&self) -> Result<RopeBlockParams, ModelError> {
        let mut p = match self.ports.get_integer(ivr::SCENARIO)? {
            scenario::LIFT => RopeBlockParams::default(),
            scenario::TURNOVER => RopeBlockParams::turnover(),
            s => {
                return Err(ModelError::InvalidValue(format!(
                    "scenario {s} does not exist (0 lift, 1 turn-over)"
                )));
            }
        };
        let d = RopeBlockParams::default();
        for (i, spec) in REAL_PARAMS.iter().enumerate() {
            let x = self.ports.get_real(i as ValueRef)?;
            let range = spec.range(&d);
            if !range.contains(x) {
                return Err(ModelError::InvalidValue(format!(
                    "{} = {x} refused: it must be in [{}, {}] whether or not its effect is switched on",
                    spec.name,
                    range.min.unwrap_or(f64::NEG_INFINITY),
                    range.max.unwrap_or(f64::INFINITY)
                )));
            }
            (spec.set)(&mut p, x);
        }
        let on = |vr| self.ports.get_boolean(vr);
        let r = |vr: ValueRef| self.ports.get_real(vr);
        // a value whose effect is switched off is not used
        if !on(bvr::FRICTION)? {
            p.rope.friction = 0.0;
        }
        if !on(bvr::BENDING)? {
            p.rope.bending_stiffness = 0.0;
        }
        if !on(bvr::DRAG)? {
            p.rope.drag_coefficient = 0.0;
        }
        if !on(bvr::GRAVITY_ON)? {
            p.gravity = 0.0;
        }
        p.contact = on(bvr::CONTACT)?;
        if !on(bvr::GROUND_CONTACT)? {
            p.ground = None;
        }
        p.settle = true;
        p.segments = self.ports.get_integer(ivr::SEGMENTS)? as usize;
        p.integrator = integrator_of(self.choice(ivr::INTEGRATOR, ivr::INTEGRATOR_NUMBER)?);
        let law = self.choice(ivr::FRICTION_LAW, ivr::FRICTION_LAW_NUMBER)?;
        p.rope.friction_law =
            crate::rope::friction::FrictionLaw::from_code(law).ok_or_else(|| {
                ModelError::InvalidValue(format!(
                    "friction_law = {law} does not exist (1 edge_first, 2 pseudo_coefficient)"
                ))
            })?;
        p.contact_outputs = self.ports.get_integer(ivr::CONTACT_OUTPUTS)? as usize;
        let file = self.ports.get_string(SVR_MESH_FILE)?;
        if let Some(rig) = &self.rig_file {
            if rig.block.is_some() && !file.is_empty() {
                return Err(ModelError::InvalidValue(format!(
                    "mesh_file = \"{file}\" and the scene file's [block] both give the block: give the mesh in [block] (mesh = \"...\") and leave mesh_file empty"
                )));
            }
            p.rig = rig.apply(&p.rig);
        }
        if let Some(pose) = p.rig.block.pose {
            p.block_origin = pose.position;
            p.block_orientation = pose.orientation;
        }
        if !file.is_empty() {
            p.rig.block.geometry = BlockGeometry::Mesh {
                file: self.mesh_path(&file)?.to_string_lossy().into_owned(),
                scale: r(rvr::MESH_SCALE)?,
            };
        }
        p.validate().map_err(ModelError::InvalidValue)?;
        Ok(p)
    }

    fn scene(&mut self) -> Result<&mut RopeBlockScene, ModelError> {
        self.scene
            .as_mut()
            .ok_or_else(|| ModelError::NotAllowed("the model is not initialized".into()))
    }

    /// Maps the scene's output names onto ports (`.` becomes `_`).
    fn map_targets(scene: &RopeBlockScene) -> Vec<Option<Target>> {
        let info = info();
        scene
            .output_names()
            .iter()
            .map(|n| {
                let p = info.port_by_name(&n.replace('.', "_"))?;
                match p.ty {
                    PortType::Real { .. } => Some(Target::Real(p.vr)),
                    PortType::Integer { .. } => Some(Target::Integer(p.vr)),
                    _ => None,
                }
            })
            .collect()
    }

    /// Every output to its empty value (0; contact-slot sling -1).
    fn clear_outputs(&mut self) -> Result<(), ModelError> {
        for i in 0..real_outputs().len() {
            self.ports.put_real(vr_output(i), 0.0)?;
        }
        self.ports.put_integer(ivr::CONTACT_COUNT, 0)?;
        self.ports.put_integer(ivr::REBUILDS, 0)?;
        for i in 0..MAX_CONTACT_SLOTS {
            self.ports.put_integer(ivr_slot(i, 0), -1)?;
            self.ports.put_integer(ivr_slot(i, 1), 0)?;
        }
        Ok(())
    }

    /// Writes every output port from the scene.
    fn publish(&mut self) -> Result<(), ModelError> {
        let scene = self.scene()?;
        let out = scene.outputs();
        let rebuilds = scene.sim.counters.rebuilds;
        for (v, t) in out.iter().zip(&self.targets) {
            match *t {
                Some(Target::Real(vr)) => self.ports.put_real(vr, *v)?,
                Some(Target::Integer(vr)) => self.ports.put_integer(vr, v.round() as i32)?,
                None => {}
            }
        }
        let rebuilds = rebuilds.min(i32::MAX as u64) as i32;
        self.ports.put_integer(ivr::REBUILDS, rebuilds)
    }

    /// The item number in effect for a choice parameter: its Integer twin at `number` when not 0,
    /// else its Enumeration at `enumeration` ([`crate::scene::choice`]).
    fn choice(&self, enumeration: ValueRef, number: ValueRef) -> Result<i32, ModelError> {
        Ok(crate::scene::choice::effective(
            self.ports.get_integer(enumeration)?,
            self.ports.get_integer(number)?,
        ))
    }

    /// Applies hook commands that changed since they were last applied: with `hook_command` =
    /// velocity the velocity and pay-out inputs, with position the displacement and pay-out
    /// inputs (the others are ignored, and a change of them costs nothing).
    fn apply_inputs(&mut self) -> Result<(), ModelError> {
        let position = match self.choice(ivr::HOOK_COMMAND, ivr::HOOK_COMMAND_NUMBER)? {
            hook_command::VELOCITY => false,
            hook_command::POSITION => true,
            c => {
                return Err(ModelError::InvalidValue(format!(
                    "hook_command = {c} does not exist (1 velocity, 2 position)"
                )));
            }
        };
        let used: &[usize] = if position {
            &[
                HOOK_PAYOUT,
                HOOK_DISPLACEMENT,
                HOOK_DISPLACEMENT + 1,
                HOOK_DISPLACEMENT + 2,
            ]
        } else {
            &[
                HOOK_VELOCITY,
                HOOK_VELOCITY + 1,
                HOOK_VELOCITY + 2,
                HOOK_PAYOUT,
            ]
        };
        let mut cmds = self.applied;
        for (k, c) in cmds.iter_mut().enumerate() {
            for &j in used {
                c[j] = self.ports.get_real(vr_input(k, j))?;
            }
        }
        let Some(scene) = self.scene.as_mut() else {
            return Err(ModelError::NotAllowed(
                "the model is not initialized".into(),
            ));
        };
        let n_hooks = scene.params.rig.hooks.len().min(MAX_HOOKS);
        for (k, (c, a)) in cmds.iter().zip(self.applied.iter_mut()).enumerate() {
            if k >= n_hooks || c == a {
                continue;
            }
            let rate = c[HOOK_PAYOUT];
            let d = HOOK_DISPLACEMENT;
            let message = if position {
                let start = scene.params.rig.hooks[k].position;
                let target = start + Vec3::new(c[d], c[d + 1], c[d + 2]);
                scene
                    .set_hook_target(k, target, rate)
                    .map_err(ModelError::InvalidValue)?;
                format!(
                    "hook {k}: new command at t = {:.6} s: to ({}, {}, {}) m from its start position, pay-out {rate} m/s",
                    self.clock.time(),
                    c[d],
                    c[d + 1],
                    c[d + 2]
                )
            } else {
                let v = HOOK_VELOCITY;
                scene
                    .set_hook(k, Vec3::new(c[v], c[v + 1], c[v + 2]), rate)
                    .map_err(ModelError::InvalidValue)?;
                format!(
                    "hook {k}: new command at t = {:.6} s: velocity ({}, {}, {}) m/s, pay-out {rate} m/s",
                    self.clock.time(),
                    c[v],
                    c[v + 1],
                    c[v + 2]
                )
            };
            *a = *c;
            self.log.push(LogRecord {
                level: LogLevel::Event,
                message,
            });
        }
        Ok(())
    }

    fn contact_count(&self) -> i32 {
        self.ports.get_integer(ivr::CONTACT_COUNT).unwrap_or(0)
    }

    /// Builds, settles and publishes (panics caught by the caller).
    fn start(&mut self) -> Result<(), ModelError> {
        let p = self.params()?;
        self.mesh_digest = mesh_digest_of(&p)?;
        self.rig_digest = Some(RigDigest::of(&p.rig));
        let mut warnings = check_rig(&p)
            .map_err(|e| ModelError::InvalidValue(format!("RopeBlock rig refused: {e}")))?;
        if p.rig.slings.len() > MAX_SLINGS {
            warnings.push(format!(
                "the rig has {} slings; the FMU's outputs cover slings 0-{} (slings {}-{} are simulated, and count in the hook loads, but not reported)",
                p.rig.slings.len(),
                MAX_SLINGS - 1,
                MAX_SLINGS,
                p.rig.slings.len() - 1
            ));
        }
        for w in warnings {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: w,
            });
        }
        let scene = RopeBlockScene::new(p)
            .map_err(|e| ModelError::InvalidValue(format!("RopeBlock could not be set up: {e}")))?;
        for w in &scene.sim.sim.warnings {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: w.clone(),
            });
        }
        self.targets = Self::map_targets(&scene);
        self.scene = Some(scene);
        self.applied = [[0.0; N_HOOK_INPUTS]; MAX_HOOKS];
        self.apply_inputs()?;
        self.clear_outputs()?;
        self.publish()?;
        let n_v = self
            .scene
            .as_ref()
            .map_or(0, |s| s.sim.sim.system.model.n_v);
        self.log.push(LogRecord {
            level: LogLevel::Solver,
            message: format!(
                "set up at static equilibrium: {n_v} speeds, {} contact nodes",
                self.contact_count()
            ),
        });
        Ok(())
    }
}

impl CoSimModel for RopeBlockModel {
    fn ports(&self) -> &PortStore {
        &self.ports
    }
    fn ports_mut(&mut self) -> &mut PortStore {
        &mut self.ports
    }

    fn set_up(&mut self, t_start: f64) -> Result<(), ModelError> {
        self.clock = Clock::new(t_start)?;
        self.start()?;
        Ok(())
    }

    fn do_step_watched(
        &mut self,
        request: StepRequest,
        watch: &mut dyn StepWatch,
    ) -> Result<StepEnd, ModelError> {
        let (t, h) = (request.t(), request.h());
        let step = self.clock.step(request)?;
        // a step that h_max cannot cover within the integrator's max_steps per call fails only
        // after minutes of CPU (fmi3DoStep(t, 1e300) without a stop time took 97 s): refuse it
        let (h_max, max_steps) = {
            let p = &self.scene()?.params;
            (p.h_max, solver_settings(p).0.max_steps)
        };
        if step.h / h_max > max_steps as f64 {
            return Err(ModelError::InvalidValue(format!(
                "the step from t = {t} s with h = {h} s needs more than max_steps = {max_steps} integrator steps of h_max = {h_max} s: shorten the communication step or raise h_max"
            )));
        }
        self.apply_inputs()?;
        let before = self.contact_count();
        let (t0, t_end) = (self.clock.elapsed(), step.end);
        let start = self.clock.start();
        let scene = self.scene()?;
        let stopped = match advance_watched(&mut scene.sim, t_end, start, watch) {
            Ok(stopped) => {
                for note in scene.sim.sim.take_solver_notes() {
                    self.log.push(LogRecord {
                        level: LogLevel::Warning,
                        message: note,
                    });
                }
                stopped
            }
            Err(e) => {
                return Err(ModelError::SolverFailure(format!(
                    "RopeBlock solver failed in the step from t = {} s to {} s: {e}{}",
                    start + t0,
                    start + t_end,
                    remedy(&e)
                )));
            }
        };
        let now = self.scene()?.sim.time();
        let end = stopped.finish(&mut self.clock, &step, now);
        self.publish()?;
        let after = self.contact_count();
        if after != before {
            self.log.push(LogRecord {
                level: LogLevel::Event,
                message: format!(
                    "contact nodes: {before} -> {after} at t = {:.6} s",
                    self.clock.time()
                ),
            });
        }
        Ok(end)
    }

    fn time(&self) -> f64 {
        self.clock.time()
    }

    fn clone_box(&self) -> Box<dyn CoSimModel> {
        Box::new(self.clone())
    }

    fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.header(IDENTIFIER, STATE_FORMAT);
        self.ports.write(&mut w);
        self.clock.write(&mut w);
        for c in &self.applied {
            w.f64s(c);
        }
        w.bool(self.mesh_digest.is_some());
        w.u64(self.mesh_digest.unwrap_or(0));
        w.bool(self.rig_digest.is_some());
        for d in self.rig_digest.map_or([0; 4], |d| d.parts) {
            w.u64(d);
        }
        match &self.scene {
            None => w.bool(false),
            Some(s) => {
                w.bool(true);
                write_sim(&mut w, &s.sim);
            }
        }
        w.into_bytes()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let mut r = ByteReader::new(bytes);
        let version = r.header(IDENTIFIER, STATE_FORMAT)?;
        let ports = self.ports.read(&mut r)?;
        let clock = if version >= 3 {
            Clock::read(&mut r)?
        } else {
            let time = r.finite_f64("time")?;
            Clock::restore(0.0, time, time)?
        };
        // before version 5: two hooks, velocity and pay-out only
        let (hooks, per_hook) = if version >= 5 {
            (MAX_HOOKS, N_HOOK_INPUTS)
        } else {
            (2, 4)
        };
        let mut applied = [[0.0; N_HOOK_INPUTS]; MAX_HOOKS];
        for c in applied.iter_mut().take(hooks) {
            let v = r.f64s_exact(per_hook, "hook command")?;
            c[..per_hook].copy_from_slice(&v);
        }
        let mesh_digest = if version >= 4 {
            let some = r.bool("mesh digest present")?;
            let d = r.u64("mesh digest")?;
            some.then_some(d)
        } else {
            None
        };
        let rig_digest = if version >= 5 {
            let some = r.bool("rig digest present")?;
            let mut parts = [0u64; 4];
            for d in parts.iter_mut() {
                *d = r.u64("rig digest")?;
            }
            some.then_some(RigDigest { parts })
        } else {
            None
        };
        let mut restored = RopeBlockModel {
            ports,
            scene: None,
            targets: Vec::new(),
            applied,
            clock,
            mesh_digest,
            rig_digest,
            resource_dir: self.resource_dir.clone(),
            rig_file: self.rig_file.clone(),
            log: Vec::new(),
        };
        if r.bool("initialized scene")? {
            let params = restored.params()?;
            if let Some(d) = mesh_digest {
                let now = mesh_digest_of(&params)?;
                if now != Some(d) {
                    return Err(ModelError::BadState(format!(
                        "mesh_file `{}` changed since this state was taken (digest {d:016x}, now {}): a state restores only with the mesh it was taken with",
                        params.mesh_file().unwrap_or(""),
                        now.map_or("no mesh".to_string(), |n| format!("{n:016x}"))
                    )));
                }
            }
            let now = RigDigest::of(&params.rig);
            if let Some(d) = rig_digest
                && let Some(parts) = d.differences(&now)
            {
                return Err(ModelError::BadState(format!(
                    "RopeBlock state refused: it was taken with another rig ({parts} differ from this instance's, made from its scenario and scene file); a state restores only into an instance with the same rig"
                )));
            }
            restored.rig_digest = Some(now);
            let sim = read_sim(&mut r, &params, version, restored.clock.elapsed())?;
            let scene = RopeBlockScene::from_sim(params, sim).map_err(ModelError::BadState)?;
            restored.targets = Self::map_targets(&scene);
            restored.scene = Some(scene);
        }
        r.finish()?;
        *self = restored;
        Ok(())
    }

    fn reset(&mut self) {
        let dir = self.resource_dir.take();
        *self = RopeBlockModel::new();
        self.resource_dir = dir;
    }

    fn snapshot(&mut self) -> Option<Snapshot> {
        let start = self.clock.start();
        self.scene.as_mut().map(|s| s.snapshot(start))
    }

    fn take_log(&mut self) -> Vec<LogRecord> {
        std::mem::take(&mut self.log)
    }

    fn solver_stats(&self) -> Option<crate::integrator::Stats> {
        self.scene.as_ref().map(|s| s.sim.sim.stats())
    }

    fn set_resource_dir(&mut self, dir: &Path) -> Result<(), ModelError> {
        self.resource_dir = Some(dir.to_path_buf());
        Ok(())
    }

    /// Reads the scene file's rig and checks it against its block with the parameters set so
    /// far (they are checked again at initialization, with the importer's values).
    fn set_tables(&mut self, tables: &[SceneTable], origin: &str) -> Result<(), String> {
        if self.ports.is_initialized() {
            return Err(format!("{origin}: a rig is set before initialization only"));
        }
        let dir = Path::new(origin).parent();
        let rig = read_rig(tables, origin, dir)?;
        self.rig_file = (!rig.is_empty()).then_some(rig);
        let p = self.params().map_err(|e| format!("{origin}: {e}"))?;
        let warnings = check_rig(&p).map_err(|e| format!("{origin}: rig refused: {e}"))?;
        for w in warnings {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: format!("{origin}: {w}"),
            });
        }
        Ok(())
    }
}

/// Digest of the bytes of the scene's mesh file, `None` for the parametric block.
fn mesh_digest_of(p: &RopeBlockParams) -> Result<Option<u64>, ModelError> {
    let Some(file) = p.mesh_file() else {
        return Ok(None);
    };
    let bytes = crate::bounded_file::read_bytes(Path::new(file), &MESH_FILE)
        .map_err(|e| ModelError::InvalidValue(format!("mesh_file `{file}`: {e}")))?;
    Ok(Some(checksum64(&bytes)))
}

/// RopeBlock's advice for a step the integrator could not complete (the integrator's own message
/// is model-neutral).
fn remedy(message: &str) -> &'static str {
    if message.contains("slip modes not settled") {
        "; in RopeBlock this comes from a contact node at its friction limit whose stick/slip decision keeps switching within the step, which BDF's Newton iteration did not settle (seen with 240 segments per sling over 0.05 s communication steps): use integrator = gen_alpha, or shorter communication steps"
    } else if message.contains("step size fell below") {
        "; in RopeBlock this comes from slings too stiff or too strongly damped for the integrator (BDF's Newton iteration diverged at rope_damping 5e6 N s while the rope law clamped the total tension): use integrator = gen_alpha, lower rope_damping or rope_ea, or use fewer segments (longer segments are softer)"
    } else {
        ""
    }
}
