//! PanelLock as a co-simulation model: ports in, the native scene inside, outputs after each step.

use super::array::{HingeTable, PanelTable};
use super::array_file::read_array;
use super::locked_frequency::Update;
use super::params::DEFAULT_FLEX_MODES;
use super::ports::*;
use super::{PanelLock, PanelLockParams};
use crate::integrator::Stats;
use crate::scene::bytes::{ByteReader, ByteWriter};
use crate::scene::clock::Clock;
use crate::scene::port::ValueRef;
use crate::scene::scene_file::SceneTable;
use crate::scene::store::PortStore;
use crate::scene::view::Snapshot;
use crate::scene::watch::{StepEnd, StepWatch, advance_watched};
use crate::scene::{CoSimModel, LogLevel, LogRecord, ModelError, StepRequest};

/// Version of the serialized FMU state (2: the clock, start time and elapsed time, in
/// place of the time, and the solver counters; version 1 states start at 0 s and count from 0;
/// 3: the digest of the array's per-hinge and per-panel values, checked on restore; 4: the
/// root interface peaks, after the counters; 5: the integrator's monitors
/// ([`crate::integrator::Integrator::monitors`]), after the peaks; older states restore with the
/// rank baseline taken afresh); 6: the root interface's work ([`super::interface::InterfacePeaks::work`]),
/// after the monitors (older states restore with it at 0); 7: the locked frequency and the
/// locked set it belongs to ([`super::locked_frequency::LockedFrequency`]), after the work (older
/// states compute it from the restored state).
const STATE_FORMAT: u32 = 7;

/// A new PanelLock instance at default parameters.
pub fn create() -> Box<dyn CoSimModel> {
    Box::new(PanelLockModel::new())
}

/// The co-simulation model.
#[derive(Debug, Clone)]
pub struct PanelLockModel {
    ports: PortStore,
    scene: Option<PanelLock>,
    /// Start time and time since the start (the scene's own time axis begins at 0).
    clock: Clock,
    /// The scene file's `[[hinge]]` and `[[panel]]` tables (empty: the globals everywhere).
    tables: (Vec<HingeTable>, Vec<PanelTable>),
    log: Vec<LogRecord>,
}

impl Default for PanelLockModel {
    fn default() -> Self {
        Self::new()
    }
}

impl PanelLockModel {
    /// Default parameters, not initialized.
    pub fn new() -> Self {
        PanelLockModel {
            ports: PortStore::new(info()),
            scene: None,
            clock: Clock::default(),
            tables: (Vec::new(), Vec::new()),
            log: Vec::new(),
        }
    }

    /// The item number in effect for a choice parameter: its Integer twin at `number` when not 0,
    /// else its Enumeration at `enumeration` ([`crate::scene::choice`]).
    fn choice(&self, enumeration: ValueRef, number: ValueRef) -> Result<i32, ModelError> {
        Ok(crate::scene::choice::effective(
            self.ports.get_integer(enumeration)?,
            self.ports.get_integer(number)?,
        ))
    }

    /// The scene parameters from the current port values.
    pub fn params(&self) -> Result<PanelLockParams, ModelError> {
        let gravity_on = self.ports.get_boolean(bvr::GRAVITY_ON)?;
        let flexible_panels = self.ports.get_boolean(bvr::FLEXIBLE_PANELS)?;
        let mut p = PanelLockParams {
            n_panels: self.ports.get_integer(ivr::N_PANELS)? as usize,
            integrator: integrator_of(self.choice(ivr::INTEGRATOR, ivr::INTEGRATOR_NUMBER)?),
            contact_law: law_of(self.choice(ivr::CONTACT_LAW, ivr::CONTACT_LAW_NUMBER)?),
            latches: self.ports.get_boolean(bvr::LATCHES)?,
            cable_loop: self.ports.get_boolean(bvr::CABLE_LOOP)?,
            free_satellite: self.ports.get_boolean(bvr::FREE_SATELLITE)?,
            gravity: gravity_on.then_some(9.81),
            flexible_panels,
            n_modes: match self.ports.get_integer(ivr::N_MODES)?.max(0) as usize {
                0 if flexible_panels => DEFAULT_FLEX_MODES,
                n => n,
            },
            load_frame: load_frame_of(self.choice(ivr::LOAD_FRAME, ivr::LOAD_FRAME_NUMBER)?),
            hinge_tables: self.tables.0.clone(),
            panel_tables: self.tables.1.clone(),
            ..PanelLockParams::default()
        };
        for (i, rp) in REAL_PARAMS.iter().enumerate() {
            (rp.set)(&mut p, self.ports.get_real(i as ValueRef)?);
        }
        p.validate().map_err(ModelError::InvalidValue)?;
        Ok(p)
    }

    fn scene(&mut self) -> Result<&mut PanelLock, ModelError> {
        self.scene
            .as_mut()
            .ok_or_else(|| ModelError::NotAllowed("the model is not initialized".into()))
    }

    /// Writes every output port from the scene.
    fn publish(&mut self) -> Result<(), ModelError> {
        let start = self.clock.start();
        let scene = self.scene()?;
        let o = scene.outputs();
        let stats = scene.sim.stats();
        let used = integrator_code(Some(scene.sim.integrator_kind()));
        let sat = scene.satellite_output();
        let panels = scene.panel_flex_outputs();
        for k in 1..=MAX_PANELS {
            let f = panels.get(k - 1).copied().unwrap_or_default();
            let vals = [f.tip_deflection, f.modes[0], f.modes[1], f.modes[2]];
            for (j, v) in vals.iter().enumerate() {
                self.ports.put_real(vr_panel(k, j), *v)?;
            }
        }
        for k in 0..MAX_HINGES {
            let h = o.hinges.get(k);
            let vals = match h {
                Some(h) => [
                    h.angle,
                    h.rate,
                    h.contact_force,
                    h.peak_force,
                    if h.lock_time.is_finite() {
                        start + h.lock_time
                    } else {
                        start - 1.0
                    },
                ],
                None => [0.0, 0.0, 0.0, 0.0, start - 1.0],
            };
            for (j, v) in vals.iter().enumerate() {
                self.ports.put_real(vr_hinge(k, j), *v)?;
            }
            self.ports
                .put_boolean(bvr::LATCHED0 + k as ValueRef, h.is_some_and(|h| h.engaged))?;
        }
        let g = [
            o.root_force.x,
            o.root_force.y,
            o.root_force.z,
            o.root_torque.x,
            o.root_torque.y,
            o.root_torque.z,
            o.tip_normal_velocity,
            o.kinetic,
            o.potential,
            o.dissipated,
            o.input_work,
            o.root_peak_force,
            o.root_peak_torque,
            o.root_power,
            o.root_work,
        ];
        for (j, v) in g.iter().enumerate() {
            self.ports.put_real(vr_global(j), *v)?;
        }
        let (q, w, r, v, h) = (
            sat.attitude,
            sat.rate,
            sat.position,
            sat.velocity,
            sat.angular_momentum,
        );
        let s = [
            q[0], q[1], q[2], q[3], w.x, w.y, w.z, r.x, r.y, r.z, v.x, v.y, v.z, h.x, h.y, h.z,
        ];
        for (j, v) in s.iter().enumerate() {
            self.ports.put_real(vr_satellite_output(j), *v)?;
        }
        let clamp = |x: u64| x.min(i32::MAX as u64) as i32;
        self.ports.put_integer(ivr::STEPS, clamp(stats.steps))?;
        self.ports
            .put_integer(ivr::REJECTED, clamp(stats.rejected))?;
        self.ports
            .put_integer(ivr::NEWTON, clamp(stats.newton_iterations))?;
        self.ports
            .put_integer(ivr::FACTORIZATIONS, clamp(stats.factorizations))?;
        self.ports.put_integer(ivr::INTEGRATOR_USED, used)?;
        self.ports
            .put_real(vr_locked_frequency(), o.locked_frequency)?;
        Ok(())
    }

    /// Lock times before a step, to log the lock-ups it contains.
    fn lock_times(&mut self) -> Vec<f64> {
        self.scene
            .as_mut()
            .map(|s| s.lock_times())
            .unwrap_or_default()
    }
}

impl CoSimModel for PanelLockModel {
    fn ports(&self) -> &PortStore {
        &self.ports
    }
    fn ports_mut(&mut self) -> &mut PortStore {
        &mut self.ports
    }

    fn set_real(&mut self, vr: ValueRef, value: f64) -> Result<(), ModelError> {
        let old = self.ports.get_real(vr).ok();
        self.ports.set_real(vr, value)?;
        let load = (0..SATELLITE_LOAD_INPUTS.len()).find(|&j| vr == vr_satellite_load(j));
        let applied = match self.scene.as_mut() {
            Some(s) if vr == vr_motor() => s.set_motor_torque(value),
            Some(s) => load.map_or(Ok(()), |j| s.set_satellite_load(j, value)),
            None => Ok(()),
        };
        if let Err(e) = applied {
            // the port keeps the value the scene runs with
            if let Some(old) = old {
                self.ports.put_real(vr, old)?;
            }
            return Err(ModelError::InvalidValue(e));
        }
        Ok(())
    }

    fn set_up(&mut self, t_start: f64) -> Result<(), ModelError> {
        let clock = Clock::new(t_start)?;
        let p = self.params()?;
        let solver = p.solver_settings();
        self.log.push(LogRecord {
            level: LogLevel::Solver,
            message: format!(
                "integrator {}{} at rtol {:e}, atol {:e}",
                integrator_name(p.integrator_kind()),
                if p.integrator.is_none() {
                    " (auto: dopri5_tree for rigid panels on a fixed satellite, else gen_alpha)"
                } else {
                    ""
                },
                solver.rtol,
                solver.atol
            ),
        });
        let mut scene = PanelLock::new(p).map_err(ModelError::InvalidValue)?;
        for w in &scene.sim.warnings {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: w.clone(),
            });
        }
        scene
            .set_motor_torque(self.ports.get_real(vr_motor())?)
            .map_err(ModelError::InvalidValue)?;
        for j in 0..SATELLITE_LOAD_INPUTS.len() {
            scene
                .set_satellite_load(j, self.ports.get_real(vr_satellite_load(j))?)
                .map_err(ModelError::InvalidValue)?;
        }
        if let Update::Failed(note) = scene.update_locked_frequency() {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: note,
            });
        }
        self.scene = Some(scene);
        self.clock = clock;
        self.publish()?;
        Ok(())
    }

    fn do_step_watched(
        &mut self,
        request: StepRequest,
        watch: &mut dyn StepWatch,
    ) -> Result<StepEnd, ModelError> {
        let (t, h) = (request.t(), request.h());
        let step = self.clock.step(request)?;
        let start = self.clock.start();
        let before = self.lock_times();
        let scene = self.scene()?;
        // a communication step h_max cannot cover within max_steps fails only after minutes of
        // CPU (h_max at its floor 1e-8 s and a 0.01 s step: 1e6 steps): refuse it at once
        let settings = &scene.params.settings;
        if step.h / settings.h_max > settings.max_steps as f64 {
            return Err(ModelError::InvalidValue(format!(
                "the step from t = {t} s with h = {h} s needs more than max_steps = {} integrator steps of h_max = {} s: raise h_max or shorten the communication step",
                settings.max_steps, settings.h_max
            )));
        }
        let stopped = advance_watched(scene, step.end, start, watch).map_err(|e| {
            ModelError::SolverFailure(format!(
                "PanelLock solver failed: {e}{}",
                scene.params.fast_deployment_note()
            ))
        })?;
        let notes = scene.sim.take_solver_notes();
        let now = scene.sim.state.t;
        for note in notes {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: note,
            });
        }
        let end = stopped.finish(&mut self.clock, &step, now);
        let scene = self.scene()?;
        let t_now = scene.sim.state.t;
        match scene.update_locked_frequency() {
            Update::Failed(note) => self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: note,
            }),
            Update::Computed { hz, cpu } if hz > 0.0 => self.log.push(LogRecord {
                level: LogLevel::Event,
                message: format!(
                    "locked_frequency = {hz:.6} Hz (array linearized about its equilibrium at t = {:.6} s, {:.1} ms)",
                    self.clock.start() + t_now,
                    1e3 * cpu
                ),
            }),
            _ => {}
        }
        let after = self.lock_times();
        for (k, (a, b)) in after.iter().zip(&before).enumerate() {
            if a.is_finite() && !b.is_finite() {
                self.log.push(LogRecord {
                    level: LogLevel::Event,
                    message: format!("hinge {k} locked at t = {:.6} s", self.clock.start() + a),
                });
            }
        }
        self.publish()?;
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
        match &self.scene {
            None => w.bool(false),
            Some(s) => {
                w.bool(true);
                w.u64(s.params.array_digest());
                crate::scene::sim_state::write_state(&mut w, &s.sim.state);
                w.f64s(&s.sim.system.inputs);
                w.f64s(&s.sim.integrator_memory());
                w.f64s(&s.sim.stats().to_numbers());
                w.f64(s.interface_peaks.force);
                w.f64(s.interface_peaks.torque);
                w.f64s(&s.sim.integrator_monitors());
                w.f64(s.interface_peaks.work);
                w.f64(s.locked_frequency.hz);
                w.f64s(
                    &s.locked_frequency
                        .locked
                        .iter()
                        .map(|&l| if l { 1.0 } else { 0.0 })
                        .collect::<Vec<f64>>(),
                );
            }
        }
        w.into_bytes()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let mut r = ByteReader::new(bytes);
        let version = r.header(IDENTIFIER, STATE_FORMAT)?;
        let ports = self.ports.read(&mut r)?;
        let clock = if version >= 2 {
            Clock::read(&mut r)?
        } else {
            let time = r.finite_f64("time")?;
            Clock::restore(0.0, time, time)?
        };
        let mut restored = PanelLockModel {
            ports,
            scene: None,
            clock,
            tables: self.tables.clone(),
            log: Vec::new(),
        };
        if r.bool("initialized scene")? {
            let digest = if version >= 3 {
                Some(r.u64("array digest")?)
            } else {
                None
            };
            let params = restored.params()?;
            if let Some(d) = digest.filter(|d| *d != params.array_digest()) {
                return Err(ModelError::BadState(format!(
                    "the state was taken from an array with other per-hinge or per-panel values (digest {d:016x}, this instance {:016x}): a state restores only into an instance made with the same [[hinge]] and [[panel]] tables of its scene file (and the same n_panels)",
                    params.array_digest()
                )));
            }
            let state =
                crate::scene::sim_state::read_state(&mut r, Some(restored.clock.elapsed()))?;
            let inputs = r.f64s("inputs")?;
            let memory = r.f64s("integrator memory")?;
            let stats = if version >= 2 {
                Some(
                    Stats::from_numbers(&r.f64s("solver counters")?)
                        .map_err(ModelError::BadState)?,
                )
            } else {
                None
            };
            let mut scene = PanelLock::new(params).map_err(ModelError::BadState)?;
            if inputs.len() != scene.sim.system.inputs.len() {
                return Err(ModelError::BadState(
                    "serialized PanelLock state has the wrong number of inputs".into(),
                ));
            }
            scene.sim.system.inputs = inputs;
            scene
                .sim
                .restore(state, &memory)
                .map_err(ModelError::BadState)?;
            if let Some(stats) = stats {
                scene.sim.set_stats(stats);
            }
            if version >= 4 {
                for (what, peak) in [
                    ("root peak force", &mut scene.interface_peaks.force),
                    ("root peak torque", &mut scene.interface_peaks.torque),
                ] {
                    *peak = r.finite_f64(what)?;
                    if *peak < 0.0 {
                        return Err(ModelError::BadState(format!(
                            "corrupt state: the {what} is negative ({peak})"
                        )));
                    }
                }
            } else {
                // older states: the peaks from the restored point on
                let now = scene
                    .root_wrench()
                    .map_err(|e| ModelError::BadState(e.to_string()))?;
                scene.interface_peaks = Default::default();
                scene.interface_peaks.note(&now);
            }
            if version >= 5 {
                let monitors = r.f64s("integrator monitors")?;
                scene
                    .sim
                    .restore_integrator_monitors(&monitors)
                    .map_err(ModelError::BadState)?;
            }
            if version >= 6 {
                scene.interface_peaks.work = r.finite_f64("root interface work")?;
            }
            if version >= 7 {
                let hz = r.finite_f64("locked frequency")?;
                let locked = r.f64s("locked set")?;
                if hz < 0.0 || locked.iter().any(|&l| l != 0.0 && l != 1.0) {
                    return Err(ModelError::BadState(format!(
                        "corrupt state: locked frequency {hz} Hz or locked set {locked:?}"
                    )));
                }
                scene.locked_frequency.hz = hz;
                scene.locked_frequency.locked = locked.iter().map(|&l| l == 1.0).collect();
            } else if let Update::Failed(note) = scene.update_locked_frequency() {
                restored.log.push(LogRecord {
                    level: LogLevel::Warning,
                    message: note,
                });
            }
            restored.scene = Some(scene);
        }
        r.finish()?;
        *self = restored;
        Ok(())
    }

    /// Back to a fresh instance, tables included (the FMI wrapper applies the scene file again).
    fn reset(&mut self) {
        *self = PanelLockModel::new();
    }

    fn snapshot(&mut self) -> Option<Snapshot> {
        let start = self.clock.start();
        self.scene.as_mut().map(|s| s.snapshot(start))
    }

    fn take_log(&mut self) -> Vec<LogRecord> {
        std::mem::take(&mut self.log)
    }

    fn solver_stats(&self) -> Option<Stats> {
        self.scene.as_ref().map(|s| s.sim.stats())
    }

    /// Reads the scene file's `[[hinge]]` and `[[panel]]` tables and checks them with the
    /// parameters set so far (again at initialization, with the importer's values).
    fn set_tables(&mut self, tables: &[SceneTable], origin: &str) -> Result<(), String> {
        if self.ports.is_initialized() {
            return Err(format!(
                "{origin}: the array's tables are set before initialization only"
            ));
        }
        self.tables = read_array(tables, origin)?;
        self.params()
            .map(|_| ())
            .map_err(|e| format!("{origin}: {e}"))
    }
}
