//! The FMI 3.0 functions this FMU does not provide (the model description says so): each one
//! refuses with `fmi3Error` and the reason logged, so that importers binding the whole API load
//! the library and learn why a call failed.

use crate::fmi::boundary::guard;
use crate::fmi::machine::ALIVE;
use crate::fmi::types3::*;

macro_rules! unsupported {
    ($name:ident, $why:literal $(, $arg:ident : $ty:ty)*) => {
        #[doc = concat!("Not provided: `fmi3Error` (", $why, ").")]
        ///
        /// # Safety
        /// `instance` NULL or a live handle; the other arguments are not read.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(instance: fmi3Instance $(, $arg: $ty)*) -> fmi3Status {
            unsafe {
                guard(instance, stringify!($name), ALIVE, |_| {
                    Err(concat!("not supported: ", $why).into())
                })
            }
        }
    };
}

unsupported!(
    fmi3EnterEventMode,
    "hasEventMode=\"false\": Co-Simulation without event mode"
);
unsupported!(
    fmi3EnterConfigurationMode,
    "the models have no structural parameters"
);
unsupported!(
    fmi3ExitConfigurationMode,
    "the models have no structural parameters"
);
unsupported!(
    fmi3GetNumberOfVariableDependencies,
    "providesPerElementDependencies=\"false\"; the dependencies are in modelDescription.xml",
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut usize
);
unsupported!(
    fmi3GetVariableDependencies,
    "providesPerElementDependencies=\"false\"; the dependencies are in modelDescription.xml",
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut fmi3DependencyKind,
    _nDependencies: usize
);
unsupported!(
    fmi3GetDirectionalDerivative,
    "providesDirectionalDerivatives=\"false\"",
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: usize,
    _knowns: *const fmi3ValueReference,
    _nKnowns: usize,
    _seed: *const fmi3Float64,
    _nSeed: usize,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: usize
);
unsupported!(
    fmi3GetAdjointDerivative,
    "providesAdjointDerivatives=\"false\"",
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: usize,
    _knowns: *const fmi3ValueReference,
    _nKnowns: usize,
    _seed: *const fmi3Float64,
    _nSeed: usize,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: usize
);
unsupported!(
    fmi3GetIntervalDecimal,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _intervals: *mut fmi3Float64,
    _qualifiers: *mut fmi3IntervalQualifier
);
unsupported!(
    fmi3GetIntervalFraction,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _counters: *mut fmi3UInt64,
    _resolutions: *mut fmi3UInt64,
    _qualifiers: *mut fmi3IntervalQualifier
);
unsupported!(
    fmi3GetShiftDecimal,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _shifts: *mut fmi3Float64
);
unsupported!(
    fmi3GetShiftFraction,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _counters: *mut fmi3UInt64,
    _resolutions: *mut fmi3UInt64
);
unsupported!(
    fmi3SetIntervalDecimal,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _intervals: *const fmi3Float64
);
unsupported!(
    fmi3SetIntervalFraction,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _counters: *const fmi3UInt64,
    _resolutions: *const fmi3UInt64
);
unsupported!(
    fmi3SetShiftDecimal,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _shifts: *const fmi3Float64
);
unsupported!(
    fmi3SetShiftFraction,
    "the models have no clocks",
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _counters: *const fmi3UInt64,
    _resolutions: *const fmi3UInt64
);
unsupported!(
    fmi3EvaluateDiscreteStates,
    "providesEvaluateDiscreteStates=\"false\""
);
unsupported!(
    fmi3UpdateDiscreteStates,
    "hasEventMode=\"false\": no event mode",
    _discreteStatesNeedUpdate: *mut fmi3Boolean,
    _terminateSimulation: *mut fmi3Boolean,
    _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    _nextEventTimeDefined: *mut fmi3Boolean,
    _nextEventTime: *mut fmi3Float64
);
unsupported!(
    fmi3EnterContinuousTimeMode,
    "Model Exchange is not provided"
);
unsupported!(
    fmi3CompletedIntegratorStep,
    "Model Exchange is not provided",
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    _enterEventMode: *mut fmi3Boolean,
    _terminateSimulation: *mut fmi3Boolean
);
unsupported!(fmi3SetTime, "Model Exchange is not provided", _time: fmi3Float64);
unsupported!(
    fmi3SetContinuousStates,
    "Model Exchange is not provided",
    _continuousStates: *const fmi3Float64,
    _nContinuousStates: usize
);
unsupported!(
    fmi3GetContinuousStateDerivatives,
    "Model Exchange is not provided",
    _derivatives: *mut fmi3Float64,
    _nContinuousStates: usize
);
unsupported!(
    fmi3GetEventIndicators,
    "Model Exchange is not provided",
    _eventIndicators: *mut fmi3Float64,
    _nEventIndicators: usize
);
unsupported!(
    fmi3GetContinuousStates,
    "Model Exchange is not provided",
    _continuousStates: *mut fmi3Float64,
    _nContinuousStates: usize
);
unsupported!(
    fmi3GetNominalsOfContinuousStates,
    "Model Exchange is not provided",
    _nominals: *mut fmi3Float64,
    _nContinuousStates: usize
);
unsupported!(
    fmi3GetNumberOfEventIndicators,
    "Model Exchange is not provided",
    _nEventIndicators: *mut usize
);
unsupported!(
    fmi3GetNumberOfContinuousStates,
    "Model Exchange is not provided",
    _nContinuousStates: *mut usize
);
unsupported!(
    fmi3ActivateModelPartition,
    "Scheduled Execution is not provided",
    _clockReference: fmi3ValueReference,
    _activationTime: fmi3Float64
);
