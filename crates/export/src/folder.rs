//! Writing the export files and recording them: every file is written atomically
//! (`karst_artifact::atomic`), streamed through a BLAKE3 hasher on its way, so that the
//! [`Manifest`] (name, format, bytes, digest) costs no second read.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use karst_artifact::atomic;
use karst_mesher::{Mesh, TriMesh, vertex_normals};
use karst_scene::params::{ExportFormat, MeshSurface};

use crate::error::ExportError;
use crate::payload::{ExportedFile, Manifest};

/// A deferred writer of some bytes: the writers lay out a file from its counts first, then
/// stream each block through one of these.
pub type Fill<'a> = Box<dyn Fn(&mut dyn Write) -> io::Result<()> + 'a>;

/// The export folder being written.
pub struct Folder {
    dir: PathBuf,
    manifest: Manifest,
}

impl Folder {
    /// Creates `dir` if needed.
    pub fn create(dir: &Path) -> Result<Folder, ExportError> {
        std::fs::create_dir_all(dir)
            .map_err(|source| ExportError::Write { path: dir.to_path_buf(), source })?;
        Ok(Folder { dir: dir.to_path_buf(), manifest: Manifest::default() })
    }

    /// Atomically writes `name` with the bytes `fill` produces, and records it.
    pub fn write(
        &mut self,
        name: &str,
        format: ExportFormat,
        fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), ExportError> {
        let path = self.dir.join(name);
        let mut record = None;
        atomic::write_with(&path, |file| {
            let mut hashing = Hashing { inner: file, hasher: blake3::Hasher::new(), bytes: 0 };
            {
                let mut buffered = BufWriter::with_capacity(1 << 16, &mut hashing);
                fill(&mut buffered)?;
                buffered.flush()?;
            }
            record = Some((hashing.bytes, hashing.hasher.finalize().to_hex().to_string()));
            Ok(())
        })
        .map_err(|source| ExportError::Write { path, source })?;
        let (bytes, blake3) = record.expect("a successful write records its size");
        self.manifest.files.push(ExportedFile {
            name: name.into(),
            format: format.name().into(),
            bytes,
            blake3,
        });
        Ok(())
    }

    /// A scratch file for a format built by a library that writes its own file (the
    /// GeoPackage's SQLite): beside the export folder's files, hidden, never recorded.
    pub fn scratch_path(&self, name: &str) -> PathBuf {
        self.dir.join(format!(".{name}.building"))
    }

    /// The manifest of everything written.
    pub fn finish(self) -> Manifest {
        self.manifest
    }
}

/// Passes bytes through, counting and hashing them.
struct Hashing<'a> {
    inner: &'a mut dyn Write,
    hasher: blake3::Hasher,
    bytes: u64,
}

impl Write for Hashing<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.update(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// The surfaces the mesh formats write, each with its vertex normals computed once.
pub struct Surfaces<'a> {
    pub list: Vec<NamedSurface<'a>>,
}

/// One surface, its name and its normals.
pub struct NamedSurface<'a> {
    pub name: &'static str,
    pub surface: &'a TriMesh,
    pub normals: Vec<[f32; 3]>,
}

impl<'a> Surfaces<'a> {
    /// The `chosen` surfaces of `mesh`, in mesh order; normals only when a format needs them.
    pub fn new(mesh: &'a Mesh, chosen: &[MeshSurface], formats: &[ExportFormat]) -> Surfaces<'a> {
        let with_normals = formats.iter().any(|f| {
            matches!(f, ExportFormat::Gltf | ExportFormat::Obj | ExportFormat::Ply | ExportFormat::VtkMeshes)
        });
        let all = [
            (MeshSurface::Terrain, &mesh.terrain),
            (MeshSurface::Cave, &mesh.cave),
            (MeshSurface::Water, &mesh.water),
        ];
        let list = all
            .into_iter()
            .filter(|(which, _)| chosen.contains(which))
            .map(|(which, surface)| NamedSurface {
                name: surface_name(which),
                surface,
                normals: if with_normals { unit_normals(surface) } else { Vec::new() },
            })
            .collect();
        Surfaces { list }
    }
}

/// The surface's name: terrain, cave or water.
pub fn surface_name(surface: MeshSurface) -> &'static str {
    match surface {
        MeshSurface::Terrain => "terrain",
        MeshSurface::Cave => "cave",
        MeshSurface::Water => "water",
    }
}

/// Vertex normals, each of unit length: a vertex no triangle uses (none after the mesher's
/// cleanup, but a reader must never see a zero normal) gets +z.
pub(crate) fn unit_normals(surface: &TriMesh) -> Vec<[f32; 3]> {
    let mut normals = vertex_normals(surface);
    for n in &mut normals {
        if *n == [0.0; 3] {
            *n = [0.0, 0.0, 1.0];
        }
    }
    normals
}
