//! Reading the data files a scene names (heightfield image or GeoTIFF, TIN or raster surfaces,
//! potential grid), relative to the scene file's folder. Each file's BLAKE3 goes into the
//! scene's serialized form, so that editing a data file changes the hash of the sections that
//! use it. GeoTIFFs are cropped to the domain's footprint, and the CRS of every file that
//! carries one is checked against the scene's `crs` ([`crate::crs`]).

use std::path::Path;
use std::sync::Arc;

use crate::spans::line_of_path;
use crate::validate::Problem;
use karst_geodata::crs::{self, Epsg, FileCrs};
use karst_geodata::geotiff::{Footprint, GeoRaster};
use karst_geology::field::ValueGrid;
use karst_geology::grids;
use karst_geology::heightfield::{Georeference, HeightGrid};
use karst_geology::surface::Geometry;
use karst_geology::tin::Tin;
use karst_geology::{Domain, Terrain};

use crate::point_table::Row;
use crate::{KeyPointKind, Scene};

/// Reads every data file of `scene`; returns the problems (unreadable or invalid files).
pub(crate) fn attach_files(scene: &mut Scene, folder: &Path, text: &str) -> Vec<Problem> {
    let mut loader =
        Loader { folder, text, footprint: footprint(&scene.domain), problems: Vec::new(), crs: Vec::new() };
    if let Terrain::Noise { anchor, .. } = &mut scene.terrain {
        *anchor = [scene.domain.min[0], scene.domain.min[1]];
    }
    loader.terrain(&mut scene.terrain);
    loader.surfaces(scene);
    loader.potential_grid(scene);
    loader.lithology(scene);
    attach_tables(scene, &mut loader);
    loader.calibration_target(scene);
    crate::links::resolve(scene, &mut |field, message| loader.report(field, message));
    loader.check_crs(scene.crs.as_deref());
    loader.problems
}

/// What has been read so far, and what went wrong.
pub(crate) struct Loader<'a> {
    pub(crate) folder: &'a Path,
    text: &'a str,
    /// The domain's xy rectangle, None when the domain itself is invalid (reported elsewhere).
    pub(crate) footprint: Option<Footprint>,
    problems: Vec<Problem>,
    /// The CRS of each file that declares one.
    crs: Vec<FileCrs>,
}

/// The domain's xy rectangle, when it is a usable box.
fn footprint(domain: &Domain) -> Option<Footprint> {
    let ok = (0..2)
        .all(|a| domain.min[a].is_finite() && domain.max[a].is_finite() && domain.min[a] < domain.max[a]);
    ok.then_some([[domain.min[0], domain.max[0]], [domain.min[1], domain.max[1]]])
}

impl Loader<'_> {
    pub(crate) fn report(&mut self, field: &str, message: String) {
        self.problems.push(Problem { line: line_of_path(self.text, field), field: field.into(), message });
    }

    /// Notes the CRS `file` (named by `field`) declares.
    pub(crate) fn file_crs(&mut self, field: &str, file: &Path, crs: Option<Epsg>) {
        if let Some(crs) = crs {
            self.crs.push(FileCrs { field: field.into(), file: file.display().to_string(), crs });
        }
    }

    /// A GeoTIFF cropped to the domain's footprint, its CRS noted; None (reported) when it
    /// cannot be read or the domain is unusable.
    pub(crate) fn geotiff(&mut self, field: &str, path: &Path, nodata: Option<f64>) -> Option<GeoRaster> {
        let footprint = self.footprint?;
        match GeoRaster::read(path, Some(footprint), nodata) {
            Ok(raster) => {
                self.file_crs(field, path, raster.crs);
                Some(raster)
            }
            Err(e) => {
                self.report(field, e.to_string());
                None
            }
        }
    }

    fn terrain(&mut self, terrain: &mut Terrain) {
        let Terrain::Heightfield { file, origin, cell_size, vertical_scale, offset, nodata, content, grid } =
            terrain
        else {
            return;
        };
        let path = self.folder.join(&*file);
        if grids::is_geotiff(file) {
            for (field, given) in
                [("terrain.origin", origin.is_some()), ("terrain.cell_size", cell_size.is_some())]
            {
                if given {
                    self.report(field, format!("{file} is a GeoTIFF: it carries its own georeferencing"));
                }
            }
            if let Some(raster) = self.geotiff("terrain.file", &path, *nodata) {
                *content = hash_file(&path);
                *grid = Arc::new(grids::height_grid(raster, *vertical_scale, *offset));
            }
            return;
        }
        let (Some(origin), Some(cell_size)) = (*origin, *cell_size) else {
            self.report(
                "terrain",
                format!("{file} needs `origin` and `cell_size` (only GeoTIFFs carry them)"),
            );
            return;
        };
        let geo = Georeference {
            origin,
            cell_size,
            vertical_scale: *vertical_scale,
            offset: *offset,
            nodata: *nodata,
        };
        let usable = cell_size > 0.0 && origin.iter().all(|v| v.is_finite()) && vertical_scale.is_finite();
        if usable {
            match HeightGrid::read(&path, &geo) {
                Ok(g) => {
                    *content = hash_file(&path);
                    *grid = Arc::new(g);
                }
                Err(e) => self.report("terrain.file", e.to_string()),
            }
        }
    }

    fn surfaces(&mut self, scene: &mut Scene) {
        let geology = &mut scene.geology;
        for (list, surfaces) in [
            ("water_tables", &mut geology.water_tables),
            ("horizons", &mut geology.horizons),
            ("faults", &mut geology.faults),
        ] {
            for (i, s) in surfaces.iter_mut().enumerate() {
                let Geometry::Tin { file, content, mesh } = &mut s.geometry else { continue };
                let field = format!("geology.{list}[{i}].file");
                let path = self.folder.join(&*file);
                let tin = if grids::is_geotiff(file) {
                    let Some(raster) = self.geotiff(&field, &path, None) else { continue };
                    grids::tin(&raster, &path.display().to_string())
                } else {
                    Tin::read(&path)
                };
                match tin {
                    Ok(tin) => {
                        *content = hash_file(&path);
                        *mesh = Arc::new(tin);
                    }
                    Err(e) => self.report(&field, e.to_string()),
                }
            }
        }
    }

    fn potential_grid(&mut self, scene: &mut Scene) {
        let Some(grid) = &mut scene.geology.grid else { return };
        let path = self.folder.join(&grid.file);
        match ValueGrid::read(&path) {
            Ok(values) => {
                grid.content = hash_file(&path);
                grid.values = Arc::new(values);
            }
            Err(e) => self.report("geology.grid.file", e.to_string()),
        }
    }

    fn lithology(&mut self, scene: &mut Scene) {
        let Some(lithology) = &mut scene.geology.lithology else { return };
        if self.footprint.is_none() {
            return;
        }
        match lithology.load(self.folder, &scene.domain) {
            Ok(grid) => {
                lithology.content = hash_file(&self.folder.join(&lithology.file));
                lithology.grid = Arc::new(grid);
            }
            Err(e) => self.report("geology.lithology.file", e.to_string()),
        }
    }

    /// `calibrate.target`: resolved against the scene's folder and hashed (both files of a
    /// karstnet pair); a missing file is reported here, its contents are read by the metrics
    /// crate.
    fn calibration_target(&mut self, scene: &mut Scene) {
        let Some(calibrate) = &mut scene.calibrate else { return };
        let Some(file) = &calibrate.target else { return };
        let path = self.folder.join(file);
        let mut hasher = blake3::Hasher::new();
        for part in target_files(&path) {
            match std::fs::read(&part) {
                Ok(bytes) => {
                    hasher.update(&bytes);
                }
                Err(e) => {
                    self.report("calibrate.target", format!("{}: cannot read: {e}", part.display()));
                    return;
                }
            }
        }
        calibrate.target_content = hasher.finalize().to_hex().to_string();
        calibrate.target_path = Some(path);
    }

    /// The scene's `crs` against every file's.
    fn check_crs(&mut self, declared: Option<&str>) {
        let declared = match declared.map(Epsg::parse) {
            Some(Ok(code)) => Some(code),
            Some(Err(message)) => return self.report("crs", message.to_string()),
            None => None,
        };
        let files = std::mem::take(&mut self.crs);
        for (field, message) in crs::disagreements(declared, &files) {
            self.report(&field, message);
        }
    }
}

/// The files of a calibration target: a GOCAD PLine or CSV file itself, a karstnet network's
/// two files (`BASE_nodes.dat`, `BASE_links.dat`) whether given by its base or either file.
fn target_files(path: &Path) -> Vec<std::path::PathBuf> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let base = ["_nodes.dat", "_links.dat"].iter().find_map(|suffix| name.strip_suffix(suffix));
    match (base, path.extension()) {
        (Some(base), _) if !base.is_empty() => {
            ["_nodes.dat", "_links.dat"].map(|s| path.with_file_name(format!("{base}{s}"))).to_vec()
        }
        (_, None) => ["_nodes.dat", "_links.dat"].map(|s| path.with_file_name(format!("{name}{s}"))).to_vec(),
        _ => vec![path.to_path_buf()],
    }
}

/// BLAKE3 of a file's bytes, streamed (a DEM need not be held in memory twice).
pub(crate) fn hash_file(path: &Path) -> String {
    let mut hasher = blake3::Hasher::new();
    match std::fs::File::open(path).and_then(|mut f| std::io::copy(&mut f, &mut hasher)) {
        Ok(_) => hasher.finalize().to_hex().to_string(),
        Err(_) => String::new(),
    }
}

/// Reads every table of the scene, appends its points to `scene.keypoints` (z from the terrain
/// where absent) and its springs to their phases; problems and each file's CRS go to `loader`.
fn attach_tables(scene: &mut Scene, loader: &mut Loader) {
    for t in 0..scene.keypoints_from.len() {
        let field = format!("keypoints_from[{t}].file");
        let path = loader.folder.join(&scene.keypoints_from[t].file);
        let rows = match scene.keypoints_from[t].read(&path) {
            Ok((code, rows)) => {
                loader.file_crs(&field, &path, code);
                rows
            }
            Err(problems) => {
                for p in problems.iter().take(10) {
                    loader.report(&field, p.to_string());
                }
                if problems.len() > 10 {
                    loader.report(
                        &field,
                        format!("... and {} more problems in {}", problems.len() - 10, path.display()),
                    );
                }
                continue;
            }
        };
        let mut labels = Vec::new();
        for mut row in rows {
            if row.z.is_none() {
                let ground = scene.terrain.height(row.point.position[0], row.point.position[1]);
                if !ground.is_finite() {
                    loader.report(
                        &field,
                        format!("{}: z is empty and the terrain has no elevation there", row.label),
                    );
                    continue;
                }
                row.point.position[2] = ground;
            }
            for phase in &row.phases {
                join_phase(scene, &field, &row, phase, loader);
            }
            labels.push(row.label);
            scene.keypoints.push(row.point);
        }
        scene.keypoints_from[t].content = hash_file(&path);
        scene.keypoints_from[t].rows = labels;
    }
}

/// Adds a spring read from a table to the springs of `phase`.
fn join_phase(scene: &mut Scene, field: &str, row: &Row, phase: &str, loader: &mut Loader) {
    if row.point.kind != KeyPointKind::Spring {
        return loader.report(
            field,
            format!(
                "{}: phase: only springs have phases (\"{}\" is not a spring)",
                row.label, row.point.name
            ),
        );
    }
    match scene.phases.iter_mut().find(|p| p.name == phase) {
        Some(p) if p.springs.contains(&row.point.name) => {}
        Some(p) => p.springs.push(row.point.name.clone()),
        None => {
            loader.report(field, format!("{}: phase: \"{phase}\" is not a phase of [[phases]]", row.label))
        }
    }
}
