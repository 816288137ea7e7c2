//! The attributes of the vertices a dent's refinement adds to a Bevy mesh: each new vertex sits
//! at `fraction` along the edge between its two parents, so 32- and 64-bit float attributes (UVs,
//! colours, custom data) and four-component unsigned normalised ones (packed colours) are
//! interpolated there, tangents are interpolated, made perpendicular to the new normal and unit
//! with their handedness kept, and every other format (joint indices, half floats, signed
//! normalised data), and the joint weights that go with the indices, is the nearer parent's.

use bevy::mesh::{Mesh, VertexAttributeValues};
use dentbend::glam::{Vec3, Vec4};
use dentbend::mesh::Refinement;

/// Appends one value per vertex of `refinement` to every attribute of `mesh` but its positions
/// and normals (which the caller writes), and re-orthogonalises the new tangents against
/// `normals` (the dented mesh's, one per vertex, new ones included).
pub(crate) fn extend_attributes(mesh: &mut Mesh, refinement: &Refinement, normals: &[Vec3]) {
    let ids: Vec<_> = match mesh.try_attributes() {
        Ok(attributes) => attributes.map(|(a, _)| a.id).collect(),
        Err(_) => return,
    };
    for id in ids {
        if id == Mesh::ATTRIBUTE_POSITION.id || id == Mesh::ATTRIBUTE_NORMAL.id {
            continue;
        }
        let nearest = id == Mesh::ATTRIBUTE_JOINT_WEIGHT.id;
        let Ok(values) = mesh.try_attribute_mut(id) else { continue };
        if values.len() == refinement.base_vertex_count {
            extend(values, refinement, nearest);
        } else {
            // Not one value per vertex (the asset was changed under the plug-in): no value of it
            // can be trusted for the new vertices, and a short attribute would make the mesh
            // invalid.
            log::warn!(
                "bevy_dentbend: a refined mesh's attribute {id:?} had {} values for {} vertices; removed",
                values.len(),
                refinement.base_vertex_count
            );
            mesh.remove_attribute(id);
        }
    }
    let first_new = normals.len() - refinement.vertices.len();
    if let Ok(Some(VertexAttributeValues::Float32x4(tangents))) = mesh.try_attribute_mut_option(Mesh::ATTRIBUTE_TANGENT)
    {
        for (t, n) in tangents.iter_mut().zip(normals).skip(first_new) {
            *t = orthogonal_tangent(Vec4::from_array(*t), *n).to_array();
        }
    }
}

/// `tangent` (xyz, w the handedness) made unit and perpendicular to the unit `normal`, w ±1;
/// left as it is where nothing of it is perpendicular to the normal.
fn orthogonal_tangent(tangent: Vec4, normal: Vec3) -> Vec4 {
    let t = tangent.truncate();
    let along = t - normal * normal.dot(t);
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    along.try_normalize().map_or(tangent, |u| u.extend(w))
}

/// The parent of `split` nearer to it (the first at exactly half way).
fn nearer(parents: [u32; 2], fraction: f32) -> usize {
    (if fraction <= 0.5 { parents[0] } else { parents[1] }) as usize
}

/// Appends one value per new vertex: interpolated for float and normalised formats (the nearer
/// parent's when `nearest`), the nearer parent's for integer ones.
fn extend(values: &mut VertexAttributeValues, refinement: &Refinement, nearest: bool) {
    use VertexAttributeValues as V;
    if nearest {
        return copy_nearer(values, refinement);
    }
    match values {
        V::Float32(v) => lerp(v, refinement, |a, b, t| a + (b - a) * t),
        V::Float32x2(v) => lerp(v, refinement, lerp_array),
        V::Float32x3(v) => lerp(v, refinement, lerp_array),
        V::Float32x4(v) => lerp(v, refinement, lerp_array),
        V::Float64(v) => lerp(v, refinement, |a, b, t| a + (b - a) * f64::from(t)),
        V::Unorm8x4(v) | V::Unorm8x4Bgra(v) => lerp(v, refinement, |a, b, t| {
            std::array::from_fn(|k| (f32::from(a[k]) + (f32::from(b[k]) - f32::from(a[k])) * t).round() as u8)
        }),
        V::Unorm16x4(v) => lerp(v, refinement, |a, b, t| {
            std::array::from_fn(|k| (f32::from(a[k]) + (f32::from(b[k]) - f32::from(a[k])) * t).round() as u16)
        }),
        _ => copy_nearer(values, refinement),
    }
}

/// Component-wise `a + (b − a)·t`.
fn lerp_array<const N: usize>(a: [f32; N], b: [f32; N], t: f32) -> [f32; N] {
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t)
}

/// Appends `blend(parent 0, parent 1, fraction)` per new vertex (a missing parent reads as
/// the default value).
fn lerp<T: Copy + Default>(v: &mut Vec<T>, refinement: &Refinement, blend: impl Fn(T, T, f32) -> T) {
    for split in &refinement.vertices {
        let [a, b] = split.parents.map(|p| v.get(p as usize).copied().unwrap_or_default());
        v.push(blend(a, b, split.fraction));
    }
}

/// Appends the nearer parent's value per new vertex, whatever the format.
fn copy_nearer(values: &mut VertexAttributeValues, refinement: &Refinement) {
    use VertexAttributeValues as V;
    fn push<T: Copy + Default>(v: &mut Vec<T>, refinement: &Refinement) {
        for split in &refinement.vertices {
            let value = v.get(nearer(split.parents, split.fraction)).copied().unwrap_or_default();
            v.push(value);
        }
    }
    match values {
        V::Uint8(v) | V::Unorm8(v) => push(v, refinement),
        V::Uint8x2(v) | V::Unorm8x2(v) => push(v, refinement),
        V::Uint8x4(v) | V::Unorm8x4(v) | V::Unorm8x4Bgra(v) => push(v, refinement),
        V::Sint8(v) | V::Snorm8(v) => push(v, refinement),
        V::Sint8x2(v) | V::Snorm8x2(v) => push(v, refinement),
        V::Sint8x4(v) | V::Snorm8x4(v) => push(v, refinement),
        V::Uint16(v) | V::Unorm16(v) => push(v, refinement),
        V::Uint16x2(v) | V::Unorm16x2(v) => push(v, refinement),
        V::Uint16x4(v) | V::Unorm16x4(v) => push(v, refinement),
        V::Sint16(v) | V::Snorm16(v) => push(v, refinement),
        V::Sint16x2(v) | V::Snorm16x2(v) => push(v, refinement),
        V::Sint16x4(v) | V::Snorm16x4(v) => push(v, refinement),
        V::Float16(v) => push(v, refinement),
        V::Float16x2(v) => push(v, refinement),
        V::Float16x4(v) => push(v, refinement),
        V::Float32(v) => push(v, refinement),
        V::Float32x2(v) => push(v, refinement),
        V::Float32x3(v) => push(v, refinement),
        V::Float32x4(v) => push(v, refinement),
        V::Uint32(v) | V::Unorm10_10_10_2(v) => push(v, refinement),
        V::Uint32x2(v) => push(v, refinement),
        V::Uint32x3(v) => push(v, refinement),
        V::Uint32x4(v) => push(v, refinement),
        V::Sint32(v) => push(v, refinement),
        V::Sint32x2(v) => push(v, refinement),
        V::Sint32x3(v) => push(v, refinement),
        V::Sint32x4(v) => push(v, refinement),
        V::Float64(v) => push(v, refinement),
        V::Float64x2(v) => push(v, refinement),
        V::Float64x3(v) => push(v, refinement),
        V::Float64x4(v) => push(v, refinement),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::PrimitiveTopology;
    use dentbend::mesh::SplitVertex;

    /// One new vertex a quarter of the way from vertex 0 to vertex 1 of a triangle: its UV and
    /// colour interpolated there, its tangent unit and perpendicular to the new normal with the
    /// parents' handedness, its joints and their weights vertex 0's (the nearer parent).
    #[test]
    fn a_split_vertex_takes_its_attributes_from_its_edge() {
        let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::MAIN_WORLD)
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; 3])
            .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 1.0, 0.0]; 3])
            .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, vec![[0.0f32, 0.0], [1.0, 0.5], [0.0, 1.0]])
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_COLOR,
                vec![[1.0f32, 0.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0], [0.0; 4]],
            )
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_TANGENT,
                vec![[1.0f32, 0.0, 0.0, -1.0], [0.0, 0.0, 1.0, -1.0], [1.0, 0.0, 0.0, -1.0]],
            )
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_JOINT_INDEX,
                VertexAttributeValues::Uint16x4(vec![[1, 2, 0, 0], [3, 4, 0, 0], [5, 6, 0, 0]]),
            )
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_JOINT_WEIGHT,
                vec![[0.75f32, 0.25, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]],
            );
        let refinement = Refinement {
            base_vertex_count: 3,
            base_face_count: 1,
            vertices: vec![SplitVertex { parents: [0, 1], fraction: 0.25 }],
            ..Default::default()
        };
        // The new vertex's normal tilts towards +x, so the interpolated tangent is not
        // perpendicular to it until re-orthogonalised.
        let normal = Vec3::new(0.6, 0.8, 0.0);
        extend_attributes(&mut mesh, &refinement, &[Vec3::Y, Vec3::Y, Vec3::Y, normal]);
        let last = |id| match mesh.attribute(id) {
            Some(VertexAttributeValues::Float32x2(v)) => v[3].to_vec(),
            Some(VertexAttributeValues::Float32x4(v)) => v[3].to_vec(),
            Some(VertexAttributeValues::Uint16x4(v)) => v[3].iter().map(|&j| f32::from(j)).collect(),
            other => panic!("{other:?}"),
        };
        assert_eq!(last(Mesh::ATTRIBUTE_UV_0), vec![0.25, 0.125]);
        assert_eq!(last(Mesh::ATTRIBUTE_COLOR), vec![0.75, 0.0, 0.25, 1.0]);
        assert_eq!(last(Mesh::ATTRIBUTE_JOINT_INDEX), vec![1.0, 2.0, 0.0, 0.0]);
        assert_eq!(last(Mesh::ATTRIBUTE_JOINT_WEIGHT), vec![0.75, 0.25, 0.0, 0.0]);
        let t = last(Mesh::ATTRIBUTE_TANGENT);
        let (xyz, w) = (Vec3::new(t[0], t[1], t[2]), t[3]);
        assert!((xyz.length() - 1.0).abs() < 1e-6 && xyz.dot(normal).abs() < 1e-6, "{t:?}");
        assert_eq!(w, -1.0);
        // Positions and normals are the caller's to write: not extended here.
        assert_eq!(mesh.count_vertices(), 3);
    }
}
