//! Triangulated surfaces (TIN) with the geometric queries water tables, horizons and faults
//! need (KarstNSim §1.1 uses TINs for all three); their files (GOCAD TSurf, plain text) are read
//! by [`karst_geodata::tin`].
//!
//! Queries use a bucket grid over the xy footprint: each bucket lists the triangles whose xy
//! bounding box overlaps it. [`Tin::elevation_at`] is the barycentric elevation of the triangle
//! over (x, y); outside the footprint the surface continues as the plane of the triangle
//! nearest in xy. [`Tin::closest`] is the exact closest point, searching buckets ring by ring
//! until no farther bucket can hold a closer triangle.

use std::path::Path;

use glam::{DVec2, DVec3};
use karst_geodata::tin::TinError;
use serde::{Deserialize, Serialize};

/// A triangulated surface.
#[derive(Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Tin {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    #[serde(skip)]
    buckets: Buckets,
}

impl std::fmt::Debug for Tin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Tin({} vertices, {} triangles)", self.vertices.len(), self.triangles.len())
    }
}

#[derive(Clone, Default, PartialEq)]
struct Buckets {
    lo: DVec2,
    size: f64,
    dims: [usize; 2],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Elevation range [min, max] of the triangles of each bucket.
    z: Vec<[f64; 2]>,
}

impl Tin {
    /// Reads a `.ts` TSurf or a plain vertices/triangles text ([`karst_geodata::tin`]).
    pub fn read(path: &Path) -> Result<Tin, TinError> {
        let (vertices, triangles) = karst_geodata::tin::read(path)?;
        Tin::new(vertices, triangles, &path.display().to_string())
    }

    /// Checks the triangles (indices, degeneracy) and builds the search structure.
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>, file: &str) -> Result<Tin, TinError> {
        if triangles.is_empty() {
            return Err(TinError::Empty { file: file.into() });
        }
        for (index, t) in triangles.iter().enumerate() {
            let bad = |message: String| TinError::Triangle { file: file.into(), index, message };
            if let Some(v) = t.iter().find(|v| **v as usize >= vertices.len()) {
                return Err(bad(format!("uses vertex {v}, but there are {} vertices", vertices.len())));
            }
            let [a, b, c] = t.map(|v| DVec3::from_array(vertices[v as usize]));
            let area = 0.5 * (b - a).cross(c - a).length();
            let scale = (b - a).length().max((c - a).length()).max(1e-300);
            if area.is_nan() || area <= 1e-9 * scale * scale {
                return Err(bad(format!("{t:?} is degenerate (area {area:e} m²)")));
            }
        }
        let mut tin = Tin { vertices, triangles, buckets: Buckets::default() };
        tin.buckets = tin.bucket_grid();
        Ok(tin)
    }

    /// Moves the triangles by `by` (their search structure rebuilt where they now are).
    pub fn translate(&mut self, by: [f64; 3]) {
        for v in &mut self.vertices {
            for (c, d) in v.iter_mut().zip(by) {
                *c += d;
            }
        }
        self.buckets = self.bucket_grid();
    }

    fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|v| DVec3::from_array(self.vertices[v as usize]))
    }

    fn bucket_grid(&self) -> Buckets {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for v in &self.vertices {
            lo = lo.min(DVec2::new(v[0], v[1]));
            hi = hi.max(DVec2::new(v[0], v[1]));
        }
        let span = (hi - lo).max(DVec2::splat(1e-9));
        let target = (self.triangles.len() as f64).sqrt().ceil().max(1.0);
        let size = span.max_element() / target;
        let dims = [((span.x / size).ceil() as usize).max(1), ((span.y / size).ceil() as usize).max(1)];
        let mut lists = vec![Vec::new(); dims[0] * dims[1]];
        let cell = |p: DVec2| {
            let c = ((p - lo) / size).floor();
            [(c.x.max(0.0) as usize).min(dims[0] - 1), (c.y.max(0.0) as usize).min(dims[1] - 1)]
        };
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.corners(t).map(|p| p.truncate());
            let (l, h) = (cell(a.min(b).min(c)), cell(a.max(b).max(c)));
            for j in l[1]..=h[1] {
                for i in l[0]..=h[0] {
                    lists[j * dims[0] + i].push(t as u32);
                }
            }
        }
        let mut start = vec![0u32];
        let mut items = Vec::new();
        let mut z = Vec::with_capacity(lists.len());
        for list in lists {
            let range = list
                .iter()
                .flat_map(|&t| self.corners(t as usize))
                .fold([f64::INFINITY, f64::NEG_INFINITY], |[l, h], c| [l.min(c.z), h.max(c.z)]);
            z.push(range);
            items.extend(list);
            start.push(items.len() as u32);
        }
        Buckets { lo, size, dims, start, items, z }
    }

    fn bucket(&self, i: usize, j: usize) -> &[u32] {
        let b = &self.buckets;
        let k = j * b.dims[0] + i;
        &b.items[b.start[k] as usize..b.start[k + 1] as usize]
    }

    /// Visits buckets ring by ring around (x, y); `visit` gets each triangle and returns the
    /// current search radius, the search stops when the next ring is beyond it. With
    /// `z = Some(elevation)` a bucket is skipped when the 3D distance from (x, y, elevation) to
    /// its box (xy rectangle × elevation range of its triangles) is beyond the radius.
    fn search(&self, p: DVec2, z: Option<f64>, limit: f64, mut visit: impl FnMut(usize) -> f64) {
        let b = &self.buckets;
        let c = ((p - b.lo) / b.size).floor();
        let (ci, cj) = (c.x as i64, c.y as i64);
        let outside = (-ci).max(-cj).max(ci - b.dims[0] as i64 + 1).max(cj - b.dims[1] as i64 + 1).max(0);
        let mut reach = limit;
        let rings = b.dims[0].max(b.dims[1]) as i64 + outside;
        for ring in outside.max(0)..=rings {
            if (ring - 1).max(0) as f64 * b.size > reach {
                return;
            }
            // Only the ring's cells inside the grid: a point far outside the surface's footprint
            // costs the grid's size per ring, not the ring's area.
            let (rows, cols) = (b.dims[1] as i64, b.dims[0] as i64);
            for j in (cj - ring).max(0)..=(cj + ring).min(rows - 1) {
                // The whole row on the ring's top and bottom, its two ends in between.
                let (mut i, last, step) = if (j - cj).abs() == ring {
                    ((ci - ring).max(0), (ci + ring).min(cols - 1), 1)
                } else {
                    (ci - ring, ci + ring, 2 * ring)
                };
                while i <= last {
                    let column = i;
                    i += step;
                    if column < 0 || column >= cols {
                        continue;
                    }
                    let i = column;
                    if let Some(z) = z {
                        let k = j as usize * b.dims[0] + i as usize;
                        let lo = b.lo + DVec2::new(i as f64, j as f64) * b.size;
                        let dxy = (lo - p).max(p - lo - DVec2::splat(b.size)).max(DVec2::ZERO);
                        let [zl, zh] = b.z[k];
                        let dz = (zl - z).max(z - zh).max(0.0);
                        if dxy.length_squared() + dz * dz >= reach * reach {
                            continue;
                        }
                    }
                    for &t in self.bucket(i as usize, j as usize) {
                        reach = reach.min(visit(t as usize));
                    }
                }
            }
        }
    }

    /// The closest point of the surface to `p` and the unit normal (upward when the triangle is
    /// not vertical) of the triangle it lies on.
    pub fn closest(&self, p: DVec3) -> (DVec3, DVec3) {
        self.closest_within(p, f64::INFINITY).expect("a TIN has triangles")
    }

    /// [`Tin::closest`] when the surface comes within `limit` of `p`; None otherwise (faster
    /// than the unbounded search far from the surface).
    pub fn closest_within(&self, p: DVec3, limit: f64) -> Option<(DVec3, DVec3)> {
        let mut best = (limit, DVec3::ZERO, usize::MAX);
        self.search(p.truncate(), Some(p.z), limit, |t| {
            let [a, b, c] = self.corners(t);
            let gap = (a.min(b).min(c) - p).max(p - a.max(b).max(c)).max(DVec3::ZERO).length();
            if gap >= best.0 {
                return best.0;
            }
            let q = closest_on_triangle(p, a, b, c);
            let d = q.distance(p);
            if d < best.0 {
                best = (d, q, t);
            }
            best.0
        });
        (best.2 != usize::MAX).then(|| (best.1, self.normal_of(best.2)))
    }

    fn normal_of(&self, t: usize) -> DVec3 {
        let [a, b, c] = self.corners(t);
        let n = (b - a).cross(c - a).normalize();
        if n.z < 0.0 || (n.z == 0.0 && (n.y < 0.0 || (n.y == 0.0 && n.x < 0.0))) { -n } else { n }
    }

    /// Mean unit normal, area-weighted, upward.
    pub fn mean_normal(&self) -> DVec3 {
        let sum: DVec3 = (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                self.normal_of(t) * (b - a).cross(c - a).length()
            })
            .sum();
        sum.normalize_or(DVec3::Z)
    }

    /// Elevation of the surface above (x, y): barycentric in the triangle covering (x, y),
    /// else on the plane of the triangle nearest in xy.
    pub fn elevation_at(&self, x: f64, y: f64) -> f64 {
        let p = DVec2::new(x, y);
        let mut best = (f64::INFINITY, f64::NAN);
        self.search(p, None, f64::INFINITY, |t| {
            let [a, b, c] = self.corners(t);
            let (d, z) = xy_distance_and_plane_z(p, a, b, c);
            if d < best.0 {
                best = (d, z);
            }
            best.0
        });
        best.1
    }

    /// Total area, m².
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// The corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [DVec3; 3] {
        self.corners(t)
    }
}

/// xy distance from `p` to triangle abc's projection (0 inside) and the elevation of abc's
/// plane above `p`.
fn xy_distance_and_plane_z(p: DVec2, a: DVec3, b: DVec3, c: DVec3) -> (f64, f64) {
    let (a2, b2, c2) = (a.truncate(), b.truncate(), c.truncate());
    let det = (b2 - a2).perp_dot(c2 - a2);
    if det.abs() < 1e-12 {
        return (f64::INFINITY, f64::NAN); // vertical triangle: no elevation
    }
    let u = (p - a2).perp_dot(c2 - a2) / det;
    let v = (b2 - a2).perp_dot(p - a2) / det;
    let z = a.z + u * (b.z - a.z) + v * (c.z - a.z);
    let inside = u >= 0.0 && v >= 0.0 && u + v <= 1.0;
    let d = if inside {
        0.0
    } else {
        segment_distance(p, a2, b2).min(segment_distance(p, b2, c2)).min(segment_distance(p, c2, a2))
    };
    (d, z)
}

fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// Closest point to `p` on triangle abc (Ericson, Real-Time Collision Detection §5.1.5).
pub fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3-vertex grid over [0, 100]² on the plane z = 50 + 0.1 x.
    fn sheet() -> Tin {
        let mut vertices = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let (x, y) = (50.0 * i as f64, 50.0 * j as f64);
                vertices.push([x, y, 50.0 + 0.1 * x]);
            }
        }
        let mut triangles = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let a = j * 3 + i;
                triangles.push([a, a + 1, a + 4]);
                triangles.push([a, a + 4, a + 3]);
            }
        }
        Tin::new(vertices, triangles, "sheet").unwrap()
    }

    #[test]
    fn queries_match_the_plane() {
        let tin = sheet();
        assert!((tin.elevation_at(33.0, 71.0) - 53.3).abs() < 1e-9);
        assert!((tin.elevation_at(150.0, 20.0) - 65.0).abs() < 1e-9, "extended beyond the footprint");
        let p = DVec3::new(40.0, 40.0, 70.0);
        let (q, n) = tin.closest(p);
        let plane_n = DVec3::new(-0.1, 0.0, 1.0).normalize();
        assert!((q.distance(p) - (70.0 - 54.0) * plane_n.z).abs() < 1e-9);
        assert!((n - plane_n).length() < 1e-12);
        assert!((tin.area() - 100.0 * 100.0 * 1.01f64.sqrt()).abs() < 1e-6);
    }

    /// A surface whose footprint is a micrometre wide, queried 100 km away: the search starts
    /// 10¹¹ rings out and must visit the grid's cells only, not the ring's 10²² (this query
    /// never returned before).
    #[test]
    fn a_query_far_outside_a_tiny_footprint_visits_only_the_grid() {
        let tin =
            Tin::new(vec![[0.0, 0.0, 7.0], [1e-6, 0.0, 7.0], [0.0, 1e-6, 7.0]], vec![[0, 1, 2]], "speck")
                .unwrap();
        assert_eq!(tin.elevation_at(1e5, -1e5), 7.0);
        assert!(tin.closest_within(DVec3::new(-1e5, 1e5, 0.0), 1e3).is_none());
        let (q, _) = tin.closest(DVec3::new(-1e5, 1e5, 5.0));
        assert!(q.distance(DVec3::new(0.0, 1e-6, 7.0)) < 1e-9);
    }

    #[test]
    fn closest_point_is_exact_against_brute_force() {
        let tin = sheet();
        for k in 0..200 {
            let p =
                DVec3::new((k * 37 % 260) as f64 - 80.0, (k * 53 % 240) as f64 - 70.0, (k % 13) as f64 * 9.0);
            let brute = (0..tin.triangles.len())
                .map(|t| {
                    let [a, b, c] = tin.triangle(t);
                    closest_on_triangle(p, a, b, c).distance(p)
                })
                .fold(f64::INFINITY, f64::min);
            assert!((tin.closest(p).0.distance(p) - brute).abs() < 1e-9, "{p}");
            match tin.closest_within(p, 12.0) {
                Some((q, _)) => assert!((q.distance(p) - brute).abs() < 1e-9 && brute < 12.0),
                None => assert!(brute >= 12.0),
            }
        }
    }

    #[test]
    fn tsurf_round_trip_and_degenerate_triangles() {
        let dir = std::env::temp_dir().join(format!("karst-tin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("h.ts");
        let tin = sheet();
        karst_geodata::tin::write_tsurf(&path, "h", &tin.vertices, &tin.triangles).unwrap();
        assert_eq!(Tin::read(&path).unwrap(), tin);
        let bad = dir.join("bad.ts");
        std::fs::write(&bad, "GOCAD TSurf 1\nVRTX 1 0 0 0\nVRTX 2 1 0 0\nVRTX 3 2 0 0\nTRGL 1 2 3\n")
            .unwrap();
        let e = Tin::read(&bad).unwrap_err().to_string();
        assert!(e.contains("triangle 0 [0, 1, 2] is degenerate"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
