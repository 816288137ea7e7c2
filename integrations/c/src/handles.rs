//! Which handles are alive, in debug builds: freeing a mesh twice, or using a freed one, is
//! undefined behaviour in release builds (as `free` is) and a reported error in debug builds.

#[cfg(debug_assertions)]
use std::collections::HashSet;
#[cfg(debug_assertions)]
use std::sync::Mutex;

#[cfg(debug_assertions)]
static LIVE: Mutex<Option<HashSet<usize>>> = Mutex::new(None);

/// Notes `address` as a live handle.
pub(crate) fn born(address: usize) {
    #[cfg(debug_assertions)]
    LIVE.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert_with(HashSet::new).insert(address);
    let _ = address;
}

/// Whether `address` is a live handle (always true in release builds, which do not track).
pub(crate) fn alive(address: usize) -> bool {
    #[cfg(debug_assertions)]
    return LIVE.lock().unwrap_or_else(|e| e.into_inner()).as_ref().is_some_and(|live| live.contains(&address));
    #[cfg(not(debug_assertions))]
    {
        let _ = address;
        true
    }
}

/// Notes `address` as freed; false when it was not alive.
pub(crate) fn died(address: usize) -> bool {
    #[cfg(debug_assertions)]
    return LIVE.lock().unwrap_or_else(|e| e.into_inner()).as_mut().is_some_and(|live| live.remove(&address));
    #[cfg(not(debug_assertions))]
    {
        let _ = address;
        true
    }
}
