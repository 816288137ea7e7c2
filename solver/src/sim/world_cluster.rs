//! Condensing bodies into rigid clusters and back (paper §4.2): a quiet articulated body is
//! simulated as one rigid body; a hit un-condenses it.
//!
//! A cluster is simulated by a proxy body: its mass, centre of mass and inertia are the members'
//! summed, its velocity conserves their linear and angular momentum, and its collider is the
//! compound of the members' colliders, so contacts land where they would on the members. The
//! members leave the step (no contacts, no integration, their joints to each other idle) and
//! follow the proxy rigidly after every step. Joints from a member to a body outside the cluster
//! move to the proxy while it is condensed. Collision events name the member hit, not the proxy.
//!
//! A child module of `world` (declared there with `#[path]`) so that it can edit the world's
//! bodies, joints and joined pairs together.

use std::sync::Arc;

use glam::{Mat3, Vec3};
use parry3d::math::Pose;
use parry3d::shape::SharedShape;

use super::{World, invalid};
use crate::sim::activity::Activity;
use crate::sim::cluster::{Cluster, Member, Role};
use crate::sim::{BodyKind, ColliderKind, RigidBody, SimError};
use dentbend::mesh::TriMesh;

impl World {
    /// Condenses the bodies `members` (world indices, at least two) into one rigid cluster and
    /// returns its id. From the next step on they move as one rigid body: mass, centre of mass
    /// and inertia summed, linear and angular momentum kept, relative poses frozen (joints
    /// between them rest), collider the compound of theirs. Their poses and velocities in
    /// [`bodies`](Self::bodies) follow the cluster after every step; events name the member hit.
    /// The cluster is simulated by a proxy body (see [`RigidBody::is_cluster_proxy`]), added to
    /// the world or reused from a dissolved cluster.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for fewer than two members, an index out of range or repeated, a
    /// body that is not dynamic, already condensed or a proxy, a dentable body (its mesh
    /// changes), or a body whose collider is itself composite (triangle mesh). The world is
    /// unchanged on error.
    pub fn condense(&mut self, members: &[usize]) -> Result<usize, SimError> {
        self.check_condensable(members)?;
        let proxy_body = self.proxy_body(members)?;
        let id = self.clusters.iter().position(|c| !c.is_active()).unwrap_or(self.clusters.len());
        let proxy = match self.clusters.get(id) {
            Some(spare) => spare.proxy,
            None => self.bodies.len(),
        };
        let (position, orientation) = (proxy_body.position, proxy_body.orientation);
        let inverse = orientation.inverse();
        let placed = members
            .iter()
            .map(|&body| {
                let b = &self.bodies[body];
                Member { body, offset: inverse * (b.position - position), turn: (inverse * b.orientation).normalize() }
            })
            .collect();
        if proxy == self.bodies.len() {
            self.bodies.push(proxy_body);
            self.clusters.push(Cluster { proxy, members: Vec::new(), moved_joints: Vec::new() });
        } else {
            self.bodies[proxy] = proxy_body;
        }
        self.bodies[proxy].role = Role::Proxy(id);
        self.cache.forget(proxy);
        let mut moved = Vec::new();
        for joint in 0..self.joints.len() {
            let (a, b) = (self.joints[joint].a, self.joints[joint].b);
            let member = match (members.contains(&a), members.contains(&b)) {
                (true, false) => a,
                (false, true) => b,
                _ => continue,
            };
            self.move_joint_end(joint, member, proxy);
            moved.push((joint, member));
        }
        for &body in members {
            self.bodies[body].role = Role::Member(id);
        }
        self.clusters[id].members = placed;
        self.clusters[id].moved_joints = moved;
        self.layout += 1;
        self.sync_members();
        Ok(id)
    }

    /// Dissolves cluster `cluster`: its members move on with the cluster's rigid motion
    /// (v + ω × r at their centres of mass) and its sleep state, joints moved to the proxy go
    /// back to their members, and the proxy is kept aside for a later cluster.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for a cluster id that is not an active cluster; the world is unchanged.
    pub fn uncondense(&mut self, cluster: usize) -> Result<(), SimError> {
        if !self.clusters.get(cluster).is_some_and(Cluster::is_active) {
            return Err(invalid("cluster", cluster, "is not an active cluster of the world"));
        }
        self.sync_members();
        let proxy = self.clusters[cluster].proxy;
        let members = std::mem::take(&mut self.clusters[cluster].members);
        let moved_joints = std::mem::take(&mut self.clusters[cluster].moved_joints);
        for &(joint, member) in moved_joints.iter().rev() {
            self.move_joint_end(joint, proxy, member);
        }
        let activity = self.bodies[proxy].activity;
        for member in &members {
            let body = &mut self.bodies[member.body];
            body.role = Role::Free;
            body.activity = activity;
        }
        let spare = &mut self.bodies[proxy];
        spare.role = Role::Spare;
        spare.linear_velocity = Vec3::ZERO;
        spare.angular_velocity = Vec3::ZERO;
        spare.activity = Activity::default();
        self.cache.forget(proxy);
        self.layout += 1;
        Ok(())
    }

    /// The active cluster body `body` is condensed into, or stands in for.
    pub fn cluster_of(&self, body: usize) -> Option<usize> {
        match self.bodies.get(body)?.role {
            Role::Member(id) | Role::Proxy(id) => Some(id),
            Role::Free | Role::Spare => None,
        }
    }

    /// The members of active cluster `cluster` (world indices, in the order given to
    /// [`condense`](Self::condense)).
    pub fn cluster_members(&self, cluster: usize) -> Option<Vec<usize>> {
        let c = self.clusters.get(cluster).filter(|c| c.is_active())?;
        Some(c.members.iter().map(|m| m.body).collect())
    }

    /// The bodies joint `joint` was made between (or moved to by a split), even while one of
    /// them is condensed and the joint acts on its cluster's proxy.
    pub fn joint_ends(&self, joint: usize) -> Option<(usize, usize)> {
        let j = self.joints.get(joint)?;
        let member = |end: usize| match self.bodies[end].role {
            Role::Proxy(id) => self.clusters[id].moved_joints.iter().find(|m| m.0 == joint).map_or(end, |m| m.1),
            _ => end,
        };
        Some((member(j.a), member(j.b)))
    }

    /// Ids of the active clusters.
    pub fn clusters(&self) -> Vec<usize> {
        (0..self.clusters.len()).filter(|&k| self.clusters[k].is_active()).collect()
    }

    /// Puts every cluster's members where the cluster's rigid motion carries them.
    pub(crate) fn sync_members(&mut self) {
        for cluster in self.clusters.iter().filter(|c| c.is_active()) {
            let p = &self.bodies[cluster.proxy];
            let (position, orientation, linear, angular) =
                (p.position, p.orientation, p.linear_velocity, p.angular_velocity);
            let asleep = p.activity.asleep;
            for member in &cluster.members {
                let body = &mut self.bodies[member.body];
                body.orientation = (orientation * member.turn).normalize();
                body.position = position + orientation * member.offset;
                body.linear_velocity = linear + angular.cross(body.position - position);
                body.angular_velocity = angular;
                body.activity.asleep = asleep;
            }
        }
    }

    /// The member of a cluster whose collider part `part` of proxy `body` is; `body` itself when
    /// it is not a proxy.
    pub(crate) fn member_hit(&self, body: usize, part: u32) -> usize {
        match self.bodies[body].role {
            Role::Proxy(id) => self.clusters[id].member_of_part(part).unwrap_or(body),
            _ => body,
        }
    }

    fn check_condensable(&self, members: &[usize]) -> Result<(), SimError> {
        if members.len() < 2 {
            return Err(invalid("cluster members", members, "must be at least two bodies"));
        }
        for (k, &index) in members.iter().enumerate() {
            let Some(body) = self.bodies.get(index) else {
                return Err(invalid("cluster member", index, "is not a body of the world"));
            };
            let refuse = |reason| Err(invalid(format!("cluster member \"{}\"", body.name), index, reason));
            if members[..k].contains(&index) {
                return refuse("is listed twice");
            }
            if let Some(reason) = unclusterable(body) {
                return refuse(reason);
            }
            if body.role != Role::Free {
                return refuse("is already condensed");
            }
        }
        Ok(())
    }

    /// Whether body `index` may be in a cluster (it may be in one now): see [`unclusterable`].
    pub(crate) fn clusterable(&self, index: usize) -> bool {
        self.bodies.get(index).is_some_and(|body| unclusterable(body).is_none())
    }

    /// The proxy of `members`: summed mass properties about the common centre of mass, axes
    /// those of the first member, momentum-conserving velocities, the compound of their colliders
    /// and their meshes joined (body coordinates).
    fn proxy_body(&self, members: &[usize]) -> Result<RigidBody, SimError> {
        let bodies: Vec<&RigidBody> = members.iter().map(|&i| &self.bodies[i]).collect();
        let mass: f32 = bodies.iter().map(|b| b.mass).sum();
        let centre = bodies.iter().map(|b| b.mass * b.position).sum::<Vec3>() / mass;
        let world_inertia = |b: &RigidBody| {
            let rotation = Mat3::from_quat(b.orientation);
            rotation * b.inertia * rotation.transpose()
        };
        let mut inertia = Mat3::ZERO;
        let (mut momentum, mut spin) = (Vec3::ZERO, Vec3::ZERO);
        for b in &bodies {
            let r = b.position - centre;
            inertia += world_inertia(b) + b.mass * (Mat3::from_diagonal(Vec3::splat(r.dot(r))) - outer(r, r));
            momentum += b.mass * b.linear_velocity;
            spin += world_inertia(b) * b.angular_velocity + b.mass * r.cross(b.linear_velocity);
        }
        let orientation = bodies[0].orientation;
        let rotation = Mat3::from_quat(orientation);
        let body_inertia = rotation.transpose() * inertia * rotation;
        let inverse_inertia = body_inertia.inverse();
        let name = format!("cluster of \"{}\"", bodies[0].name);
        if !(inverse_inertia.is_finite() && mass.is_finite() && mass > 0.0) {
            return Err(SimError::BadShape { body: name, reason: "cluster inertia tensor is singular".into() });
        }
        let inverse = orientation.inverse();
        let local = |b: &RigidBody| Pose::from_parts(inverse * (b.position - centre), inverse * b.orientation);
        let parts: Vec<(Pose, SharedShape)> = bodies.iter().map(|b| (local(b), b.shape.clone())).collect();
        let (mut positions, mut faces) = (Vec::new(), Vec::new());
        for b in &bodies {
            let pose = local(b);
            let base = positions.len() as u32;
            positions.extend(b.mesh.positions().iter().map(|&p| pose.transform_point(p)));
            faces.extend(b.mesh.faces().iter().map(|f| f.map(|v| v + base)));
        }
        let all_asleep = bodies.iter().all(|b| b.activity.asleep);
        Ok(RigidBody {
            name,
            kind: BodyKind::Dynamic,
            position: centre,
            orientation,
            linear_velocity: momentum / mass,
            angular_velocity: inertia.inverse() * spin,
            surface: bodies[0].surface,
            dent: None,
            fracture: None,
            color: bodies[0].color,
            mass,
            inertia: body_inertia,
            inverse_mass: 1.0 / mass,
            inverse_inertia,
            model_offset: Vec3::ZERO,
            mesh: Arc::new(TriMesh::new(positions, faces)?),
            collider_kind: ColliderKind::ConvexHull,
            shape: SharedShape::compound(parts),
            collider_map: None,
            activity: if all_asleep { bodies[0].activity } else { Activity::default() },
            role: Role::Free,
        })
    }
}

/// The outer product a·bᵀ.
fn outer(a: Vec3, b: Vec3) -> Mat3 {
    Mat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Why `body` can never be in a cluster, if it cannot: not dynamic, a proxy itself, dentable (its
/// mesh changes) or with a composite collider (a compound cannot hold one).
fn unclusterable(body: &RigidBody) -> Option<&'static str> {
    if body.kind != BodyKind::Dynamic {
        Some("is not dynamic")
    } else if body.is_cluster_proxy() {
        Some("is a cluster's proxy")
    } else if body.dent.is_some() {
        Some("is dentable (its mesh changes) and cannot be condensed")
    } else if body.fracture.is_some() {
        Some("is breakable (its mesh changes) and cannot be condensed")
    } else if body.shape.as_composite_shape().is_some() {
        Some("has a composite collider (triangle mesh), which a cluster cannot hold")
    } else {
        None
    }
}
