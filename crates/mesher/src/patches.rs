//! The carved terrain meshed in fine patches ([`Patch`]) over a coarse ground, the patches'
//! rims stitched to it.
//!
//! The coarse lattice is polygonized whole with the caves and streams held off the patches
//! ([`Coarse`]), and its triangles inside a patch's box are dropped: what is left has a hole
//! over each patch, rimmed by the marching-cubes segments on the box's side faces. Each patch
//! is polygonized on its own lattice with the caves and streams only inside
//! [`Patch::carved`] ([`Carved`]): an open mesh rimmed by its own segments on the same faces.
//! On a patch's faces both fields have the sign of the plain ground (the terrain inside the
//! domain), rock under the ground and air over it on every vertical line (the patch stands
//! above the floor and inside the walls, its top in the air, its bottom in the rock), so each
//! rim is one loop that goes once round the box: each side face holds one segment per cell
//! that the ground crosses, and the ground crosses each vertical edge once. Both loops are
//! ordered by the distance s along the box's perimeter and merged into one polyline
//! ([`stitch`]); each rim edge's triangle is replaced by the fan from its third vertex to the
//! merged polyline's vertices between the edge's ends. Every merged edge then belongs to one
//! fan of each side, used once in each direction: the surface stays closed, manifold and
//! oriented. Where the cuts leave the ground, the field of both is the plain ground, so the two
//! loops are two samplings of the same curve and the fans are slivers in the face's plane.

use glam::DVec3;

use crate::payload::TriMesh;
use crate::polygonize::polygonize_into;
use crate::terrain_lattice::{Patch, TerrainLattice};
use crate::volume::Volume;
use crate::warp::Warped;
use karst_sdf::CarvedTerrain;

/// The plain ground: the terrain inside the domain, negative in the rock; 1-Lipschitz.
fn plain(field: &CarvedTerrain, p: DVec3) -> f64 {
    let model = field.model();
    model.terrain.distance(p).max(model.domain.signed_distance(p))
}

/// Signed distance bound to the box [lo, hi], negative inside.
fn box_distance((lo, hi): (DVec3, DVec3), p: DVec3) -> f64 {
    let (c, h) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    let q = (p - c).abs() - h;
    q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
}

/// max(plain ground, min(carved terrain, gate)): the carved terrain where the gate is above
/// it, the plain ground where the gate is below it, 1-Lipschitz when the gate is. Shared by
/// [`Coarse`] and [`Carved`].
trait Gated: Sync {
    fn field(&self) -> &CarvedTerrain;
    /// The gate at p: negative on the patches' faces.
    fn gate(&self, p: DVec3) -> f64;
}

/// The carved terrain with the caves and streams held off the patches: the gate is the
/// distance to the nearest patch less a fine cell.
struct Coarse<'a> {
    field: &'a CarvedTerrain,
    boxes: Vec<(DVec3, DVec3)>,
    fine: f64,
}

impl Gated for Coarse<'_> {
    fn field(&self) -> &CarvedTerrain {
        self.field
    }

    fn gate(&self, p: DVec3) -> f64 {
        self.boxes.iter().map(|&b| box_distance(b, p)).fold(f64::INFINITY, f64::min) - self.fine
    }
}

/// The carved terrain with the caves and streams only inside a patch's carved box: the gate is
/// the depth inside it.
struct Carved<'a> {
    field: &'a CarvedTerrain,
    carved: (DVec3, DVec3),
}

impl Gated for Carved<'_> {
    fn field(&self) -> &CarvedTerrain {
        self.field
    }

    fn gate(&self, p: DVec3) -> f64 {
        -box_distance(self.carved, p)
    }
}

/// A [`Gated`] field as a solid.
struct Gate<G>(G);

/// max(t, min(f, gate)) with f as [`Volume::eval_within`] gives it: where f is only known to
/// be at least `reach` in magnitude, so is the result (t ≤ f: carving only adds air).
impl<G: Gated> Volume for Gate<G> {
    fn eval(&self, p: DVec3) -> f64 {
        let t = plain(self.0.field(), p);
        t.max(self.0.field().eval(p).min(self.0.gate(p)))
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        let t = plain(self.0.field(), p);
        let gate = self.0.gate(p);
        if t >= reach || gate <= t {
            return t;
        }
        t.max(self.0.field().eval_within(p, reach).min(gate))
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let parts: Vec<(f64, f64)> =
            points.iter().map(|&p| (plain(self.0.field(), p), self.0.gate(p))).collect();
        let carved: Vec<DVec3> =
            points.iter().zip(&parts).filter(|&(_, &(t, g))| t < reach && g > t).map(|(&p, _)| p).collect();
        let mut values = Vec::with_capacity(carved.len());
        if !carved.is_empty() {
            Volume::eval_block(self.0.field(), lo, hi, reach, &carved, &mut values);
        }
        let mut values = values.into_iter();
        out.extend(
            parts.iter().map(
                |&(t, g)| {
                    if t < reach && g > t { t.max(values.next().unwrap_or(t).min(g)) } else { t }
                },
            ),
        );
    }

    /// As the carved terrain's: the values at the boxes' centres, with the largest reach.
    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let half = |&(l, h): &(DVec3, DVec3)| (h - l).length() * 0.5;
        let reach = boxes.iter().map(|b| half(b) * 1.001).fold(0.0, f64::max);
        let centres: Vec<DVec3> = boxes.iter().map(|&(l, h)| (l + h) * 0.5).collect();
        let mut values = Vec::with_capacity(boxes.len());
        self.eval_block(lo, hi, reach, &centres, &mut values);
        for ((o, b), v) in out.iter_mut().zip(boxes).zip(values) {
            *o = (v.abs() - half(b)).max(0.0);
        }
    }

    fn extent(&self) -> (DVec3, DVec3) {
        Volume::extent(self.0.field())
    }
}

/// A mesh in the world, and its vertices in its lattice's space and precisely in the world.
struct Piece {
    mesh: TriMesh,
    lattice: Vec<[f32; 3]>,
    world: Vec<DVec3>,
}

fn polygonized<V: Volume>(solid: &V, lattice: &TerrainLattice) -> Piece {
    let warp = Warped::new(solid, lattice);
    let mut mesh = TriMesh::default();
    let Ok(evaluations) = polygonize_into(&warp, 1.0, &mut mesh);
    mesh.field_evaluations = evaluations;
    let world: Vec<DVec3> =
        mesh.vertices.iter().map(|&u| lattice.to_world(glam::Vec3::from_array(u).as_dvec3())).collect();
    let lattice =
        std::mem::replace(&mut mesh.vertices, world.iter().map(|p| p.as_vec3().to_array()).collect());
    Piece { mesh, lattice, world }
}

/// Why a patch's rim could not be stitched: the caller then meshes the terrain on whole slabs.
#[derive(Debug)]
pub struct Unstitched;

/// The carved terrain of `field` on `lattice` and its patches, stitched; Err when a rim is not
/// the one loop round its patch that the construction promises.
pub fn polygonize_patched(field: &CarvedTerrain, lattice: &TerrainLattice) -> Result<TriMesh, Unstitched> {
    let boxes: Vec<(DVec3, DVec3)> = lattice.patches.iter().map(|p| world_box(lattice, p)).collect();
    let coarse = polygonized(&Gate(Coarse { field, boxes: boxes.clone(), fine: lattice.fine }), lattice);
    // The coarse triangles inside a patch: their centroid is inside its box in lattice space
    // (a triangle of a cell lies in the cell, and none lies in one face of a patch's box).
    let inside = |t: &[u32; 3]| {
        let c = t.iter().fold([0.0f64; 3], |c, &v| {
            let u = coarse.lattice[v as usize];
            [c[0] + u[0] as f64, c[1] + u[1] as f64, c[2] + u[2] as f64]
        });
        let c = c.map(|x| x / 3.0);
        lattice.patches.iter().any(|p| (0..3).all(|a| (p.lo[a] as f64) < c[a] && c[a] < p.hi[a] as f64))
    };
    let mut out = TriMesh { field_evaluations: coarse.mesh.field_evaluations, ..TriMesh::default() };
    out.vertices = coarse.mesh.vertices.clone();
    out.triangles = coarse.mesh.triangles.iter().copied().filter(|t| !inside(t)).collect();
    let mut precise = coarse.world.clone();
    let coarse_rims = rim_triangles(&out.triangles, 0);
    let mut joins = Joins::default();
    for (patch, &world) in lattice.patches.iter().zip(&boxes) {
        let on_face = |v: u32| {
            let u = coarse.lattice[v as usize];
            (0..2).any(|a| u[a] == patch.lo[a] as f32 || u[a] == patch.hi[a] as f32)
                && (0..3).all(|a| patch.lo[a] as f32 <= u[a] && u[a] <= patch.hi[a] as f32)
        };
        let coarse_loop: Vec<((u32, u32), usize)> =
            coarse_rims.iter().copied().filter(|&((a, b), _)| on_face(a) && on_face(b)).collect();
        let fine = polygonized(&Gate(Carved { field, carved: patch.carved }), &patch.lattice);
        let offset = out.vertices.len() as u32;
        let fine_loop = rim_triangles(&fine.mesh.triangles, out.triangles.len())
            .into_iter()
            .map(|((a, b), k)| ((a + offset, b + offset), k))
            .collect();
        out.field_evaluations += fine.mesh.field_evaluations;
        out.vertices.extend_from_slice(&fine.mesh.vertices);
        precise.extend_from_slice(&fine.world);
        out.triangles.extend(fine.mesh.triangles.iter().map(|t| t.map(|v| v + offset)));
        stitch(&out, &precise, world, [coarse_loop, fine_loop], &mut joins)?;
    }
    let Joins { replaced, fans, same } = joins;
    let at = |v: u32| *same.get(&v).unwrap_or(&v);
    let mut k = 0;
    out.triangles.retain(|_| {
        k += 1;
        replaced.binary_search(&(k - 1)).is_err()
    });
    out.triangles.extend(fans);
    let distinct = |t: &[u32; 3]| t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    out.triangles = out.triangles.iter().map(|t| t.map(at)).filter(distinct).collect();
    compact(&mut out);
    Ok(out)
}

/// What the stitches change: the triangles replaced by fans (sorted), the fans, and the
/// vertices that became another at the same position.
#[derive(Default)]
struct Joins {
    replaced: Vec<usize>,
    fans: Vec<[u32; 3]>,
    same: std::collections::HashMap<u32, u32>,
}

/// The world box of a patch.
fn world_box(lattice: &TerrainLattice, patch: &Patch) -> (DVec3, DVec3) {
    let corner =
        |i: [usize; 3]| DVec3::new(lattice.planes[0][i[0]], lattice.planes[1][i[1]], lattice.planes[2][i[2]]);
    (corner(patch.lo), corner(patch.hi))
}

/// The directed edges of `triangles` that no triangle traverses the other way, each with its
/// triangle's index (plus `first`), sorted.
fn rim_triangles(triangles: &[[u32; 3]], first: usize) -> Vec<((u32, u32), usize)> {
    let mut edges: Vec<((u32, u32), usize)> = triangles
        .iter()
        .enumerate()
        .flat_map(|(k, t)| (0..3).map(move |e| ((t[e], t[(e + 1) % 3]), first + k)))
        .collect();
    edges.sort_unstable();
    let open = |&((a, b), _): &((u32, u32), usize)| edges.binary_search_by(|e| e.0.cmp(&(b, a))).is_err();
    edges.iter().copied().filter(open).collect()
}

/// Joins two rims of one patch's box `(lo, hi)` (the coarse hole's and the patch's own, each
/// directed edges of `mesh` with their triangles) by fans (module doc); `precise` holds the
/// vertices' world positions in f64.
fn stitch(
    mesh: &TriMesh,
    precise: &[DVec3],
    (lo, hi): (DVec3, DVec3),
    loops: [Vec<((u32, u32), usize)>; 2],
    joins: &mut Joins,
) -> Result<(), Unstitched> {
    let size = hi - lo;
    // s along the perimeter, anticlockwise from the corner (lo.x, lo.y), from the nearest side
    // face (the rim's vertices lie on them).
    let s = |v: u32| -> f64 {
        let p = precise[v as usize];
        let (dx, dy) = ((p.x - lo.x).clamp(0.0, size.x), (p.y - lo.y).clamp(0.0, size.y));
        let faces = [
            ((p.y - lo.y).abs(), dx),
            ((p.x - hi.x).abs(), size.x + dy),
            ((p.y - hi.y).abs(), size.x + size.y + (size.x - dx)),
            ((p.x - lo.x).abs(), 2.0 * size.x + size.y + (size.y - dy)),
        ];
        faces.iter().fold((f64::INFINITY, 0.0), |best, &(d, s)| if d < best.0 { (d, s) } else { best }).1
    };
    // Each loop as a cycle of vertices in its edges' direction, turned to increase in s and
    // started at its least s; and whether its edges run that way.
    let mut orders = Vec::with_capacity(2);
    for edges in &loops {
        let next: std::collections::HashMap<u32, u32> = edges.iter().map(|&(e, _)| e).collect();
        let &((start, _), _) = edges.first().ok_or(Unstitched)?;
        let mut cycle = vec![start];
        let mut v = *next.get(&start).ok_or(Unstitched)?;
        while v != start {
            if cycle.len() >= edges.len() {
                return Err(Unstitched);
            }
            cycle.push(v);
            v = *next.get(&v).ok_or(Unstitched)?;
        }
        if cycle.len() != edges.len() || next.len() != edges.len() {
            return Err(Unstitched);
        }
        let keys: Vec<f64> = cycle.iter().map(|&v| s(v)).collect();
        let n = keys.len();
        let drops = (0..n).filter(|&i| keys[(i + 1) % n] < keys[i]).count();
        let rises = (0..n).filter(|&i| keys[(i + 1) % n] > keys[i]).count();
        let increasing = match (drops, rises) {
            (1, r) if r + 1 == n => true,
            (d, 1) if d + 1 == n => false,
            _ => return Err(Unstitched),
        };
        let mut ordered: Vec<(f64, u32)> = keys.into_iter().zip(cycle).collect();
        if !increasing {
            ordered.reverse();
        }
        let first = (0..n).min_by(|&a, &b| ordered[a].0.total_cmp(&ordered[b].0)).unwrap_or(0);
        ordered.rotate_left(first);
        orders.push((ordered, increasing));
    }
    // The merged polyline, coarse first where s ties; consecutive vertices at the same
    // position (as stored) become one.
    let (a, b) = (&orders[0].0, &orders[1].0);
    let mut polyline: Vec<u32> = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    let position = |v: u32| mesh.vertices[v as usize];
    while i < a.len() || j < b.len() {
        let v = if j == b.len() || (i < a.len() && a[i].0 <= b[j].0) {
            i += 1;
            a[i - 1].1
        } else {
            j += 1;
            b[j - 1].1
        };
        match polyline.last() {
            Some(&last) if position(last) == position(v) => {
                joins.same.insert(v, last);
            }
            _ => polyline.push(v),
        }
    }
    if polyline.len() > 1 && position(polyline[0]) == position(polyline[polyline.len() - 1]) {
        let last = polyline.pop().ok_or(Unstitched)?;
        joins.same.insert(last, polyline[0]);
    }
    let at = |v: u32| *joins.same.get(&v).unwrap_or(&v);
    let index: std::collections::HashMap<u32, usize> =
        polyline.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    // Every rim edge's triangle becomes a fan over the polyline between the edge's ends. A
    // triangle at a corner of the box can have two rim edges a→b and b→c: the fan of a→b from
    // c, whose last triangle (p, b, c) is then fanned over b→c from p.
    let n = polyline.len();
    let path = |a: u32, b: u32, increasing: bool| -> Result<Vec<u32>, Unstitched> {
        let (mut here, to) = (*index.get(&at(a)).ok_or(Unstitched)?, *index.get(&at(b)).ok_or(Unstitched)?);
        let mut path = vec![polyline[here]];
        while here != to {
            here = if increasing { (here + 1) % n } else { (here + n - 1) % n };
            path.push(polyline[here]);
        }
        Ok(path)
    };
    let fan = |path: &[u32], apex: u32, fans: &mut Vec<[u32; 3]>| {
        fans.extend(path.windows(2).map(|w| [w[0], w[1], apex]));
    };
    let mut by_triangle: Vec<(usize, u32, u32, bool)> = loops
        .iter()
        .zip(&orders)
        .flat_map(|(edges, &(_, increasing))| edges.iter().map(move |&((a, b), k)| (k, a, b, increasing)))
        .collect();
    by_triangle.sort_unstable_by_key(|e| e.0);
    let mut replaced = Vec::new();
    for group in by_triangle.chunk_by(|x, y| x.0 == y.0) {
        let k = group[0].0;
        replaced.push(k);
        let t = mesh.triangles[k];
        let third = |a: u32, b: u32| t.iter().copied().find(|&v| v != a && v != b).ok_or(Unstitched);
        match *group {
            [(_, a, b, increasing)] => fan(&path(a, b, increasing)?, third(a, b)?, &mut joins.fans),
            [(_, a0, b0, i0), (_, a1, b1, i1)] => {
                let ((a, b, first), (c, second)) =
                    if b0 == a1 { ((a0, b0, i0), (b1, i1)) } else { ((a1, b1, i1), (b0, i0)) };
                let one = path(a, b, first)?;
                let two = path(b, c, second)?;
                let p = *one.iter().rev().nth(1).ok_or(Unstitched)?;
                fan(&one[..one.len() - 1], c, &mut joins.fans);
                fan(&two, p, &mut joins.fans);
            }
            _ => return Err(Unstitched),
        }
    }
    joins.replaced.extend(replaced);
    joins.replaced.sort_unstable();
    Ok(())
}

/// Drops the vertices no triangle names, keeping the others' order.
fn compact(mesh: &mut TriMesh) {
    let mut new = vec![u32::MAX; mesh.vertices.len()];
    for t in &mesh.triangles {
        for &v in t {
            new[v as usize] = 0;
        }
    }
    let mut vertices = Vec::with_capacity(mesh.vertices.len());
    for (v, n) in new.iter_mut().enumerate() {
        if *n == 0 {
            *n = vertices.len() as u32;
            vertices.push(mesh.vertices[v]);
        }
    }
    mesh.vertices = vertices;
    for t in &mut mesh.triangles {
        *t = t.map(|v| new[v as usize]);
    }
}
