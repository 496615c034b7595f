//! A surface polygonized into spill files, cleaned and copied into `mesh.bin` without ever
//! being whole in memory (the stage's streamed path, `docs/mesher.md`).
//!
//! [`SpilledSurface`] is a [`MeshSink`]: vertices and triangles go to two spill files as the
//! polygonizer hands them over, and each triangle joins its vertices in a union-find over the
//! vertex numbers (one `u32` per vertex, the only per-vertex array the stage keeps). It also
//! notes the pieces' sizes and the lowest vertex each piece of triangles names, so that the
//! spills can be *replayed* later with only the vertices still named in memory (the
//! polygonizer's front). The cleanup then takes the decisions of [`crate::clean`] exactly:
//!
//! 1. a replay numbers the components in order of first triangle (the root of each is
//!    tagged with its number in the union-find array), sums each component's signed volume in
//!    triangle order and notes whether it reaches the boundary;
//! 2. when a component's verdict depends on the sinks and springs (a hole in the rock, a cave
//!    piece that does not reach out), a second replay counts the crossings of the anchors' rays
//!    with its triangles;
//! 3. when anything is removed, the union-find array becomes the kept vertices' new numbers
//!    (a prefix count, in place), and [`SpilledSurface::encode`] copies the kept vertices and the
//!    renumbered kept triangles, in postcard's layout of a [`crate::TriMesh`].

use std::io::{self, Write};

use glam::DVec3;

use karst_artifact::check::{self, ensure};
use karst_sdf::SdfModel;

use crate::cleanup::{self, Reach, Solid, Verdict};
use crate::components::union;
use crate::payload::{Removed, signed_volume};
use crate::sink::MeshSink;
use crate::spill::Spill;

/// The union-find's mark of a component's root, whose entry then holds the component's number.
const ROOT: u32 = 1 << 31;
/// A removed vertex's new number.
const REMOVED: u32 = u32::MAX;

/// One piece handed over by the polygonizer, in order.
#[derive(Debug, Clone, Copy)]
enum Piece {
    Vertices(usize),
    /// Triangles, and the lowest vertex they name.
    Triangles(usize, u32),
}

/// A surface in spill files, with what the cleanup decided.
pub(crate) struct SpilledSurface {
    vertices: Spill<f32>,
    triangles: Spill<u32>,
    pieces: Vec<Piece>,
    /// The union-find over the vertices (None for a surface that is not cleaned); after the
    /// cleanup, the new numbers when it removed something, else None.
    parent: Option<Vec<u32>>,
    /// Vertices and triangles written to `mesh.bin`.
    kept: (u64, u64),
    pub(crate) field_evaluations: u64,
    pub(crate) removed: Removed,
}

/// What the first replay learns of each component.
#[derive(Default)]
struct Components {
    volume: Vec<f64>,
    reaches: Vec<bool>,
    triangles: Vec<u64>,
}

impl SpilledSurface {
    /// An empty surface spilled into `dir` under `name`; `cleaned` when [`Self::clean`] will run.
    pub(crate) fn create(dir: &std::path::Path, name: &str, cleaned: bool) -> io::Result<Self> {
        Ok(SpilledSurface {
            vertices: Spill::create(dir, &format!("{name}.vertices"))?,
            triangles: Spill::create(dir, &format!("{name}.triangles"))?,
            pieces: Vec::new(),
            parent: cleaned.then(Vec::new),
            kept: (0, 0),
            field_evaluations: 0,
            removed: Removed::default(),
        })
    }

    /// Ends the polygonization: every triangle is known; without a cleanup, everything is kept.
    pub(crate) fn finish(&mut self) -> io::Result<()> {
        self.vertices.finish()?;
        self.triangles.finish()?;
        self.kept = (self.vertices.len(), self.triangles.len());
        Ok(())
    }

    /// Triangles written to `mesh.bin`.
    pub(crate) fn triangles(&self) -> u64 {
        self.kept.1
    }

    /// Vertices written to `mesh.bin`.
    pub(crate) fn vertices(&self) -> u64 {
        self.kept.0
    }

    /// [`crate::clean`] on the spilled surface: the same verdicts, the same [`Removed`].
    pub(crate) fn clean(
        &mut self,
        solid: Solid,
        model: &SdfModel,
        anchors: &[DVec3],
        cell_size: f64,
    ) -> io::Result<()> {
        let mut parent = self.parent.take().ok_or_else(|| io::Error::other("a surface cleaned twice"))?;
        flatten(&mut parent);
        let reach = Reach::new(solid, model, cell_size);
        let mut found = Components::default();
        self.replay(|t, p| {
            let c = match label(&parent, t[0]) {
                Some(c) => c as usize,
                None => {
                    let r = root(&parent, t[0]) as usize;
                    parent[r] = ROOT | found.volume.len() as u32;
                    found.volume.push(0.0);
                    found.reaches.push(false);
                    found.triangles.push(0);
                    found.volume.len() - 1
                }
            };
            found.volume[c] += signed_volume(p);
            found.reaches[c] |= p.iter().any(|&v| reach.reaches(v));
            found.triangles[c] += 1;
            Ok(())
        })?;
        let holds = self.anchors_held(solid, &parent, &found, anchors, cell_size)?;
        let verdicts: Vec<Verdict> = (0..found.volume.len())
            .map(|c| cleanup::verdict(solid, found.volume[c], found.reaches[c], || holds[c]))
            .collect();
        self.removed = cleanup::removed(&verdicts, &found.volume);
        if verdicts.iter().any(|&v| v != Verdict::Keep) {
            let vertices = renumber(&mut parent, &verdicts);
            let triangles =
                (0..verdicts.len()).filter(|&c| verdicts[c] == Verdict::Keep).map(|c| found.triangles[c]);
            self.kept = (vertices, triangles.sum());
            self.parent = Some(parent);
        }
        Ok(())
    }

    /// For each component, whether it holds a sink or spring: asked only of those whose
    /// verdict depends on it ([`cleanup::asks_anchors`]), by the parity of the crossings of a ray
    /// from each anchor with the component's triangles or a corner within a cell of the anchor
    /// ([`cleanup::touches`]), as [`crate::clean`] does.
    fn anchors_held(
        &self,
        solid: Solid,
        parent: &[u32],
        found: &Components,
        anchors: &[DVec3],
        cell_size: f64,
    ) -> io::Result<Vec<bool>> {
        let count = found.volume.len();
        let asked: Vec<bool> =
            (0..count).map(|c| cleanup::asks_anchors(solid, found.volume[c], found.reaches[c])).collect();
        let mut odd = vec![false; count * anchors.len()];
        let mut near = vec![false; count];
        if !anchors.is_empty() && asked.contains(&true) {
            let direction = cleanup::ray();
            self.replay(|t, p| {
                let c = label(parent, t[0])
                    .ok_or_else(|| io::Error::other("a triangle without a component"))?
                    as usize;
                if asked[c] {
                    for (a, &anchor) in anchors.iter().enumerate() {
                        odd[c * anchors.len() + a] ^= cleanup::crosses(p, anchor, direction);
                        near[c] |= cleanup::touches(p, anchor, cell_size);
                    }
                }
                Ok(())
            })?;
        }
        Ok((0..count)
            .map(|c| near[c] || odd[c * anchors.len()..(c + 1) * anchors.len()].contains(&true))
            .collect())
    }

    /// Reads the spills back in the polygonizer's pieces, calling `each` on every triangle with
    /// its corners' positions; only the vertices that later triangles still name are kept.
    fn replay(&self, mut each: impl FnMut(&[u32; 3], [DVec3; 3]) -> io::Result<()>) -> io::Result<()> {
        // The lowest vertex named from each piece on.
        let mut lowest = vec![u32::MAX; self.pieces.len() + 1];
        for (i, piece) in self.pieces.iter().enumerate().rev() {
            lowest[i] = match *piece {
                Piece::Triangles(_, v) => v.min(lowest[i + 1]),
                Piece::Vertices(_) => lowest[i + 1],
            };
        }
        let (mut vertices, mut triangles) = (self.vertices.reader()?, self.triangles.reader()?);
        let (mut window, mut first, mut piece) = (Vec::new(), 0u32, Vec::new());
        let mut read = Vec::new();
        for (i, &p) in self.pieces.iter().enumerate() {
            let drop = (lowest[i].saturating_sub(first) as usize).min(window.len());
            window.drain(..drop);
            first += drop as u32;
            match p {
                Piece::Vertices(n) => {
                    vertices.read(n, &mut read)?;
                    window.extend(read.iter().map(|&v| glam::Vec3::from_array(v).as_dvec3()));
                }
                Piece::Triangles(n, _) => {
                    triangles.read(n, &mut piece)?;
                    for t in &piece {
                        let at = |v: u32| {
                            window.get(v.wrapping_sub(first) as usize).copied().ok_or_else(|| {
                                io::Error::other(format!("vertex {v} is not in the replayed front"))
                            })
                        };
                        each(t, [at(t[0])?, at(t[1])?, at(t[2])?])?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Writes the surface as postcard writes a [`crate::TriMesh`] of the kept vertices and
    /// triangles, checking what [`crate::Mesh`]'s validation checks; `name` names the surface in
    /// the message of a check that fails.
    pub(crate) fn encode(&self, w: &mut dyn Write, name: &str) -> io::Result<()> {
        let new = |v: u32| self.parent.as_ref().map_or(v, |numbers| numbers[v as usize]);
        varint(w, self.kept.0)?;
        let (mut v, mut written) = (0u32, 0u64);
        self.vertices.reader()?.for_each(self.vertices.len(), |p| {
            if new(v) != REMOVED {
                check::position_f32(|| format!("{name}.vertices[{written}]"), p).map_err(invalid)?;
                p.iter().try_for_each(|c| w.write_all(&c.to_le_bytes()))?;
                written += 1;
            }
            v += 1;
            Ok(())
        })?;
        varint(w, self.kept.1)?;
        let mut index = 0u64;
        self.triangles.reader()?.for_each(self.triangles.len(), |t| {
            if new(t[0]) == REMOVED {
                return Ok(());
            }
            let t = t.map(new);
            let field = || format!("{name}.triangles[{index}]");
            if let Some(&v) = t.iter().find(|&&v| u64::from(v) >= self.kept.0) {
                check::index(field, u64::from(v), self.kept.0 as usize).map_err(invalid)?;
            }
            ensure(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], field, || format!("{t:?} repeats a vertex"))
                .map_err(invalid)?;
            t.iter().try_for_each(|&v| varint(w, u64::from(v)))?;
            index += 1;
            Ok(())
        })?;
        varint(w, self.field_evaluations)?;
        let r = &self.removed;
        check::within(|| format!("{name}.removed.island_volume"), r.island_volume, 0.0, f64::MAX)
            .map_err(invalid)?;
        check::within(|| format!("{name}.removed.pocket_volume"), r.pocket_volume, 0.0, f64::MAX)
            .map_err(invalid)?;
        varint(w, u64::from(r.islands))?;
        w.write_all(&r.island_volume.to_le_bytes())?;
        varint(w, u64::from(r.pockets))?;
        w.write_all(&r.pocket_volume.to_le_bytes())
    }
}

impl MeshSink for SpilledSurface {
    type Error = io::Error;

    fn vertices(&mut self, vertices: &[[f32; 3]]) -> io::Result<()> {
        if self.vertices.len() + vertices.len() as u64 >= u64::from(ROOT) {
            return Err(io::Error::other(format!("a surface of more than {ROOT} vertices")));
        }
        if let Some(parent) = &mut self.parent {
            let first = parent.len() as u32;
            parent.extend(first..first + vertices.len() as u32);
        }
        self.pieces.push(Piece::Vertices(vertices.len()));
        self.vertices.push(vertices)
    }

    fn triangles(&mut self, triangles: &[[u32; 3]]) -> io::Result<()> {
        if let Some(parent) = &mut self.parent {
            for t in triangles {
                union(parent, t[0], t[1]);
                union(parent, t[0], t[2]);
            }
        }
        let lowest = triangles.iter().flatten().copied().min().unwrap_or(u32::MAX);
        self.pieces.push(Piece::Triangles(triangles.len(), lowest));
        self.triangles.push(triangles)
    }
}

/// Points every vertex straight at its root. The smaller root wins every union, so a vertex's
/// parent is never above it, and one pass in increasing order is enough.
fn flatten(parent: &mut [u32]) {
    for v in 0..parent.len() {
        parent[v] = parent[parent[v] as usize];
    }
}

/// The root of `v` in a flattened union-find whose roots may be tagged.
fn root(parent: &[u32], v: u32) -> u32 {
    let p = parent[v as usize];
    if p & ROOT != 0 || p == v { v } else { p }
}

/// The component of `v`, once its root is tagged.
fn label(parent: &[u32], v: u32) -> Option<u32> {
    let entry = parent[root(parent, v) as usize];
    (entry & ROOT != 0).then_some(entry & !ROOT)
}

/// Replaces the tagged union-find by the new number of every kept vertex (in their order) or
/// [`REMOVED`]: a vertex is kept when its component is (a vertex of no triangle never is, as in
/// [`crate::clean`]). Returns the number kept. In place: a vertex's root is below it, so its new
/// number is known when the vertex is reached.
fn renumber(parent: &mut [u32], verdicts: &[Verdict]) -> u64 {
    let mut kept = 0u32;
    for v in 0..parent.len() {
        let p = parent[v];
        let keep = if p & ROOT != 0 {
            verdicts[(p & !ROOT) as usize] == Verdict::Keep
        } else if p as usize == v {
            false
        } else {
            parent[p as usize] != REMOVED
        };
        parent[v] = if keep { kept } else { REMOVED };
        kept += u32::from(keep);
    }
    u64::from(kept)
}

/// A postcard varint (LEB128).
fn varint(w: &mut dyn Write, mut value: u64) -> io::Result<()> {
    let mut bytes = [0u8; 10];
    let mut n = 0;
    loop {
        let low = (value & 0x7f) as u8;
        value >>= 7;
        bytes[n] = low | if value == 0 { 0 } else { 0x80 };
        n += 1;
        if value == 0 {
            return w.write_all(&bytes[..n]);
        }
    }
}

/// A failed check of the payload as an I/O error: the artifact is not written.
pub(crate) fn invalid(e: karst_artifact::Invalid) -> io::Error {
    io::Error::other(format!(
        "built an invalid mesh payload ({}: {}): this is a bug in karstgen",
        e.field, e.problem
    ))
}
