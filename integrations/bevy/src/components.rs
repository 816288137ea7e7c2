//! The components a game puts on its entities.

use bevy::prelude::*;
use dentbend::damage::PieceId;
use dentbend::dent::{DentParams, DentSettings, VolumeMode};
use dentbend::fracture::FractureSettings;
use dentbend::mesh::MassProperties;

/// An entity whose mesh ([`Mesh3d`]) dents where things hit it. Its mesh becomes its own (the
/// plug-in gives it a private copy, so other entities sharing the asset stay undented), in the
/// entity's own coordinates, m.
///
/// On the GPU path the dent runs on Bevy's device and lands straight in Bevy's vertex buffer. The
/// paper's dent ([`kernel_params`]) is recorded into Bevy's frame and never waits; settings with
/// host stages (refinement, volume preservation, the intersection guard) run them around the
/// kernels on the render world's copy of the mesh, reading back only the vertices the kernels
/// moved; a dent that refines the mesh grows it through its mesh asset. Progressive dents take
/// the CPU path, which updates the mesh asset.
#[derive(Component, Debug, Clone)]
pub struct Dentable {
    /// How it dents (material, shape of the dent, projectile handling).
    pub settings: DentSettings,
    /// How it breaks ([`breaking`](Self::breaking)); `None`: it never does.
    pub fracture: Option<FractureSettings>,
}

impl Dentable {
    /// Dents faster than `threshold` m/s, `gain` m deep per m/s above it, at most `cap` m; the
    /// game dent ([`DentSettings::new`]'s): the mesh refined where it is too coarse for the dent,
    /// the falloff fitted to thin walls, the intersection guard, the volume lost (sheet metal;
    /// [`with_volume`](Self::with_volume) keeps it for solid bodies). On the GPU path these run
    /// around the kernels on the render world's copy of the mesh.
    pub fn new(threshold: f32, gain: f32, cap: f32) -> Self {
        Self { settings: DentSettings::new(threshold, gain, cap), fracture: None }
    }

    /// [`new`](Self::new)'s material with the paper's dent (the GPU kernels alone: no
    /// refinement, no volume rim, no guard): recorded into Bevy's frame without waiting for the
    /// GPU, the cheapest way to make many dents at once, for finely meshed bodies.
    pub fn paper(threshold: f32, gain: f32, cap: f32) -> Self {
        let mut settings = DentSettings::new(threshold, gain, cap);
        settings.params = kernel_params(cap);
        Self { settings, fracture: None }
    }

    /// What a dent does to the body's volume: [`VolumeMode::Free`] loses the cavity (sheet
    /// metal, the default), [`VolumeMode::Preserve`] puts it back as a raised rim (solids).
    pub fn with_volume(mut self, volume: VolumeMode) -> Self {
        self.settings.params.volume = volume;
        self
    }

    /// The energy model instead of the gain: a hit dents as deep as makes the plastic work,
    /// `hardness` Pa × the volume the projectile's tip sweeps, equal the kinetic energy the
    /// collision removes along the normal (still above the threshold, at most the cap).
    pub fn with_hardness(mut self, hardness: f32) -> Self {
        self.settings.hardness = Some(hardness);
        self
    }

    /// Any settings (host stages too; see the type's doc for which path they take).
    pub fn with_settings(settings: DentSettings) -> Self {
        Self { settings, fracture: None }
    }

    /// The body also breaks (prescored fracture): when a hit's energy passes the settings'
    /// toughness or its dents add up past their limit, it breaks along the pattern placed at the
    /// hit, after its dents. Its mesh becomes the rest (positions and normals: other attributes
    /// are not kept on a broken body), and each piece an entity with a [`DentPiece`] (with the
    /// `rapier` feature, a dynamic body with a convex-hull collider). Its mesh must be closed.
    /// A breakable body dents on the CPU path.
    pub fn breaking(mut self, fracture: FractureSettings) -> Self {
        self.fracture = Some(fracture);
        self
    }

    /// Whether the GPU kernels alone make this body's dents (the paper's dent: no host stage).
    pub fn kernels_only(&self) -> bool {
        self.settings.params.host_stages().is_empty() && !self.settings.progressive
    }

    /// Whether the GPU path can make this body's dents: every setting but progressive dents
    /// (which rebuild each dent from the surface before the contact, on the CPU path).
    pub fn gpu_servable(&self) -> bool {
        !self.settings.progressive && self.fracture.is_none()
    }
}

/// The paper's dent of depth `dent_distance` m: every kernel stage, no host stage.
pub fn kernel_params(dent_distance: f32) -> DentParams {
    DentParams::new(dent_distance).without_host_stages()
}

/// An entity that dents what it hits without denting itself (a ball, a hammer): its surface is
/// its [`Mesh3d`] in its own coordinates.
#[derive(Component, Debug, Clone, Copy, Default)]
pub struct DentProjectile;

/// A piece a breakable body broke into: spawned with its [`Mesh3d`] and the broken body's
/// [`Transform`] (its mesh is in the broken body's coordinates). With the `rapier` feature it
/// also gets a dynamic bevy_rapier3d body, a convex-hull collider with the piece's mass
/// properties and its velocity; without, a physics engine of the game's takes these from here.
#[derive(Component, Debug, Clone)]
pub struct DentPiece {
    /// The body it broke from.
    pub from: Entity,
    /// Its id from the damage API (deterministic for the same hits).
    pub id: PieceId,
    /// Mass, kg, centre of mass and inertia about it (the mesh's coordinates).
    pub mass: MassProperties,
    /// Velocity of its centre of mass when it broke loose, world, m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity when it broke loose, world, rad/s.
    pub angular_velocity: Vec3,
}
