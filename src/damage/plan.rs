//! [`Damage`]: one step's hits → decided dents → one batch of plain dents on the caller's
//! backend and progressive dents rebuilt from their pre-dent surfaces → a [`DamagePlan`].

use std::hash::Hash;

use glam::Vec3;

use super::fracture::{BodyFracture, break_at, breaking_hits};
use super::{DamageError, DentBackend, DentTargets, Hit, TargetView};
use crate::dent::{
    DentReport, Impact, LocalContact, ProgressiveDents, changed_vertices, decide_dent_distance, dent_batch_tracked,
    projectile_offset,
};
use crate::fracture::DentTally;
use crate::mesh::{Refinement, TriMesh};

/// One dent the plan makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AppliedDent<K> {
    /// The dented body.
    pub target: K,
    /// The body that dented it.
    pub projectile: K,
    /// The contact (world), normal into the target.
    pub impact: Impact,
    /// The contact and the projectile's pose in the target's mesh coordinates, in the exact
    /// form the dent was made from (what a replication message carries).
    pub local: LocalContact,
    /// How far from the contact the projectile was cropped, m (`projectile_reach`).
    pub reach: f32,
    /// Dent distance, m (a progressive dent's accumulated distance).
    pub dent_distance: f32,
    /// How far to move the projectile into the dent, world, m (zero unless the target's
    /// settings ask for it; only move dynamic projectiles).
    pub projectile_offset: Vec3,
    /// Enclosed volume the dent changed, target mesh units³, signed (after the rim of
    /// [`VolumeMode::Preserve`](crate::dent::VolumeMode::Preserve)); a progressive dent's is measured
    /// from its pre-dent surface. Zero from a backend that does not measure it (the GPU).
    pub volume_change: f64,
    /// The dent's cavity (|volume change| before any rim), target mesh units³.
    pub cavity_volume: f64,
    /// How deep the dent really is: its largest vertex displacement, target mesh units. Below
    /// `dent_distance` when the intersection guard limited it (`limited_to`) or the surface under
    /// it is coarse; 0 when it moved nothing. Zero from a backend that queues the dent to make
    /// later (a game engine's resident GPU path), which reports it when made.
    pub depth_made: f32,
    /// Vertices the dent moved (0 from a backend that queues it, as `depth_made`).
    pub moved_vertices: usize,
    /// Fraction of the dent's displacement kept when the intersection guard scaled it back so
    /// that no faces cross or turn over (`None`: not limited).
    pub limited_to: Option<f32>,
}

/// A target's new surface.
#[derive(Debug, Clone)]
pub struct DentedTarget<K> {
    /// The body.
    pub key: K,
    /// Its dented mesh, same coordinates as before: the same vertices and faces, or, when
    /// refined, those first and new ones appended ([`refinement`](Self::refinement)).
    pub mesh: TriMesh,
    /// The vertices that moved, ascending: refit the collider over these (when the faces are
    /// unchanged; a refined target's list includes every new vertex).
    pub moved: Vec<u32>,
    /// What refinement appended (new vertices with their parents, for the caller's per-vertex
    /// data; new faces with their parent face), from the first `base_vertex_count` vertices of
    /// the body's mesh; empty when nothing was refined.
    pub refinement: Refinement,
    /// Whether the faces differ from the body's mesh (it was refined, or a progressive dent
    /// was rebuilt from a surface with other faces): rebuild the collider from
    /// [`mesh`](Self::mesh) instead of refitting it.
    pub topology_changed: bool,
}

/// The result of one step's hits, not yet applied to the caller's bodies: apply
/// [`targets`](Self::targets), then [`fractures`](Self::fractures) (a broken body's rest
/// replaces its dented mesh).
#[derive(Debug, Clone)]
pub struct DamagePlan<K> {
    /// Every dent made, plain ones first, each group in hit order.
    pub dents: Vec<AppliedDent<K>>,
    /// Every dented body's new surface, once each.
    pub targets: Vec<DentedTarget<K>>,
    /// Every body that broke (at most once each), in order of its first breaking hit.
    pub fractures: Vec<BodyFracture<K>>,
    /// The step the plan was made for (as given to [`Damage::plan`]).
    pub step: u64,
}

/// A hit that dents, with its distance.
#[derive(Debug, Clone, Copy)]
struct Decided<'a, K> {
    hit: usize,
    data: Hit<'a, K>,
    distance: f32,
    /// The contact in the target's coordinates.
    local: LocalContact,
}

/// Engine-neutral damage state, keyed by the caller's ids: progressive dents under way, the
/// breakable bodies' accumulated dents, and how many fractures it has made (pieces' ids).
#[derive(Debug, Clone)]
pub struct Damage<K> {
    progress: ProgressiveDents<K, TriMesh>,
    tally: DentTally<K>,
    fractures_made: u64,
}

impl<K> Default for Damage<K> {
    fn default() -> Self {
        Self { progress: ProgressiveDents::default(), tally: DentTally::default(), fractures_made: 0 }
    }
}

impl<K: Copy + Eq + Hash + std::fmt::Debug> Damage<K> {
    /// No progressive dent under way.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets `body`'s progressive dents and accumulated dent (call when the caller removes
    /// it).
    pub fn forget(&mut self, body: K) {
        self.progress.forget(body);
        self.tally.forget(body);
    }

    /// Breakable body `body`'s accumulated dent, m (what its
    /// [`dent_limit`](crate::fracture::FractureSettings::dent_limit) is compared with).
    pub fn accumulated_dent(&self, body: K) -> f32 {
        self.tally.total(body)
    }

    /// How many fractures this state has made: the next one's [`PieceId::fracture`](super::PieceId::fracture).
    pub fn fractures_made(&self) -> u64 {
        self.fractures_made
    }

    /// Decides and computes the dents `hits` (of the step numbered `step`) make on `targets`,
    /// ordinary ones as one batch on `backend`, progressive ones from their pre-dent surfaces;
    /// every map comes from the undented surfaces. Hits on bodies that do not dent, and hits too
    /// slow to dent, are skipped. Then each breakable body that a hit, or its accumulated dent,
    /// breaks is broken at its most energetic breaking hit, its dents of the step kept in the
    /// pieces. State (progressive dents, accumulated dents, the fracture count) advances only
    /// when the whole plan succeeds.
    ///
    /// # Errors
    /// [`DamageError`] naming the hit; nothing changes then.
    pub fn plan(
        &mut self,
        targets: &impl DentTargets<K>,
        hits: &[Hit<'_, K>],
        step: u64,
        backend: &mut dyn DentBackend<K>,
    ) -> Result<DamagePlan<K>, DamageError> {
        let decided = decide(targets, hits)?;
        let (progressive, plain): (Vec<_>, Vec<_>) =
            decided.into_iter().partition(|d| view(targets, d).settings.progressive);
        let mut plan = plain_dents(targets, &plain, backend)?;
        plan.step = step;
        // Progressive state changes only once the whole plan stands: this step's contacts are
        // staged (a contact hit twice in one step deepens its staged dent).
        let mut staged: ProgressiveDents<K, TriMesh> = ProgressiveDents::new();
        for d in &progressive {
            let target = view(targets, d);
            let (key, projectile) = (d.data.target, d.data.projectile);
            let limits = (d.distance, target.settings.material.cap);
            let (pre_dent, distance) = if staged.contains(key, projectile) {
                staged.next(key, projectile, step, limits, || target.mesh.clone())
            } else {
                self.progress.next(key, projectile, step, limits, || latest(&plan, key).unwrap_or(target.mesh).clone())
            };
            let Some((mesh, refinement, report)) = dent_one(&target, d, distance, &pre_dent)? else { continue };
            // Rebuilt from the pre-dent surface: what moved is what differs from the surface now
            // (and every vertex past the shorter of the two).
            let now = latest(&plan, key).unwrap_or(target.mesh);
            let moved = changed_vertices(now, &mesh);
            let topology_changed = now.faces() != mesh.faces();
            staged.record(key, projectile, pre_dent, distance, step);
            plan.dents.push(with_report(applied(&target, d, distance), &report));
            let dented = DentedTarget { key, mesh, moved, refinement, topology_changed };
            match plan.targets.iter_mut().find(|t| t.key == key) {
                Some(t) => merge(t, dented),
                None => plan.targets.push(dented),
            }
        }
        let mut tally = self.tally.clone();
        for dent in &plan.dents {
            if let Some(target) = targets.target(dent.target).filter(|t| t.fracture.is_some()) {
                tally.add(dent.target, dent.projectile, dent.dent_distance, step, target.settings.progressive);
            }
        }
        plan.fractures = self.fractures(targets, hits, &tally, &plan)?;
        self.progress.end_stale(step);
        self.progress.absorb(staged);
        // A broken body starts again: no accumulated dent, no progressive dent on its old mesh.
        for fracture in &plan.fractures {
            tally.forget(fracture.body);
            self.progress.forget(fracture.body);
        }
        self.tally = tally;
        self.fractures_made += plan.fractures.len() as u64;
        Ok(plan)
    }

    /// The fractures of `hits` on `targets` after `plan`'s dents, numbered from
    /// [`fractures_made`](Self::fractures_made).
    fn fractures(
        &self,
        targets: &impl DentTargets<K>,
        hits: &[Hit<'_, K>],
        tally: &DentTally<K>,
        plan: &DamagePlan<K>,
    ) -> Result<Vec<BodyFracture<K>>, DamageError> {
        let mut made = Vec::new();
        for b in breaking_hits(targets, hits, tally) {
            let Some(target) = targets.target(b.target) else { continue };
            let Some(settings) = target.fracture else { continue };
            let mesh = latest(plan, b.target).unwrap_or(target.mesh);
            let number = self.fractures_made + made.len() as u64;
            let fracture = break_at(mesh, target.to_world, settings, &b, number)
                .map_err(|error| DamageError::Fracture { hit: b.hit, target: format!("{:?}", b.target), error })?;
            made.extend(fracture);
        }
        Ok(made)
    }
}

/// The target of a decided hit (it was looked up when decided).
fn view<'t, K: Copy>(targets: &'t impl DentTargets<K>, d: &Decided<'_, K>) -> TargetView<'t> {
    targets.target(d.data.target).expect("decided hits are on dentable targets")
}

/// Every hit's dent decision (which validates its contact), before anything is dented.
fn decide<'a, K: Copy + std::fmt::Debug>(
    targets: &impl DentTargets<K>,
    hits: &[Hit<'a, K>],
) -> Result<Vec<Decided<'a, K>>, DamageError> {
    let mut out = Vec::new();
    for (k, hit) in hits.iter().enumerate() {
        for body in [hit.target, hit.projectile] {
            if !targets.contains(body) {
                return Err(DamageError::UnknownBody { hit: k, body: format!("{body:?}") });
            }
        }
        let Some(target) = targets.target(hit.target) else { continue };
        let error = |error| DamageError::Dent { hit: k, target: format!("{:?}", hit.target), error };
        let distance = decide_dent_distance(
            target.settings,
            &hit.impact,
            &hit.target_state,
            &hit.projectile_state,
            &hit.projectile_surface,
        )
        .map_err(error)?;
        if let Some(distance) = distance {
            let local = LocalContact::new(&hit.impact, target.to_world, hit.projectile_surface.to_world);
            out.push(Decided { hit: k, data: *hit, distance, local });
        }
    }
    Ok(out)
}

/// The projectile of `d` cropped to what can shape a `distance` m dent in `target`.
fn cropped<K>(target: &TargetView<'_>, d: &Decided<'_, K>, distance: f32) -> Option<TriMesh> {
    d.local.crop(d.data.projectile_surface.mesh, target.settings.projectile_reach(target.radius, distance))
}

fn applied<K: Copy>(target: &TargetView<'_>, d: &Decided<'_, K>, distance: f32) -> AppliedDent<K> {
    AppliedDent {
        target: d.data.target,
        projectile: d.data.projectile,
        impact: d.data.impact,
        local: d.local,
        reach: target.settings.projectile_reach(target.radius, distance),
        dent_distance: distance,
        projectile_offset: projectile_offset(target.settings, &d.data.impact, distance),
        volume_change: 0.0,
        cavity_volume: 0.0,
        depth_made: 0.0,
        moved_vertices: 0,
        limited_to: None,
    }
}

/// Ordinary dents: one batch over copies of the targets hit.
fn plain_dents<K: Copy + Eq + Hash + std::fmt::Debug>(
    targets: &impl DentTargets<K>,
    plain: &[Decided<'_, K>],
    backend: &mut dyn DentBackend<K>,
) -> Result<DamagePlan<K>, DamageError> {
    let mut kept = Vec::new();
    let mut projectiles = Vec::new();
    for d in plain {
        if let Some(mesh) = cropped(&view(targets, d), d, d.distance) {
            kept.push(*d);
            projectiles.push(mesh);
        }
    }
    let (mut keys, mut meshes): (Vec<K>, Vec<TriMesh>) = (Vec::new(), Vec::new());
    let mut jobs = Vec::with_capacity(kept.len());
    for (d, projectile) in kept.iter().zip(&projectiles) {
        let slot = match keys.iter().position(|k| *k == d.data.target) {
            Some(slot) => slot,
            None => {
                keys.push(d.data.target);
                meshes.push(view(targets, d).mesh.clone());
                keys.len() - 1
            }
        };
        jobs.push(d.local.job(projectile, &view(targets, d).settings.params, d.distance, slot));
    }
    if jobs.is_empty() {
        return Ok(DamagePlan { dents: Vec::new(), targets: Vec::new(), fractures: Vec::new(), step: 0 });
    }
    let outcome = backend.dent_batch(&keys, &mut meshes, &jobs).map_err(|e| {
        let d = &kept[e.job];
        DamageError::Dent { hit: d.hit, target: format!("{:?}", d.data.target), error: e.error }
    })?;
    let dents = kept
        .iter()
        .zip(&outcome.reports)
        .map(|(d, report)| with_report(applied(&view(targets, d), d, d.distance), report))
        .collect();
    let changed: Vec<bool> = (0..keys.len()).map(|t| outcome.topology_changed(t)).collect();
    let mut refined = outcome.refined.into_iter();
    let dented = keys.into_iter().zip(meshes).zip(outcome.moved).zip(changed);
    let targets = dented
        .map(|(((key, mesh), moved), topology_changed)| {
            let refinement = refined.next().unwrap_or_default();
            DentedTarget { key, mesh, moved, refinement, topology_changed }
        })
        .collect();
    Ok(DamagePlan { dents, targets, fractures: Vec::new(), step: 0 })
}

/// A progressive dent of `d`, `distance` m deep, rebuilt from `pre_dent`, with what refinement
/// appended to `pre_dent`; `None` when no part of the projectile is near.
fn dent_one<K: std::fmt::Debug>(
    target: &TargetView<'_>,
    d: &Decided<'_, K>,
    distance: f32,
    pre_dent: &TriMesh,
) -> Result<Option<(TriMesh, Refinement, DentReport)>, DamageError> {
    let Some(projectile) = cropped(target, d, distance) else { return Ok(None) };
    let mut meshes = vec![pre_dent.clone()];
    let outcome = dent_batch_tracked(&mut meshes, &[d.local.job(&projectile, &target.settings.params, distance, 0)])
        .map_err(|e| DamageError::Dent { hit: d.hit, target: format!("{:?}", d.data.target), error: e.error })?;
    let refinement = outcome.refined.into_iter().next().unwrap_or_default();
    let report = outcome.reports.into_iter().next().unwrap_or_default();
    Ok(meshes.pop().map(|mesh| (mesh, refinement, report)))
}

/// `dent` with what its batch report measured: volume, depth, moved vertices and the guard's
/// limit.
fn with_report<K>(dent: AppliedDent<K>, report: &DentReport) -> AppliedDent<K> {
    AppliedDent {
        volume_change: report.volume_change,
        cavity_volume: report.cavity_volume,
        depth_made: report.max_displacement,
        moved_vertices: report.moved_vertices,
        limited_to: report.limited_to,
        ..dent
    }
}

/// The newest surface the plan has for `key`.
fn latest<K: PartialEq>(plan: &DamagePlan<K>, key: K) -> Option<&TriMesh> {
    plan.targets.iter().find(|t| t.key == key).map(|t| &t.mesh)
}

/// `target` takes `later`'s mesh, the union of both moved sets; a refinement of `later` (from a
/// base the target's refinement may not share) replaces the target's.
fn merge<K>(target: &mut DentedTarget<K>, later: DentedTarget<K>) {
    if !later.refinement.is_empty() {
        target.refinement = later.refinement;
    }
    target.topology_changed |= later.topology_changed;
    target.mesh = later.mesh;
    target.moved.extend(later.moved);
    target.moved.sort_unstable();
    target.moved.dedup();
    let count = target.mesh.vertex_count() as u32;
    target.moved.retain(|&v| v < count);
}
