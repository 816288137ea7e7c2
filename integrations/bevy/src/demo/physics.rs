//! The physics engine a demo scene runs on, and the few bodies the scenes make with it.

use bevy::prelude::*;
use dentbend::TriMesh;

/// The physics engine a demo app steps its bodies with.
#[derive(Resource, Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Physics {
    /// bevy_rapier3d, one 1/60 s step a frame in `PostUpdate` (`rapier` feature).
    #[cfg(feature = "rapier")]
    #[cfg_attr(feature = "rapier", default)]
    Rapier,
    /// Avian 0.8, one 1/60 s step a frame in its default `FixedPostUpdate` (virtual time
    /// advances 1/60 s a frame; `avian` feature).
    #[cfg(feature = "avian")]
    #[cfg_attr(not(feature = "rapier"), default)]
    Avian,
}

/// One physics step, s.
const STEP: f32 = 1.0 / 60.0;

impl Physics {
    /// The engine named `name` (`rapier` or `avian`), if this build has it.
    ///
    /// # Errors
    /// An unknown name, or an engine whose feature is off, with the fix.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            #[cfg(feature = "rapier")]
            "rapier" => Ok(Self::Rapier),
            #[cfg(feature = "avian")]
            "avian" => Ok(Self::Avian),
            #[cfg(not(feature = "rapier"))]
            "rapier" => Err("--physics rapier needs bevy_dentbend's `rapier` feature".into()),
            #[cfg(not(feature = "avian"))]
            "avian" => Err("--physics avian needs bevy_dentbend's `avian` feature".into()),
            _ => Err(format!("--physics takes rapier or avian, not {name:?}")),
        }
    }

    /// The engine's name, as [`from_name`](Self::from_name) takes it.
    pub fn name(self) -> &'static str {
        match self {
            #[cfg(feature = "rapier")]
            Self::Rapier => "rapier",
            #[cfg(feature = "avian")]
            Self::Avian => "avian",
        }
    }

    /// Adds the engine's plug-ins to `app`, stepping 1/60 s each frame (and the engine as a
    /// resource, for [`RainPlugin`](super::RainPlugin)).
    pub fn add_to(self, app: &mut App) {
        app.insert_resource(self);
        match self {
            #[cfg(feature = "rapier")]
            Self::Rapier => {
                use bevy_rapier3d::prelude::{NoUserData, RapierPhysicsPlugin, TimestepMode};
                app.add_plugins(RapierPhysicsPlugin::<NoUserData>::default())
                    .insert_resource(TimestepMode::Fixed { dt: STEP, substeps: 1 });
            }
            #[cfg(feature = "avian")]
            Self::Avian => {
                use bevy::time::TimeUpdateStrategy;
                use std::time::Duration;
                let step = Duration::from_secs_f32(STEP);
                app.add_plugins(avian3d::PhysicsPlugins::default())
                    .insert_resource(Time::<Fixed>::from_duration(step))
                    .insert_resource(TimeUpdateStrategy::ManualDuration(step));
            }
        }
    }

    /// Makes `entity` a fixed body whose collider is the tri-mesh `mesh`.
    pub(crate) fn fixed_trimesh(self, entity: &mut EntityCommands, mesh: &TriMesh) {
        let (positions, faces) = (mesh.positions().to_vec(), mesh.faces().to_vec());
        match self {
            #[cfg(feature = "rapier")]
            Self::Rapier => {
                use bevy_rapier3d::prelude::{Collider, RigidBody};
                entity.insert((RigidBody::Fixed, Collider::trimesh(positions, faces).expect("a valid tri-mesh")));
            }
            #[cfg(feature = "avian")]
            Self::Avian => {
                use avian3d::prelude::{Collider, RigidBody};
                entity.insert((RigidBody::Static, Collider::trimesh(positions, faces)));
            }
        }
    }

    /// Makes `entity` a fixed box of half-extents `half` m.
    pub(crate) fn fixed_box(self, entity: &mut EntityCommands, half: Vec3) {
        match self {
            #[cfg(feature = "rapier")]
            Self::Rapier => {
                use bevy_rapier3d::prelude::{Collider, RigidBody};
                entity.insert((RigidBody::Fixed, Collider::cuboid(half.x, half.y, half.z)));
            }
            #[cfg(feature = "avian")]
            Self::Avian => {
                use avian3d::prelude::{Collider, RigidBody};
                entity.insert((RigidBody::Static, Collider::cuboid(2.0 * half.x, 2.0 * half.y, 2.0 * half.z)));
            }
        }
    }

    /// Makes `entity` a dynamic ball of `radius` m and `mass` kg, moving at `velocity` m/s,
    /// restitution `restitution`.
    pub(crate) fn ball(self, entity: &mut EntityCommands, radius: f32, mass: f32, velocity: Vec3, restitution: f32) {
        let density = mass / (4.0 / 3.0 * std::f32::consts::PI * radius.powi(3));
        match self {
            #[cfg(feature = "rapier")]
            Self::Rapier => {
                use bevy_rapier3d::prelude::{Collider, ColliderMassProperties, Restitution, RigidBody, Velocity};
                entity.insert((
                    RigidBody::Dynamic,
                    Collider::ball(radius),
                    ColliderMassProperties::Density(density),
                    Restitution::coefficient(restitution),
                    Velocity::linear(velocity),
                ));
            }
            #[cfg(feature = "avian")]
            Self::Avian => {
                use avian3d::prelude::{Collider, ColliderDensity, LinearVelocity, Restitution, RigidBody};
                entity.insert((
                    RigidBody::Dynamic,
                    Collider::sphere(radius),
                    ColliderDensity(density),
                    Restitution::new(restitution),
                    LinearVelocity(velocity),
                ));
            }
        }
    }
}
