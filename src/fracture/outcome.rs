//! Breaking a closed mesh along a placed pattern ([`break_body`]): the part of the body inside
//! the pattern's bounding prism is cut out (every cut capped), split cell by cell into pieces,
//! and the rest is the body minus that part, one closed mesh. Pieces keep whatever the mesh
//! carries (a dent made first stays in them).

use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::cell_cut::CellCutter;
use super::clip::{Cap, Part, Pool};
use super::origin::{Location, Source, VertexOrigin, build};
use super::weld::{Soup, check_closed, components, weld};
use super::{FractureError, FracturePattern, PatternParams, Placement};
use crate::dent::BodyState;
use crate::mesh::{MassProperties, TriMesh, mass_properties};

/// One piece that broke loose.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Its closed surface, in the broken body's mesh coordinates (not re-centred), m.
    pub mesh: TriMesh,
    /// Mass, centre of mass (in the mesh's coordinates), inertia about it and volume, at the
    /// density [`break_body`] was given.
    pub mass: MassProperties,
    /// Index of the pattern cell it came from.
    pub cell: usize,
    /// Where each of its vertices lies on the mesh that broke (for carrying UVs and other
    /// attributes over), one per vertex.
    pub origins: Vec<VertexOrigin>,
}

impl Piece {
    /// The velocity the piece leaves with when the body moved rigidly with `body`'s state
    /// (world; its `center_of_mass` the body's): linear v + ω × r at the piece's centre, and
    /// the body's angular velocity. `to_world` maps the mesh's coordinates to the world.
    pub fn velocity(&self, body: &BodyState, to_world: glam::Affine3A) -> (Vec3, Vec3) {
        let centre = to_world.transform_point3(self.mass.center);
        (body.velocity_at(centre), body.angular_velocity)
    }
}

/// What a fracture made.
#[derive(Debug, Clone)]
pub struct FractureOutcome {
    /// The pieces, by cell then by connected part (a cell that cuts a body twice gives two).
    pub pieces: Vec<Piece>,
    /// The body minus the broken part, one closed mesh in the same coordinates; `None` when the
    /// whole body lay inside the pattern.
    pub rest: Option<TriMesh>,
    /// Where each vertex of the rest lies on the mesh that broke, one per vertex (empty with
    /// no rest).
    pub rest_origins: Vec<VertexOrigin>,
    /// The rest's mass properties at the same density (`None` with no rest).
    pub rest_mass: Option<MassProperties>,
    /// Volume of the body before, m³ (for the conservation check: pieces + rest).
    pub volume_before: f32,
}

/// A fracture as data: everything that rebuilds it bit for bit from the same mesh
/// ([`replay`]): the pattern's parameters (its seed included), where it was placed, the density,
/// and whether the output is welded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FractureRecord {
    /// The pattern (cells, seed, radius).
    pub pattern: PatternParams,
    /// Where it was placed, mesh coordinates.
    pub placement: Placement,
    /// Density of the body, kg/m³.
    pub density: f32,
    /// Whether the pieces and rest come out welded even from a mesh with seams (split
    /// vertices): how fractures of damage files of version 1 were made. New fractures keep the
    /// seams (`false`, also what a record serialized without this field reads as).
    #[serde(default)]
    pub weld_output: bool,
}

/// Rebuilds a recorded fracture on `mesh` (the body's mesh as it was when it broke): the same
/// pieces and rest, bit for bit.
///
/// # Errors
/// As [`FracturePattern::new`] and [`break_body`].
pub fn replay(mesh: &TriMesh, record: &FractureRecord) -> Result<Option<FractureOutcome>, FractureError> {
    let pattern = FracturePattern::new(record.pattern)?;
    break_as(mesh, &pattern, (&record.placement, record.density), record.weld_output)
}

/// Breaks the closed `mesh` along `pattern` placed at `placement` (mesh coordinates): every
/// cell's part of the body within the pattern's radius becomes a piece, the rest stays one
/// body. Coincident vertices are welded first; every piece and the rest are closed (each edge
/// shared by exactly two faces once coincident vertices are welded). A mesh with split
/// vertices (a game asset's seams) gives pieces and a rest split along the same seams, each cut
/// face with vertices of its own; each vertex's [`VertexOrigin`] says where it lies on `mesh`. Mass properties are at `density` (kg/m³). Returns `Ok(None)`
/// when the pattern's prism misses the body. Deterministic: the same input gives the same
/// output bit for bit.
///
/// # Errors
/// [`FractureError::InvalidParameter`] for a density that is not finite and > 0,
/// [`FractureError::InvalidPlacement`], [`FractureError::OpenMesh`] for a mesh that is not
/// closed. Nothing is changed (the mesh is borrowed).
pub fn break_body(
    mesh: &TriMesh,
    pattern: &FracturePattern,
    placement: &Placement,
    density: f32,
) -> Result<Option<FractureOutcome>, FractureError> {
    break_as(mesh, pattern, (placement, density), false)
}

/// [`break_body`], with welded output whatever the input when `weld_output` is set.
fn break_as(
    mesh: &TriMesh,
    pattern: &FracturePattern,
    (placement, density): (&Placement, f32),
    weld_output: bool,
) -> Result<Option<FractureOutcome>, FractureError> {
    placement.validate()?;
    if !(density.is_finite() && density > 0.0) {
        return Err(super::error::invalid("density", density, "must be finite and > 0"));
    }
    let soup = weld(mesh);
    let locations = soup.locations();
    let Soup { positions, faces, input_face, welded, seams } = soup;
    let source = Source { mesh, input_face: &input_face, welded: &welded, seams: seams && !weld_output };
    let vertex_count = positions.len();
    let frame = placement.frame();
    let (lo, hi) = mesh.bounds();
    let size = f64::from((hi - lo).max_element()).max(pattern.radius());
    // Planes keep 1e-6 of the size clear of every vertex, so that no cut point lands within
    // f32 resolution (6e-8 relative) of a vertex it does not coincide with.
    let tolerance = 1e-6 * size;
    // Cut out the part inside the bounding prism; what each plane leaves outside is the rest's
    // surface (the caps on its way are inside the rest and dropped).
    // Checking that the mesh is closed and cutting take about as long: side by side, the cut
    // thrown away when the mesh is open (cutting an open mesh is harmless).
    let whole = Part { from: (0..faces.len() as u32).collect(), faces, caps: Vec::new() };
    let mut pool = Pool::new(positions, locations);
    let (closed, (inside, outside)) = rayon::join(
        || check_closed(&whole.faces, vertex_count),
        || cut_out(&mut pool, &whole, frame.bound(pattern), tolerance),
    );
    closed?;
    if inside.faces.is_empty() {
        return Ok(None);
    }
    let (mut caps, mut cap_from) = (Vec::new(), Vec::new());
    inside.cap_triangles(&pool, &mut caps, &mut cap_from);
    let mut rest_faces = Vec::with_capacity(outside.len() + caps.len());
    let mut rest_from = Vec::with_capacity(rest_faces.capacity());
    // Only a face with two corners on split edges can have a split edge.
    let mut on_split = vec![false; pool.positions.len()];
    for (a, b) in pool.splits.edges() {
        (on_split[a as usize], on_split[b as usize]) = (true, true);
    }
    for (face, origin) in outside {
        if face.iter().filter(|&&v| on_split[v as usize]).count() >= 2 {
            pool.conform(face, &mut rest_faces);
        } else {
            rest_faces.push(face);
        }
        rest_from.resize(rest_faces.len(), origin);
    }
    rest_faces.extend(caps.iter().map(|f| [f[0], f[2], f[1]]));
    rest_from.extend(cap_from);
    let broken_vertices = compact(&pool, &inside);
    // The rest and the pieces are independent: build them side by side.
    let (rest, pieces) = rayon::join(
        || -> Result<_, FractureError> {
            let volume_before = mesh.volume().abs();
            if rest_faces.is_empty() {
                return Ok((None, Vec::new(), None, volume_before));
            }
            // The rest's caps face the other way: out of the rest, into the broken part.
            let cap_normals: Vec<_> = inside.cap_normals().into_iter().map(|n| -n).collect();
            let vertices = (&pool.positions[..], &pool.locations[..]);
            let (rest, origins) = build(&source, vertices, (&rest_faces, &rest_from), &cap_normals)?;
            let mass = mass_properties(&rest, density);
            Ok((Some(rest), origins, mass, volume_before))
        },
        || cut_cells(&source, &broken_vertices, (pattern, &frame), tolerance, density),
    );
    let (rest, rest_origins, rest_mass, volume_before) = rest?;
    Ok(Some(FractureOutcome { pieces: pieces?, rest, rest_origins, rest_mass, volume_before }))
}

/// Cuts `whole` by `planes` in turn: what is inside them all (closed, capped), and the surface
/// faces each cut left outside, in order.
fn cut_out(
    pool: &mut Pool,
    whole: &Part,
    planes: impl IntoIterator<Item = super::clip::Plane>,
    tolerance: f64,
) -> (Part, Vec<([u32; 3], u32)>) {
    let (mut inside, mut next) = (Part::default(), Part::default());
    let mut outside: Vec<([u32; 3], u32)> = Vec::new();
    let mut planes = planes.into_iter();
    // The first cut reads the whole mesh itself.
    match planes.next() {
        Some(plane) => pool.cut(whole, plane, tolerance, &mut inside, Some(&mut outside)),
        None => inside.clone_from(whole),
    }
    for plane in planes {
        pool.cut(&inside, plane, tolerance, &mut next, Some(&mut outside));
        std::mem::swap(&mut inside, &mut next);
    }
    (inside, outside)
}

/// The pieces of the broken part (over its own vertices): each cell's share (cut by the
/// cell's shared sides only: the part is inside the bounding prism already), split into
/// connected parts.
fn cut_cells(
    source: &Source,
    broken: &BrokenPart,
    (pattern, frame): (&FracturePattern, &super::placement::Frame),
    tolerance: f64,
    density: f32,
) -> Result<Vec<Piece>, FractureError> {
    // Cells are independent: cut them on all cores, collected in cell order (deterministic).
    let per_cell: Vec<Result<Vec<Piece>, FractureError>> = pattern
        .cells()
        .par_iter()
        .enumerate()
        .map_init(CellCutter::default, |cutter, (k, cell)| {
            let planes = cell.sides.iter().filter(|s| s.shared).map(|s| frame.side(s));
            let base = (&broken.positions[..], &broken.locations[..]);
            let (pool, faces, from, cap_normals) = cutter.cut(base, &broken.part, planes, tolerance);
            let mut pieces = Vec::new();
            for group in components(&faces, pool.positions.len()) {
                let group_faces: Vec<[u32; 3]> = group.iter().map(|&f| faces[f]).collect();
                let group_from: Vec<u32> = group.iter().map(|&f| from[f]).collect();
                let vertices = (&pool.positions[..], &pool.locations[..]);
                let (mesh, origins) = build(source, vertices, (&group_faces, &group_from), &cap_normals)?;
                if let Some(mass) = mass_properties(&mesh, density) {
                    pieces.push(Piece { mesh, mass, cell: k, origins });
                }
            }
            Ok(pieces)
        })
        .collect();
    let mut pieces = Vec::new();
    for cell in per_cell {
        pieces.extend(cell?);
    }
    Ok(pieces)
}

/// The broken part over its own vertices only.
struct BrokenPart {
    positions: Vec<glam::DVec3>,
    locations: Vec<Location>,
    part: Part,
}

/// `part` over its own vertices of `pool` only (ids renumbered in order of first use).
fn compact(pool: &Pool, part: &Part) -> BrokenPart {
    let mut remap = vec![u32::MAX; pool.positions.len()];
    let (mut positions, mut locations) = (Vec::new(), Vec::new());
    let mut id = |v: u32| {
        if remap[v as usize] == u32::MAX {
            remap[v as usize] = positions.len() as u32;
            positions.push(pool.positions[v as usize]);
            locations.push(pool.locations[v as usize]);
        }
        remap[v as usize]
    };
    let faces = part.faces.iter().map(|f| f.map(&mut id)).collect();
    let caps = part
        .caps
        .iter()
        .map(|c| Cap { plane: c.plane, edges: c.edges.iter().map(|&(a, b)| (id(a), id(b))).collect() })
        .collect();
    BrokenPart { positions, locations, part: Part { faces, from: part.from.clone(), caps } }
}

/// Sum of the pieces' volumes and the rest's, m³.
pub fn volume_after(outcome: &FractureOutcome) -> f64 {
    let pieces: f64 = outcome.pieces.iter().map(|p| f64::from(p.mass.volume)).sum();
    pieces + outcome.rest_mass.map_or(0.0, |m| f64::from(m.volume))
}
