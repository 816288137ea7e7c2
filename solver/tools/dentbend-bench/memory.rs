//! The process's resident memory, for watching a long run for growth: read from
//! `/proc/self/status` on Linux, unknown (`None`) elsewhere.

/// Resident set size now (`VmRSS`), MiB.
pub fn resident_mb() -> Option<f64> {
    status_kb("VmRSS:").map(|kb| kb / 1024.0)
}

/// The largest resident set size so far (`VmHWM`, the high-water mark), MiB.
pub fn peak_resident_mb() -> Option<f64> {
    status_kb("VmHWM:").map(|kb| kb / 1024.0)
}

/// The value of the `/proc/self/status` line starting with `key`, in kB.
#[cfg(target_os = "linux")]
fn status_kb(key: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    // "VmRSS:	   12345 kB"
    line[key.len()..].split_whitespace().next()?.parse().ok()
}

#[cfg(not(target_os = "linux"))]
fn status_kb(_: &str) -> Option<f64> {
    None
}
