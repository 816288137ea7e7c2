//! Which handles are alive, in debug builds (and with the `track-handles` feature): freeing a
//! mesh twice, or using a freed one, is undefined behaviour in release builds (as `free` is)
//! and a reported error where handles are tracked.

use crate::status::{Failure, guarded};

use std::any::TypeId;
#[cfg(any(debug_assertions, feature = "track-handles"))]
use std::collections::HashMap;
#[cfg(any(debug_assertions, feature = "track-handles"))]
use std::sync::Mutex;

#[cfg(any(debug_assertions, feature = "track-handles"))]
static LIVE: Mutex<Option<HashMap<usize, TypeId>>> = Mutex::new(None);

/// Notes `address` as a live handle of type `kind`.
fn born(address: usize, kind: TypeId) {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    LIVE.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert_with(HashMap::new).insert(address, kind);
    let _ = (address, kind);
}

/// Whether `address` is a live handle of type `kind` (always true where handles are not
/// tracked).
fn alive(address: usize, kind: TypeId) -> bool {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    return LIVE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .as_ref()
        .is_some_and(|live| live.get(&address) == Some(&kind));
    #[cfg(not(any(debug_assertions, feature = "track-handles")))]
    {
        let _ = (address, kind);
        true
    }
}

/// Notes `address` as freed; false when it was not a live handle of type `kind`.
fn died(address: usize, kind: TypeId) -> bool {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    {
        let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        let live = live.get_or_insert_with(HashMap::new);
        if live.get(&address) != Some(&kind) {
            return false;
        }
        live.remove(&address);
        true
    }
    #[cfg(not(any(debug_assertions, feature = "track-handles")))]
    {
        let _ = (address, kind);
        true
    }
}

/// A new handle owning `value`.
pub(crate) fn make<T: 'static>(value: T) -> *mut T {
    let handle = Box::into_raw(Box::new(value));
    born(handle as usize, TypeId::of::<T>());
    handle
}

/// The value behind `handle` (`what` names it in messages): not null, and alive where handles
/// are tracked.
///
/// # Safety
/// `handle` is null or a handle of [`make`] not freed yet.
pub(crate) unsafe fn get<'a, T: 'static>(handle: *const T, what: &str) -> Result<&'a T, Failure> {
    if handle.is_null() {
        return Err(Failure::null(what));
    }
    if !alive(handle as usize, TypeId::of::<T>()) {
        return Err(Failure::invalid(format!(
            "{what} is not alive (freed, another kind of handle, or not made by this library)"
        )));
    }
    // SAFETY: not null, and alive by the caller's contract.
    Ok(unsafe { &*handle })
}

/// As [`get`], mutably.
///
/// # Safety
/// As [`get`], and no other reference to the value is in use.
pub(crate) unsafe fn get_mut<'a, T: 'static>(handle: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    // SAFETY: the caller's contract.
    unsafe { get(handle.cast_const(), what)? };
    // SAFETY: checked above; exclusive by the caller's contract.
    Ok(unsafe { &mut *handle })
}

/// Frees `handle` (null: nothing), reporting a second free where handles are tracked.
///
/// # Safety
/// `handle` is null or a handle of [`make`] not freed yet.
pub(crate) unsafe fn free<T: 'static>(handle: *mut T, what: &str) {
    guarded(|| {
        if handle.is_null() {
            return Ok(());
        }
        if !died(handle as usize, TypeId::of::<T>()) {
            return Err(Failure::invalid(format!(
                "{what}: not alive (freed twice, another kind of handle, or not made by this library)"
            )));
        }
        // SAFETY: made by `Box::into_raw` in `make`, not freed yet by the contract.
        drop(unsafe { Box::from_raw(handle) });
        Ok(())
    });
}
