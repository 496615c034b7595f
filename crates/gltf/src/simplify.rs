//! Reducing a triangle mesh to a triangle count, for files meant to be looked at: meshoptimizer's
//! edge-collapse simplifier, which keeps the topology (a closed surface stays closed) and, with
//! its border locked, the open edges where a sheet meets the rest of the model (water against
//! rock, a chunk against its neighbour). Where that topology allows no fewer triangles (many
//! small closed pieces), the sloppy simplifier, which merges vertices on a grid, finishes the
//! reduction.

use meshopt::SimplifyOptions;

/// A simplified mesh: only the vertices its triangles use, in order of first use.
#[derive(Debug, Clone, PartialEq)]
pub struct Simplified {
    pub positions: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// meshoptimizer's estimate of the largest distance from the input, relative to its extent.
    pub relative_error: f32,
}

/// `triangles` over `positions` reduced to at most about `target` triangles (the input itself
/// when it has no more).
pub fn to_triangles(positions: &[[f32; 3]], triangles: &[[u32; 3]], target: usize) -> Simplified {
    let indices: Vec<u32> = triangles.iter().flatten().copied().collect();
    let mut relative_error = 0.0f32;
    let mut kept = indices;
    if triangles.len() > target {
        // An error bound of the whole extent: the triangle count, not the error, stops it.
        kept = meshopt::simplify_decoder(
            &kept,
            positions,
            target * 3,
            1.0,
            SimplifyOptions::LockBorder,
            Some(&mut relative_error),
        );
        if kept.len() / 3 > target {
            let mut sloppy_error = 0.0f32;
            kept =
                meshopt::simplify_sloppy_decoder(&kept, positions, target * 3, 1.0, Some(&mut sloppy_error));
            relative_error = relative_error.max(sloppy_error);
        }
    }
    compact(positions, &kept, relative_error)
}

/// The vertices `indices` use, renumbered in order of first use.
fn compact(positions: &[[f32; 3]], indices: &[u32], relative_error: f32) -> Simplified {
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    let remapped: Vec<u32> = indices
        .iter()
        .map(|&v| {
            let v = v as usize;
            if new_index[v] == u32::MAX {
                new_index[v] = kept.len() as u32;
                kept.push(positions[v]);
            }
            new_index[v]
        })
        .collect();
    let triangles = remapped.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Simplified { positions: kept, triangles, relative_error }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed surface: an octahedron subdivided `levels` times, its vertices pushed out to the
    /// unit sphere (edges shared, so no seam is open).
    fn sphere(levels: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let mut positions: Vec<[f32; 3]> = vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let mut triangles: Vec<[u32; 3]> =
            vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        for _ in 0..levels {
            let mut middle = std::collections::BTreeMap::new();
            let mut split = |a: u32, b: u32, positions: &mut Vec<[f32; 3]>| {
                *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (p, q) = (positions[a as usize], positions[b as usize]);
                    let m = [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]));
                    let norm = m.iter().map(|c| c * c).sum::<f32>().sqrt();
                    positions.push(m.map(|c| c / norm));
                    positions.len() as u32 - 1
                })
            };
            triangles = triangles
                .iter()
                .flat_map(|&[a, b, c]| {
                    let (ab, bc, ca) = (
                        split(a, b, &mut positions),
                        split(b, c, &mut positions),
                        split(c, a, &mut positions),
                    );
                    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
                })
                .collect();
        }
        (positions, triangles)
    }

    /// Edges used by exactly one triangle (zero on a closed surface).
    fn open_edges(triangles: &[[u32; 3]]) -> usize {
        let mut count = std::collections::BTreeMap::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        count.values().filter(|&&c| c == 1).count()
    }

    #[test]
    fn a_closed_surface_reaches_its_target_and_stays_closed() {
        let (positions, triangles) = sphere(5);
        assert_eq!(triangles.len(), 8 * 4usize.pow(5));
        let s = to_triangles(&positions, &triangles, 1000);
        assert!(s.triangles.len() <= 1000 && s.triangles.len() >= 500, "{} triangles", s.triangles.len());
        assert_eq!(open_edges(&s.triangles), 0, "the sphere stays closed");
        assert!(s.positions.len() < positions.len());
        for p in &s.positions {
            let r = p.iter().map(|c| c * c).sum::<f32>().sqrt();
            assert!((r - 1.0).abs() < 1e-5, "kept vertices are input vertices");
        }
        assert!(s.relative_error > 0.0 && s.relative_error < 0.05, "{}", s.relative_error);
        let whole = to_triangles(&positions, &triangles, triangles.len());
        assert_eq!(whole.triangles.len(), triangles.len(), "no reduction below the input's count");
    }
}
