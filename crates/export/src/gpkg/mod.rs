//! `karst.gpkg`: the run as an OGC GeoPackage 1.3 (an SQLite database with the GeoPackage
//! tables), the format QGIS and ArcGIS open natively, in the scene's CRS.
//!
//! Layers ([`layers`]): `segments`, `conduits`, `passages`, `key_points`, `streams`,
//! `routes`. Each layer is a feature table with an integer primary key `fid` numbered from 1
//! (the ids of every other table of the export), a geometry column `geom` of GeoPackage
//! binary geometries ([`geometry`]), a row in `gpkg_contents` with its extent and one in
//! `gpkg_geometry_columns`, an R-tree spatial index (the `gpkg_rtree_index` extension, filled
//! once and kept up to date by the extension's standard triggers when a GIS edits the layer)
//! and a default QGIS style in `layer_styles` ([`style`]).
//!
//! The CRS: the scene's `crs = "EPSG:NNNN"` is registered in `gpkg_spatial_ref_sys` with the
//! WKT of the `crs-definitions` crate (the EPSG definitions as PROJ exports them); a code it
//! lacks is registered as `undefined`, which GDAL and QGIS resolve from the EPSG code
//! themselves. A scene without a CRS writes the GeoPackage only when `gpkg` is among its
//! formats, in the standard's undefined Cartesian SRS (`srs_id` −1).
//!
//! SQLite comes from `rusqlite`'s bundled amalgamation (built with the R-tree module), so no
//! system library is needed. The database is built in a scratch file beside the export folder
//! and then copied into the folder as any other export file; every write is deterministic (no
//! clock: `last_change` is the Unix epoch), so one run gives one byte-identical file.

mod geometry;
pub mod layers;
pub mod style;

use std::path::Path;

use rusqlite::{Connection, params};

use karst_geodata::crs::Epsg;
use karst_scene::params::ExportFormat;

use crate::ExportError;
use crate::folder::Folder;
pub use geometry::{Geometry, millimetre};
pub use layers::{Layer, Value};

/// The export's file name.
pub const FILE: &str = "karst.gpkg";

/// `gpkg_contents.last_change` of every table: fixed, so that a run gives one file.
const LAST_CHANGE: &str = "1970-01-01T00:00:00.000Z";

/// A spatial reference system as `gpkg_spatial_ref_sys` records it.
#[derive(Debug, Clone, PartialEq)]
pub struct Srs {
    pub id: i32,
    pub name: String,
    pub organization: String,
    pub code: i32,
    pub definition: String,
}

impl Srs {
    /// The SRS of a run's CRS (`EPSG:NNNN`), or the undefined Cartesian SRS without one.
    pub fn of(crs: Option<&str>) -> Result<Srs, ExportError> {
        let Some(text) = crs else {
            return Ok(Srs {
                id: -1,
                name: "Undefined cartesian SRS".into(),
                organization: "NONE".into(),
                code: -1,
                definition: "undefined".into(),
            });
        };
        let epsg = Epsg::parse(text).map_err(|e| ExportError::Unsupported(format!("crs: {e}")))?;
        let code = i32::try_from(epsg.0)
            .map_err(|_| ExportError::Unsupported(format!("crs: EPSG code {} is out of range", epsg.0)))?;
        let wkt = u16::try_from(epsg.0).ok().and_then(crs_definitions::from_code).map(|d| d.wkt);
        let name = wkt.and_then(wkt_name).unwrap_or_else(|| epsg.to_string());
        Ok(Srs {
            id: code,
            name,
            organization: "EPSG".into(),
            code,
            definition: wkt.unwrap_or("undefined").to_string(),
        })
    }
}

/// The name of a WKT definition: the first quoted string.
fn wkt_name(wkt: &str) -> Option<String> {
    let start = wkt.find('"')? + 1;
    let end = start + wkt[start..].find('"')?;
    Some(wkt[start..end].to_string())
}

/// Writes `layers` as `karst.gpkg` into the export folder.
pub fn write(folder: &mut Folder, srs: &Srs, layers: &[Layer]) -> Result<(), ExportError> {
    let scratch = folder.scratch_path(FILE);
    let failed = |e: rusqlite::Error| ExportError::Write {
        path: scratch.clone(),
        source: std::io::Error::other(e.to_string()),
    };
    let _ = std::fs::remove_file(&scratch);
    let built = build(&scratch, srs, layers).map_err(failed);
    let bytes = built.and_then(|()| {
        std::fs::read(&scratch).map_err(|source| ExportError::Write { path: scratch.clone(), source })
    });
    let _ = std::fs::remove_file(&scratch);
    let bytes = bytes?;
    folder.write(FILE, ExportFormat::Gpkg, |w| w.write_all(&bytes))
}

/// Creates the database at `path`: the GeoPackage tables, then every layer, in one transaction.
fn build(path: &Path, srs: &Srs, layers: &[Layer]) -> rusqlite::Result<()> {
    let mut db = Connection::open(path)?;
    db.execute_batch(
        "PRAGMA application_id = 1196444487; PRAGMA user_version = 10300; PRAGMA journal_mode = OFF;",
    )?;
    let tx = db.transaction()?;
    tx.execute_batch(SCHEMA)?;
    tx.execute(
        "INSERT OR REPLACE INTO gpkg_spatial_ref_sys VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
        params![srs.name, srs.id, srs.organization, srs.code, srs.definition, "the scene's crs"],
    )?;
    for layer in layers {
        write_layer(&tx, srs.id, layer)?;
    }
    tx.commit()?;
    db.close().map_err(|(_, e)| e)
}

/// The GeoPackage's own tables (GeoPackage 1.3, clauses 1.1.2, 1.1.3, 2.1.5, 2.3) with the
/// three SRS every GeoPackage holds, and the `layer_styles` table QGIS reads default styles
/// from.
const SCHEMA: &str = r#"
CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER PRIMARY KEY,
  organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL,
  definition TEXT NOT NULL, description TEXT);
INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1, 'undefined',
  'undefined cartesian coordinate reference system');
INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined geographic SRS', 0, 'NONE', 0, 'undefined',
  'undefined geographic coordinate reference system');
INSERT INTO gpkg_spatial_ref_sys VALUES ('WGS 84 geodetic', 4326, 'EPSG', 4326,
  'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AXIS["Latitude",NORTH],AXIS["Longitude",EAST],AUTHORITY["EPSG","4326"]]',
  'longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid');
CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL,
  identifier TEXT UNIQUE, description TEXT DEFAULT '',
  last_change DATETIME NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')),
  min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER,
  CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id));
CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL,
  geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT NOT NULL,
  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),
  CONSTRAINT uk_gc_table_name UNIQUE (table_name),
  CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),
  CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id));
CREATE TABLE gpkg_extensions (table_name TEXT, column_name TEXT, extension_name TEXT NOT NULL,
  definition TEXT NOT NULL, scope TEXT NOT NULL,
  CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name));
CREATE TABLE layer_styles (id INTEGER PRIMARY KEY AUTOINCREMENT, f_table_catalog TEXT(256),
  f_table_schema TEXT(256), f_table_name TEXT(256), f_geometry_column TEXT(256),
  styleName TEXT(30), styleQML TEXT, styleSLD TEXT, useAsDefault BOOLEAN, description TEXT,
  owner TEXT(30), ui TEXT(30), update_time DATETIME);
INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change)
  VALUES ('layer_styles', 'attributes', 'layer_styles', 'default QGIS styles of the layers',
  '1970-01-01T00:00:00.000Z');
"#;

/// One feature table, its registration, R-tree and style.
fn write_layer(tx: &rusqlite::Transaction, srs_id: i32, layer: &Layer) -> rusqlite::Result<()> {
    let name = layer.name;
    let columns: String = layer.columns.iter().map(|(c, ty)| format!(", \"{c}\" {ty}")).collect();
    let geometry = layer.geometry_type;
    tx.execute_batch(&format!(
        "CREATE TABLE \"{name}\" (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, geom {geometry}{columns});"
    ))?;
    let placeholders: String = (0..layer.columns.len()).map(|i| format!(", ?{}", i + 3)).collect();
    let names: String = layer.columns.iter().map(|(c, _)| format!(", \"{c}\"")).collect();
    let mut insert =
        tx.prepare(&format!("INSERT INTO \"{name}\" (fid, geom{names}) VALUES (?1, ?2{placeholders})"))?;
    let mut rtree = Vec::with_capacity(layer.features.len());
    for (i, feature) in layer.features.iter().enumerate() {
        let fid = i as i64 + 1;
        let mut values: Vec<rusqlite::types::Value> = Vec::with_capacity(feature.values.len() + 2);
        values.push(fid.into());
        values.push(feature.geometry.to_gpkg(srs_id).into());
        values.extend(feature.values.iter().map(Value::to_sql));
        insert.execute(rusqlite::params_from_iter(values))?;
        rtree.push((fid, feature.geometry.envelope()));
    }
    drop(insert);
    let extent = rtree.iter().fold(None::<[f64; 4]>, |acc, (_, e)| {
        Some(acc.map_or(*e, |a| [a[0].min(e[0]), a[1].max(e[1]), a[2].min(e[2]), a[3].max(e[3])]))
    });
    let [min_x, max_x, min_y, max_y] = extent.map_or([None; 4], |e| e.map(Some));
    tx.execute(
        "INSERT INTO gpkg_contents VALUES (?1, 'features', ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
        params![name, layer.description, LAST_CHANGE, min_x, min_y, max_x, max_y, srs_id],
    )?;
    tx.execute(
        "INSERT INTO gpkg_geometry_columns VALUES (?1, 'geom', ?2, ?3, ?4, 0)",
        params![name, geometry, srs_id, i32::from(layer.has_z)],
    )?;
    write_rtree(tx, name, &rtree)?;
    tx.execute(
        "INSERT INTO layer_styles (f_table_catalog, f_table_schema, f_table_name, f_geometry_column, styleName, \
         styleQML, styleSLD, useAsDefault, description, owner, ui, update_time) \
         VALUES ('', '', ?1, 'geom', ?1, ?2, '', 1, 'karstgen default style', '', NULL, ?3)",
        params![name, layer.style, LAST_CHANGE],
    )?;
    Ok(())
}

/// The layer's R-tree (GeoPackage 1.3, clause F.3), filled from the features' envelopes, and
/// the extension's triggers that keep it in step with later edits (they call the ST_ functions
/// GDAL registers; this writer fires none of them).
fn write_rtree(tx: &rusqlite::Transaction, table: &str, boxes: &[(i64, [f64; 4])]) -> rusqlite::Result<()> {
    let rtree = format!("rtree_{table}_geom");
    tx.execute_batch(&format!("CREATE VIRTUAL TABLE \"{rtree}\" USING rtree(id, minx, maxx, miny, maxy);"))?;
    let mut insert = tx.prepare(&format!("INSERT INTO \"{rtree}\" VALUES (?1, ?2, ?3, ?4, ?5)"))?;
    for (fid, [min_x, max_x, min_y, max_y]) in boxes {
        insert.execute(params![fid, min_x, max_x, min_y, max_y])?;
    }
    drop(insert);
    let bounds = "NEW.fid, ST_MinX(NEW.geom), ST_MaxX(NEW.geom), ST_MinY(NEW.geom), ST_MaxY(NEW.geom)";
    let present = "NEW.geom NOT NULL AND NOT ST_IsEmpty(NEW.geom)";
    let absent = "NEW.geom ISNULL OR ST_IsEmpty(NEW.geom)";
    let t = format!("\"{table}\"");
    let r = format!("\"{rtree}\"");
    tx.execute_batch(&format!(
        "CREATE TRIGGER \"{rtree}_insert\" AFTER INSERT ON {t} WHEN ({present}) \
           BEGIN INSERT OR REPLACE INTO {r} VALUES ({bounds}); END;
         CREATE TRIGGER \"{rtree}_update1\" AFTER UPDATE OF geom ON {t} WHEN OLD.fid = NEW.fid AND ({present}) \
           BEGIN INSERT OR REPLACE INTO {r} VALUES ({bounds}); END;
         CREATE TRIGGER \"{rtree}_update2\" AFTER UPDATE OF geom ON {t} WHEN OLD.fid = NEW.fid AND ({absent}) \
           BEGIN DELETE FROM {r} WHERE id = OLD.fid; END;
         CREATE TRIGGER \"{rtree}_update3\" AFTER UPDATE ON {t} WHEN OLD.fid != NEW.fid AND ({present}) \
           BEGIN DELETE FROM {r} WHERE id = OLD.fid; INSERT OR REPLACE INTO {r} VALUES ({bounds}); END;
         CREATE TRIGGER \"{rtree}_update4\" AFTER UPDATE ON {t} WHEN OLD.fid != NEW.fid AND ({absent}) \
           BEGIN DELETE FROM {r} WHERE id IN (OLD.fid, NEW.fid); END;
         CREATE TRIGGER \"{rtree}_delete\" AFTER DELETE ON {t} WHEN OLD.geom NOT NULL \
           BEGIN DELETE FROM {r} WHERE id = OLD.fid; END;"
    ))?;
    tx.execute(
        "INSERT INTO gpkg_extensions VALUES (?1, 'geom', 'gpkg_rtree_index', \
         'http://www.geopackage.org/spec120/#extension_rtree', 'write-only')",
        params![table],
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_epsg_crs_is_registered_with_its_wkt() {
        let srs = Srs::of(Some("EPSG:2154")).unwrap();
        assert_eq!((srs.id, srs.code, srs.organization.as_str()), (2154, 2154, "EPSG"));
        assert_eq!(srs.name, "RGF93 / Lambert-93");
        assert!(srs.definition.starts_with("PROJCS[\"RGF93 / Lambert-93\""), "{}", srs.definition);
        assert_eq!(Srs::of(None).unwrap().id, -1);
        assert!(Srs::of(Some("2154")).is_err());
    }
}
