//! Quiet Vulkan start-up on machines without a display. Mesa's `device_select` layer, loaded
//! implicitly with every Vulkan driver, connects to a Wayland display to order the adapters; on a
//! headless machine (CI, a render farm, a container) that fails and libwayland prints
//! `error: XDG_RUNTIME_DIR is invalid or not set` to stderr, on runs that then succeed. wgpu
//! picks its adapter itself, so the layer is switched off (`NODEVICE_SELECT=1`) when there is no
//! display to find — unless the user set that variable already.

/// Switches the `device_select` layer off when no Wayland or X display is reachable. Call first
/// thing in `main`, before any thread starts (the environment is process-wide).
pub fn quiet_headless_vulkan() {
    let headless = ["XDG_RUNTIME_DIR", "WAYLAND_DISPLAY", "DISPLAY"].iter().all(|v| std::env::var_os(v).is_none());
    if headless && std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: called at the top of `main`, while the process has one thread, so no other
        // thread can read the environment concurrently.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}
