//! What is wrong with the inputs of a skinning call ([`skin`](super::skin),
//! [`skin_bones`](super::skin_bones)), and how far a vertex's weights may sum from one.

/// How far a vertex's weights may sum from one.
pub const WEIGHT_SUM_TOLERANCE: f32 = 1e-4;

/// What is wrong with the inputs of a skinning call.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SkinError {
    /// A slice has the wrong number of entries.
    #[error("{what} has {len} entries, expected {expected}")]
    Length {
        /// Which input.
        what: &'static str,
        /// Its length.
        len: usize,
        /// The length it must have.
        expected: usize,
    },
    /// A weight is NaN or infinite.
    #[error("vertex {vertex}: weight {slot} is not finite")]
    NonFiniteWeight {
        /// The vertex.
        vertex: usize,
        /// Which of its four influences.
        slot: usize,
    },
    /// A weight is negative.
    #[error("vertex {vertex}: weight {slot} is {weight}, below zero")]
    NegativeWeight {
        /// The vertex.
        vertex: usize,
        /// Which of its four influences.
        slot: usize,
        /// The weight.
        weight: f32,
    },
    /// A vertex's weights do not sum to one within [`WEIGHT_SUM_TOLERANCE`].
    #[error("vertex {vertex}: weights sum to {sum}, not 1 (± {WEIGHT_SUM_TOLERANCE})")]
    WeightSum {
        /// The vertex.
        vertex: usize,
        /// The sum of its weights.
        sum: f32,
    },
    /// A vertex names a bone that does not exist.
    #[error("vertex {vertex} names bone {bone}, but there are only {bone_count} bones")]
    BoneIndex {
        /// The vertex.
        vertex: usize,
        /// The bone index it names.
        bone: u32,
        /// The number of bones.
        bone_count: u32,
    },
    /// A bone matrix or pose holds NaN or ∞.
    #[error("bone {bone}: its transform is not finite")]
    NonFiniteBone {
        /// The bone.
        bone: usize,
    },
    /// A bone's rest pose cannot be inverted.
    #[error("bone {bone}: its rest pose is not invertible")]
    SingularRestPose {
        /// The bone.
        bone: usize,
    },
    /// A rest position or normal holds NaN or ∞.
    #[error("vertex {vertex}: its rest position or normal is not finite")]
    NonFiniteRest {
        /// The vertex.
        vertex: usize,
    },
    /// The GPU path failed (device error or a size over the device's limits): a
    /// `gpu::GpuError`, shared so this layer does not name the GPU's types.
    #[error(transparent)]
    Gpu(std::sync::Arc<dyn std::error::Error + Send + Sync>),
}
