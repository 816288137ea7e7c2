//! The vertex attributes of a damage context's game assets (UVs, authored normals): kept beside
//! the bodies' meshes and brought through every dent, fracture and restore, so that a render
//! mesh read back from the context never cracks or loses its texture where a dent refined it.

use std::collections::HashMap;
use std::hash::Hash;

use dentbend::TriMesh;
use dentbend::damage::{BodyFracture, DentedTarget};
use dentbend::dent::changed_vertices;
use dentbend::fracture::carry_asset;
use dentbend::glam::{Vec2, Vec3};
use dentbend::mesh::{Asset, Refinement, VertexAttributes};
use dentbend::record::replication::ReplicaChange;

use crate::status::Failure;

/// The assets of the bodies that have attributes, by id (a context's 64-bit ids, a replica's
/// wire ids).
#[derive(Debug)]
pub(crate) struct Attributes<K>(HashMap<K, Asset>);

impl<K> Default for Attributes<K> {
    fn default() -> Self {
        Self(HashMap::new())
    }
}

/// A step's (or message's) assets, made before anything is committed: each changed body's new
/// asset (`None`: the body is gone), and each fracture's pieces' (`None` for a body without
/// attributes).
#[derive(Debug)]
pub(crate) struct Followed<K> {
    bodies: Vec<(K, Option<Asset>)>,
    pub(crate) pieces: Vec<Option<Vec<Asset>>>,
}

/// Whether `attributes` holds anything beyond positions and faces.
pub(crate) fn any(attributes: &VertexAttributes) -> bool {
    !attributes.uvs.is_empty()
        || attributes.normals.is_some()
        || attributes.tangents.is_some()
        || !attributes.colors.is_empty()
        || attributes.skin.is_some()
}

fn failed(e: impl std::fmt::Display) -> Failure {
    Failure::invalid(format!("the body's attributes cannot follow: {e}"))
}

impl<K: Copy + Eq + Hash> Attributes<K> {
    /// Keeps `asset` as body `id`'s when it has attributes (forgets the body's otherwise).
    pub(crate) fn keep(&mut self, id: K, asset: Asset) {
        match any(asset.attributes()) {
            true => self.0.insert(id, asset),
            false => self.0.remove(&id),
        };
    }

    /// Body `id`'s asset, if it has attributes.
    pub(crate) fn get(&self, id: K) -> Option<&Asset> {
        self.0.get(&id)
    }

    /// Body `id`'s normals to shade with: the authored ones brought through its dents, when it
    /// has them.
    pub(crate) fn normals(&self, id: K) -> Option<&[Vec3]> {
        self.0.get(&id).and_then(|a| a.attributes().normals.as_deref())
    }

    /// Body `id`'s first UV set, when it has one.
    pub(crate) fn uvs(&self, id: K) -> Option<&[Vec2]> {
        self.0.get(&id).and_then(|a| a.attributes().uvs.first()).map(Vec::as_slice)
    }

    /// The assets a step's `targets` (its dented meshes) and `fractures` give the bodies that
    /// have attributes, and each fracture's pieces'; nothing is changed.
    ///
    /// # Errors
    /// A dent or fracture that does not describe a body's mesh (a bug, not an input).
    pub(crate) fn follow(
        &self,
        targets: &[DentedTarget<K>],
        fractures: &[BodyFracture<K>],
    ) -> Result<Followed<K>, Failure> {
        let mut now: HashMap<K, Option<Asset>> = HashMap::new();
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
            if broken.mesh() != &f.broken_mesh {
                return Err(failed("the body's asset is not of the mesh that broke"));
            }
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
    pub(crate) fn commit(&mut self, followed: &mut Followed<K>) {
        for (id, asset) in followed.bodies.drain(..) {
            match asset {
                Some(asset) => self.0.insert(id, asset),
                None => self.0.remove(&id),
            };
        }
    }

    /// Whether no body has attributes.
    pub(crate) fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Gives body `id` `asset` (a restore's, checked by the caller).
    pub(crate) fn replace(&mut self, id: K, asset: Asset) {
        self.0.insert(id, asset);
    }

    /// The assets a replica's `changes` (from a message or snapshot) give its bodies that have
    /// attributes, `mesh` giving each body's mesh after them, and each fracture's pieces', in
    /// the order of the changes' fractures; nothing is changed.
    ///
    /// # Errors
    /// A body whose attributes cannot follow its new mesh: a message's dents and breaks always
    /// can (the client computes them); a snapshot's mesh only when it is the base's, moved.
    pub(crate) fn follow_replica<'m>(
        &self,
        changes: &[ReplicaChange],
        mesh: impl Fn(K) -> Option<&'m TriMesh>,
        key: impl Fn(u32) -> K,
    ) -> Result<Followed<K>, Failure> {
        let mut bodies = Vec::new();
        let mut pieces = Vec::new();
        for c in changes {
            let id = key(c.id);
            let Some(asset) = self.0.get(&id) else {
                pieces.extend(c.fracture.as_ref().map(|_| None));
                continue;
            };
            if c.removed && c.fracture.is_none() {
                bodies.push((id, None));
                continue;
            }
            let mut asset = asset.clone();
            // Up to the mesh that broke, or the new mesh.
            let edited = match (&c.fracture, mesh(id)) {
                (Some(f), _) => &f.broken,
                (None, Some(now)) => now,
                (None, None) => continue,
            };
            if asset.mesh() != edited {
                follow_change(&mut asset, edited, c)?;
            }
            if let Some(f) = &c.fracture {
                let made: Vec<Asset> = f
                    .pieces
                    .iter()
                    .map(|(_, p)| carry_asset(&asset, p.mesh.clone(), &p.origins))
                    .collect::<Result<_, _>>()
                    .map_err(failed)?;
                pieces.push(Some(made));
                let rest = match (c.removed, mesh(id)) {
                    (false, Some(rest)) => Some(carry_asset(&asset, rest.clone(), &f.rest_origins).map_err(failed)?),
                    _ => None,
                };
                bodies.push((id, rest));
            } else {
                bodies.push((id, Some(asset)));
            }
        }
        Ok(Followed { bodies, pieces })
    }
}

/// Brings `asset` from its mesh to `edited`, change `c`'s mesh (or the mesh that broke): with
/// the refinement the client computed, exactly; without one (a change that came as a mesh),
/// only when the faces are the same (positions moved, normals recomputed).
///
/// # Errors
/// A change that refined the mesh without saying how.
fn follow_change(asset: &mut Asset, edited: &TriMesh, c: &ReplicaChange) -> Result<(), Failure> {
    let moved = changed_vertices(asset.mesh(), edited);
    match &c.refinement {
        Some(refinement) => asset.follow_dent(edited.clone(), refinement, &moved).map_err(failed),
        None if asset.mesh().faces() == edited.faces() => {
            asset.follow_dent(edited.clone(), &Refinement::default(), &moved).map_err(failed)
        }
        None => Err(Failure::invalid(format!(
            "body {}'s attributes (UVs, normals) cannot follow: its mesh came refined, without the edges its new \
             vertices split (a snapshot after a refining dent or a break); join before the body is damaged, or add \
             it without attributes",
            c.id
        ))),
    }
}
