//! Articulated rigid bodies in maximal coordinates (Weinstein–Teran–Fedkiw 2006, "Dynamic
//! simulation of articulated rigid bodies with contact and collision"): joints held by
//! impulse-based pre-stabilization (before the position update) and post-stabilization (after
//! it), with the paper's plastic (§4.1) and elastic (§4.3) joints for bending.

mod band;
mod batches;
mod damped_bends;
mod elastic;
mod groups;
mod joint;
mod plastic;
mod poststabilize;
mod prestabilize;
mod solve;
mod system;

pub(crate) use elastic::apply_springs;
pub(crate) use groups::{pair, sync_sleep};
pub use joint::{BendEvent, Joint, JointKind};
pub(crate) use joint::{angle_between, rotation_vector};
pub(crate) use poststabilize::poststabilize;
pub(crate) use prestabilize::{NEWTON, prestabilize};
