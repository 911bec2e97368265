//! The FMI 3.0 entry points of [`Instance`]: the same instance, state machine, variable table and
//! FMU states as FMI 2.0; only the value references ([`super::super::variables3`]), the value
//! types and the argument shapes differ. Each method resolves FMI 3.0 references to the FMI 2.0
//! ones (an array to its elements, [`super::super::arrays3`]) and calls the shared FMI 2.0 body
//! where one exists.

use std::os::raw::{c_char, c_int};

use super::super::arrays3::{Var3, View3};
use super::super::machine::past_initialization;
use super::super::types::fmi2OK;
use super::super::variables3::{TIME_NAME, TIME_VR, Type3};
use super::{Instance, Outcome};
use crate::scene::port::{BaseType, ValueRef};
use crate::scene::store::{check_integer, check_writable};

impl Instance {
    /// The FMI 3.0 variables of this model (built at the first call).
    fn view3(&self) -> Outcome<&View3> {
        self.view3
            .get_or_init(|| View3::new(self.info))
            .as_ref()
            .map_err(|e| e.clone())
    }

    /// The variable behind FMI 3.0 value reference `vr3`, which must be of type `want`; `None`
    /// for the independent variable `time` (a Float64).
    fn var3(&self, want: Type3, vr3: u32) -> Outcome<Option<&Var3>> {
        let info = self.info;
        let view = self.view3()?;
        if vr3 == TIME_VR && want == Type3::Float64 {
            return Ok(None);
        }
        let Some(var) = view.get(vr3) else {
            let hint = match view.folded(vr3) {
                Some((array, j)) => format!(
                    " (in FMI 3.0, `{}` is element {j} of the array `{}`, value reference {})",
                    info.ports[array.ports[j]].name, array.name, array.vr
                ),
                None => String::new(),
            };
            return Err(format!(
                "unknown value reference {vr3}: `{}` has no {} variable with it{hint}",
                info.identifier,
                want.element()
            ));
        };
        if var.ty != want {
            return Err(format!(
                "value reference {vr3} is `{}`, {} {} variable, not {}",
                var.name,
                // "an Int32", "an Enumeration"
                if var.ty.element().starts_with(['E', 'I']) {
                    "an"
                } else {
                    "a"
                },
                var.ty.accessor(),
                want.element()
            ));
        }
        Ok(Some(var))
    }

    /// The FMI 2.0 value references behind `vrs` (all of type `want`), each array expanded into
    /// its elements in order (`None` stands for `time`); fails unless they are `n_values`
    /// values, as FMI 3.0 counts `nValues`.
    fn expand3(&self, want: Type3, vrs: &[u32], n_values: usize) -> Outcome<Vec<Option<ValueRef>>> {
        let info = self.info;
        let mut refs = Vec::with_capacity(vrs.len());
        let mut arrays = Vec::new();
        for &v in vrs {
            match self.var3(want, v)? {
                None => refs.push(None),
                Some(var) => {
                    if var.is_array() {
                        arrays.push(format!("`{}` ({v}) has {}", var.name, var.ports.len()));
                    }
                    refs.extend(var.ports.iter().map(|&i| Some(info.ports[i].vr)));
                }
            }
        }
        if refs.len() != n_values {
            let detail = if arrays.is_empty() {
                "every one is a scalar".to_string()
            } else {
                format!("an array counts its elements: {}", arrays.join(", "))
            };
            return Err(format!(
                "nValues = {n_values} does not match the {} values of the {} value references ({detail})",
                refs.len(),
                vrs.len()
            ));
        }
        Ok(refs)
    }

    /// [`Self::expand3`] for a type without `time`.
    fn refs3(&self, want: Type3, vrs: &[u32], n_values: usize) -> Outcome<Vec<ValueRef>> {
        Ok(self
            .expand3(want, vrs, n_values)?
            .into_iter()
            .flatten()
            .collect())
    }

    /// [`Self::expand3`] for a setter: `time` and arrays that cannot be written are refused.
    fn set_refs3(&self, want: Type3, vrs: &[u32], n_values: usize) -> Outcome<Vec<ValueRef>> {
        let initialized = past_initialization(self.machine.state);
        for &v in vrs {
            match self.var3(want, v)? {
                None => {
                    return Err(format!(
                        "value reference {v} is the independent variable `{TIME_NAME}`, which cannot be set"
                    ));
                }
                Some(var) if var.is_array() => {
                    check_writable(var.head(self.info), initialized).map_err(|e| {
                        format!(
                            "{e} (element 0 of the FMI 3.0 array `{}`, value reference {v})",
                            var.name
                        )
                    })?;
                }
                Some(_) => {}
            }
        }
        self.refs3(want, vrs, n_values)
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

    /// `fmi3GetFloat64`: `time` included; an array gives its elements in order.
    pub fn get_float64(&mut self, vrs: &[u32], out: &mut [f64]) -> Outcome {
        let refs = self.expand3(Type3::Float64, vrs, out.len())?;
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
        let refs = self.refs3(Type3::Int32, vrs, out.len())?;
        self.get_integers(&refs, out)
    }

    /// `fmi3GetInt64`: enumerations.
    pub fn get_int64(&mut self, vrs: &[u32], out: &mut [i64]) -> Outcome {
        let refs = self.refs3(Type3::Enumeration, vrs, out.len())?;
        let mut values: Vec<c_int> = vec![0; refs.len()];
        let status = self.get_integers(&refs, &mut values)?;
        for (o, v) in out.iter_mut().zip(values) {
            *o = i64::from(v);
        }
        Ok(status)
    }

    /// `fmi3GetBoolean`: 1 or 0.
    pub fn get_boolean3(&mut self, vrs: &[u32], out: &mut [u8]) -> Outcome {
        let refs = self.refs3(Type3::Boolean, vrs, out.len())?;
        let mut values: Vec<c_int> = vec![0; refs.len()];
        let status = self.get_booleans(&refs, &mut values)?;
        for (o, v) in out.iter_mut().zip(values) {
            *o = u8::from(v != 0);
        }
        Ok(status)
    }

    /// `fmi3GetString`: the pointers stay valid until the next call on this instance.
    pub fn get_string3(&mut self, vrs: &[u32], out: &mut [*const c_char]) -> Outcome {
        let refs = self.refs3(Type3::String, vrs, out.len())?;
        self.get_strings(&refs, out)
    }

    /// `fmi3SetFloat64`: NaN, infinities and values outside `[min, max]` are refused.
    pub fn set_float64(&mut self, vrs: &[u32], values: &[f64]) -> Outcome {
        let refs = self.set_refs3(Type3::Float64, vrs, values.len())?;
        self.set_reals(&refs, values)
    }

    /// `fmi3SetInt32`.
    pub fn set_int32(&mut self, vrs: &[u32], values: &[i32]) -> Outcome {
        let refs = self.set_refs3(Type3::Int32, vrs, values.len())?;
        self.set_integers(&refs, values)
    }

    /// `fmi3SetInt64`: enumerations; a value outside the items is refused.
    pub fn set_int64(&mut self, vrs: &[u32], values: &[i64]) -> Outcome {
        let refs = self.set_refs3(Type3::Enumeration, vrs, values.len())?;
        let mut narrow = Vec::with_capacity(refs.len());
        for (vr, v) in refs.iter().zip(values) {
            let spec = self.spec(BaseType::Integer, *vr)?;
            let small = i32::try_from(*v).map_err(|_| {
                format!("`{}` = {v} is not one of its enumeration items", spec.name)
            })?;
            check_integer(spec, small).map_err(|e| e.to_string())?;
            narrow.push(small);
        }
        self.set_integers(&refs, &narrow)
    }

    /// `fmi3SetBoolean`: any non-zero byte is true.
    pub fn set_boolean3(&mut self, vrs: &[u32], values: &[u8]) -> Outcome {
        let refs = self.set_refs3(Type3::Boolean, vrs, values.len())?;
        let wide: Vec<c_int> = values.iter().map(|v| c_int::from(*v != 0)).collect();
        self.set_booleans(&refs, &wide)
    }

    /// `fmi3SetString`.
    pub fn set_string3(&mut self, vrs: &[u32], values: &[&str]) -> Outcome {
        let refs = self.set_refs3(Type3::String, vrs, values.len())?;
        self.set_strings(&refs, values)
    }
}
