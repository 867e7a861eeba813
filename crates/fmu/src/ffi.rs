//! What both FMI versions' C boundaries share: the guard that turns a panic into an error
//! status (nothing unwinds into the importer), the instance behind an opaque pointer, C
//! strings and arrays, and the resource folder from FMI 2.0's URI.

use crate::instance::{FmuError, Instance, SavedState, Status};
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// `f`'s status, or [`Status::Fatal`] when it panicked (the panic's message is printed to
/// standard error by the panic hook: no logger can be trusted then).
pub fn guard(f: impl FnOnce() -> Status) -> c_int {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(s) => s as c_int,
        Err(_) => Status::Fatal as c_int,
    }
}

/// The instance behind `ptr` (`None` for a null pointer).
///
/// # Safety
/// `ptr` is null or came from [`into_raw`] and was not freed.
pub unsafe fn instance<'a>(ptr: *mut c_void) -> Option<&'a mut Instance> {
    (ptr as *mut Instance).as_mut()
}

/// `instance` as the opaque pointer handed to the importer.
pub fn into_raw(instance: Instance) -> *mut c_void {
    Box::into_raw(Box::new(instance)) as *mut c_void
}

/// A new instance as the opaque pointer, or null with the reason given to `logger` (no
/// resource folder, a configuration or dataset that cannot be read, another FMU's token).
pub fn instantiate(
    name: String,
    resources: Option<PathBuf>,
    token: Option<String>,
    logger: impl Fn(Status, &str, &str) + Clone + 'static,
    logging_on: bool,
) -> *mut c_void {
    let made = catch_unwind(AssertUnwindSafe(|| {
        let Some(resources) = resources else {
            return Err(FmuError::Resources {
                path: "(none)".into(),
                why: "the importer gave no resource location".into(),
            });
        };
        Instance::new(
            name,
            &resources,
            token.as_deref(),
            Box::new(logger.clone()),
            logging_on,
        )
    }));
    match made {
        Ok(Ok(i)) => into_raw(i),
        Ok(Err(e)) => {
            logger(Status::Error, "logStatusError", &e.to_string());
            std::ptr::null_mut()
        }
        Err(_) => std::ptr::null_mut(),
    }
}

/// Frees an instance made by [`into_raw`].
///
/// # Safety
/// `ptr` is null or came from [`into_raw`] and was not freed.
pub unsafe fn free(ptr: *mut c_void) {
    if !ptr.is_null() {
        drop(Box::from_raw(ptr as *mut Instance));
    }
}

/// A C string as Rust text (`None` for null).
///
/// # Safety
/// `p` is null or a NUL-terminated string.
pub unsafe fn text(p: *const c_char) -> Option<String> {
    (!p.is_null()).then(|| CStr::from_ptr(p).to_string_lossy().into_owned())
}

/// A C string of `s` (a NUL inside becomes a space).
pub fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

/// A call on value references of a type this FMU has no variable of (the FMU's types are
/// `kinds`): fine when empty.
pub fn none_of_type(vrs: &[u32], kinds: &'static str) -> Result<(), FmuError> {
    match vrs.first() {
        None => Ok(()),
        Some(&vr) => Err(FmuError::WrongType { vr, kind: kinds }),
    }
}

/// `n` values at `p` (empty for a null pointer or 0).
///
/// # Safety
/// `p` points at `n` values, or `n` is 0.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if p.is_null() || n == 0 {
        &[]
    } else {
        std::slice::from_raw_parts(p, n)
    }
}

/// `n` writable values at `p`.
///
/// # Safety
/// `p` points at `n` writable values, or `n` is 0.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if p.is_null() || n == 0 {
        &mut []
    } else {
        std::slice::from_raw_parts_mut(p, n)
    }
}

/// Runs `f` on the instance behind `ptr`, its error logged and returned as a status.
///
/// # Safety
/// As [`instance`].
pub unsafe fn with(
    ptr: *mut c_void,
    f: impl FnOnce(&mut Instance) -> Result<(), FmuError>,
) -> c_int {
    guard(|| match instance(ptr) {
        Some(inst) => {
            let result = f(inst);
            inst.status(result)
        }
        None => Status::Error,
    })
}

/// The FMU state cannot be serialised (`canSerializeFMUState="false"`).
pub const NO_SERIALIZATION: FmuError =
    FmuError::Unsupported("the FMU state cannot be serialised (canSerializeFMUState=false)");

/// The instance's state into `*state` (a new one when it is null, else the one there
/// overwritten): FMI's get FMU state.
///
/// # Safety
/// `state` is null or points at null or at a state made here and not freed.
pub unsafe fn save_state(i: &mut Instance, state: *mut *mut c_void) -> Result<(), FmuError> {
    let saved = i.save()?;
    if state.is_null() {
        return Err(FmuError::Unsupported("no place for the FMU state"));
    }
    let old = *state as *mut SavedState;
    if old.is_null() {
        *state = Box::into_raw(Box::new(saved)) as *mut c_void;
    } else {
        *old = saved;
    }
    Ok(())
}

/// Back to the state at `state` (made by [`save_state`]).
///
/// # Safety
/// `state` is null or a state made by [`save_state`] and not freed.
pub unsafe fn restore_state(i: &mut Instance, state: *mut c_void) -> Result<(), FmuError> {
    match (state as *const SavedState).as_ref() {
        Some(s) => i.restore(s),
        None => Err(FmuError::Unsupported("no FMU state given")),
    }
}

/// Frees the state at `*state` and sets it to null.
///
/// # Safety
/// As [`restore_state`], for `*state`.
pub unsafe fn free_state(state: *mut *mut c_void) -> Status {
    if !state.is_null() && !(*state).is_null() {
        drop(Box::from_raw(*state as *mut SavedState));
        *state = std::ptr::null_mut();
    }
    Status::Ok
}

/// `values[k] = get(vrs[k])` for every k (the lengths must match).
pub fn get_each<T>(
    inst: &mut Instance,
    vrs: &[u32],
    values: &mut [T],
    mut get: impl FnMut(&mut Instance, u32) -> Result<T, FmuError>,
) -> Result<(), FmuError> {
    if vrs.len() != values.len() {
        return Err(FmuError::Unsupported(
            "one value per value reference (arrays are not used by this FMU)",
        ));
    }
    for (vr, slot) in vrs.iter().zip(values.iter_mut()) {
        *slot = get(inst, *vr)?;
    }
    Ok(())
}

/// `set(vrs[k], values[k])` for every k (the lengths must match).
pub fn set_each<T: Copy>(
    inst: &mut Instance,
    vrs: &[u32],
    values: &[T],
    mut set: impl FnMut(&mut Instance, u32, T) -> Result<(), FmuError>,
) -> Result<(), FmuError> {
    if vrs.len() != values.len() {
        return Err(FmuError::Unsupported(
            "one value per value reference (arrays are not used by this FMU)",
        ));
    }
    for (vr, v) in vrs.iter().zip(values) {
        set(inst, *vr, *v)?;
    }
    Ok(())
}

/// The folder of FMI 2.0's resource location URI (`file:///tmp/x/resources`,
/// `file:/tmp/x/resources`, percent-escapes decoded); a plain path is taken as it is.
pub fn path_of_uri(uri: &str) -> PathBuf {
    let rest = uri
        .strip_prefix("file://localhost")
        .or_else(|| uri.strip_prefix("file://"))
        .or_else(|| uri.strip_prefix("file:"))
        .unwrap_or(uri);
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    PathBuf::from(String::from_utf8_lossy(&out).into_owned())
}

/// FMI functions this FMU does not offer (model exchange, clocks, derivatives): each logs why
/// on the instance it is called on and returns the error status.
macro_rules! unsupported {
    ($($name:ident($($arg:ident: $t:ty),*) => $why:literal;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(inst: *mut c_void $(, $arg: $t)*) -> c_int {
            $(let _ = $arg;)*
            $crate::ffi::with(inst, |_| Err($crate::instance::FmuError::Unsupported($why)))
        }
    )*};
}
pub(crate) use unsupported;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_uris_become_paths() {
        assert_eq!(
            path_of_uri("file:///tmp/a%20b/resources"),
            PathBuf::from("/tmp/a b/resources")
        );
        assert_eq!(path_of_uri("file:/tmp/r/"), PathBuf::from("/tmp/r/"));
        assert_eq!(path_of_uri("/tmp/r"), PathBuf::from("/tmp/r"));
        assert_eq!(path_of_uri("file:///x%2"), PathBuf::from("/x%2"));
    }
}
