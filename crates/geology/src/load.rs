//! Reading the data files a scene names (heightfield image, TIN surfaces, potential grid),
//! relative to the scene file's folder. Each file's BLAKE3 goes into the scene's serialized
//! form, so that editing a data file changes the hash of the sections that use it.

use std::path::Path;
use std::sync::Arc;

use crate::field::ValueGrid;
use crate::heightfield::{Georeference, HeightGrid};
use crate::spans::line_of_path;
use crate::surface::Geometry;
use crate::tin::Tin;
use crate::validate::Problem;
use crate::{Scene, Terrain};

/// Reads every data file of `scene`; returns the problems (unreadable or invalid files).
pub(crate) fn attach_files(scene: &mut Scene, folder: &Path, text: &str) -> Vec<Problem> {
    let mut problems = Vec::new();
    let mut report = |field: &str, message: String| {
        problems.push(Problem { line: line_of_path(text, field), field: field.into(), message })
    };
    if let Terrain::Heightfield { file, origin, cell_size, vertical_scale, offset, nodata, content, grid } =
        &mut scene.terrain
    {
        let geo = Georeference {
            origin: *origin,
            cell_size: *cell_size,
            vertical_scale: *vertical_scale,
            offset: *offset,
            nodata: *nodata,
        };
        let usable = *cell_size > 0.0 && origin.iter().all(|v| v.is_finite()) && vertical_scale.is_finite();
        let path = folder.join(&*file);
        if usable {
            match HeightGrid::read(&path, &geo) {
                Ok(g) => {
                    *content = hash_file(&path);
                    *grid = Arc::new(g);
                }
                Err(e) => report("terrain.file", e.to_string()),
            }
        }
    }
    let geology = &mut scene.geology;
    for (list, surfaces) in [
        ("water_tables", &mut geology.water_tables),
        ("horizons", &mut geology.horizons),
        ("faults", &mut geology.faults),
    ] {
        for (i, s) in surfaces.iter_mut().enumerate() {
            if let Geometry::Tin { file, content, mesh } = &mut s.geometry {
                let path = folder.join(&*file);
                match Tin::read(&path) {
                    Ok(tin) => {
                        *content = hash_file(&path);
                        *mesh = Arc::new(tin);
                    }
                    Err(e) => report(&format!("geology.{list}[{i}].file"), e.to_string()),
                }
            }
        }
    }
    if let Some(grid) = &mut geology.grid {
        let path = folder.join(&grid.file);
        match ValueGrid::read(&path) {
            Ok(values) => {
                grid.content = hash_file(&path);
                grid.values = Arc::new(values);
            }
            Err(e) => report("geology.grid.file", e),
        }
    }
    problems
}

fn hash_file(path: &Path) -> String {
    std::fs::read(path).map(|bytes| blake3::hash(&bytes).to_hex().to_string()).unwrap_or_default()
}
