//! The FMI 3.0 entry points of [`Instance`]: the same instance, state machine, variable table and
//! FMU states as FMI 2.0; only the value references ([`super::super::variables3`]), the value
//! types and the argument shapes differ. Each method resolves FMI 3.0 references to the FMI 2.0
//! ones and calls the shared FMI 2.0 body where one exists.

use std::os::raw::{c_char, c_int};

use super::super::types::fmi2OK;
use super::super::variables3::{TIME_NAME, TIME_VR, Type3, split};
use super::{Instance, Outcome};
use crate::scene::port::{PortSpec, ValueRef};
use crate::scene::store::check_integer;

impl Instance {
    /// The port behind FMI 3.0 value reference `vr3`, which must be of type `want`.
    fn spec3(&self, want: Type3, vr3: u32) -> Outcome<&'static PortSpec> {
        let info = self.info;
        let unknown = || {
            format!(
                "unknown value reference {vr3}: `{}` has no {} variable with it",
                info.identifier,
                want.element()
            )
        };
        if vr3 == TIME_VR {
            return if want == Type3::Float64 {
                Err(format!(
                    "value reference {vr3} is the independent variable `{TIME_NAME}`, which cannot be set"
                ))
            } else {
                Err(unknown())
            };
        }
        let (base, vr) = split(vr3).ok_or_else(unknown)?;
        let spec = self
            .index
            .get(base, vr)
            .map(|i| &info.ports[i])
            .ok_or_else(unknown)?;
        let found = Type3::of(&spec.ty);
        if found != want {
            return Err(format!(
                "value reference {vr3} is `{}`, a {} variable, not {}",
                spec.name,
                found.accessor(),
                want.element()
            ));
        }
        Ok(spec)
    }

    /// The FMI 2.0 value references behind `vrs` (all of type `want`).
    fn vrs2(&self, want: Type3, vrs: &[u32]) -> Outcome<Vec<ValueRef>> {
        vrs.iter()
            .map(|v| self.spec3(want, *v).map(|s| s.vr))
            .collect()
    }

    /// End time of the last successful step (or the start time) [s].
    pub fn last_successful_time(&self) -> f64 {
        self.machine.last_successful_time
    }

    /// `fmi3EnterInitializationMode`: the experiment of `fmi2SetupExperiment`, then
    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode3(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Outcome {
        self.setup_experiment(tolerance, start, stop)?;
        self.enter_initialization_mode()
    }

    /// `fmi3GetFloat64`: `time` included.
    pub fn get_float64(&mut self, vrs: &[u32], out: &mut [f64]) -> Outcome {
        let mut refs = Vec::with_capacity(vrs.len());
        for v in vrs {
            refs.push(if *v == TIME_VR {
                None
            } else {
                Some(self.spec3(Type3::Float64, *v)?.vr)
            });
        }
        let start = self.machine.start_time;
        let in_init = self.machine.state == super::State::InitializationMode;
        let m = self.reader()?;
        for (o, r) in out.iter_mut().zip(&refs) {
            *o = match r {
                Some(vr) => m.get_real(*vr).map_err(|e| e.to_string())?,
                None if in_init => start,
                None => m.time(),
            };
        }
        Ok(fmi2OK)
    }

    /// `fmi3GetInt32`.
    pub fn get_int32(&mut self, vrs: &[u32], out: &mut [i32]) -> Outcome {
        let refs = self.vrs2(Type3::Int32, vrs)?;
        self.get_integers(&refs, out)
    }

    /// `fmi3GetInt64`: enumerations.
    pub fn get_int64(&mut self, vrs: &[u32], out: &mut [i64]) -> Outcome {
        let refs = self.vrs2(Type3::Enumeration, vrs)?;
        let mut values: Vec<c_int> = vec![0; refs.len()];
        let status = self.get_integers(&refs, &mut values)?;
        for (o, v) in out.iter_mut().zip(values) {
            *o = i64::from(v);
        }
        Ok(status)
    }

    /// `fmi3GetBoolean`: 1 or 0.
    pub fn get_boolean3(&mut self, vrs: &[u32], out: &mut [u8]) -> Outcome {
        let refs = self.vrs2(Type3::Boolean, vrs)?;
        let mut values: Vec<c_int> = vec![0; refs.len()];
        let status = self.get_booleans(&refs, &mut values)?;
        for (o, v) in out.iter_mut().zip(values) {
            *o = u8::from(v != 0);
        }
        Ok(status)
    }

    /// `fmi3GetString`: the pointers stay valid until the next call on this instance.
    pub fn get_string3(&mut self, vrs: &[u32], out: &mut [*const c_char]) -> Outcome {
        let refs = self.vrs2(Type3::String, vrs)?;
        self.get_strings(&refs, out)
    }

    /// `fmi3SetFloat64`: NaN, infinities and values outside `[min, max]` are refused.
    pub fn set_float64(&mut self, vrs: &[u32], values: &[f64]) -> Outcome {
        let refs = self.vrs2(Type3::Float64, vrs)?;
        self.set_reals(&refs, values)
    }

    /// `fmi3SetInt32`.
    pub fn set_int32(&mut self, vrs: &[u32], values: &[i32]) -> Outcome {
        let refs = self.vrs2(Type3::Int32, vrs)?;
        self.set_integers(&refs, values)
    }

    /// `fmi3SetInt64`: enumerations; a value outside the items is refused.
    pub fn set_int64(&mut self, vrs: &[u32], values: &[i64]) -> Outcome {
        let mut refs = Vec::with_capacity(vrs.len());
        let mut narrow = Vec::with_capacity(vrs.len());
        for (vr3, v) in vrs.iter().zip(values) {
            let spec = self.spec3(Type3::Enumeration, *vr3)?;
            let small = i32::try_from(*v).map_err(|_| {
                format!("`{}` = {v} is not one of its enumeration items", spec.name)
            })?;
            check_integer(spec, small).map_err(|e| e.to_string())?;
            refs.push(spec.vr);
            narrow.push(small);
        }
        self.set_integers(&refs, &narrow)
    }

    /// `fmi3SetBoolean`: any non-zero byte is true.
    pub fn set_boolean3(&mut self, vrs: &[u32], values: &[u8]) -> Outcome {
        let refs = self.vrs2(Type3::Boolean, vrs)?;
        let wide: Vec<c_int> = values.iter().map(|v| c_int::from(*v != 0)).collect();
        self.set_booleans(&refs, &wide)
    }

    /// `fmi3SetString`.
    pub fn set_string3(&mut self, vrs: &[u32], values: &[&str]) -> Outcome {
        let refs = self.vrs2(Type3::String, vrs)?;
        self.set_strings(&refs, values)
    }
}
