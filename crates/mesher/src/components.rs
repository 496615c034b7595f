//! Connected components of a surface: triangles linked through shared vertices. On a closed
//! 2-manifold mesh each component is one closed sheet bounding one connected piece of the
//! solid or of its complement.

use crate::payload::TriMesh;

/// The component of every triangle, numbered in order of first triangle, and their count.
pub fn label(surface: &TriMesh) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..surface.vertices.len() as u32).collect();
    for t in &surface.triangles {
        union(&mut parent, t[0], t[1]);
        union(&mut parent, t[0], t[2]);
    }
    let mut number = vec![u32::MAX; parent.len()];
    let mut count = 0;
    let labels = surface
        .triangles
        .iter()
        .map(|t| {
            let root = find(&mut parent, t[0]) as usize;
            if number[root] == u32::MAX {
                number[root] = count;
                count += 1;
            }
            number[root]
        })
        .collect();
    (labels, count as usize)
}

/// Number of components.
pub fn count(surface: &TriMesh) -> usize {
    label(surface).1
}

fn find(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        let up = parent[parent[v as usize] as usize];
        parent[v as usize] = up;
        v = up;
    }
    v
}

pub(crate) fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    // The smaller root wins, so the result does not depend on the order of the unions.
    let (lo, hi) = (ra.min(rb), ra.max(rb));
    parent[hi as usize] = lo;
}
