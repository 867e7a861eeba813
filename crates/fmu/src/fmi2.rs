//! The FMI 2.0 co-simulation functions (`fmi2…`, C ABI, no prefix), each a guarded call on an
//! [`Instance`]. Model exchange is not offered (instantiating it returns null); there are no
//! Integer or String variables; inputs are held over a step (`canInterpolateInputs="false"`:
//! input derivatives are refused); the FMU state can be got and set, not serialised.
#![allow(clippy::missing_safety_doc)]

use crate::ffi::c_string;
use crate::ffi::{
    free_state, get_each, guard, instance, path_of_uri, restore_state, save_state, set_each, slice,
    slice_mut, text, with,
};
use crate::instance::{FmuError, Instance, Status};
use std::ffi::{c_char, c_int, c_void};

/// `void (*)(fmi2ComponentEnvironment, fmi2String instanceName, fmi2Status, fmi2String
/// category, fmi2String message, ...)`: the message is a printf format, so it is passed
/// as the argument of `"%s"`.
pub type Logger = Option<
    unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char, ...),
>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    pub logger: Logger,
    pub allocate_memory: *mut c_void,
    pub free_memory: *mut c_void,
    pub step_finished: *mut c_void,
    pub component_environment: *mut c_void,
}

/// `fmi2CoSimulation`.
const CO_SIMULATION: c_int = 1;

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: *mut c_void,
    logging_on: c_int,
    _n_categories: usize,
    _categories: *const *const c_char,
) -> c_int {
    with(c, |i| {
        i.logging_on = logging_on != 0;
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: c_int,
    logging_on: c_int,
) -> *mut c_void {
    let (log, env) = match functions.as_ref() {
        Some(f) => (f.logger, f.component_environment as usize),
        None => (None, 0),
    };
    let instance_name = text(name).unwrap_or_default();
    let c_name = c_string(&instance_name);
    let logger = move |status: Status, category: &str, message: &str| {
        if let Some(log) = log {
            let (c, m) = (c_string(category), c_string(message));
            log(
                env as *mut c_void,
                c_name.as_ptr(),
                status as c_int,
                c.as_ptr(),
                c"%s".as_ptr(),
                m.as_ptr(),
            );
        }
    };
    if fmu_type != CO_SIMULATION {
        logger(
            Status::Error,
            "logStatusError",
            "this FMU offers co-simulation only",
        );
        return std::ptr::null_mut();
    }
    crate::ffi::instantiate(
        instance_name,
        text(resource_location).map(|l| path_of_uri(&l)),
        text(guid),
        logger,
        logging_on != 0,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    let _ = std::panic::catch_unwind(|| crate::ffi::free(c));
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: *mut c_void,
    _tolerance_defined: c_int,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: c_int,
    _stop_time: f64,
) -> c_int {
    with(c, |i| {
        i.setup(start_time);
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: *mut c_void) -> c_int {
    with(c, |i| i.enter_initialization(i.start_time()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: *mut c_void) -> c_int {
    with(c, Instance::exit_initialization)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: *mut c_void) -> c_int {
    with(c, Instance::terminate)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: *mut c_void) -> c_int {
    with(c, Instance::reset)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *mut f64,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice_mut(values, nvr));
    with(c, |i| get_each(i, vrs, values, Instance::get_real))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *const f64,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice(values, nvr));
    with(c, |i| set_each(i, vrs, values, Instance::set_real))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *mut c_int,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice_mut(values, nvr));
    with(c, |i| {
        get_each(i, vrs, values, |i, vr| i.get_bool(vr).map(c_int::from))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    values: *const c_int,
) -> c_int {
    let (vrs, values) = (slice(vrs, nvr), slice(values, nvr));
    with(c, |i| {
        set_each(i, vrs, values, |i, vr, v| i.set_bool(vr, v != 0))
    })
}

/// A call on value references of a type this FMU has no variable of: fine when empty.
fn none_of_type(vrs: &[u32]) -> Result<(), FmuError> {
    crate::ffi::none_of_type(vrs, "Real or Boolean")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *mut c_int,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(c, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *const c_int,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(c, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *mut *const c_char,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(c, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: *mut c_void,
    vrs: *const u32,
    nvr: usize,
    _values: *const *const c_char,
) -> c_int {
    let vrs = slice(vrs, nvr);
    with(c, |_| none_of_type(vrs))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: *mut c_void, state: *mut *mut c_void) -> c_int {
    with(c, |i| save_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: *mut c_void, state: *mut c_void) -> c_int {
    with(c, |i| restore_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(_c: *mut c_void, state: *mut *mut c_void) -> c_int {
    guard(|| free_state(state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: *mut c_void,
    _state: *mut c_void,
    _size: *mut usize,
) -> c_int {
    with(c, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: *mut c_void,
    _state: *mut c_void,
    _bytes: *mut u8,
    _size: usize,
) -> c_int {
    with(c, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: *mut c_void,
    _bytes: *const u8,
    _size: usize,
    _state: *mut *mut c_void,
) -> c_int {
    with(c, |_| Err(crate::ffi::NO_SERIALIZATION))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: *mut c_void,
    _unknown: *const u32,
    _n_unknown: usize,
    _known: *const u32,
    _n_known: usize,
    _dv_known: *const f64,
    _dv_unknown: *mut f64,
) -> c_int {
    with(c, |_| {
        Err(FmuError::Unsupported(
            "directional derivatives are not provided",
        ))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: *mut c_void,
    _vrs: *const u32,
    _nvr: usize,
    _orders: *const c_int,
    _values: *const f64,
) -> c_int {
    with(c, |_| {
        Err(FmuError::Unsupported(
            "inputs are held over a step (canInterpolateInputs=false)",
        ))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: *mut c_void,
    _vrs: *const u32,
    _nvr: usize,
    _orders: *const c_int,
    _values: *mut f64,
) -> c_int {
    with(c, |_| {
        Err(FmuError::Unsupported(
            "output derivatives are not provided (maxOutputDerivativeOrder = 0)",
        ))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: *mut c_void,
    time: f64,
    step: f64,
    _no_set_state_prior: c_int,
) -> c_int {
    with(c, |i| i.do_step(time, step))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: *mut c_void) -> c_int {
    with(c, |_| {
        Err(FmuError::Unsupported(
            "steps run to their end (doStep never returns pending)",
        ))
    })
}

/// `fmi2LastSuccessfulTime`.
const LAST_SUCCESSFUL_TIME: c_int = 2;

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(c: *mut c_void, _kind: c_int, _value: *mut c_int) -> c_int {
    with(c, |_| {
        Err(FmuError::Unsupported("no asynchronous step status"))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: *mut c_void, kind: c_int, value: *mut f64) -> c_int {
    guard(|| {
        let Some(i) = instance(c) else {
            return Status::Error;
        };
        if kind != LAST_SUCCESSFUL_TIME || value.is_null() {
            i.log(
                Status::Error,
                "only fmi2LastSuccessfulTime is a real status",
            );
            return Status::Error;
        }
        *value = i.get_real(0).unwrap_or(f64::NAN);
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: *mut c_void,
    _kind: c_int,
    _value: *mut c_int,
) -> c_int {
    fmi2GetStatus(c, 0, std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: *mut c_void,
    _kind: c_int,
    _value: *mut c_int,
) -> c_int {
    fmi2GetStatus(c, 0, std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: *mut c_void,
    _kind: c_int,
    _value: *mut *const c_char,
) -> c_int {
    fmi2GetStatus(c, 0, std::ptr::null_mut())
}

crate::ffi::unsupported! {
    fmi2EnterEventMode() => "this FMU offers co-simulation only";
    fmi2NewDiscreteStates(event_info: *mut c_void) => "this FMU offers co-simulation only";
    fmi2EnterContinuousTimeMode() => "this FMU offers co-simulation only";
    fmi2CompletedIntegratorStep(no_set_prior: c_int, enter_event: *mut c_int, terminate: *mut c_int)
        => "this FMU offers co-simulation only";
    fmi2SetTime(time: f64) => "this FMU offers co-simulation only";
    fmi2SetContinuousStates(x: *const f64, n: usize) => "this FMU offers co-simulation only";
    fmi2GetDerivatives(dx: *mut f64, n: usize) => "this FMU offers co-simulation only";
    fmi2GetEventIndicators(z: *mut f64, n: usize) => "this FMU offers co-simulation only";
    fmi2GetContinuousStates(x: *mut f64, n: usize) => "this FMU offers co-simulation only";
    fmi2GetNominalsOfContinuousStates(x: *mut f64, n: usize)
        => "this FMU offers co-simulation only";
}
