//! Which handles are alive, in debug builds (and with the `track-handles` feature): freeing a
//! mesh twice, or using a freed one, is undefined behaviour in release builds (as `free` is)
//! and a reported error where handles are tracked.

#[cfg(any(debug_assertions, feature = "track-handles"))]
use std::collections::HashSet;
#[cfg(any(debug_assertions, feature = "track-handles"))]
use std::sync::Mutex;

#[cfg(any(debug_assertions, feature = "track-handles"))]
static LIVE: Mutex<Option<HashSet<usize>>> = Mutex::new(None);

/// Notes `address` as a live handle.
pub(crate) fn born(address: usize) {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    LIVE.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert_with(HashSet::new).insert(address);
    let _ = address;
}

/// Whether `address` is a live handle (always true where handles are not tracked).
pub(crate) fn alive(address: usize) -> bool {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    return LIVE.lock().unwrap_or_else(|e| e.into_inner()).as_ref().is_some_and(|live| live.contains(&address));
    #[cfg(not(any(debug_assertions, feature = "track-handles")))]
    {
        let _ = address;
        true
    }
}

/// Notes `address` as freed; false when it was not alive.
pub(crate) fn died(address: usize) -> bool {
    #[cfg(any(debug_assertions, feature = "track-handles"))]
    return LIVE.lock().unwrap_or_else(|e| e.into_inner()).as_mut().is_some_and(|live| live.remove(&address));
    #[cfg(not(any(debug_assertions, feature = "track-handles")))]
    {
        let _ = address;
        true
    }
}
