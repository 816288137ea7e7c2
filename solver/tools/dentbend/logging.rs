//! Log output on stderr as `warning: …` lines, each warning printed once even when the library
//! both logs it and returns it in a report.

use std::io::Write;
use std::sync::Mutex;

use log::Level;

/// Warning messages already printed by the logger.
static PRINTED: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Installs `env_logger`: level `warn` unless `RUST_LOG` says otherwise.
pub fn init() {
    let env = env_logger::Env::default().default_filter_or("warn");
    let _ = env_logger::Builder::from_env(env)
        .format(|out, record| {
            let message = record.args().to_string();
            let label = match record.level() {
                Level::Error => "error",
                Level::Warn => "warning",
                Level::Info => "info",
                Level::Debug => "debug",
                Level::Trace => "trace",
            };
            if record.level() == Level::Warn
                && let Ok(mut printed) = PRINTED.lock()
            {
                printed.push(message.clone());
            }
            writeln!(out, "{label}: {message}")
        })
        .try_init();
}

/// Prints `warning: {message}` on stderr unless the logger already printed it.
pub fn warn_once(message: &str) {
    let seen = PRINTED.lock().map(|printed| printed.iter().any(|m| m == message)).unwrap_or(false);
    if !seen {
        eprintln!("warning: {message}");
    }
}
