//! `summary.json` of a headless run.

use serde_json::{Value, json};

use super::FrameClock;
use crate::{DentStats, GpuStatus};

/// A run's numbers.
#[derive(Debug, Clone)]
pub struct Summary {
    /// Frames rendered.
    pub frames: u32,
    /// The plug-in's totals.
    pub stats: DentStats,
    /// Median wall time between frames, ms.
    pub frame_ms_median: f64,
    /// The GPU path's status.
    pub gpu: GpuStatus,
    /// Whether the scene's bodies were dentable.
    pub dents_enabled: bool,
    /// Bytes of captured frames read back for the PNG files (not part of rendering a dent).
    pub capture_readback_bytes: u64,
}

impl Summary {
    /// From a run's clock and totals.
    pub fn new(clock: &FrameClock, stats: &DentStats, gpu: GpuStatus, dents_enabled: bool, capture: u64) -> Self {
        let frame_ms_median = clock.median_ms();
        Self {
            frames: clock.frame,
            stats: stats.clone(),
            frame_ms_median,
            gpu,
            dents_enabled,
            capture_readback_bytes: capture,
        }
    }

    /// As JSON: `frames`, `dents`, `gpu_dents`, `render_readback_bytes`,
    /// `collider_readback_bytes`, `frame_ms_median`, and more.
    pub fn to_json(&self) -> Value {
        let (path, adapter) = match &self.gpu {
            GpuStatus::Ready(name) => ("gpu", name.clone()),
            GpuStatus::Unavailable(why) => ("cpu", why.clone()),
            GpuStatus::Pending => ("cpu", "pending".into()),
        };
        let s = &self.stats;
        json!({
            "frames": self.frames,
            "dents": s.dents,
            "gpu_dents": s.gpu_dents,
            "render_readback_bytes": s.render_readback_bytes,
            "collider_readback_bytes": s.collider_readback_bytes,
            "frame_ms_median": self.frame_ms_median,
            "dents_per_frame": if self.frames == 0 { 0.0 } else { s.dents as f64 / f64::from(self.frames) },
            "gpu_batches": s.gpu_batches,
            "rejected_contacts": s.rejected_contacts,
            "cpu_dents": s.cpu_dents,
            "refined_triangles": s.refined_triangles,
            "limited_dents": s.limited_dents,
            "empty_dents": s.empty_dents,
            "fractures": s.fractures,
            "bendable_dents": s.bendable_dents,
            "splits": s.splits,
            "pieces": s.pieces,
            "dents_enabled": self.dents_enabled,
            "path": path,
            "adapter": adapter,
            "capture_readback_bytes": self.capture_readback_bytes,
        })
    }
}
