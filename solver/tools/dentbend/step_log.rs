//! The per-step records of `dentbend run`, streamed to disk as they happen so that memory stays
//! flat for any frame count: each step is one JSON line in a hidden file of the output folder,
//! whose lines become `summary.json`'s `steps` array when the summary is written (then the file
//! is removed; on an error or interruption it is removed too).

use std::fs::{self, File};
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use dentbend_solver::coupling::{StepStats, StepStatsStream, StepTiming};
use serde::ser::{Error as _, SerializeSeq};
use serde::{Serialize, Serializer};

use crate::error::CliError;

/// The open log of a run's steps and their running statistics.
pub struct StepLog {
    path: PathBuf,
    writer: Option<BufWriter<File>>,
    stats: StepStatsStream,
}

impl StepLog {
    /// Starts an empty log in `dir`.
    pub fn create(dir: &Path) -> Result<Self, CliError> {
        let path = dir.join(format!(".steps.{}.jsonl", std::process::id()));
        let file = File::create(&path).map_err(|source| CliError::Write { path: path.clone(), source })?;
        Ok(Self { path, writer: Some(BufWriter::new(file)), stats: StepStatsStream::default() })
    }

    /// Appends one step.
    pub fn push(&mut self, timing: &StepTiming) -> Result<(), CliError> {
        self.stats.push(timing);
        let write_error = |source| CliError::Write { path: self.path.clone(), source };
        let writer = self.writer.as_mut().ok_or_else(|| write_error(std::io::Error::other("the log is closed")))?;
        serde_json::to_writer(&mut *writer, timing).map_err(|e| write_error(e.into()))?;
        writer.write_all(b"\n").map_err(write_error)
    }

    /// Statistics of every step so far.
    pub fn stats(&self) -> StepStats {
        self.stats.stats()
    }

    /// Flushes the log and returns the steps as a sequence to serialize (read back line by line).
    pub fn steps(&mut self) -> Result<LoggedSteps<'_>, CliError> {
        if let Some(writer) = self.writer.take() {
            writer.into_inner().map_err(|e| CliError::Write { path: self.path.clone(), source: e.into_error() })?;
        }
        Ok(LoggedSteps { path: &self.path })
    }
}

impl Drop for StepLog {
    fn drop(&mut self) {
        self.writer = None;
        let _ = fs::remove_file(&self.path);
    }
}

/// The logged steps, serialized as a JSON array without holding them in memory.
#[derive(Debug)]
pub struct LoggedSteps<'a> {
    path: &'a Path,
}

impl Serialize for LoggedSteps<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let file = File::open(self.path).map_err(S::Error::custom)?;
        let mut seq = serializer.serialize_seq(None)?;
        for line in BufReader::new(file).lines() {
            let line = line.map_err(S::Error::custom)?;
            let timing: StepTiming = serde_json::from_str(&line).map_err(S::Error::custom)?;
            seq.serialize_element(&timing)?;
        }
        seq.end()
    }
}
