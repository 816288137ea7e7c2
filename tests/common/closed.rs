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
    let mut id: HashMap<[u32; 3], u32> = HashMap::new();
    let welded: Vec<u32> = mesh
        .positions()
        .iter()
        .map(|p| {
            let n = id.len() as u32;
            *id.entry(p.to_array().map(|x| (x + 0.0).to_bits())).or_insert(n)
        })
        .collect();
    let mut count: HashMap<(u32, u32), i32> = HashMap::new();
    for f in mesh.faces() {
        let f = f.map(|v| welded[v as usize]);
        if f[0] == f[1] || f[1] == f[2] || f[2] == f[0] {
            continue;
        }
        for k in 0..3 {
            *count.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &count {
        assert_eq!(n, 1, "{what}: edge ({a}, {b}) used {n} times");
        assert_eq!(count.get(&(b, a)), Some(&1), "{what}: edge ({a}, {b}) has no twin");
    }
}
