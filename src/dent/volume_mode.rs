//! The volume setting of a dent (volume lost, the paper's, or kept); the stage itself is `volume.rs`.

/// What a dent does to the body's volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VolumeMode {
    /// The paper's behaviour: the dent's cavity is lost from the body (a sheet thins).
    #[default]
    Free,
    /// Raise a rim around the crater until the enclosed volume is back: within 2 % of the
    /// cavity volume, usually far closer (a solid's material is pushed aside, not destroyed).
    Preserve,
}
