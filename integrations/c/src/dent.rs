//! One dent: a projectile mesh hits a target mesh.

use dentbend::dent::{DentError, DentJob, DentParams, Impact, Refine, VolumeMode, dent_batch_tracked};
use dentbend::glam::Vec3;
use std::ffi::c_int;

use crate::mesh::DbMesh;
use crate::status::{DB_ERR_DENT, Failure, guarded};

/// An impact, world coordinates, as at the moment of contact.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbImpact {
    /// Contact point, m.
    pub point: [f32; 3],
    /// Denting normal: from the contact into the target (any non-zero length).
    pub normal: [f32; 3],
    /// The projectile's velocity relative to the target, m/s (all zero: head-on along
    /// `normal`).
    pub relative_velocity: [f32; 3],
}

/// How a dent is shaped; start from `db_dent_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbDentOptions {
    /// Peak displacement, m (> 0).
    pub dent_distance: f32,
    /// Width of the dent's smoothing, m; 0 for half the dent distance.
    pub sigma: f32,
    /// Non-zero: put the dent's volume back as a raised rim around it.
    pub preserve_volume: c_int,
    /// Non-zero: refine the target under the dent where it is too coarse for it (new vertices
    /// are appended, new triangles replace split ones).
    pub refine: c_int,
    /// Non-zero: scale a dent back so that no faces of the target cross.
    pub guard_crossings: c_int,
}

/// What a dent did.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct DbDentReport {
    /// Vertices moved.
    pub moved_vertices: usize,
    /// Vertices the refinement added (appended after the existing ones).
    pub added_vertices: usize,
    /// Largest displacement of a vertex, m.
    pub max_displacement: f32,
    /// Fraction of the dent kept by the crossing guard (1: all of it).
    pub kept: f32,
}

/// The default options for a dent of `dent_distance` m: automatic smoothing, no rim,
/// refinement and the crossing guard on.
#[unsafe(no_mangle)]
pub extern "C" fn db_dent_options_default(dent_distance: f32) -> DbDentOptions {
    DbDentOptions { dent_distance, sigma: 0.0, preserve_volume: 0, refine: 1, guard_crossings: 1 }
}

/// Dents `target` where `projectile` hits it (both in world coordinates at the impact), `dent_distance`
/// m deep at most, with the default options. Returns `DB_OK` (0) or an error status, with the
/// reason in `db_last_error`; on failure `target` is unchanged.
///
/// # Safety
/// `target` and `projectile` are null or live meshes, not the same one; `impact` is null or
/// points to a `DbImpact`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_dent(
    target: *mut DbMesh,
    projectile: *const DbMesh,
    impact: *const DbImpact,
    dent_distance: f32,
) -> c_int {
    let options = db_dent_options_default(dent_distance);
    // SAFETY: the caller's contract, and `options` and the report are ours.
    unsafe { db_dent_ex(target, projectile, impact, &options, std::ptr::null_mut()) }
}

/// As `db_dent`, shaped by `options`, and writes what it did to `report` when that is not null.
///
/// # Safety
/// As `db_dent`; `options` is null or points to a `DbDentOptions`, `report` is null or points
/// to a writable `DbDentReport`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_dent_ex(
    target: *mut DbMesh,
    projectile: *const DbMesh,
    impact: *const DbImpact,
    options: *const DbDentOptions,
    report: *mut DbDentReport,
) -> c_int {
    guarded(|| {
        if std::ptr::eq(target.cast_const(), projectile) && !target.is_null() {
            return Err(Failure::invalid("the target and the projectile are the same mesh: dent it with a copy"));
        }
        // SAFETY: the caller's contract; distinct meshes, checked above.
        let (target, projectile) =
            unsafe { (DbMesh::get_mut(target, "target")?, DbMesh::get(projectile, "projectile")?) };
        if impact.is_null() {
            return Err(Failure::null("impact"));
        }
        if options.is_null() {
            return Err(Failure::null("options"));
        }
        // SAFETY: not null, and by the caller's contract a `DbImpact` and a `DbDentOptions`.
        let (impact, options) = unsafe { (*impact, *options) };
        let impact = Impact {
            point: Vec3::from_array(impact.point),
            normal: Vec3::from_array(impact.normal),
            relative_velocity: match Vec3::from_array(impact.relative_velocity) {
                v if v == Vec3::ZERO => Vec3::from_array(impact.normal),
                v => v,
            },
        };
        let params = params(&options)?;
        // One dent as a batch of one: it hands back what the refinement appended, which the
        // mesh's UVs and authored normals follow.
        let mut meshes = [target.mesh().clone()];
        let job = DentJob { target: 0, projectile: projectile.mesh(), impact, params };
        let outcome = dent_batch_tracked(&mut meshes, &[job]).map_err(|e| dent_failure(e.error))?;
        let [dented] = meshes;
        let refinement = outcome.refined.first().cloned().unwrap_or_default();
        let moved = outcome.moved.into_iter().next().unwrap_or_default();
        target.asset.follow_dent(dented, &refinement, &moved).map_err(|e| Failure::invalid(e.to_string()))?;
        target.moved = moved;
        let done = outcome.reports.into_iter().next().unwrap_or_default();
        if !report.is_null() {
            let made = DbDentReport {
                moved_vertices: done.moved_vertices,
                added_vertices: done.refined_vertices,
                max_displacement: done.max_displacement,
                kept: done.limited_to.unwrap_or(1.0),
            };
            // SAFETY: not null, and by the caller's contract a writable `DbDentReport`.
            unsafe { report.write(made) };
        }
        Ok(())
    })
}

/// The library's parameters for `options`, checked.
fn params(options: &DbDentOptions) -> Result<DentParams, Failure> {
    let mut params = DentParams::new(options.dent_distance);
    if options.sigma != 0.0 {
        params.sigma = Some(options.sigma);
    }
    params.volume = if options.preserve_volume != 0 { VolumeMode::Preserve } else { VolumeMode::Free };
    params.refine = if options.refine != 0 { Refine::default() } else { Refine::Off };
    params.guard_crossings = options.guard_crossings != 0;
    params.validate().map_err(|e| Failure::invalid(e.to_string()))?;
    Ok(params)
}

/// The status and message of a failed dent: a bad argument, or a dent the impact cannot make.
fn dent_failure(error: DentError) -> Failure {
    match error {
        DentError::InvalidParameter { .. } | DentError::InvalidImpact(_) | DentError::Mesh(_) => {
            Failure::invalid(error.to_string())
        }
        other => Failure { status: DB_ERR_DENT, message: other.to_string() },
    }
}
