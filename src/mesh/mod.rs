//! Triangle meshes: the [`TriMesh`] type, game assets ([`Asset`]: a mesh with UVs, authored
//! normals, tangents, colours, skin and face groups, carried through a dent), file input and
//! output (OBJ, PLY, glTF), procedural primitives, the built-in meshes that work wherever a mesh
//! path is accepted, and local refinement ([`refine`]).

mod asset;
mod asset_follow;
mod asset_io;
mod atomic_write;
mod builtin;
mod builtin_crate;
#[cfg(feature = "io")]
mod confined;
mod content_hash;
mod convex_hull;
pub(crate) mod cover_mask;
mod edit;
mod error;
pub(crate) mod face_grid;
pub(crate) mod face_sort;
#[cfg(feature = "io")]
mod glb;
#[cfg(feature = "io")]
mod gltf;
#[cfg(feature = "io")]
mod gltf_access;
#[cfg(feature = "io")]
mod gltf_asset_read;
#[cfg(feature = "io")]
mod gltf_asset_write;
#[cfg(feature = "io")]
mod gltf_read;
pub(crate) mod height_field;
pub(crate) mod local_vertices;
mod mass;
mod obj;
mod obj_asset;
mod obj_asset_write;
mod ply;
mod ply_header;
mod ply_source;
mod primitives;
mod principal_axis;
mod refine;
mod refine_crossings;
mod save;
pub(crate) mod self_intersect;
mod split_inference;
pub(crate) mod star;
mod subdivide;
pub(crate) mod tri_tri;
mod trimesh;
pub(crate) mod turned_over;
pub(crate) mod umbrella;
pub(crate) mod weld;

#[cfg(feature = "io")]
pub(crate) use self::gltf::save_glb;
#[cfg(feature = "io")]
pub use self::gltf::{DEFAULT_GLTF_COLOR, GltfNode, save_glb_scene};
pub use asset::{Asset, FaceGroup, Skin, VertexAttributes};
pub use asset_follow::orthogonal_tangent;
pub use asset_io::{builtin_asset, load_asset, save_asset};
pub use builtin::{BUILTIN_NAMES, builtin, load};
#[cfg(feature = "io")]
pub use confined::resolve_inside;
pub use content_hash::content_hash;
pub(crate) use content_hash::{fnv1a64, fnv1a64_start};
pub use edit::MeshEdit;
pub use error::MeshError;
#[cfg(feature = "io")]
pub use gltf_asset_read::{MAX_ATTRIBUTE_SETS, parse_gltf_asset};
#[cfg(feature = "io")]
pub use gltf_asset_write::glb_asset_bytes;
#[cfg(feature = "io")]
pub(crate) use gltf_asset_write::save_glb_asset;
#[cfg(feature = "io")]
pub use gltf_read::parse_gltf;
pub use mass::{MassProperties, mass_properties};
pub use obj::parse_obj;
pub(crate) use obj::save_obj;
pub use obj_asset::parse_obj_asset;
pub use obj_asset_write::obj_asset_text;
pub(crate) use obj_asset_write::save_obj_asset;

pub use atomic_write::write_file_atomically;
pub use ply::parse_ply;
pub use primitives::{MAX_PRIMITIVE_TRIANGLES, cylinder, icosphere, plank, subdivided_box, uv_sphere};
pub(crate) use principal_axis::principal_axis;
pub use principal_axis::vertex_principal_axis;
pub use refine::{Ball, OrientedBox, RefineError, RefineRegion, Refinement, SplitVertex, refine};
pub(crate) use refine::{any_too_long, refine_parts};
pub use save::save;
pub(crate) use split_inference::infer_splits;
pub use subdivide::{subdivide_loop, subdivide_midpoint, subdivide_midpoint_n};

pub(crate) use trimesh::in_coordinate_range;
pub use trimesh::{EdgeLengths, MAX_COORDINATE, TriMesh, validate};
pub use turned_over::{SHAPE_TOLERANCE, turned_over_faces};

#[cfg(test)]
pub(crate) mod test_support;
