//! Running the real `dentbend` binary.

use std::process::{Command, Output};

/// Runs `dentbend` with `args` (no `RUST_LOG`, so only warnings are logged).
pub fn dentbend(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dentbend")).args(args).env_remove("RUST_LOG").output().unwrap()
}
