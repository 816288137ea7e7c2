//! Rigid clusters (paper §4.2, "condensation"): bodies collapsed into one rigid body with a single
//! mass, centre of mass, inertia tensor and velocity, simulated through a stand-in body (the
//! proxy) whose collider is the compound of its members' colliders. See
//! [`World::condense`](super::World::condense).

use glam::{Quat, Vec3};

/// What a body is to the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum Role {
    /// Simulated on its own.
    #[default]
    Free,
    /// Condensed into cluster `.0`: it follows the proxy rigidly and the step skips it.
    Member(usize),
    /// The stand-in body simulating cluster `.0`.
    Proxy(usize),
    /// A proxy whose cluster was dissolved, kept for the next cluster (the step skips it).
    Spare,
}

/// A member's place in its cluster.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Member {
    /// Its world index.
    pub body: usize,
    /// Its centre of mass in the proxy's body frame, m.
    pub offset: Vec3,
    /// Its orientation relative to the proxy's: `q_member = q_proxy · turn`.
    pub turn: Quat,
}

/// One cluster: its proxy, its members and the joints moved from a member to the proxy.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cluster {
    /// World index of the proxy body.
    pub proxy: usize,
    /// The members (empty when dissolved).
    pub members: Vec<Member>,
    /// Joints that had one end on a member, moved to the proxy while condensed: (joint, member).
    pub moved_joints: Vec<(usize, usize)>,
}

impl Cluster {
    /// Whether the cluster holds bodies now.
    pub fn is_active(&self) -> bool {
        !self.members.is_empty()
    }

    /// The member whose collider is part `part` of the proxy's compound collider.
    pub fn member_of_part(&self, part: u32) -> Option<usize> {
        self.members.get(part as usize).map(|m| m.body)
    }
}
