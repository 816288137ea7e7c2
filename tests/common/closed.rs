//! Whether a mesh bounds a solid: every edge used once in each direction.

use std::collections::HashMap;

use dentbend::TriMesh;

/// Every edge used once in each direction, by vertex index, and again after welding bit-equal
/// positions (faces that collapse to a point or a segment then bound nothing and are skipped).
pub fn assert_closed(mesh: &TriMesh, what: &str) {
    let mut count: HashMap<(u32, u32), i32> = HashMap::new();
    for f in mesh.faces() {
        for k in 0..3 {
            *count.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &count {
        assert_eq!(n, 1, "{what}: edge ({a}, {b}) used {n} times");
        assert_eq!(count.get(&(b, a)), Some(&1), "{what}: edge ({a}, {b}) has no twin");
    }
    let mut count: HashMap<(u32, u32), i32> = HashMap::new();
    for f in super::seams::welded_faces(mesh) {
        for k in 0..3 {
            *count.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &count {
        assert_eq!(n, 1, "{what}: edge ({a}, {b}) used {n} times");
        assert_eq!(count.get(&(b, a)), Some(&1), "{what}: edge ({a}, {b}) has no twin");
    }
}
