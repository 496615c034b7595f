//! Marching tetrahedra over the Kuhn triangulation of a cube.
//!
//! A cube's corners are numbered x + 2y + 4z. Its six tetrahedra all share the diagonal 0–7;
//! each follows one monotone path 0 → e_a → e_a + e_b → 7. Neighbouring cubes split their
//! shared face along the same diagonal, so the tetrahedra form one triangulation of space.
//!
//! Rock is f < 0. A tetrahedron with 1, 2 or 3 rock corners yields 1, 2 or 1 triangles whose
//! vertices lie on its rock–air edges. Orientation is decided combinatorially, not
//! geometrically: with the tetrahedron's corners in a positively oriented order, the face
//! opposite a corner faces away from it, which fixes every case so that normals point from rock
//! to air and every edge is used once in each direction.

/// The six tetrahedra: corner indices, and the sign of det[v1−v0, v2−v0, v3−v0].
pub const TETRAHEDRA: [([usize; 4], i8); 6] = [
    ([0, 1, 3, 7], 1),
    ([0, 1, 5, 7], -1),
    ([0, 2, 3, 7], -1),
    ([0, 2, 6, 7], 1),
    ([0, 4, 5, 7], 1),
    ([0, 4, 6, 7], -1),
];

/// An edge of a tetrahedron, from its rock corner to its air corner (cube corner indices).
pub type Crossing = (usize, usize);

/// The triangles of one tetrahedron given its corner values, as crossings.
pub fn triangles(tet: &([usize; 4], i8), values: &[f64; 8], out: &mut Vec<[Crossing; 3]>) {
    let (corners, sign) = tet;
    let rock: Vec<usize> = corners.iter().copied().filter(|&c| values[c] < 0.0).collect();
    let air: Vec<usize> = corners.iter().copied().filter(|&c| values[c] >= 0.0).collect();
    match rock.len() {
        1 => {
            let [i, a, b, c] = positive(corners, *sign, [rock[0], air[0], air[1], air[2]]);
            out.push([(i, a), (i, b), (i, c)]);
        }
        3 => {
            let [o, a, b, c] = positive(corners, *sign, [air[0], rock[0], rock[1], rock[2]]);
            out.push([(a, o), (c, o), (b, o)]);
        }
        2 => {
            let [i1, i2, o1, o2] = positive(corners, *sign, [rock[0], rock[1], air[0], air[1]]);
            let quad = [(i1, o1), (i1, o2), (i2, o2), (i2, o1)];
            out.push([quad[0], quad[1], quad[2]]);
            out.push([quad[0], quad[2], quad[3]]);
        }
        _ => {}
    }
}

/// Reorders `order` (a permutation of `corners`) into a positively oriented one by swapping its
/// last two entries when needed.
fn positive(corners: &[usize; 4], sign: i8, mut order: [usize; 4]) -> [usize; 4] {
    let position = |c: usize| corners.iter().position(|&x| x == c).expect("a corner of the tetrahedron");
    let p = order.map(position);
    let inversions =
        (0..4).flat_map(|i| (i + 1..4).map(move |j| (i, j))).filter(|&(i, j)| p[i] > p[j]).count();
    let parity: i8 = if inversions % 2 == 0 { 1 } else { -1 };
    if parity * sign < 0 {
        order.swap(2, 3);
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn corner(c: usize) -> DVec3 {
        DVec3::new((c & 1) as f64, ((c >> 1) & 1) as f64, ((c >> 2) & 1) as f64)
    }

    #[test]
    fn signs_match_the_geometry() {
        for (t, sign) in TETRAHEDRA {
            let [a, b, c, d] = t.map(corner);
            let det = (b - a).dot((c - a).cross(d - a));
            assert_eq!(det.signum() as i8, sign, "{t:?}");
        }
    }

    #[test]
    fn normals_point_from_rock_to_air() {
        // Every sign pattern of every tetrahedron: each triangle's normal has a positive
        // component along (air centroid − rock centroid).
        for (t, sign) in TETRAHEDRA {
            for pattern in 1..15u32 {
                let mut values = [1.0; 8];
                for (k, &c) in t.iter().enumerate() {
                    values[c] = if pattern >> k & 1 == 1 { -1.0 } else { 1.0 };
                }
                let mut tris = Vec::new();
                triangles(&(t, sign), &values, &mut tris);
                let centroid = |rock: bool| {
                    let cs: Vec<DVec3> =
                        t.iter().filter(|&&c| (values[c] < 0.0) == rock).map(|&c| corner(c)).collect();
                    cs.iter().sum::<DVec3>() / cs.len() as f64
                };
                let outward = centroid(false) - centroid(true);
                for tri in tris {
                    let [p, q, r] = tri.map(|(a, b)| (corner(a) + corner(b)) * 0.5);
                    assert!((q - p).cross(r - p).dot(outward) > 0.0, "{t:?} {pattern:04b}");
                }
            }
        }
    }
}
