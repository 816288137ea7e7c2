//! Status codes, the thread's last error message, the guard every entry point runs in, and
//! how arrays are handed out.

use std::cell::RefCell;
use std::ffi::{CString, c_char, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Success.
pub const DB_OK: c_int = 0;
/// A pointer that must not be null was null.
pub const DB_ERR_NULL_POINTER: c_int = 1;
/// An argument was out of range, not finite, of the wrong size, or a handle not alive.
pub const DB_ERR_INVALID_ARGUMENT: c_int = 2;
/// The dent could not be made (the message says why: a projectile behind the contact plane, a
/// separating impact, ...).
pub const DB_ERR_DENT: c_int = 3;
/// A bug inside the library (a caught panic): the objects involved may have changed part way;
/// free them.
pub const DB_ERR_INTERNAL: c_int = 4;

/// A failed call: its status (a `DB_ERR_*` code) and message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    /// The status the C function returns.
    pub status: c_int,
    /// What went wrong, and the fix where there is one.
    pub message: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Failure {}

impl Failure {
    /// A null `what`.
    pub(crate) fn null(what: &str) -> Self {
        Self { status: DB_ERR_NULL_POINTER, message: format!("{what} is null") }
    }

    /// A bad argument, with the message.
    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        Self { status: DB_ERR_INVALID_ARGUMENT, message: message.into() }
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Keeps `message` as this thread's last error (an interior NUL, which no message of ours
/// has, would cut it there).
fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    let _ = LAST_ERROR.try_with(|last| *last.borrow_mut() = text);
}

/// The message of the last call that failed on this thread (UTF-8, NUL-terminated; empty
/// when none has). Valid until the next failing call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn db_last_error() -> *const c_char {
    LAST_ERROR.try_with(|last| last.borrow().as_ptr()).unwrap_or(c"".as_ptr())
}

/// Runs `body`, turning a failure or a panic into its status and this thread's message.
pub(crate) fn guarded(body: impl FnOnce() -> Result<(), Failure>) -> c_int {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => DB_OK,
        Ok(Err(failure)) => {
            set_last_error(&failure.message);
            failure.status
        }
        Err(panic) => {
            set_last_error(&format!("internal error (a bug in dentbend, please report it): {}", panic_text(&panic)));
            DB_ERR_INTERNAL
        }
    }
}

/// As [`guarded`], for a body that makes a value: `None` on failure.
pub(crate) fn guarded_value<T>(body: impl FnOnce() -> Result<T, Failure>) -> Option<T> {
    let mut out = None;
    guarded(|| body().map(|value| out = Some(value)));
    out
}

/// A panic payload's text.
fn panic_text(panic: &Box<dyn std::any::Any + Send>) -> &str {
    panic.downcast_ref::<&str>().copied().or_else(|| panic.downcast_ref::<String>().map(String::as_str)).unwrap_or("")
}

/// Writes the length of `bytes` (0 when none) to `length` when that is not null; the pointer,
/// null for none or an empty array.
///
/// # Safety
/// `length` is null or writable.
pub(crate) unsafe fn hand_out<T>(bytes: Option<(*const T, usize)>, length: *mut usize) -> *const T {
    let (pointer, n) = bytes.filter(|b| b.1 > 0).unwrap_or((std::ptr::null(), 0));
    if !length.is_null() {
        // SAFETY: not null, writable by the caller's contract.
        unsafe { length.write(n) };
    }
    pointer
}
