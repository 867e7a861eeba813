//! The FMI 3.0 co-simulation functions (`fmi3…`, C ABI, no prefix), each a guarded call on
//! an [`Instance`]. Model exchange and scheduled execution are not offered (their
//! instantiation returns null); the types without variables (Float32, the integers, String,
//! Binary, Clock) accept empty calls only; the FMU state can be got and set but not
//! serialised (`canSerializeFMUState="false"`).
#![allow(clippy::missing_safety_doc)]

use crate::ffi::c_string;
use crate::ffi::{
    free_state, get_each, guard, instance, restore_state, save_state, set_each, slice, slice_mut,
    text, with,
};
use crate::instance::{FmuError, Instance, Status};
use std::ffi::{c_char, c_int, c_void};
use std::path::PathBuf;

/// `void (*)(fmi3InstanceEnvironment, fmi3Status, fmi3String category, fmi3String message)`.
pub type LogMessage =
    Option<unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char)>;

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    inst: *mut c_void,
    logging_on: bool,
    _n_categories: usize,
    _categories: *const *const c_char,
) -> c_int {
    with(inst, |i| {
        i.logging_on = logging_on;
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _name: *const c_char,
    _token: *const c_char,
    _resources: *const c_char,
    _visible: bool,
    _logging_on: bool,
    env: *mut c_void,
    log: LogMessage,
) -> *mut c_void {
    if let Some(log) = log {
        let m = c_string("this FMU offers co-simulation only");
        log(
            env,
            Status::Error as c_int,
            c"logStatusError".as_ptr(),
            m.as_ptr(),
        );
    }
    std::ptr::null_mut()
}

#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    name: *const c_char,
    token: *const c_char,
    resources: *const c_char,
    _visible: bool,
    logging_on: bool,
    _event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate: *const u32,
    _n_required_intermediate: usize,
    env: *mut c_void,
    log: LogMessage,
    _intermediate_update: *mut c_void,
) -> *mut c_void {
    let env_addr = env as usize;
    let logger = move |status: Status, category: &str, message: &str| {
        if let Some(log) = log {
            let (c, m) = (c_string(category), c_string(message));
            log(
                env_addr as *mut c_void,
                status as c_int,
                c.as_ptr(),
                m.as_ptr(),
            );
        }
    };
    crate::ffi::instantiate(
        text(name).unwrap_or_default(),
        text(resources).map(PathBuf::from),
        text(token),
        logger,
        logging_on,
    )
}

#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _name: *const c_char,
    _token: *const c_char,
    _resources: *const c_char,
    _visible: bool,
    _logging_on: bool,
    env: *mut c_void,
    log: LogMessage,
    _clock_update: *mut c_void,
    _lock: *mut c_void,
    _unlock: *mut c_void,
) -> *mut c_void {
    fmi3InstantiateModelExchange(
        std::ptr::null(),
        std::ptr::null(),
        std::ptr::null(),
        false,
        false,
        env,
        log,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(inst: *mut c_void) {
    let _ = std::panic::catch_unwind(|| crate::ffi::free(inst));
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    inst: *mut c_void,
    _tolerance_defined: bool,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: bool,
    _stop_time: f64,
) -> c_int {
    with(inst, |i| i.enter_initialization(start_time))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(inst: *mut c_void) -> c_int {
    with(inst, Instance::exit_initialization)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(inst: *mut c_void) -> c_int {
    with(inst, |_| {
        Err(FmuError::Unsupported("this FMU has no event mode"))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(inst: *mut c_void) -> c_int {
    with(inst, |_| Ok(()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(inst: *mut c_void) -> c_int {
    with(inst, Instance::terminate)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(inst: *mut c_void) -> c_int {
    with(inst, Instance::reset)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *mut f64,
    n_values: usize,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice_mut(values, n_values));
    with(inst, |i| get_each(i, vrs, values, Instance::get_real))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *const f64,
    n_values: usize,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice(values, n_values));
    with(inst, |i| set_each(i, vrs, values, Instance::set_real))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *mut bool,
    n_values: usize,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice_mut(values, n_values));
    with(inst, |i| get_each(i, vrs, values, Instance::get_bool))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *const bool,
    n_values: usize,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice(values, n_values));
    with(inst, |i| set_each(i, vrs, values, Instance::set_bool))
}

/// A call on value references of a type this FMU has no variable of: fine when empty.
fn none_of_type(vrs: &[u32]) -> Result<(), FmuError> {
    crate::ffi::none_of_type(vrs, "Float64 or Boolean")
}

/// Getters and setters of the types without variables.
macro_rules! no_variables_of_type {
    ($($get:ident $set:ident $t:ty;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            inst: *mut c_void, vrs: *const u32, nvr: usize, _values: *mut $t, _n: usize,
        ) -> c_int {
            let vrs = slice(vrs, nvr);
            with(inst, |_| none_of_type(vrs))
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            inst: *mut c_void, vrs: *const u32, nvr: usize, _values: *const $t, _n: usize,
        ) -> c_int {
            let vrs = slice(vrs, nvr);
            with(inst, |_| none_of_type(vrs))
        }
    )*};
}

no_variables_of_type! {
    fmi3GetFloat32 fmi3SetFloat32 f32;
    fmi3GetInt8 fmi3SetInt8 i8;
    fmi3GetUInt8 fmi3SetUInt8 u8;
    fmi3GetInt16 fmi3SetInt16 i16;
    fmi3GetUInt16 fmi3SetUInt16 u16;
    fmi3GetInt32 fmi3SetInt32 i32;
    fmi3GetUInt32 fmi3SetUInt32 u32;
    fmi3GetInt64 fmi3SetInt64 i64;
    fmi3GetUInt64 fmi3SetUInt64 u64;
    fmi3GetString fmi3SetString *const c_char;
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _sizes: *mut usize,
    _values: *mut *const u8,
    _n: usize,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(inst, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _sizes: *const usize,
    _values: *const *const u8,
    _n: usize,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(inst, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *mut bool,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(inst, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    inst: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *const bool,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(inst, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(inst: *mut c_void, state: *mut *mut c_void) -> c_int {
    with(inst, |i| save_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(inst: *mut c_void, state: *mut c_void) -> c_int {
    with(inst, |i| restore_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(_inst: *mut c_void, state: *mut *mut c_void) -> c_int {
    guard(|| free_state(state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    inst: *mut c_void,
    _state: *mut c_void,
    _size: *mut usize,
) -> c_int {
    with(inst, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    inst: *mut c_void,
    _state: *mut c_void,
    _bytes: *mut u8,
    _size: usize,
) -> c_int {
    with(inst, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    inst: *mut c_void,
    _bytes: *const u8,
    _size: usize,
    _state: *mut *mut c_void,
) -> c_int {
    with(inst, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    inst: *mut c_void,
    _vrs: *const u32,
    _nvr: usize,
    _orders: *const i32,
    _values: *mut f64,
    _n: usize,
) -> c_int {
    with(inst, |_| {
        Err(FmuError::Unsupported(
            "output derivatives are not provided (maxOutputDerivativeOrder = 0)",
        ))
    })
}

crate::ffi::unsupported! {
    fmi3GetNumberOfVariableDependencies(vr: u32, n: *mut usize)
        => "variable dependencies are not provided";
    fmi3GetVariableDependencies(
        dependent: u32, dependent_elements: *mut usize, independents: *mut u32,
        independent_elements: *mut usize, kinds: *mut c_int, n: usize
    ) => "variable dependencies are not provided";
    fmi3GetDirectionalDerivative(
        unknowns: *const u32, n_unknowns: usize, knowns: *const u32, n_knowns: usize,
        seed: *const f64, n_seed: usize, sensitivity: *mut f64, n_sensitivity: usize
    ) => "directional derivatives are not provided";
    fmi3GetAdjointDerivative(
        unknowns: *const u32, n_unknowns: usize, knowns: *const u32, n_knowns: usize,
        seed: *const f64, n_seed: usize, sensitivity: *mut f64, n_sensitivity: usize
    ) => "adjoint derivatives are not provided";
    fmi3EnterConfigurationMode() => "this FMU has no structural parameters";
    fmi3ExitConfigurationMode() => "this FMU has no structural parameters";
    fmi3ActivateModelPartition(clock: u32, time: f64) => "this FMU has no clocks";
    fmi3GetIntervalDecimal(vrs: *const u32, nvr: usize, intervals: *mut f64, qualifiers: *mut c_int)
        => "this FMU has no clocks";
    fmi3GetIntervalFraction(
        vrs: *const u32, nvr: usize, counters: *mut u64, resolutions: *mut u64,
        qualifiers: *mut c_int
    ) => "this FMU has no clocks";
    fmi3GetShiftDecimal(vrs: *const u32, nvr: usize, shifts: *mut f64) => "this FMU has no clocks";
    fmi3GetShiftFraction(vrs: *const u32, nvr: usize, counters: *mut u64, resolutions: *mut u64)
        => "this FMU has no clocks";
    fmi3SetIntervalDecimal(vrs: *const u32, nvr: usize, intervals: *const f64)
        => "this FMU has no clocks";
    fmi3SetIntervalFraction(
        vrs: *const u32, nvr: usize, counters: *const u64, resolutions: *const u64
    ) => "this FMU has no clocks";
    fmi3SetShiftDecimal(vrs: *const u32, nvr: usize, shifts: *const f64) => "this FMU has no clocks";
    fmi3SetShiftFraction(
        vrs: *const u32, nvr: usize, counters: *const u64, resolutions: *const u64
    ) => "this FMU has no clocks";
    fmi3EvaluateDiscreteStates() => "this FMU has no event mode";
    fmi3UpdateDiscreteStates(
        need_update: *mut bool, terminate: *mut bool, nominals_changed: *mut bool,
        values_changed: *mut bool, next_event_defined: *mut bool, next_event: *mut f64
    ) => "this FMU has no event mode";
    fmi3EnterContinuousTimeMode() => "this FMU offers co-simulation only";
    fmi3CompletedIntegratorStep(no_set_prior: bool, enter_event: *mut bool, terminate: *mut bool)
        => "this FMU offers co-simulation only";
    fmi3SetTime(time: f64) => "this FMU offers co-simulation only";
    fmi3SetContinuousStates(x: *const f64, n: usize) => "this FMU offers co-simulation only";
    fmi3GetContinuousStateDerivatives(dx: *mut f64, n: usize)
        => "this FMU offers co-simulation only";
    fmi3GetEventIndicators(z: *mut f64, n: usize) => "this FMU offers co-simulation only";
    fmi3GetContinuousStates(x: *mut f64, n: usize) => "this FMU offers co-simulation only";
    fmi3GetNominalsOfContinuousStates(x: *mut f64, n: usize)
        => "this FMU offers co-simulation only";
    fmi3GetNumberOfEventIndicators(n: *mut usize) => "this FMU offers co-simulation only";
    fmi3GetNumberOfContinuousStates(n: *mut usize) => "this FMU offers co-simulation only";
}

#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn fmi3DoStep(
    inst: *mut c_void,
    time: f64,
    step: f64,
    _no_set_state_prior: bool,
    event_handling_needed: *mut bool,
    terminate: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> c_int {
    for flag in [event_handling_needed, terminate, early_return] {
        if !flag.is_null() {
            *flag = false;
        }
    }
    let status = with(inst, |i| i.do_step(time, step));
    if !last_successful_time.is_null() {
        let reached = instance(inst).and_then(|i| i.get_real(0).ok());
        *last_successful_time = reached.unwrap_or(time);
    }
    status
}
