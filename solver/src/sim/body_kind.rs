//! How a body moves: static, dynamic or kinematic.

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// Never moves; infinite mass.
    Static,
    /// Moved by gravity, collisions and contacts.
    #[default]
    Dynamic,
    /// Moves with its given velocities, pushes dynamic bodies, is not pushed back.
    Kinematic,
}
