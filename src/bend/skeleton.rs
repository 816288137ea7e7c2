//! The articulated skeleton of a bendable body: bones as segments in the body's rest (model) frame,
//! connected into one tree by joints, and the bone split that adds a joint where a hit lands
//! (paper §4, "dynamic joints").

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::BendError;
use super::geometry::segment_param;

/// Smallest bone length accepted, as a fraction of the skeleton's extent (bounding-box diagonal
/// of all bone endpoints).
pub(crate) const MIN_BONE_FRACTION: f32 = 1e-6;
/// Smallest bone length accepted in absolute terms, m (guards a skeleton of coincident points).
pub(crate) const MIN_BONE_LENGTH: f32 = 1e-9;
/// A split point must project at least this fraction of the bone's length away from either end.
pub(crate) const SPLIT_END_FRACTION: f32 = 0.05;
/// A child's head must lie within this fraction of the child's own length from its parent bone.
pub(crate) const JOINT_GAP_FRACTION: f32 = 0.5;

/// How a bone is given in code and in scene files (`[[body.bend.bone]] head = [x, y, z]`,
/// `tail = [x, y, z]`, `parent = 0`).
///
/// # Example
/// ```
/// use dentbend::bend::{BoneDesc, Skeleton};
/// let bones: Vec<BoneDesc> = serde_json::from_str(
///     r#"[{"head": [0, 0, 0], "tail": [1, 0, 0]}, {"head": [1, 0, 0], "tail": [2, 0, 0], "parent": 0}]"#,
/// ).unwrap();
/// let skeleton = Skeleton::new(bones).unwrap();
/// assert_eq!(skeleton.joints()[0].point, dentbend::glam::Vec3::X);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoneDesc {
    /// Start of the bone (where it joins its parent), rest frame, m.
    pub head: Vec3,
    /// End of the bone, rest frame, m.
    pub tail: Vec3,
    /// Index of the parent bone; `None` (omitted) for the root.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<usize>,
}

impl BoneDesc {
    /// A bone from `head` to `tail` (m) under `parent`.
    pub fn new(head: Vec3, tail: Vec3, parent: Option<usize>) -> Self {
        Self { head, tail, parent }
    }
}

/// One validated bone: a segment in the rest frame with its place in the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Bone {
    /// Start of the bone, rest frame, m.
    pub head: Vec3,
    /// End of the bone, rest frame, m.
    pub tail: Vec3,
    /// Index of the parent bone, `None` for the root.
    pub parent: Option<usize>,
}

impl Bone {
    /// Length, m.
    pub fn length(&self) -> f32 {
        self.head.distance(self.tail)
    }

    /// Unit direction from head to tail.
    pub fn direction(&self) -> Vec3 {
        (self.tail - self.head).normalize_or_zero()
    }

    /// The point a fraction `t` of the way from head (0) to tail (1), m.
    pub fn point_at(&self, t: f32) -> Vec3 {
        self.head.lerp(self.tail, t)
    }

    /// Fraction along the bone (clamped to `[0, 1]`) of the bone point nearest to `p`.
    pub fn project(&self, p: Vec3) -> f32 {
        segment_param(p, self.head, self.tail)
    }

    /// Distance from `p` to the bone segment, m.
    pub fn distance(&self, p: Vec3) -> f32 {
        p.distance(self.point_at(self.project(p)))
    }
}

/// A joint: where a child bone's head meets its parent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoneJoint {
    /// Index of the parent bone.
    pub parent: usize,
    /// Index of the child bone.
    pub child: usize,
    /// The joint's position in the rest frame, m: the child's head.
    pub point: Vec3,
}

/// An articulated skeleton: one tree of bones (exactly one root, no cycles).
///
/// A forest is refused: the bones of one rigid body must all be articulated to each other, or
/// its sub-bodies would fall apart in the simulation. Bone indices are stable: [`split_bone`]
/// keeps the split bone's index for its first half and appends the second.
///
/// [`split_bone`]: Skeleton::split_bone
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<BoneDesc>", into = "Vec<BoneDesc>")]
pub struct Skeleton {
    bones: Vec<Bone>,
}

impl Skeleton {
    /// Validates `bones` and builds the skeleton.
    ///
    /// # Errors
    /// [`BendError::NoBones`], [`BendError::NonFiniteBone`], [`BendError::ZeroLengthBone`]
    /// (length ≤ 10⁻⁶ × the skeleton's extent or ≤ 1 nm),
    /// [`BendError::ParentOutOfRange`], [`BendError::Cycle`] (a bone its own parent included),
    /// [`BendError::MultipleRoots`] or [`BendError::DetachedJoint`] (a child's head farther than
    /// half of its length from the parent bone).
    pub fn new(bones: Vec<BoneDesc>) -> Result<Self, BendError> {
        if bones.is_empty() {
            return Err(BendError::NoBones);
        }
        for (bone, desc) in bones.iter().enumerate() {
            for (end, value) in [("head", desc.head), ("tail", desc.tail)] {
                if !value.is_finite() {
                    return Err(BendError::NonFiniteBone { bone, end, value: value.to_array() });
                }
            }
        }
        let (lo, hi) = bones.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), b| {
            (lo.min(b.head).min(b.tail), hi.max(b.head).max(b.tail))
        });
        let minimum = (MIN_BONE_FRACTION * lo.distance(hi)).max(MIN_BONE_LENGTH);
        for (bone, desc) in bones.iter().enumerate() {
            let length = desc.head.distance(desc.tail);
            if length <= minimum {
                return Err(BendError::ZeroLengthBone { bone, length, minimum });
            }
            if let Some(parent) = desc.parent.filter(|&p| p >= bones.len()) {
                return Err(BendError::ParentOutOfRange { bone, parent, count: bones.len() });
            }
        }
        check_tree(&bones)?;
        let bones: Vec<Bone> =
            bones.into_iter().map(|d| Bone { head: d.head, tail: d.tail, parent: d.parent }).collect();
        for (bone, b) in bones.iter().enumerate() {
            if let Some(parent) = b.parent {
                let gap = bones[parent].distance(b.head);
                let limit = JOINT_GAP_FRACTION * b.length();
                if gap > limit {
                    return Err(BendError::DetachedJoint { bone, parent, gap, limit });
                }
            }
        }
        Ok(Self { bones })
    }

    /// The bones, indexed as given.
    pub fn bones(&self) -> &[Bone] {
        &self.bones
    }

    /// Bone `index`, or `None` if out of range.
    pub fn bone(&self, index: usize) -> Option<&Bone> {
        self.bones.get(index)
    }

    /// Number of bones (at least one).
    pub fn len(&self) -> usize {
        self.bones.len()
    }

    /// Always `false`: a skeleton has at least one bone.
    pub fn is_empty(&self) -> bool {
        self.bones.is_empty()
    }

    /// Index of the root bone (the only one without a parent).
    pub fn root(&self) -> usize {
        self.bones.iter().position(|b| b.parent.is_none()).unwrap_or(0)
    }

    /// Indices of the bones whose parent is `bone`, ascending.
    pub fn children(&self, bone: usize) -> Vec<usize> {
        (0..self.bones.len()).filter(|&c| self.bones[c].parent == Some(bone)).collect()
    }

    /// One joint per non-root bone, in bone order.
    pub fn joints(&self) -> Vec<BoneJoint> {
        self.bones
            .iter()
            .enumerate()
            .filter_map(|(child, b)| b.parent.map(|parent| BoneJoint { parent, child, point: b.head }))
            .collect()
    }

    /// The bone nearest to `point` (the lowest index on ties) with the fraction along it of the
    /// nearest bone point and the distance, m. `None` for a non-finite point.
    pub fn nearest_bone(&self, point: Vec3) -> Option<(usize, f32, f32)> {
        if !point.is_finite() {
            return None;
        }
        self.bones.iter().enumerate().fold(None, |best, (i, b)| {
            let t = b.project(point);
            let d = point.distance(b.point_at(t));
            match best {
                Some((_, _, bd)) if bd <= d => best,
                _ => Some((i, t, d)),
            }
        })
    }

    /// The bone descriptors, for saving (the inverse of [`Skeleton::new`]).
    pub fn descs(&self) -> Vec<BoneDesc> {
        self.bones.iter().map(|b| BoneDesc::new(b.head, b.tail, b.parent)).collect()
    }

    /// Splits `bone` at the projection of `point` onto it, adding a joint there.
    ///
    /// The first half (head → split point) keeps index `bone` and its parent; the second half
    /// (split point → tail) is appended as bone `len()` with the first half as parent. Children
    /// of the old bone are re-parented to the half nearest to their head (a child whose head
    /// projects at or beyond the split point goes to the second half). Returns
    /// `(first, second)`.
    ///
    /// # Errors
    /// [`BendError::BoneOutOfRange`], [`BendError::InvalidParameter`] for a non-finite point, or
    /// [`BendError::SplitNearEnd`] when the point projects within 5 % of the
    /// bone's length from either end (or beyond it). The skeleton is unchanged on error.
    ///
    /// # Example
    /// ```
    /// use dentbend::bend::{BoneDesc, Skeleton};
    /// use dentbend::glam::Vec3;
    /// let mut s = Skeleton::new(vec![BoneDesc::new(Vec3::ZERO, 4.0 * Vec3::X, None)]).unwrap();
    /// let (a, b) = s.split_bone(0, Vec3::new(1.0, 0.5, 0.0)).unwrap();
    /// assert_eq!((a, b), (0, 1));
    /// assert_eq!(s.bones()[1].head, Vec3::X);
    /// ```
    pub fn split_bone(&mut self, bone: usize, point: Vec3) -> Result<(usize, usize), BendError> {
        let count = self.bones.len();
        let old = self.bones.get(bone).ok_or(BendError::BoneOutOfRange { bone, count })?.clone();
        if !point.is_finite() {
            let value = format!("{:?}", point.to_array());
            return Err(BendError::InvalidParameter { name: "point", value, reason: "must be finite" });
        }
        let ab = old.tail - old.head;
        let t = (point - old.head).dot(ab) / ab.length_squared();
        let (min, max) = (SPLIT_END_FRACTION, 1.0 - SPLIT_END_FRACTION);
        if !(min..=max).contains(&t) {
            return Err(BendError::SplitNearEnd { bone, t, min, max });
        }
        let split = old.point_at(t);
        let second = count;
        for child in self.children(bone) {
            if old.project(self.bones[child].head) >= t {
                self.bones[child].parent = Some(second);
            }
        }
        self.bones[bone].tail = split;
        self.bones.push(Bone { head: split, tail: old.tail, parent: Some(bone) });
        Ok((bone, second))
    }
}

impl TryFrom<Vec<BoneDesc>> for Skeleton {
    type Error = BendError;

    fn try_from(bones: Vec<BoneDesc>) -> Result<Self, BendError> {
        Self::new(bones)
    }
}

impl From<Skeleton> for Vec<BoneDesc> {
    fn from(skeleton: Skeleton) -> Self {
        skeleton.descs()
    }
}

/// Checks that the parent links form one tree: no cycles, exactly one root. Parents are in range.
fn check_tree(bones: &[BoneDesc]) -> Result<(), BendError> {
    // 0 = unvisited, 1 = on the current walk, 2 = known to reach the root.
    let mut state = vec![0u8; bones.len()];
    for start in 0..bones.len() {
        let mut walk = Vec::new();
        let mut current = Some(start);
        while let Some(bone) = current {
            match state[bone] {
                2 => break,
                1 => {
                    let from = walk.iter().position(|&b| b == bone).unwrap_or(0);
                    let cycle = walk[from..].to_vec();
                    return Err(BendError::Cycle { bone, cycle });
                }
                _ => {
                    state[bone] = 1;
                    walk.push(bone);
                    current = bones[bone].parent;
                }
            }
        }
        walk.iter().for_each(|&b| state[b] = 2);
    }
    let roots: Vec<usize> = (0..bones.len()).filter(|&b| bones[b].parent.is_none()).collect();
    if roots.len() > 1 {
        return Err(BendError::MultipleRoots { roots });
    }
    Ok(())
}
