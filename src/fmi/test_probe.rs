//! A test model for the wrapper tests: every variable type, a fixed parameter with a minimum,
//! an enumeration, a model warning on negative force, a solver failure on a huge force and a
//! panic on request.

use std::sync::OnceLock;

use crate::scene::bytes::{ByteReader, ByteWriter};
use crate::scene::port::{Causality, ModelInfo, PortSpec, PortType, Variability};
use crate::scene::store::PortStore;
use crate::scene::{CoSimModel, LogLevel, LogRecord, ModelEntry, ModelError};

const MODES: &[(&str, &str)] = &[("slow", "Slow mode."), ("fast", "Fast mode.")];

/// Real value reference: fixed parameter `mass` [kg], min 0.
pub const MASS: u32 = 0;
/// Real value reference: tunable parameter `gain`.
pub const GAIN: u32 = 1;
/// Real value reference: input `force` [N].
pub const FORCE: u32 = 2;
/// Real value reference: output `x` [m].
pub const X: u32 = 3;
/// Real value references of the outputs `arm0_x`, `arm1_x`, `arm2_x` [m] (`arm<k>_x` =
/// (k + 1) x): an FMI 3.0 array `arm_x`.
pub const ARM_X: [u32; 3] = [4, 5, 6];
/// Boolean value reference: tunable `panic_now` (panic in the next step).
pub const PANIC_NOW: u32 = 0;

fn test_info() -> &'static ModelInfo {
    static INFO: OnceLock<ModelInfo> = OnceLock::new();
    INFO.get_or_init(|| ModelInfo {
        identifier: "Probe",
        guid: "{probe}",
        description: "Test model.",
        ports: vec![
            PortSpec::real_parameter("mass", MASS, Variability::Fixed, 1.0, Some("kg"), "Mass.")
                .with_min(0.0),
            PortSpec::real_parameter("gain", GAIN, Variability::Tunable, 1.0, None, "Gain."),
            PortSpec::real_input("force", FORCE, 0.0, Some("N"), "Force."),
            PortSpec::real_output("x", X, Some("m"), "Position."),
            PortSpec::real_output("arm0_x", ARM_X[0], Some("m"), "Arm 0: position x."),
            PortSpec::real_output("arm1_x", ARM_X[1], Some("m"), "Arm 1: position 2 x."),
            PortSpec::real_output("arm2_x", ARM_X[2], Some("m"), "Arm 2: position 3 x."),
            PortSpec {
                name: "mode".into(),
                vr: 0,
                causality: Causality::Parameter,
                variability: Variability::Fixed,
                ty: PortType::Enumeration {
                    type_name: "Mode",
                    items: MODES,
                    start: Some(1),
                },
                unit: None,
                description: "Mode.".into(),
            },
            PortSpec {
                name: "label".into(),
                vr: 0,
                causality: Causality::Parameter,
                variability: Variability::Tunable,
                ty: PortType::String { start: Some("a") },
                unit: None,
                description: "Label.".into(),
            },
            PortSpec::boolean_parameter(
                "panic_now",
                PANIC_NOW,
                Variability::Tunable,
                false,
                "Panic in the next step.",
            ),
        ],
        default_stop_time: 1.0,
        default_step: 0.1,
        initial_dependencies: crate::scene::port::on_all_knowns,
    })
}

#[derive(Clone)]
struct Probe {
    ports: PortStore,
    time: f64,
    log: Vec<LogRecord>,
}

impl Probe {
    /// Writes `x` and the arm outputs derived from it.
    fn put_x(&mut self, x: f64) -> Result<(), ModelError> {
        self.ports.put_real(X, x)?;
        for (k, vr) in ARM_X.iter().enumerate() {
            self.ports.put_real(*vr, (k + 1) as f64 * x)?;
        }
        Ok(())
    }

    fn boxed() -> Box<dyn CoSimModel> {
        Box::new(Probe {
            ports: PortStore::new(test_info()),
            time: 0.0,
            log: Vec::new(),
        })
    }
}

impl CoSimModel for Probe {
    fn ports(&self) -> &PortStore {
        &self.ports
    }
    fn ports_mut(&mut self) -> &mut PortStore {
        &mut self.ports
    }
    fn set_up(&mut self, t: f64) -> Result<(), ModelError> {
        self.time = t;
        let x0 = self.ports.get_real(MASS)? * self.ports.get_real(FORCE)?;
        self.put_x(x0)?;
        Ok(())
    }
    fn do_step_watched(
        &mut self,
        request: crate::scene::StepRequest,
        _watch: &mut dyn crate::scene::watch::StepWatch,
    ) -> Result<crate::scene::watch::StepEnd, ModelError> {
        let (t, h) = (request.t(), request.h());
        if self.ports.get_boolean(PANIC_NOW)? {
            panic!("probe asked to panic");
        }
        let f = self.ports.get_real(FORCE)?;
        if f > 1e6 {
            return Err(ModelError::SolverFailure(
                "force too large: the probe diverged".into(),
            ));
        }
        let x = self.ports.get_real(X)? + self.ports.get_real(GAIN)? * f * h;
        self.put_x(x)?;
        self.time = t + h;
        self.log.push(LogRecord {
            level: LogLevel::Event,
            message: format!("stepped to {}", self.time),
        });
        if f < 0.0 {
            self.log.push(LogRecord {
                level: LogLevel::Warning,
                message: "negative force".into(),
            });
        }
        Ok(crate::scene::watch::StepEnd::Complete)
    }
    fn time(&self) -> f64 {
        self.time
    }
    fn clone_box(&self) -> Box<dyn CoSimModel> {
        Box::new(self.clone())
    }
    fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.header("Probe", 1);
        self.ports.write(&mut w);
        w.f64(self.time);
        w.into_bytes()
    }
    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let mut r = ByteReader::new(bytes);
        r.header("Probe", 1)?;
        let ports = self.ports.read(&mut r)?;
        let time = r.f64("time")?;
        r.finish()?;
        *self = Probe {
            ports,
            time,
            log: Vec::new(),
        };
        Ok(())
    }
    fn reset(&mut self) {
        *self = Probe {
            ports: PortStore::new(test_info()),
            time: 0.0,
            log: Vec::new(),
        };
    }
    fn take_log(&mut self) -> Vec<LogRecord> {
        std::mem::take(&mut self.log)
    }
}

pub fn probe_entry() -> ModelEntry {
    ModelEntry::new(test_info, Probe::boxed)
}
