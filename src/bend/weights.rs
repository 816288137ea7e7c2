//! Skinning weights: per vertex, the bones that move it and how much, stored compactly and handed
//! to the skinning kernel as four influences per vertex.

use super::BendError;

/// Most influences a vertex can be given at the start ([`WeightParams::influences`]); bone splits
/// may add one more each to the vertices they touch.
pub const MAX_INFLUENCES: usize = 8;

/// How skinning weights are computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeightParams {
    /// Level-set resolution (cells along the longest side); see
    /// [`LevelSet::build`](super::LevelSet::build). Default 64.
    pub resolution: u32,
    /// Bones per vertex, 1..=[`MAX_INFLUENCES`]: the nearest ones by geodesic distance.
    /// Default 4.
    pub influences: usize,
    /// Exponent p of the inverse-distance kernel w ∝ d⁻ᵖ, in (0, 16]. Larger is sharper and more
    /// local: past a joint of a bar of radius R the far bone's weight falls to about (R/x)ᵖ at a
    /// distance x. Default 4 (about 1 % at x = 3R; with 2 the bunny's tail keeps 13 % on its ears).
    pub falloff: f32,
}

impl Default for WeightParams {
    fn default() -> Self {
        Self { resolution: super::DEFAULT_RESOLUTION, influences: 4, falloff: 4.0 }
    }
}

impl WeightParams {
    /// Checks every field.
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] naming the first bad field.
    pub fn validate(&self) -> Result<(), BendError> {
        let (lo, hi) = (super::LevelSet::MIN_RESOLUTION, super::LevelSet::MAX_RESOLUTION);
        if !(lo..=hi).contains(&self.resolution) {
            let value = self.resolution.to_string();
            return Err(BendError::InvalidParameter { name: "resolution", value, reason: "must be in 8..=256" });
        }
        if !(1..=MAX_INFLUENCES).contains(&self.influences) {
            let value = self.influences.to_string();
            return Err(BendError::InvalidParameter { name: "influences", value, reason: "must be in 1..=8" });
        }
        if !(self.falloff.is_finite() && self.falloff > 0.0 && self.falloff <= 16.0) {
            let value = self.falloff.to_string();
            return Err(BendError::InvalidParameter { name: "falloff", value, reason: "must be in (0, 16]" });
        }
        Ok(())
    }
}

/// Skinning weights of a mesh's vertices over a skeleton's bones.
///
/// Each vertex has one or more `(bone, weight)` influences, sorted by decreasing weight (lower
/// bone index first on ties), every weight positive and their sum 1 (to f32 rounding). Built by
/// [`SkinWeights::compute`] and updated after a bone split by [`SkinWeights::after_split`].
#[derive(Debug, Clone, PartialEq)]
pub struct SkinWeights {
    /// Start of vertex v's influences in `bones`/`weights`; `vertex_count + 1` entries.
    offsets: Vec<u32>,
    bones: Vec<u32>,
    weights: Vec<f32>,
    bone_count: usize,
}

impl SkinWeights {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of bones of the skeleton the weights were computed for.
    pub fn bone_count(&self) -> usize {
        self.bone_count
    }

    /// The influences of `vertex`: bone indices and weights, by decreasing weight. Empty slices
    /// for an out-of-range vertex.
    pub fn influences(&self, vertex: usize) -> (&[u32], &[f32]) {
        match (self.offsets.get(vertex), self.offsets.get(vertex + 1)) {
            (Some(&a), Some(&b)) => (&self.bones[a as usize..b as usize], &self.weights[a as usize..b as usize]),
            _ => (&[], &[]),
        }
    }

    /// Weight of `bone` on `vertex` (0 when the bone does not influence it or an index is out
    /// of range).
    pub fn weight(&self, vertex: usize, bone: usize) -> f32 {
        u32::try_from(bone).ok().and_then(|b| self.find(vertex, b)).unwrap_or(0.0)
    }

    /// Weight of `bone` on `vertex`, `None` when the bone does not influence it.
    pub(crate) fn find(&self, vertex: usize, bone: u32) -> Option<f32> {
        let (bones, weights) = self.influences(vertex);
        bones.iter().position(|&b| b == bone).map(|i| weights[i])
    }

    /// The bone with the largest weight on `vertex` (lowest index on ties), `None` out of range.
    pub fn dominant_bone(&self, vertex: usize) -> Option<usize> {
        self.influences(vertex).0.first().map(|&b| b as usize)
    }

    /// Most influences any vertex has.
    pub fn max_influence_count(&self) -> usize {
        self.offsets.windows(2).map(|w| (w[1] - w[0]) as usize).max().unwrap_or(0)
    }

    /// Four influences per vertex for the skinning kernel: the four largest, renormalised to sum
    /// to 1, padded with bone 0 at weight 0.
    pub fn influences4(&self) -> Vec<([u32; 4], [f32; 4])> {
        (0..self.vertex_count())
            .map(|v| {
                let (bones, weights) = self.influences(v);
                let n = bones.len().min(4);
                let total: f32 = weights[..n].iter().sum();
                let mut out = ([0u32; 4], [0.0f32; 4]);
                for i in 0..n {
                    out.0[i] = bones[i];
                    out.1[i] = weights[i] / total;
                }
                out
            })
            .collect()
    }
}

/// Builds [`SkinWeights`] vertex by vertex.
#[derive(Debug, Default)]
pub(crate) struct WeightsBuilder {
    offsets: Vec<u32>,
    entries: Vec<(u32, f32)>,
}

impl WeightsBuilder {
    /// A builder with room for `vertices` vertices of about `per_vertex` influences.
    pub(crate) fn with_capacity(vertices: usize, per_vertex: usize) -> Self {
        let mut offsets = Vec::with_capacity(vertices + 1);
        offsets.push(0);
        Self { offsets, entries: Vec::with_capacity(vertices * per_vertex) }
    }

    /// Appends the next vertex's influences, sorting them by decreasing weight (lower bone first
    /// on ties).
    pub(crate) fn push_vertex(&mut self, influences: impl IntoIterator<Item = (u32, f32)>) {
        let start = self.entries.len();
        self.entries.extend(influences);
        self.entries[start..].sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        self.offsets.push(self.entries.len() as u32);
    }

    /// The weights, for a skeleton of `bone_count` bones.
    pub(crate) fn finish(self, bone_count: usize) -> SkinWeights {
        let (bones, weights) = self.entries.into_iter().unzip();
        SkinWeights { offsets: self.offsets, bones, weights, bone_count }
    }
}
