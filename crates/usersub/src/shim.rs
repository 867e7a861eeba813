//! The utility-routine shim: a small shared library (compiled from `shim/utilities.c` by the
//! build script and embedded here) that defines `sysfnc_`, `c_sysfnc`, … and forwards them to
//! [`crate::callbacks`]. It is loaded once, with `RTLD_GLOBAL`, from an anonymous in-memory
//! file (`memfd_create`: nothing is written to disk), before any user library, so that a
//! user library's references to the utility routines resolve to it.

use crate::callbacks;
use crate::error::UserError;
use libloading::os::unix::{Library, RTLD_GLOBAL, RTLD_NOW};
use std::ffi::{c_char, c_int};
use std::io::Write;
use std::os::fd::FromRawFd;
use std::sync::OnceLock;

/// The callbacks handed to the shim (`struct linkage_callbacks` in `shim/utilities.c`).
#[repr(C)]
pub(crate) struct Table {
    sysfnc: unsafe extern "C" fn(*const c_char, usize, *const c_int, c_int, *mut f64, *mut c_int),
    sysary: unsafe extern "C" fn(
        *const c_char,
        usize,
        *const c_int,
        c_int,
        *mut f64,
        *mut c_int,
        *mut c_int,
    ),
    timget: unsafe extern "C" fn(*mut f64),
    errmes: unsafe extern "C" fn(c_int, *const c_char, usize, c_int, *const c_char, usize),
    usrmes: unsafe extern "C" fn(c_int, *const c_char, usize, c_int, *const c_char, usize),
    utility:
        unsafe extern "C" fn(*const c_char, *const f64, c_int, c_int, c_int, *mut f64, *mut c_int),
    gtaray: unsafe extern "C" fn(c_int, *mut f64, *mut c_int, *mut c_int),
}

impl Table {
    pub(crate) fn new() -> Table {
        Table {
            sysfnc: callbacks::sysfnc,
            sysary: callbacks::sysary,
            timget: callbacks::timget,
            errmes: callbacks::errmes,
            usrmes: callbacks::usrmes,
            utility: crate::utilities::utility,
            gtaray: callbacks::gtaray,
        }
    }
}

static SHIM: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/liblinkage_utilities.so"));

/// The loaded shim (kept for the life of the process; user libraries refer to it).
static LOADED: OnceLock<Result<Library, Box<dyn std::error::Error + Send + Sync>>> =
    OnceLock::new();

/// Loads the shim and installs the callbacks, once per process.
pub(crate) fn ensure() -> Result<(), UserError> {
    LOADED
        .get_or_init(load)
        .as_ref()
        .map(|_| ())
        .map_err(|why| UserError::Shim(why.to_string()))
}

fn load() -> Result<Library, Box<dyn std::error::Error + Send + Sync>> {
    // SAFETY: memfd_create with a NUL-terminated name and no flags has no preconditions.
    let fd = unsafe { libc::memfd_create(c"linkage-utilities".as_ptr(), 0) };
    if fd < 0 {
        return Err(std::io::Error::last_os_error().into());
    }
    // SAFETY: `fd` is a fresh descriptor this function owns.
    let mut file = unsafe { std::fs::File::from_raw_fd(fd) };
    file.write_all(SHIM)?;
    let path = format!("/proc/self/fd/{fd}");
    // SAFETY: the shim is our own code; its initialisers do nothing.
    let lib = unsafe { Library::open(Some(&path), RTLD_NOW | RTLD_GLOBAL)? };
    // SAFETY: the symbol has this signature in shim/utilities.c.
    let install: libloading::os::unix::Symbol<unsafe extern "C" fn(*const Table)> =
        unsafe { lib.get(b"linkage_usersub_install\0")? };
    let table = Table::new();
    // SAFETY: the shim copies the table.
    unsafe { install(&table) };
    drop(file);
    Ok(lib)
}
