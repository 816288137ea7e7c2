//! One pass over a mesh's faces that sorts them around a region: the faces with a marked
//! corner (those a change touches), and the other faces that may reach into a box (not all
//! their corners beyond one side of it, by out-codes per vertex). The volume stage and the
//! intersection guard of a dent share one such pass.

use glam::{Vec3, Vec3A};

use super::face_grid::Aabb;

/// Out-code bits of a vertex: beyond the box's low (bits 0–2) or high (bits 3–5) side on x, y, z.
const OUTSIDE: u8 = 0b11_1111;
/// The two marks a vertex can carry (a face with either on a corner is marked).
pub(crate) const MARK_A: u8 = 1 << 6;
pub(crate) const MARK_B: u8 = 1 << 7;

/// The out-code of `p` against `region` (0 inside, closed).
pub(crate) fn out_code(p: Vec3, region: &Aabb) -> u8 {
    // (Aligned lanes: one vector compare each, a third faster over a mesh than `Vec3`'s.)
    let (p, min, max) = (Vec3A::from(p), Vec3A::from(region.min), Vec3A::from(region.max));
    (p.cmplt(min).bitmask() | p.cmpgt(max).bitmask() << 3) as u8
}

/// Faces sorted by [`FaceSort::new`].
pub(crate) struct FaceSort {
    /// The box the out-codes were taken against.
    pub(crate) region: Aabb,
    /// Faces with a marked corner, in face order.
    pub(crate) marked: Vec<u32>,
    /// Faces without one that are not wholly beyond one side of `region`, in face order (none
    /// without a region).
    pub(crate) maybe: Vec<u32>,
    /// Whether every corner of every marked face lies in `region`.
    pub(crate) inside: bool,
}

impl FaceSort {
    /// Sorts `faces` by `codes` (per vertex: the marks, or'ed with [`out_code`] against
    /// `region` when there is one; without a region only the marked faces are listed).
    pub(crate) fn new(faces: &[[u32; 3]], codes: &[u8], region: Option<Aabb>) -> Self {
        let (mut marked, mut maybe, mut inside) = (Vec::new(), Vec::new(), true);
        for (f, face) in faces.iter().enumerate() {
            let [a, b, c] = face.map(|v| codes[v as usize]);
            let any = a | b | c;
            if any & (MARK_A | MARK_B) != 0 {
                marked.push(f as u32);
                inside &= any & OUTSIDE == 0;
            } else if a & b & c == 0 && region.is_some() {
                maybe.push(f as u32);
            }
        }
        Self { region: region.unwrap_or(Aabb::EMPTY), marked, maybe, inside }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_sorted_by_marks_and_reach() {
        let region = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let positions = [
            Vec3::splat(0.5),
            Vec3::new(2.0, 0.5, 0.5),
            Vec3::new(2.0, 0.6, 0.5),
            Vec3::new(2.0, 0.5, 0.7),
            Vec3::new(-1.0, 0.5, 0.5),
        ];
        let mut codes: Vec<u8> = positions.iter().map(|&p| out_code(p, &region)).collect();
        assert_eq!(codes, [0, 0b1000, 0b1000, 0b1000, 0b1]);
        codes[0] |= MARK_A;
        // Face 0: marked, inside. Face 1: all beyond x = 1. Face 2: straddles the box (beyond
        // opposite sides). Face 3: marked, with a corner outside.
        let faces = [[0, 0, 0], [1, 2, 3], [1, 4, 2], [0, 1, 2]];
        let sort = FaceSort::new(&faces, &codes, Some(region));
        assert_eq!((sort.marked, sort.maybe, sort.inside), (vec![0, 3], vec![2], false));
        // Without a region, the marked faces only.
        let marks: Vec<u8> = codes.iter().map(|c| c & MARK_A).collect();
        let sort = FaceSort::new(&faces, &marks, None);
        assert_eq!((sort.marked, sort.maybe), (vec![0, 3], vec![]));
    }
}
