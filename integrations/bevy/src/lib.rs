//! dentbend for Bevy 0.20: rigid bodies that keep their dents (SCA 2014, *Efficient Denting and
//! Bending of Rigid Bodies*), computed on Bevy's own GPU device and written straight into Bevy's
//! vertex buffers.
//!
//! Add [`DentbendPlugin`], give dentable entities a [`Dentable`] (with their [`Mesh3d`]) and
//! the things that hit them a [`DentProjectile`]. Contacts come from bevy_rapier3d (feature
//! `rapier`, on by default), Avian 0.8 (feature `avian`) or any source that writes
//! [`DentContact`] messages; each step the plug-in decides every dent through dentbend's
//! world-free damage API.
//!
//! - **GPU path** (chosen when Bevy's device runs dentbend's kernels): the dentable meshes stay
//!   resident on Bevy's device; each frame's dents are recorded as one batch in the render world
//!   and the dented positions and normals are written into each mesh's slot of Bevy's mesh
//!   allocator slab (its offset and stride). Nothing is read back for rendering. The vertices a
//!   batch moved are read back asynchronously for the physics colliders
//!   ([`DentStats::collider_readback_bytes`]).
//! - **CPU path** (no usable device, [`DentbendPlugin::cpu_only`], or settings that need the
//!   host stages): dents are made on all cores and the mesh asset is updated.
//!
//! Bending (on bevy_rapier3d or Avian): a [`Bendable`] entity is cut into one body of the engine
//! per bone of its skeleton, joined by the engine's spherical joints under plastic or elastic
//! rules (dentbend's engine-neutral `bend::JointState`); a fast hit splits the bone it lands on,
//! a dentable one dents where it is hit; its mesh is skinned from the bones every frame they
//! move, on the GPU path by dentbend's `skin` kernel straight into Bevy's vertex slab.
//!
//! Units: metres, seconds, kilograms; a dentable's mesh is in its entity's own coordinates. A
//! scaled dentable or projectile (uniform or not; not mirrored) dents in metres on the CPU path:
//! the plug-in keeps its mesh with the scale baked in and writes the asset back without it;
//! bendable entities have unit scale.
//!
//! A ball falls on a block and dents it (with `rapier`: bevy_rapier3d steps the bodies):
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_dentbend::{DentProjectile, Dentable, DentbendPlugin, bevy_mesh, dentbend};
//! use bevy_rapier3d::prelude::*;
//!
//! fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>) {
//!     // A fixed block whose tri-mesh collider has the render mesh's vertices.
//!     let block = dentbend::mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).expect("a box");
//!     let collider = Collider::trimesh(block.positions().to_vec(), block.faces().to_vec()).expect("a tri-mesh");
//!     // 2 m/s threshold, 1 cm per m/s above it, at most 5 cm.
//!     let dentable = Dentable::new(2.0, 0.01, 0.05);
//!     commands.spawn((Mesh3d(meshes.add(bevy_mesh(&block))), RigidBody::Fixed, collider, dentable));
//!     // A ball dropped on it at 6 m/s.
//!     commands.spawn((
//!         Mesh3d(meshes.add(Sphere::new(0.1).mesh().ico(2).expect("a sphere"))),
//!         Transform::from_xyz(0.0, 1.0, 0.0),
//!         RigidBody::Dynamic,
//!         Collider::ball(0.1),
//!         Velocity::linear(Vec3::new(0.0, -6.0, 0.0)),
//!         DentProjectile,
//!     ));
//! }
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, RapierPhysicsPlugin::<NoUserData>::default(), DentbendPlugin::default()))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```

#[cfg(feature = "avian")]
mod avian;
mod backend;
#[cfg(any(feature = "rapier", feature = "avian"))]
mod bend;
mod components;
mod contact;
mod decide;
#[cfg(any(feature = "rapier", feature = "avian"))]
pub mod demo;
#[cfg(any(feature = "rapier", feature = "avian"))]
mod engine;
mod events;
mod fracture;
mod fracture_attributes;
mod link;
mod mesh_data;
#[cfg(feature = "rapier")]
mod rapier;
mod register;
mod render;
mod save;
mod scale;
mod split_attributes;
mod stats;
mod world;

use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocatorSettings;
use bevy::render::render_resource::BufferUsages;
use bevy::render::{Render, RenderApp, RenderStartup, RenderSystems};

#[cfg(any(feature = "rapier", feature = "avian"))]
pub use bend::{BendPiece, Bendable, Bends};
pub use components::{DentPiece, DentProjectile, Dentable, kernel_params};
pub use contact::{DentBody, DentContact};
#[cfg(any(feature = "rapier", feature = "avian"))]
pub use dentbend::bend::{BendSettings, JointRule};
pub use events::{BodyBroken, DentApplied, MeshDented};
pub use link::GpuStatus;
pub use mesh_data::{MeshDataError, SlabLayout, bevy_mesh, slab_layout, tri_mesh};
pub use register::{DentAdvice, DentRefused, DentRegistered};
pub use save::{DamageRestored, RestoreDamage};
pub use stats::{DentPath, DentStats};
pub use world::DentWorld;

pub use dentbend;

/// The plug-in's system sets in `PostUpdate`, in order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DentSystems {
    /// New bodies registered, removed ones forgotten.
    Register,
    /// Contacts turned into dents.
    Decide,
    /// Dents applied to what depends on the meshes (colliders).
    Apply,
}

/// Dents (and, with the `rapier` or `avian` feature, contacts from bevy_rapier3d or Avian) for
/// a Bevy app.
///
/// With `rapier`, the plug-in records the bodies' states before each bevy_rapier3d step, reads
/// its impacts after it and applies the bendable bodies' joint rules, in the schedule that
/// step runs in: `PostUpdate` by default, `FixedUpdate` with bevy_rapier3d's
/// `in_fixed_schedule()`. It finds that schedule itself; [`in_schedule`](Self::in_schedule)
/// names it when bevy_rapier3d's systems are set up by hand. With `avian`, when the app steps
/// Avian (`FixedPostUpdate` by default, or the schedule given to Avian's `PhysicsPlugins`), it
/// does the same around Avian's step, in the schedule it finds. Dents are decided and applied
/// once a frame in `PostUpdate` (every fixed step's impacts of the frame together).
#[derive(Debug, Clone, Copy)]
pub struct DentbendPlugin {
    /// Let dents run on Bevy's GPU device when it can (default); `false` keeps every body on
    /// the CPU path.
    pub gpu: bool,
    /// The schedule bevy_rapier3d steps in, for an app that sets up bevy_rapier3d's systems
    /// after this plug-in is finished; `None` (default): `PostUpdate`. Avian's schedule is
    /// always found (a schedule named here that differs only draws a warning). The schedule the
    /// engine's step is found in (bevy_rapier3d's `PhysicsSet::StepSimulation`, Avian's
    /// `PhysicsSystems::StepSimulation`) always wins, with a warning when it is not the one
    /// named here.
    pub physics_schedule: Option<InternedScheduleLabel>,
}

impl Default for DentbendPlugin {
    fn default() -> Self {
        Self { gpu: true, physics_schedule: None }
    }
}

impl DentbendPlugin {
    /// Every dent on the CPU, updating mesh assets.
    pub fn cpu_only() -> Self {
        Self { gpu: false, ..Self::default() }
    }

    /// bevy_rapier3d steps in `schedule` (as its own `in_schedule`).
    pub fn in_schedule(mut self, schedule: impl ScheduleLabel) -> Self {
        self.physics_schedule = Some(schedule.intern());
        self
    }

    /// bevy_rapier3d steps in `FixedUpdate` (as its own `in_fixed_schedule()`).
    pub fn in_fixed_schedule(self) -> Self {
        self.in_schedule(FixedUpdate)
    }
}

#[cfg(any(feature = "rapier", feature = "avian"))]
impl DentbendPlugin {
    /// Takes contacts from the engine that steps in `app`: Avian when its step is found
    /// (`avian`), else bevy_rapier3d (`rapier`: in the schedule its step is found in, else the
    /// one named, else `PostUpdate`).
    fn add_contact_source(&self, app: &mut App) {
        // There whichever engine steps (or none): systems of the app may read it.
        app.init_resource::<bend::Bends>();
        #[cfg(feature = "avian")]
        if let Some(found) = avian::physics_schedule(app) {
            self.check_named(found, "Avian");
            info!("bevy_dentbend: contacts from Avian, which steps in {found:?}");
            avian::build(app, found);
            bend::build::<avian::Avian>(app, found);
            return;
        }
        #[cfg(feature = "rapier")]
        {
            let found = rapier::physics_schedule(app);
            if let Some(found) = found {
                self.check_named(found, "bevy_rapier3d");
            }
            let schedule = found.or(self.physics_schedule).unwrap_or(PostUpdate.intern());
            rapier::build(app, schedule);
            bend::build::<rapier::Rapier>(app, schedule);
        }
        #[cfg(not(feature = "rapier"))]
        warn!(
            "bevy_dentbend: no Avian step was found when DentbendPlugin was finished, so no contact will dent; add \
             Avian's PhysicsPlugins to the app, or write DentContact messages"
        );
    }

    /// Warns when the engine steps in `found` but the plug-in was told another schedule.
    fn check_named(&self, found: InternedScheduleLabel, engine: &str) {
        if let Some(named) = self.physics_schedule
            && named != found
        {
            warn!(
                "{engine} steps in {found:?} but DentbendPlugin was told {named:?}: its impacts would be missed and \
                 nothing would dent; use DentbendPlugin::in_schedule({found:?}) (dentbend follows {engine}'s schedule)"
            );
        }
    }
}

/// The GPU's status, readable by the application.
#[derive(Resource, Clone)]
pub struct DentGpu(link::MainLink);

impl DentGpu {
    /// Whether dents run on Bevy's device (and its name), not yet known, or not (why).
    pub fn status(&self) -> GpuStatus {
        self.0.status()
    }
}

impl Plugin for DentbendPlugin {
    fn build(&self, app: &mut App) {
        let (main, render) = link::link();
        if !self.gpu {
            render.set_status(GpuStatus::Unavailable("DentbendPlugin::cpu_only".into()));
        }
        app.init_resource::<DentWorld>()
            .init_resource::<DentStats>()
            .insert_resource(DentGpu(main.clone()))
            .insert_resource(main)
            .add_message::<DentContact>()
            .add_message::<DentApplied>()
            .add_message::<MeshDented>()
            .add_message::<BodyBroken>()
            .add_message::<RestoreDamage>()
            .add_message::<DamageRestored>()
            .configure_sets(PostUpdate, (DentSystems::Register, DentSystems::Decide, DentSystems::Apply).chain())
            // Registration reads each body's global transform (its pose, its scale).
            .configure_sets(PostUpdate, DentSystems::Register.after(TransformSystems::Propagate))
            .add_systems(
                PostUpdate,
                (
                    register::forget_removed,
                    register::register_dentables,
                    register::register_projectiles,
                    register::promote_to_gpu,
                    save::restore_damage,
                )
                    .chain()
                    .in_set(DentSystems::Register),
            )
            .add_systems(
                PostUpdate,
                (decide::receive_from_render, decide::decide_dents).chain().in_set(DentSystems::Decide),
            );
        match app.get_sub_app_mut(RenderApp) {
            Some(render_app) => {
                render_app
                    .insert_resource(render)
                    .init_resource::<render::ResidentDents>()
                    .add_systems(RenderStartup, render::start_on_bevys_device)
                    .add_systems(Render, render::make_dents.in_set(RenderSystems::PrepareResources));
            }
            None => render.set_status(GpuStatus::Unavailable("the app has no render world".into())),
        }
    }

    fn finish(&self, app: &mut App) {
        // Every plug-in is built now: the physics engine's step is in its schedule.
        #[cfg(any(feature = "rapier", feature = "avian"))]
        self.add_contact_source(app);
        // The dent kernels write into Bevy's vertex slabs, which need STORAGE usage.
        if let Some(render_app) = app.get_sub_app_mut(RenderApp)
            && let Some(mut settings) = render_app.world_mut().get_resource_mut::<MeshAllocatorSettings>()
        {
            settings.extra_buffer_usages |= BufferUsages::STORAGE;
        }
    }
}
