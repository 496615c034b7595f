//! Marching cubes with one ambiguity rule for every face, its 256-case table built in code.
//!
//! A cube's corners are numbered x + 2y + 4z, rock is f < 0. The table is derived, not typed
//! in: for each sign pattern,
//!
//! 1. on each of the six faces, the edges whose two corners differ in sign are paired into
//!    segments. A face with two such edges has one segment. A face with four (rock and air on
//!    alternate corners: the ambiguous face) always joins its rock corners: each segment cuts
//!    off one air corner. The decision depends only on the four signs of the face, so the two
//!    cubes sharing a face draw the same segments on it: no crack between cells.
//! 2. every crossed edge belongs to two faces of the cube, so it ends exactly two segments and
//!    the segments close into loops. Each segment is directed so that, seen from the air, the
//!    loop turns counter-clockwise (the rock lies behind the patch): the two cubes of a face
//!    traverse a shared segment in opposite directions, so the orientation is consistent.
//! 3. each loop is fan-triangulated from its lowest edge, unless a fan diagonal would join two
//!    vertices of one face (a loop through both segments of an ambiguous face): that diagonal
//!    would lie in the face, where the neighbouring cube could draw it too. Such a loop is
//!    triangulated around an added vertex, the mean of its vertices, private to the cell.
//!
//! Every segment of a face is shared by the two cells of that face and every diagonal by two
//! triangles of one cell, and loops of one cube share no vertex: the result is a closed,
//! oriented 2-manifold, with one vertex per crossed lattice edge (about a third of marching
//! tetrahedra's, which also cut the face and body diagonals) and about 2 triangles per
//! vertex.

use std::sync::OnceLock;

use glam::DVec3;

/// The twelve edges of a cube as (lower corner, upper corner).
pub const EDGES: [(usize, usize); 12] = edges();

const fn edges() -> [(usize, usize); 12] {
    let mut out = [(0, 0); 12];
    let mut n = 0;
    let mut axis = 0;
    while axis < 3 {
        let bit = 1 << axis;
        let mut c = 0;
        while c < 8 {
            if c & bit == 0 {
                out[n] = (c, c | bit);
                n += 1;
            }
            c += 1;
        }
        axis += 1;
    }
    out
}

/// The surface of one sign pattern inside a cube.
#[derive(Debug, Clone, Default)]
pub struct Case {
    /// Triangles counter-clockwise seen from the air, by vertex: an edge index (< 12), or
    /// 12 + i for the centre of loop i of `centres`.
    pub triangles: Vec<[u8; 3]>,
    /// Loops triangulated around an added centre vertex (the mean of the loop's vertices), as
    /// their edge indices.
    pub centres: Vec<Vec<u8>>,
}

/// For each sign pattern (bit c set when corner c is rock), its surface.
pub fn table() -> &'static [Case; 256] {
    static TABLE: OnceLock<[Case; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|case| triangles(case as u8)))
}

/// Whether two edges lie on one face of the cube (all four corners agree on one axis).
fn share_a_face(e: u8, f: u8) -> bool {
    let ((a, b), (c, d)) = (EDGES[e as usize], EDGES[f as usize]);
    (0..3).any(|axis| {
        let bit = |x: usize| x >> axis & 1;
        bit(a) == bit(b) && bit(b) == bit(c) && bit(c) == bit(d)
    })
}

fn corner(c: usize) -> DVec3 {
    DVec3::new((c & 1) as f64, (c >> 1 & 1) as f64, (c >> 2 & 1) as f64)
}

fn edge_index(a: usize, b: usize) -> usize {
    let key = (a.min(b), a.max(b));
    EDGES.iter().position(|&e| e == key).expect("two corners one bit apart")
}

fn midpoint(e: usize) -> DVec3 {
    (corner(EDGES[e].0) + corner(EDGES[e].1)) * 0.5
}

/// The surface of one sign pattern.
fn triangles(case: u8) -> Case {
    let rock = |c: usize| case >> c & 1 == 1;
    let mut next = [usize::MAX; 12];
    for axis in 0..3 {
        let bit = 1 << axis;
        let (b1, b2) = (1 << ((axis + 1) % 3), 1 << ((axis + 2) % 3));
        for side in 0..2 {
            let base = if side == 1 { bit } else { 0 };
            let cycle = [base, base | b1, base | b1 | b2, base | b2];
            let mut normal = DVec3::ZERO;
            normal[axis] = if side == 1 { 1.0 } else { -1.0 };
            let centre = cycle.iter().map(|&c| corner(c)).sum::<DVec3>() * 0.25;
            let crossed: Vec<usize> =
                (0..4).filter(|&k| rock(cycle[k]) != rock(cycle[(k + 1) % 4])).collect();
            // (first edge, second edge, a vector pointing from the rock side to the air side).
            let mut segments = Vec::new();
            match crossed.len() {
                0 => {}
                2 => {
                    let side_centroid = |want: bool| {
                        let cs: Vec<DVec3> =
                            cycle.iter().filter(|&&c| rock(c) == want).map(|&c| corner(c)).collect();
                        cs.iter().sum::<DVec3>() / cs.len() as f64
                    };
                    let e: Vec<usize> =
                        crossed.iter().map(|&k| edge_index(cycle[k], cycle[(k + 1) % 4])).collect();
                    segments.push((e[0], e[1], side_centroid(false) - side_centroid(true)));
                }
                4 => {
                    // The ambiguous face: rock corners joined, each air corner cut off.
                    for k in 0..4 {
                        let c = cycle[k];
                        if !rock(c) {
                            let before = edge_index(cycle[(k + 3) % 4], c);
                            let after = edge_index(c, cycle[(k + 1) % 4]);
                            segments.push((before, after, corner(c) - centre));
                        }
                    }
                }
                _ => unreachable!("a face's sign changes come in pairs"),
            }
            for (a, b, air) in segments {
                // Seen from the air the loop turns counter-clockwise: along the segment, the
                // direction is air × outward normal.
                let along = air.cross(normal);
                let (from, to) = if (midpoint(b) - midpoint(a)).dot(along) > 0.0 { (a, b) } else { (b, a) };
                assert_eq!(next[from], usize::MAX, "case {case}: edge {from} starts two segments");
                next[from] = to;
            }
        }
    }
    let mut out = Case::default();
    let mut visited = [false; 12];
    for start in 0..12 {
        if next[start] == usize::MAX || visited[start] {
            continue;
        }
        let mut ring = Vec::new();
        let mut e = start;
        while !visited[e] {
            visited[e] = true;
            ring.push(e as u8);
            e = next[e];
        }
        assert_eq!(e, start, "case {case}: the segments close into loops");
        // A diagonal between two vertices of one face would lie in that face, where the
        // neighbouring cube may draw the same diagonal: such loops (through both segments of
        // an ambiguous face) get a centre vertex instead of a fan.
        let len = ring.len();
        let in_face_diagonal = (0..len)
            .any(|i| (i + 2..len).any(|j| !(i == 0 && j == len - 1) && share_a_face(ring[i], ring[j])));
        if in_face_diagonal {
            let centre = 12 + out.centres.len() as u8;
            for k in 0..len {
                out.triangles.push([centre, ring[k], ring[(k + 1) % len]]);
            }
            out.centres.push(ring);
        } else {
            for k in 1..len - 1 {
                out.triangles.push([ring[0], ring[k], ring[k + 1]]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_rock_corner_is_one_triangle_facing_away_from_it() {
        let t = &table()[1].triangles;
        assert_eq!(t.len(), 1);
        let [a, b, c] = t[0].map(|e| midpoint(e as usize));
        assert!((b - a).cross(c - a).dot(DVec3::ONE) > 0.0);
        assert!(table()[0].triangles.is_empty() && table()[255].triangles.is_empty());
    }

    #[test]
    fn a_vertex_on_every_crossed_edge_and_only_there() {
        for case in 0..=255u8 {
            let t = &table()[case as usize].triangles;
            let used: std::collections::BTreeSet<u8> =
                t.iter().flatten().copied().filter(|&e| e < 12).collect();
            let crossed: std::collections::BTreeSet<u8> = (0..12u8)
                .filter(|&e| {
                    let (a, b) = EDGES[e as usize];
                    (case >> a & 1) != (case >> b & 1)
                })
                .collect();
            assert_eq!(used, crossed, "case {case}: a vertex on every crossed edge and only there");
        }
    }

    #[test]
    fn every_face_segment_is_traversed_the_other_way_by_the_neighbour() {
        // The cube above a face (along each axis) sees that face as its lower one, with the
        // same four signs; its segments there must be the reverse of ours.
        for axis in 0..3 {
            let bit = 1usize << axis;
            let upper: Vec<_> = (0..=255u8).map(|case| face_segments(case, axis, true)).collect();
            let lower: Vec<_> = (0..=255u8).map(|case| face_segments(case, axis, false)).collect();
            for (case, ours) in upper.iter().enumerate() {
                for (other, theirs) in lower.iter().enumerate() {
                    // `other`'s lower face has the signs of `case`'s upper face.
                    let agrees =
                        (0..8).filter(|c| c & bit == 0).all(|c| (case >> (c | bit) & 1) == (other >> c & 1));
                    if !agrees {
                        continue;
                    }
                    let mut reversed: Vec<_> = theirs.iter().map(|&(a, b)| (b, a)).collect();
                    reversed.sort();
                    assert_eq!(*ours, reversed, "axis {axis}, cases {case} and {other}");
                }
            }
        }
    }

    /// Directed boundary segments of a case's triangles on one face, as pairs of points (edge
    /// midpoints projected on the face, ×2 to stay integral), sorted.
    fn face_segments(case: u8, axis: usize, upper: bool) -> Vec<([i32; 2], [i32; 2])> {
        let on_face = |e: u8| {
            if e >= 12 {
                return false;
            }
            let (a, b) = EDGES[e as usize];
            let side = if upper { 1 << axis } else { 0 };
            (a & (1 << axis)) == side && (b & (1 << axis)) == side
        };
        let project = |e: u8| {
            let m = midpoint(e as usize) * 2.0;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            [m[u] as i32, m[v] as i32]
        };
        let mut edges = Vec::new();
        for t in &table()[case as usize].triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if on_face(a) && on_face(b) {
                    edges.push((project(a), project(b)));
                }
            }
        }
        edges.sort();
        edges
    }
}
