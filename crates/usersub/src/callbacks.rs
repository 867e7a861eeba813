//! The utility routines a subroutine calls back into (SYSFNC, SYSARY, TIMGET, ERRMES, USRMES)
//! and the record of one subroutine call they write to.
//!
//! A call of a subroutine pushes a [`Frame`] on this thread's stack: the environment the
//! expression evaluator gave (time, measures, states), whether gradients are wanted, the
//! perturbation of one quantity while partials are differenced, and what the subroutine did
//! (the quantities it read with their gradients, ERRMES with STOP, a read that failed).
//! SYSFNC evaluates `NAME(ipar…)` with the expression language's own evaluator, so every
//! measure the language has (DX…, VX…, WX…, ACCX…, PSI/THETA/PHI, FX…, element forces,
//! VARVAL, DIF, ARYVAL, PINVAL, …) is available with the same meaning.

use crate::error::ReadError;
use linkage_expr::{evaluate, evaluate_with_gradient, parse, Dual, Env, Expr};
use std::cell::RefCell;
use std::collections::HashMap;
use std::ffi::{c_char, c_int};

/// A quantity a subroutine reads: TIME (its argument and TIMGET), or `NAME(ipar…)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Key {
    Time,
    Measure(String, Vec<i32>),
}

/// One subroutine call in progress.
pub(crate) struct Frame {
    /// The evaluator's environment, its lifetime erased: valid while the frame is on the
    /// stack ([`with_frame`] pops it before the borrow ends).
    env: *const (dyn Env + 'static),
    gradient: bool,
    /// The quantity being perturbed and by how much (partials by differences).
    perturb: Option<(Key, f64)>,
    /// Every distinct quantity read, with its value and gradient, in the order first read.
    pub reads: Vec<(Key, Dual)>,
    /// ERRMES with STOP: the subroutine's message.
    pub stop: Option<String>,
    /// The first read that could not be evaluated (SYSFNC/SYSARY returned ERRFLG).
    pub failure: Option<String>,
}

/// A SYSFNC name and its integer arguments as an expression, or why they are none.
type Parsed = Result<Expr, ReadError>;

thread_local! {
    static STACK: RefCell<Vec<Frame>> = const { RefCell::new(Vec::new()) };
    static PARSED: RefCell<HashMap<(String, Vec<i32>), Parsed>> = RefCell::new(HashMap::new());
}

/// Runs `call` with a frame for `env` on this thread's stack; returns its result and the
/// frame. `time` is the value TIME has in this call (perturbed when `perturb` is TIME).
pub(crate) fn with_frame<R>(
    env: &dyn Env,
    gradient: bool,
    perturb: Option<(Key, f64)>,
    call: impl FnOnce() -> R,
) -> (R, Frame) {
    // SAFETY: the frame holding the erased reference is popped below, before `env`'s borrow
    // ends; nothing else keeps it.
    let env: &'static (dyn Env + 'static) = unsafe { std::mem::transmute(env) };
    STACK.with(|s| {
        s.borrow_mut().push(Frame {
            env,
            gradient,
            perturb,
            reads: Vec::new(),
            stop: None,
            failure: None,
        })
    });
    let r = call();
    // Unreachable: the frame pushed above is popped only here, and every call `call` makes
    // in between (nested subroutines included) pushes and pops its own frame in pairs.
    let frame = STACK.with(|s| s.borrow_mut().pop().expect("the frame pushed above"));
    (r, frame)
}

/// The value of `key` in the current call, recorded (and perturbed when it is the perturbed
/// quantity). `None` outside a call.
pub(crate) fn read(key: Key) -> Result<f64, ReadError> {
    let (env, gradient) = STACK
        .with(|s| s.borrow().last().map(|f| (f.env, f.gradient)))
        .ok_or(ReadError::NoCall)?;
    // SAFETY: the frame is on the stack, so the environment is alive (see `with_frame`).
    let env: &dyn Env = unsafe { &*env };
    let d = match &key {
        Key::Time => match (gradient, env.time_variable()) {
            (true, Some(v)) => Dual::variable(env.time(), v),
            _ => Dual::constant(env.time()),
        },
        Key::Measure(name, ipar) => {
            let expr = PARSED.with(|p| {
                p.borrow_mut()
                    .entry((name.clone(), ipar.clone()))
                    .or_insert_with(|| measure_expr(name, ipar))
                    .clone()
            })?;
            let value = if gradient {
                evaluate_with_gradient(&expr, env)
            } else {
                evaluate(&expr, env).map(Dual::constant)
            };
            value.map_err(|e| ReadError::Evaluate {
                what: expr.to_string(),
                why: e.message,
            })?
        }
    };
    STACK.with(|s| {
        let mut s = s.borrow_mut();
        // The frame found above is still there (nested calls push and pop in pairs); should it
        // not be, the read is outside a call.
        let f = s.last_mut().ok_or(ReadError::NoCall)?;
        let shift = match &f.perturb {
            Some((k, h)) if *k == key => *h,
            _ => 0.0,
        };
        let v = d.value() + shift;
        if !f.reads.iter().any(|(k, _)| *k == key) {
            f.reads.push((key, d));
        }
        Ok(v)
    })
}

/// Runs `f` with the environment of the subroutine call in progress (`None` outside one).
pub(crate) fn with_current_env<R>(f: impl FnOnce(Option<&dyn Env>) -> R) -> R {
    let env = STACK.with(|s| s.borrow().last().map(|f| f.env));
    // SAFETY: the frame is on the stack, so the environment is alive (see `with_frame`).
    f(env.map(|e| unsafe { &*e }))
}

/// `NAME(ipar…)` as an expression of the language; the name must be a plain word (no
/// expression can be smuggled in through it).
fn measure_expr(name: &str, ipar: &[i32]) -> Parsed {
    let bad = |why: Option<String>| ReadError::BadName {
        name: name.to_string(),
        why,
    };
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(bad(None));
    }
    let args: Vec<String> = ipar.iter().map(|i| i.to_string()).collect();
    parse(&format!("{name}({})", args.join(","))).map_err(|e| bad(Some(e.message)))
}

/// Records a failed read in the current frame (the first one is kept).
fn fail(why: String) {
    STACK.with(|s| {
        if let Some(f) = s.borrow_mut().last_mut() {
            f.failure.get_or_insert(why);
        }
    });
}

/// A Fortran CHARACTER argument (or a C string with its length): trimmed, upper-cased.
///
/// # Safety
/// `p` points to `len` readable bytes (or is null).
unsafe fn text(p: *const c_char, len: usize) -> String {
    if p.is_null() {
        return String::new();
    }
    let bytes = std::slice::from_raw_parts(p.cast::<u8>(), len);
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(len);
    String::from_utf8_lossy(&bytes[..end]).trim().to_string()
}

/// # Safety
/// `ipar` points to `n` integers (or `n <= 0`).
unsafe fn ints<'a>(ipar: *const c_int, n: c_int) -> &'a [c_int] {
    if ipar.is_null() || n <= 0 {
        &[]
    } else {
        std::slice::from_raw_parts(ipar, n as usize)
    }
}

/// SYSFNC(FNCNAM, IPAR, NSIZE, STATES, ERRFLG): one value of `FNCNAM(IPAR…)`.
pub(crate) unsafe extern "C" fn sysfnc(
    name: *const c_char,
    name_len: usize,
    ipar: *const c_int,
    nsize: c_int,
    states: *mut f64,
    errflg: *mut c_int,
) {
    let name = text(name, name_len).to_ascii_uppercase();
    let ipar = ints(ipar, nsize).to_vec();
    let r = std::panic::catch_unwind(|| read(Key::Measure(name.clone(), ipar)))
        .unwrap_or_else(|_| Err(ReadError::Panicked(format!("SYSFNC {name}"))));
    match r {
        Ok(v) => {
            *states = v;
            *errflg = 0;
        }
        Err(why) => {
            *states = 0.0;
            *errflg = 1;
            fail(format!("SYSFNC {why}"));
        }
    }
}

/// The measures SYSARY returns for each of its names, in order (Adams' SYSARY names).
fn sysary_names(name: &str) -> Option<&'static [&'static str]> {
    Some(match name {
        "TDISP" => &["DX", "DY", "DZ"],
        "RDISP" => &["PSI", "THETA", "PHI"],
        "DISP" => &["DX", "DY", "DZ", "PSI", "THETA", "PHI"],
        "TVEL" => &["VX", "VY", "VZ"],
        "RVEL" => &["WX", "WY", "WZ"],
        "VEL" => &["VX", "VY", "VZ", "WX", "WY", "WZ"],
        "TACC" => &["ACCX", "ACCY", "ACCZ"],
        "RACC" => &["WDTX", "WDTY", "WDTZ"],
        "ACC" => &["ACCX", "ACCY", "ACCZ", "WDTX", "WDTY", "WDTZ"],
        _ => return None,
    })
}

/// SYSARY(FNCNAM, IPAR, NSIZE, STATES, NSTATES, ERRFLG): several values at once — TDISP,
/// RDISP, DISP (marker ids i, j, k as DX…), TVEL, RVEL, VEL, TACC, RACC, ACC (i, j, k, l as
/// VX…; the rotational ones take i, j, k).
pub(crate) unsafe extern "C" fn sysary(
    name: *const c_char,
    name_len: usize,
    ipar: *const c_int,
    nsize: c_int,
    states: *mut f64,
    nstates: *mut c_int,
    errflg: *mut c_int,
) {
    let name = text(name, name_len).to_ascii_uppercase();
    let ipar = ints(ipar, nsize).to_vec();
    let Some(parts) = sysary_names(&name) else {
        *nstates = 0;
        *errflg = 1;
        fail(ReadError::UnknownArray(name).to_string());
        return;
    };
    let r = std::panic::catch_unwind(|| {
        parts
            .iter()
            .map(|m| {
                // Angles and angular measures take the markers i, j (and k for WX…).
                let n = match *m {
                    "PSI" | "THETA" | "PHI" => 2,
                    "WX" | "WY" | "WZ" => 3,
                    _ => 4,
                };
                let args = ipar.iter().copied().take(n).collect();
                read(Key::Measure((*m).to_string(), args))
            })
            .collect::<Result<Vec<f64>, ReadError>>()
    })
    .unwrap_or_else(|_| Err(ReadError::Panicked(format!("SYSARY {name}"))));
    match r {
        Ok(values) => {
            for (k, v) in values.iter().enumerate() {
                *states.add(k) = *v;
            }
            *nstates = values.len() as c_int;
            *errflg = 0;
        }
        Err(why) => {
            *nstates = 0;
            *errflg = 1;
            fail(format!("SYSARY {why}"));
        }
    }
}

/// The most values GTARAY returns (an ARRAY longer than this is an error).
const GTARAY_MAX: i32 = 10_000;

/// GTARAY(ID, ARRAY, NUMBER, ISTAT): the values of ARRAY/ID (ARYVAL(ID, 1), ARYVAL(ID, 2), …,
/// each read like SYSFNC's, so a states array's values carry their dependencies) and how many;
/// ISTAT 0, or 1 when the array has no value (no such array) or more than [`GTARAY_MAX`].
/// ARRAY must have room for every value, as in Adams.
pub(crate) unsafe extern "C" fn gtaray(
    id: c_int,
    array: *mut f64,
    number: *mut c_int,
    istat: *mut c_int,
) {
    let r = std::panic::catch_unwind(|| {
        let mut values = Vec::new();
        for k in 1..=GTARAY_MAX {
            match read(Key::Measure("ARYVAL".into(), vec![id, k])) {
                Ok(v) => values.push(v),
                Err(_) => break,
            }
        }
        values
    })
    .unwrap_or_default();
    for (k, v) in r.iter().enumerate() {
        *array.add(k) = *v;
    }
    *number = r.len() as c_int;
    *istat = c_int::from(r.is_empty() || r.len() as i32 == GTARAY_MAX);
}

/// TIMGET(TIME): the current simulation time.
pub(crate) unsafe extern "C" fn timget(time: *mut f64) {
    *time = read(Key::Time).unwrap_or(0.0);
}

/// ERRMES(ERRFLG, MESAGE, ID, ENDFLG): when ERRFLG is true, reports MESAGE; ENDFLG = STOP
/// ends the analysis (after the subroutine returns) with the message.
pub(crate) unsafe extern "C" fn errmes(
    errflg: c_int,
    msg: *const c_char,
    msg_len: usize,
    id: c_int,
    end: *const c_char,
    end_len: usize,
) {
    if errflg == 0 {
        return;
    }
    let msg = text(msg, msg_len);
    let stop = text(end, end_len).to_ascii_uppercase().starts_with("STOP");
    if stop {
        STACK.with(|s| {
            if let Some(f) = s.borrow_mut().last_mut() {
                f.stop.get_or_insert(format!("{msg} (id {id})"));
            }
        });
    } else {
        eprintln!("warning: user subroutine (id {id}): {msg}");
    }
}

/// USRMES(MSGFLG, MESAGE, ID, MSGTYP): a message of type INFO, WARN, ERROR or FAULT, written
/// to standard error when MSGFLG is true.
pub(crate) unsafe extern "C" fn usrmes(
    msgflg: c_int,
    msg: *const c_char,
    msg_len: usize,
    id: c_int,
    kind: *const c_char,
    kind_len: usize,
) {
    if msgflg != 0 {
        let kind = text(kind, kind_len).to_ascii_lowercase();
        let kind = if kind.is_empty() { "info".into() } else { kind };
        eprintln!("{kind}: user subroutine (id {id}): {}", text(msg, msg_len));
    }
}
