//! Skinning every bending body of a world at once (paper Algorithm 2, step 13: the parent mesh
//! follows its sub-bodies every frame), on the GPU's `skin` kernel ([`GpuSkinner`], rest data
//! resident) or on its CPU twin [`cpu::skin`](dentbend::cpu::skin) (the fallback and the
//! reference, the same as [`ArticulatedBody::skinned_mesh`]).

#[cfg(feature = "gpu")]
use super::GpuSkinner;
use super::{ArticulatedBody, Bending};
use crate::sim::{GpuDevice, SimError, World};
use dentbend::cpu::{SkinBone, Skinned};
use dentbend::mesh::TriMesh;

/// Most vertices of one group of bodies skinned together on the GPU (unless a single body has
/// more): what one change uploads again, 64 bytes of rest data per vertex (4 MiB).
pub(crate) const GROUP_VERTICES: usize = 1 << 16;

/// Skins the bending bodies of a [`Bending`] on the GPU or the CPU and keeps the results.
///
/// ```no_run
/// use dentbend_solver::coupling::Skinner;
/// use dentbend_solver::scene::{SceneSize, load_sized};
///
/// let scene = load_sized("plank", SceneSize::Demo)?;
/// let mut skinner = Skinner::new(dentbend::gpu::shared_context().ok());
/// skinner.skin(&scene.bending, &scene.world)?;
/// for (name, mesh, _colour) in skinner.meshes(&scene.bending)? {
///     println!("{name}: {} vertices", mesh.vertex_count());
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Skinner {
    context: Option<&'static GpuDevice>,
    /// Built at the first skin with bodies on the GPU.
    #[cfg(feature = "gpu")]
    gpu: Option<GpuSkinner>,
    group_vertices: usize,
    /// The last skin's results per body: the CPU twin's, or the GPU's once read back.
    outputs: Vec<Skinned>,
    /// Whether `outputs` holds the last skin's results (false until a GPU skin is read back).
    read: bool,
}

impl Skinner {
    /// Skins on `gpu` when given, else on the CPU twin. Nothing is compiled or uploaded before
    /// the first [`skin`](Self::skin).
    pub fn new(gpu: Option<&'static GpuDevice>) -> Self {
        Self {
            context: gpu,
            #[cfg(feature = "gpu")]
            gpu: None,
            group_vertices: GROUP_VERTICES,
            outputs: Vec::new(),
            read: true,
        }
    }

    /// Builder: on the GPU, at most `vertices` vertices per group of bodies skinned together
    /// (see [`GpuSkinner`]; 65,536 vertices by default); takes effect at the first skin.
    pub fn with_group_vertices(mut self, vertices: usize) -> Self {
        self.group_vertices = vertices;
        self
    }

    /// Whether skinning runs on the GPU.
    pub fn on_gpu(&self) -> bool {
        self.context.is_some()
    }

    /// The GPU skinner (resident meshes, upload count), once the first GPU skin made it.
    #[cfg(feature = "gpu")]
    pub fn gpu(&self) -> Option<&GpuSkinner> {
        self.gpu.as_ref()
    }

    /// Skins every body of `bending` to its sub-bodies' poses in `world` (world coordinates, m).
    /// On the GPU the results stay resident until [`skinned`](Self::skinned) reads them back.
    /// After an error there are no results until the next skin.
    ///
    /// # Errors
    /// [`SimError::GpuSkinning`] for a device error; [`SimError::Invalid`] if a sub-body is
    /// missing from `world`; [`SimError::BadShape`] for rest data or poses the kernel refuses.
    pub fn skin(&mut self, bending: &Bending, world: &World) -> Result<(), SimError> {
        let skinned = self.skin_all(bending, world);
        if skinned.is_err() {
            // No half-made results: asking for them says to skin again.
            self.outputs.clear();
            self.read = true;
        }
        skinned
    }

    /// [`skin`](Self::skin) but for clearing the results on error.
    fn skin_all(&mut self, bending: &Bending, world: &World) -> Result<(), SimError> {
        let bodies = bending.bodies();
        match self.context {
            #[cfg(feature = "gpu")]
            Some(context) if !bodies.is_empty() => {
                self.read = false;
                let gpu = match &mut self.gpu {
                    Some(gpu) => gpu,
                    None => self.gpu.insert(GpuSkinner::new(context, self.group_vertices)?),
                };
                gpu.skin(bending, world)
            }
            _ => {
                self.outputs.resize_with(bodies.len(), Skinned::default);
                for (body, out) in bodies.iter().zip(&mut self.outputs) {
                    skin_on_cpu(body, &bone_matrices(body, world)?, out)?;
                }
                self.read = true;
                Ok(())
            }
        }
    }

    /// The last [`skin`](Self::skin)'s results, one per bending body in [`Bending::bodies`]
    /// order: positions and unit normals straight from the kernel (world, m); read back from the
    /// GPU once per skin. Empty before the first skin.
    ///
    /// # Errors
    /// [`SimError::GpuSkinning`] if the read-back fails.
    pub fn skinned(&mut self) -> Result<&[Skinned], SimError> {
        if !self.read {
            #[cfg(feature = "gpu")]
            if let Some(gpu) = &self.gpu {
                self.outputs = gpu.read_back()?;
            }
            self.read = true;
        }
        Ok(&self.outputs)
    }

    /// The last [`skin`](Self::skin)'s results as meshes: (name, mesh, colour) per body of
    /// `bending` (the one skinned), each its rest mesh with the skinned positions and normals
    /// recomputed from them, as [`ArticulatedBody::skinned_mesh`] makes it.
    ///
    /// # Errors
    /// As [`skinned`](Self::skinned); [`SimError::Invalid`] if `bending` is not what was skinned
    /// (another body count or vertex count).
    pub fn meshes(&mut self, bending: &Bending) -> Result<Vec<(String, TriMesh, [f32; 3])>, SimError> {
        let skinned = self.skinned()?;
        if skinned.len() != bending.bodies().len() {
            return Err(stale(format!("{} bodies skinned, {} now", skinned.len(), bending.bodies().len())));
        }
        bending
            .bodies()
            .iter()
            .zip(skinned)
            .map(|(body, out)| {
                let mut mesh = body.rest_mesh().clone();
                if out.positions.len() != mesh.vertex_count() {
                    return Err(stale(format!(
                        "{} vertices skinned, {} now",
                        out.positions.len(),
                        mesh.vertex_count()
                    )));
                }
                mesh.set_positions(out.positions.clone()).map_err(|e| body.skin_error(e))?;
                Ok((body.name().to_owned(), mesh, body.color()))
            })
            .collect()
    }
}

/// A [`SimError::Invalid`] for results of another [`Bending`] than the one asked about.
fn stale(value: String) -> SimError {
    SimError::Invalid { what: "skinned meshes".into(), value, reason: "do not match the bending bodies: skin again" }
}

/// `body`'s skinning matrices now: its sub-bodies' model transforms (model → world).
pub(crate) fn bone_matrices(body: &ArticulatedBody, world: &World) -> Result<Vec<SkinBone>, SimError> {
    Ok(body.bone_transforms(world)?.into_iter().map(SkinBone::from_affine).collect())
}

/// [`cpu::skin`](dentbend::cpu::skin) of `body`'s rest mesh with `bones` into `out` (resized to
/// the vertex count).
pub(crate) fn skin_on_cpu(body: &ArticulatedBody, bones: &[SkinBone], out: &mut Skinned) -> Result<(), SimError> {
    body.skin_rest_on_cpu(body.rest_mesh(), bones, out)
}
