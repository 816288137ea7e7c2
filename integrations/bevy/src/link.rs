//! The two channels between the main world (which decides dents) and the render world (which
//! makes them on Bevy's device), and the GPU's status both worlds read.

use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::cpu::{SkinBone, SkinInfluence};
use dentbend::dent::{DentParams, DentReport, Impact};
use dentbend::gpu::MovedVertices;
use dentbend::mesh::Refinement;

use crate::mesh_data::SlabLayout;

/// Whether dents can run on Bevy's GPU device.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GpuStatus {
    /// The render world has not started yet.
    Pending,
    /// Bevy's device runs dentbend's kernels; the adapter's name.
    Ready(String),
    /// No dent runs on the GPU (why); every body takes the CPU path.
    Unavailable(String),
}

/// One dent for the render world, owning its data (the projectile in the target's mesh
/// coordinates, cropped to what shapes the dent); `id` numbers it for its report.
#[derive(Debug, Clone)]
pub(crate) struct GpuJob {
    pub id: u64,
    pub target: Entity,
    pub projectile: TriMesh,
    pub impact: Impact,
    pub params: DentParams,
}

/// Main world → render world.
#[derive(Debug)]
pub(crate) enum ToRender {
    /// Keep `mesh` resident for `entity`, whose vertices Bevy holds in asset `asset` laid out as
    /// `layout`.
    Register { entity: Entity, asset: AssetId<Mesh>, mesh: TriMesh, layout: SlabLayout },
    /// `entity` is gone (despawned, or no longer dentable).
    Forget(Entity),
    /// A dent to make.
    Dent(GpuJob),
    /// Skin `entity` (Bevy asset `asset`, laid out as `layout`) from its rest vertices (its own
    /// coordinates) with `influences` over `bones` bones. Only bending (the `rapier` or `avian`
    /// feature) sends this and `Pose`.
    #[cfg_attr(not(any(feature = "rapier", feature = "avian")), allow(dead_code))]
    RegisterSkin {
        entity: Entity,
        asset: AssetId<Mesh>,
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        influences: Vec<SkinInfluence>,
        bones: u32,
        layout: SlabLayout,
    },
    /// This frame's bone matrices of skinned `entity` (rest frame → its own coordinates).
    #[cfg_attr(not(any(feature = "rapier", feature = "avian")), allow(dead_code))]
    Pose { entity: Entity, bones: Vec<SkinBone> },
}

/// Render world → main world.
#[derive(Debug)]
pub(crate) enum ToMain {
    /// The vertices of `entity` a batch moved, read back for its collider; `bytes` read.
    Moved { entity: Entity, moved: MovedVertices, bytes: u64 },
    /// A batch of `dents` dents was recorded and submitted.
    Batch { dents: u64 },
    /// Dents that could not be made (logged in the render world), by id.
    Dropped { ids: Vec<u64> },
    /// These bodies could not be made resident on the GPU: they take the CPU path from now on.
    Demote(Vec<Entity>),
    /// A batch ran with its host stages (refinement, guard, volume rim): each dent's report by
    /// its job's id, and the bytes the batch read back (moved vertices, and the maps of falloffs
    /// fitted to a wall).
    Made { reports: Vec<(u64, DentReport)>, bytes: u64 },
    /// A dent refined `entity`: its mesh now (the denter's host copy, never read back), what
    /// refinement appended, and the vertices that moved (every new one included).
    Refined { entity: Entity, mesh: TriMesh, refinement: Refinement, moved: Vec<u32> },
}

/// The main world's ends.
#[derive(Resource, Clone)]
pub(crate) struct MainLink {
    pub to_render: Sender<ToRender>,
    pub from_render: Arc<Mutex<Receiver<ToMain>>>,
    pub status: Arc<Mutex<GpuStatus>>,
}

/// The render world's ends.
#[derive(Resource)]
pub(crate) struct RenderLink {
    pub from_main: Mutex<Receiver<ToRender>>,
    pub to_main: Sender<ToMain>,
    pub status: Arc<Mutex<GpuStatus>>,
}

/// A connected pair.
pub(crate) fn link() -> (MainLink, RenderLink) {
    let (to_render, from_main) = channel();
    let (to_main, from_render) = channel();
    let status = Arc::new(Mutex::new(GpuStatus::Pending));
    let main = MainLink { to_render, from_render: Arc::new(Mutex::new(from_render)), status: status.clone() };
    (main, RenderLink { from_main: Mutex::new(from_main), to_main, status })
}

impl MainLink {
    /// The GPU's status now.
    pub fn status(&self) -> GpuStatus {
        self.status.lock().map(|s| s.clone()).unwrap_or_else(|e| e.into_inner().clone())
    }

    /// Sends to the render world (which lives as long as the app; a send after it is gone is
    /// dropped).
    pub fn send(&self, message: ToRender) {
        let _ = self.to_render.send(message);
    }

    /// Everything the render world sent since the last call.
    pub fn receive(&self) -> Vec<ToMain> {
        let receiver = self.from_render.lock().unwrap_or_else(|e| e.into_inner());
        receiver.try_iter().collect()
    }
}

impl RenderLink {
    /// Sets the GPU's status.
    pub fn set_status(&self, status: GpuStatus) {
        *self.status.lock().unwrap_or_else(|e| e.into_inner()) = status;
    }

    /// Everything the main world sent since the last call.
    pub fn receive(&self) -> Vec<ToRender> {
        let receiver = self.from_main.lock().unwrap_or_else(|e| e.into_inner());
        receiver.try_iter().collect()
    }

    /// Sends to the main world.
    pub fn send(&self, message: ToMain) {
        let _ = self.to_main.send(message);
    }
}
