//! The target's local thickness along a dent's axis, and the falloff fitted to it so the front of
//! a wall cannot be pushed through its back (the no-fold condition of paper §3.1, Figure 2d,
//! measured on the body instead of assumed).
//!
//! A wall whose front lies at depth `z_f` and back at `z_b` (thickness `T = z_b − z_f`) under a
//! map cell that pushes by `D` along the axis ends `T − D·(a(z_f) − a(z_b))` thick. The dent
//! keeps at least [`MIN_WALL_KEPT`] of every measured wall; where the falloff would keep less,
//! it is stretched in depth (`a(z/k)`, `k > 1`, which tends to moving the wall as a whole) by
//! the least `k` that satisfies every measurement.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::{Attenuation, Grid};

/// The parts of a dent map the fit reads (the map's grid, cells and dent distance, world units).
pub(crate) struct MapView<'a> {
    pub grid: Grid,
    pub cells: &'a [[f32; 4]],
    pub dent_distance: f32,
}

/// Least fraction of a wall's thickness along the dent axis that a dent leaves.
pub(crate) const MIN_WALL_KEPT: f32 = 0.5;
/// A falloff that would leave less than this fraction of a wall folds it (or squashes it flat):
/// that, and only that, is warned about.
pub(crate) const FOLD_KEPT: f32 = 0.1;
/// Map cells pushing less than this fraction of the deepest push are not measured.
const MEASURED_PUSH: f32 = 0.25;
/// Rays per side of the map: the footprint is sampled on at most this many squared cells.
const RAYS_PER_SIDE: u32 = 8;

/// The falloff a dent uses on one target and why.
#[derive(Debug, Clone)]
pub(crate) struct FittedFalloff {
    /// The falloff to apply: the caller's, or it stretched in depth.
    pub(crate) attenuation: Attenuation,
    /// The thinnest wall measured under the dent, world units (`None`: not measured, because
    /// the falloff cannot fold any wall under this map, or no ray met the body).
    pub(crate) thickness: Option<f32>,
    /// Set when the caller's falloff would have folded the wall.
    pub(crate) warning: Option<String>,
}

/// One wall measured along the axis under a map cell: front and back depths below the
/// collision plane and the cell's push along the axis, world units.
#[derive(Debug, Clone, Copy)]
struct Wall {
    front: f32,
    back: f32,
    push: f32,
}

impl Wall {
    /// Fraction of the wall left after the push with falloff `a(z/stretch)`.
    fn kept(&self, attenuation: &Attenuation, d: f32, stretch: f32) -> f32 {
        let a = |z: f32| attenuation.eval(z / stretch, d);
        let thickness = self.back - self.front;
        (thickness - self.push * (a(self.front) - a(self.back))) / thickness
    }
}

/// Fits `attenuation` to the body (`positions`, `faces`) under `map`; see the module docs.
pub(crate) fn fit_falloff(
    map: &MapView<'_>,
    positions: &[Vec3],
    faces: &[[u32; 3]],
    attenuation: &Attenuation,
) -> FittedFalloff {
    let unchanged = |thickness| FittedFalloff { attenuation: attenuation.clone(), thickness, warning: None };
    let d = map.dent_distance;
    let axis = map.grid.axis_z;
    let push = |cell: &[f32; 4]| Vec3::new(cell[0], cell[1], cell[2]).dot(axis).max(0.0);
    let deepest = map.cells.iter().map(push).fold(0.0, f32::max);
    if !may_fold(attenuation, deepest, d) {
        return unchanged(None);
    }
    let walls = measure_walls(map, positions, faces, deepest * MEASURED_PUSH, push);
    let thinnest = walls.iter().map(|w| w.back - w.front).reduce(f32::min);
    let kept = |stretch: f32| walls.iter().map(|w| w.kept(attenuation, d, stretch)).fold(1.0, f32::min);
    let kept_as_given = kept(1.0);
    if kept_as_given >= MIN_WALL_KEPT {
        return unchanged(thinnest);
    }
    let stretch = least_stretch(kept);
    let thickness = thinnest.unwrap_or(0.0);
    let warning = (kept_as_given < FOLD_KEPT).then(|| {
        let message = format!(
            "the falloff would fold the {thickness:.4}-thick wall under this dent (it would keep {:.0} % of it): \
             stretched {stretch:.2}× in depth to keep {:.0} %",
            100.0 * kept_as_given.max(-1.0),
            100.0 * MIN_WALL_KEPT
        );
        log::warn!("{message}");
        message
    });
    FittedFalloff { attenuation: stretched(attenuation, stretch), thickness: thinnest, warning }
}

/// Whether `attenuation` (for dent distance `d`) pushing by at most `deepest` along the axis
/// could leave less than [`MIN_WALL_KEPT`] of some wall: if not, [`fit_falloff`] keeps it
/// without measuring. Slope bound: no wall of any thickness loses more than `deepest·max|a'|`
/// of its thickness.
pub(crate) fn may_fold(attenuation: &Attenuation, deepest: f32, d: f32) -> bool {
    let steepness = match attenuation {
        Attenuation::None => 0.0,
        Attenuation::Logistic => 0.5,
        Attenuation::Linear { scale } => 1.0 / scale,
        Attenuation::Custom(_) => attenuation.max_steepness(d),
    };
    deepest * steepness / d > 1.0 - MIN_WALL_KEPT
}

/// The least stretch `k ≥ 1` (to 0.1 %) with `kept(k) ≥ MIN_WALL_KEPT`; as `k` grows the falloff
/// tends to 1 over every wall, so one exists.
fn least_stretch(kept: impl Fn(f32) -> f32) -> f32 {
    let mut hi = 2.0;
    while kept(hi) < MIN_WALL_KEPT && hi < 1e12 {
        hi *= 2.0;
    }
    let mut lo = hi / 2.0;
    while hi - lo > 1e-3 * lo {
        let mid = 0.5 * (lo + hi);
        if kept(mid) >= MIN_WALL_KEPT { hi = mid } else { lo = mid }
    }
    hi
}

/// `attenuation` stretched in depth by `stretch`: `a(z/stretch)`.
fn stretched(attenuation: &Attenuation, stretch: f32) -> Attenuation {
    match attenuation {
        Attenuation::None => Attenuation::None,
        Attenuation::Linear { scale } => Attenuation::Linear { scale: scale * stretch },
        other => {
            let base = other.clone();
            Attenuation::Custom(Arc::new(move |z, d| base.eval(z / stretch, d)))
        }
    }
}

/// The walls under the map cells that push at least `least_push`, sampled on a grid of at most
/// [`RAYS_PER_SIDE`]² cells and at the deepest cell: along each cell's ray (parallel to the axis), the front is where the
/// ray enters the body nearest the collision plane and the back where it next leaves.
fn measure_walls(
    map: &MapView<'_>,
    positions: &[Vec3],
    faces: &[[u32; 3]],
    least_push: f32,
    push: impl Fn(&[f32; 4]) -> f32,
) -> Vec<Wall> {
    let g = &map.grid;
    let shift = 0.5 * g.res as f32 - 0.5;
    let stride = g.res.div_ceil(RAYS_PER_SIDE).max(1);
    let deepest_cell = (0..map.cells.len()).max_by(|&a, &b| push(&map.cells[a]).total_cmp(&push(&map.cells[b])));
    let sampled = (stride / 2..g.res)
        .step_by(stride as usize)
        .flat_map(|row| (stride / 2..g.res).step_by(stride as usize).map(move |col| (row * g.res + col) as usize));
    let mut rays: Vec<(Vec2, f32)> = Vec::new();
    for cell in deepest_cell.into_iter().chain(sampled) {
        let p = push(&map.cells[cell]);
        if p >= least_push && p > 0.0 {
            let (row, col) = ((cell as u32 / g.res) as f32, (cell as u32 % g.res) as f32);
            rays.push((Vec2::new(col - shift, row - shift) * g.cell_size, p));
        }
    }
    if rays.is_empty() {
        return Vec::new();
    }
    let span = rays.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), r| (lo.min(r.0), hi.max(r.0)));
    let frame: Vec<Vec3> = positions
        .iter()
        .map(|&p| {
            let r = p - g.origin;
            Vec3::new(r.dot(g.axis_x), r.dot(g.axis_y), r.dot(g.axis_z))
        })
        .collect();
    let mut hits: Vec<Vec<(f32, bool)>> = vec![Vec::new(); rays.len()];
    for face in faces {
        let [a, b, c] = face.map(|v| frame[v as usize]);
        let [a2, b2, c2] = [a, b, c].map(Vec3::truncate);
        let (lo, hi) = (a2.min(b2).min(c2), a2.max(b2).max(c2));
        if lo.cmpgt(span.1).any() || hi.cmplt(span.0).any() {
            continue;
        }
        let area = (b2 - a2).perp_dot(c2 - a2);
        if area == 0.0 {
            continue;
        }
        // Faces are counter-clockwise from outside: the ray (along +axis) enters the body
        // through a face whose outward normal points back against it.
        let [pa, pb, pc] = face.map(|v| positions[v as usize]);
        let entering = (pb - pa).cross(pc - pa).dot(g.axis_z) < 0.0;
        for ((at, _), list) in rays.iter().zip(hits.iter_mut()) {
            if at.cmplt(lo).any() || at.cmpgt(hi).any() {
                continue;
            }
            let wa = (b2 - *at).perp_dot(c2 - *at);
            let wb = (c2 - *at).perp_dot(a2 - *at);
            let wc = (a2 - *at).perp_dot(b2 - *at);
            let inside =
                if area > 0.0 { wa >= 0.0 && wb >= 0.0 && wc >= 0.0 } else { wa <= 0.0 && wb <= 0.0 && wc <= 0.0 };
            if inside {
                list.push(((wa * a.z + wb * b.z + wc * c.z) / area, entering));
            }
        }
    }
    rays.iter()
        .zip(hits)
        .filter_map(|(&(_, push), mut list)| {
            list.sort_by(|x, y| x.0.total_cmp(&y.0));
            let entry = list.iter().filter(|h| h.1).min_by(|x, y| x.0.abs().total_cmp(&y.0.abs()))?.0;
            let exit = list.iter().find(|h| !h.1 && h.0 > entry)?.0;
            Some(Wall { front: entry, back: exit, push })
        })
        .collect()
}
