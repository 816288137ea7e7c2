//! How a bendable body is built and how it bends, for any engine: its pieces' density and
//! friction, its joints' rule, dynamic articulation and skinning weights.

use super::{JointRule, WeightParams};

/// How a bendable body is built and how it bends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendSettings {
    /// Density of every piece, kg/m³.
    pub density: f32,
    /// Friction coefficient of the pieces' colliders.
    pub friction: f32,
    /// The joints' rule (the skeleton's joints and the ones dynamic articulation adds).
    pub joint: JointRule,
    /// Dynamic articulation: a hit whose normal approach speed (m/s, before the step) reaches
    /// this splits the bone it lands on; `None`: never split.
    pub split_speed: Option<f32>,
    /// No split closer than this to an existing joint, m.
    pub min_joint_spacing: f32,
    /// Skinning weights (level-set resolution, influences, falloff).
    pub weights: WeightParams,
}

impl BendSettings {
    /// Plastic joints of `strength` N·m·s with post-bend damping 0.5 rad/s² + 10/s (the paper's
    /// Figure 14), density `density` kg/m³, no dynamic articulation.
    pub fn plastic(density: f32, strength: f32) -> Self {
        Self {
            density,
            friction: 0.5,
            joint: JointRule::plastic(strength),
            split_speed: None,
            min_joint_spacing: 0.3,
            weights: WeightParams::default(),
        }
    }
}
