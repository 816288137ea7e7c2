//! Where a pattern lands: centred on the impact point with its z axis along the impact normal
//! (into the body), in the body's mesh coordinates. The frame's x and y axes follow from the
//! normal alone, so a placement is reproducible from its two vectors.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use super::FractureError;
use super::clip::Plane;
use super::pattern::{BOUND_SIDES, CellSide, FracturePattern};
use crate::mesh::MAX_COORDINATE;

/// An impact as the pattern is placed on it, in the mesh's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Placement {
    /// The impact point, m (the pattern's origin).
    pub point: Vec3,
    /// The impact normal into the body (the pattern's z axis); need not be unit.
    pub normal: Vec3,
}

/// The pattern frame in mesh coordinates: origin and unit axes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub origin: DVec3,
    pub x: DVec3,
    pub y: DVec3,
    pub z: DVec3,
}

impl Placement {
    /// Checks that the point is finite and in the mesh range and the normal finite and not zero.
    ///
    /// # Errors
    /// [`FractureError::InvalidPlacement`].
    pub fn validate(&self) -> Result<(), FractureError> {
        if !(self.point.is_finite() && self.point.abs().max_element() <= MAX_COORDINATE) {
            return Err(FractureError::InvalidPlacement(format!(
                "point {} must be finite and within ±1e6 m",
                self.point
            )));
        }
        if !(self.normal.is_finite() && self.normal.length_squared() > 1e-20) {
            return Err(FractureError::InvalidPlacement(format!("normal {} must be finite and not zero", self.normal)));
        }
        Ok(())
    }

    /// The frame: origin at the point, z the unit normal, x and y from it.
    pub(crate) fn frame(&self) -> Frame {
        let z = self.normal.as_dvec3().normalize();
        let (x, y) = z.any_orthonormal_pair();
        Frame { origin: self.point.as_dvec3(), x, y, z }
    }
}

impl Frame {
    /// A cell side (a vertical plane of the frame) in mesh coordinates.
    pub(crate) fn side(&self, side: &CellSide) -> Plane {
        let normal = self.x * side.normal.x + self.y * side.normal.y;
        Plane { normal, offset: side.offset + normal.dot(self.origin) }
    }

    /// The planes of the pattern's bounding prism: the 16-gon's sides and z = ±R.
    pub(crate) fn bound(&self, pattern: &FracturePattern) -> Vec<Plane> {
        let r = pattern.radius();
        // Side k's normal is at (k + 1)·22.5°. Opposite sides in pairs, the four square ones
        // first: after four cuts what is left of the mesh is the pattern's square, so the later
        // cuts (and their caps) are small.
        const ORDER: [usize; BOUND_SIDES] = [15, 7, 3, 11, 1, 9, 5, 13, 0, 8, 4, 12, 2, 10, 6, 14];
        let sides = pattern.bound();
        let mut planes: Vec<Plane> = ORDER.iter().filter_map(|&k| sides.get(k)).map(|s| self.side(s)).collect();
        for normal in [self.z, -self.z] {
            planes.push(Plane { normal, offset: r + normal.dot(self.origin) });
        }
        planes
    }
}
