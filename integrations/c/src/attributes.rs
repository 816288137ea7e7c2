//! The vertex attributes of a damage context's game assets (UVs, authored normals): kept beside
//! the bodies' meshes and brought through every dent, fracture and restore, so that a render
//! mesh read back from the context never cracks or loses its texture where a dent refined it.

use std::collections::HashMap;

use dentbend::damage::{BodyFracture, DentedTarget};
use dentbend::fracture::carry_asset;
use dentbend::glam::{Vec2, Vec3};
use dentbend::mesh::{Asset, VertexAttributes};

use crate::status::Failure;

/// The assets of the bodies that have attributes, by id.
#[derive(Debug, Default)]
pub(crate) struct Attributes(HashMap<u64, Asset>);

/// A step's assets, made before anything is committed: each changed body's new asset (`None`:
/// the body is gone), and each fracture's pieces' (`None` for a body without attributes).
#[derive(Debug, Default)]
pub(crate) struct Followed {
    bodies: Vec<(u64, Option<Asset>)>,
    pub(crate) pieces: Vec<Option<Vec<Asset>>>,
}

/// Whether `attributes` holds anything beyond positions and faces.
fn any(attributes: &VertexAttributes) -> bool {
    !attributes.uvs.is_empty()
        || attributes.normals.is_some()
        || attributes.tangents.is_some()
        || !attributes.colors.is_empty()
        || attributes.skin.is_some()
}

fn failed(e: impl std::fmt::Display) -> Failure {
    Failure::invalid(format!("the body's attributes cannot follow: {e}"))
}

impl Attributes {
    /// Keeps `asset` as body `id`'s when it has attributes (forgets the body's otherwise).
    pub(crate) fn keep(&mut self, id: u64, asset: Asset) {
        match any(asset.attributes()) {
            true => self.0.insert(id, asset),
            false => self.0.remove(&id),
        };
    }

    /// Body `id`'s asset, if it has attributes.
    pub(crate) fn get(&self, id: u64) -> Option<&Asset> {
        self.0.get(&id)
    }

    /// Body `id`'s normals to shade with: the authored ones brought through its dents, when it
    /// has them.
    pub(crate) fn normals(&self, id: u64) -> Option<&[Vec3]> {
        self.0.get(&id).and_then(|a| a.attributes().normals.as_deref())
    }

    /// Body `id`'s first UV set, when it has one.
    pub(crate) fn uvs(&self, id: u64) -> Option<&[Vec2]> {
        self.0.get(&id).and_then(|a| a.attributes().uvs.first()).map(Vec::as_slice)
    }

    /// The assets a step's `targets` (its dented meshes) and `fractures` give the bodies that
    /// have attributes, and each fracture's pieces'; nothing is changed.
    ///
    /// # Errors
    /// A dent or fracture that does not describe a body's mesh (a bug, not an input).
    pub(crate) fn follow(
        &self,
        targets: &[DentedTarget<u64>],
        fractures: &[BodyFracture<u64>],
    ) -> Result<Followed, Failure> {
        let mut now: HashMap<u64, Option<Asset>> = HashMap::new();
        for t in targets {
            if let Some(asset) = self.0.get(&t.key) {
                let mut asset = asset.clone();
                asset.follow_dent(t.mesh.clone(), &t.refinement, &t.moved).map_err(failed)?;
                now.insert(t.key, Some(asset));
            }
        }
        let mut pieces = Vec::with_capacity(fractures.len());
        for f in fractures {
            // The mesh that broke: this step's dents included.
            let Some(broken) = now.get(&f.body).map(Option::as_ref).unwrap_or(self.0.get(&f.body)) else {
                pieces.push(None);
                continue;
            };
            let made: Vec<Asset> = f
                .pieces
                .iter()
                .map(|p| carry_asset(broken, p.mesh.clone(), &p.origins))
                .collect::<Result<_, _>>()
                .map_err(failed)?;
            let rest = f.rest.as_ref().map(|r| carry_asset(broken, r.clone(), &f.rest_origins)).transpose();
            now.insert(f.body, rest.map_err(failed)?);
            pieces.push(Some(made));
        }
        Ok(Followed { bodies: now.into_iter().collect(), pieces })
    }

    /// Takes a step's assets (its pieces' stay with the caller).
    pub(crate) fn commit(&mut self, followed: &mut Followed) {
        for (id, asset) in followed.bodies.drain(..) {
            match asset {
                Some(asset) => self.0.insert(id, asset),
                None => self.0.remove(&id),
            };
        }
    }

    /// Gives body `id` `asset` (a restore's, checked by the caller).
    pub(crate) fn replace(&mut self, id: u64, asset: Asset) {
        self.0.insert(id, asset);
    }
}
