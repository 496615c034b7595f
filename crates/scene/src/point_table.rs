//! Key points from field tables (`[[keypoints_from]]`): sinks, springs, waypoints and dead ends
//! read from a CSV file or a GeoJSON FeatureCollection of Points, as a field campaign or a GIS
//! leaves them.
//!
//! Each row (feature) is one key point with the fields of `[[keypoints]]`: `name`, `x`, `y`,
//! optional `z` (absent or empty: the terrain's elevation at (x, y), the point is on the
//! ground), `kind` (or the table's default `kind`), `weight` (or its synonym `recharge`),
//! `order`, `water_table` and `phase` (springs: the `[[phases]]` the spring drains, several
//! separated by `|`; the spring joins those phases' `springs`). Column names are matched
//! without regard to case; `columns` renames them (`columns = { x = "X_L93" }`); other columns
//! are ignored. In GeoJSON, x, y and z are the Point's coordinates and the other fields its
//! properties; the optional `crs` member (`urn:ogc:def:crs:EPSG::2154`) is checked against
//! the scene's.
//!
//! The points follow the scene's own `[[keypoints]]`, table after table, row after row, so
//! they are key points like any other: validated the same way (inside the domain, under the
//! terrain, unique names), named in `[connectivity]` and `[[phases]]`, hashed with the
//! `keypoints` section. Problems name the scene's `keypoints_from[i].file`, the file, its line
//! (CSV) or feature (GeoJSON), the column and the value.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::{KeyPoint, KeyPointKind, Scene};
use karst_geodata::crs::Epsg;
use karst_geodata::csv::Table;

/// One `[[keypoints_from]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointTable {
    /// `.csv` (or any delimited text) or `.geojson` / `.json`, relative to the scene's folder.
    pub file: String,
    /// Kind of the rows that have no `kind` of their own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<KeyPointKind>,
    /// karstgen field → the file's column (property) name, for files that name them otherwise.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub columns: BTreeMap<String, String>,
    /// BLAKE3 of the file, filled when loaded.
    #[serde(default, skip_deserializing)]
    pub content: String,
    /// Where each of its key points was read (`points.csv:7`), in order; filled when loaded.
    #[serde(skip)]
    pub rows: Vec<String>,
}

/// The fields a table may give, by karstgen's name.
const FIELDS: [&str; 10] =
    ["name", "x", "y", "z", "kind", "weight", "recharge", "order", "water_table", "phase"];

/// A field's value in a table.
#[derive(Debug, Clone)]
enum Cell {
    Text(String),
    Number(f64),
}

/// One point read from a table, before it joins the scene.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Row {
    /// `file:line` or `file: feature n`.
    pub(crate) label: String,
    pub(crate) point: KeyPoint,
    /// None: take the terrain's elevation.
    pub(crate) z: Option<f64>,
    pub(crate) phases: Vec<String>,
}

/// The CRS a file declares and its rows; or the problems that stop it being read.
pub(crate) type Read = Result<(Option<Epsg>, Vec<Row>), Vec<String>>;

impl PointTable {
    /// The file's name for karstgen's `field` (the renamed column, or the field's own name).
    fn column_of<'a>(&'a self, field: &'a str) -> &'a str {
        self.columns.get(field).map_or(field, String::as_str)
    }

    /// Reads the rows of the file; problems are `file:line: message` texts.
    pub(crate) fn read(&self, path: &Path) -> Read {
        let file = path.display().to_string();
        if let Some(bad) = self.columns.keys().find(|k| !FIELDS.contains(&k.as_str())) {
            return Err(vec![format!("columns: \"{bad}\" is not one of {}", FIELDS.join(", "))]);
        }
        let text = std::fs::read_to_string(path).map_err(|e| vec![format!("cannot read {file}: {e}")])?;
        let lower = file.to_ascii_lowercase();
        if lower.ends_with(".geojson") || lower.ends_with(".json") {
            self.read_geojson(&file, &text)
        } else {
            self.read_csv(&file, &text).map(|rows| (None, rows))
        }
    }

    fn read_csv(&self, file: &str, text: &str) -> Result<Vec<Row>, Vec<String>> {
        let table = Table::parse(text).map_err(|e| vec![format!("{file}:{e}")])?;
        if table.column(self.column_of("weight")).is_some()
            && table.column(self.column_of("recharge")).is_some()
        {
            return Err(vec![format!("{file}: has both a weight and a recharge column; keep one")]);
        }
        let mut columns = BTreeMap::new();
        for field in FIELDS {
            match table.column(self.column_of(field)) {
                Some(c) => {
                    columns.insert(field, c);
                }
                None if ["name", "x", "y"].contains(&field) || self.columns.contains_key(field) => {
                    return Err(vec![format!(
                        "{file}: has no column \"{}\" (its columns: {})",
                        self.column_of(field),
                        table.header.join(", ")
                    )]);
                }
                None => {}
            }
        }
        let mut rows = Vec::new();
        let mut problems = Vec::new();
        for record in &table.records {
            let label = format!("{file}:{}", record.line);
            let cell = |field: &str| {
                let text = columns.get(field).map(|&c| record.fields[c].as_str()).unwrap_or("");
                (!text.is_empty()).then(|| Cell::Text(text.to_string()))
            };
            let position = (|| Ok([required(self, &cell, "x")?, required(self, &cell, "y")?]))();
            match position.and_then(|xy| self.row(&label, &cell, xy, None)) {
                Ok(row) => rows.push(row),
                Err(e) => problems.push(format!("{label}: {e}")),
            }
        }
        if problems.is_empty() { Ok(rows) } else { Err(problems) }
    }

    fn read_geojson(&self, file: &str, text: &str) -> Read {
        let json: serde_json::Value =
            serde_json::from_str(text).map_err(|e| vec![format!("{file}:{}: {e}", e.line())])?;
        if json["type"] != "FeatureCollection" {
            return Err(vec![format!("{file}: is a {}, not a GeoJSON FeatureCollection", json["type"])]);
        }
        let crs = match &json["crs"]["properties"]["name"] {
            serde_json::Value::Null => None,
            name => {
                let name = name.as_str().unwrap_or_default();
                Some(Epsg::from_name(name).ok_or_else(|| {
                    vec![format!("{file}: crs \"{name}\" is not an EPSG code (urn:ogc:def:crs:EPSG::NNNN)")]
                })?)
            }
        };
        let features =
            json["features"].as_array().ok_or_else(|| vec![format!("{file}: has no \"features\" array")])?;
        let mut rows = Vec::new();
        let mut problems = Vec::new();
        for (n, feature) in features.iter().enumerate() {
            let label = format!("{file}: feature {n}");
            match self.feature(&label, feature) {
                Ok(row) => rows.push(row),
                Err(e) => problems.push(format!("{label}: {e}")),
            }
        }
        if problems.is_empty() { Ok((crs, rows)) } else { Err(problems) }
    }

    fn feature(&self, label: &str, feature: &serde_json::Value) -> Result<Row, String> {
        let geometry = &feature["geometry"];
        if geometry["type"] != "Point" {
            let kind = geometry["type"].as_str().map_or("no geometry".to_string(), |t| format!("a {t}"));
            return Err(format!("is {kind}: karstgen reads Point features only"));
        }
        let coordinates: Vec<f64> = geometry["coordinates"]
            .as_array()
            .map(|c| c.iter().filter_map(serde_json::Value::as_f64).collect())
            .unwrap_or_default();
        if !(2..=3).contains(&coordinates.len())
            || geometry["coordinates"].as_array().map(Vec::len) != Some(coordinates.len())
        {
            return Err(format!(
                "coordinates {} are not [x, y] or [x, y, z] numbers",
                geometry["coordinates"]
            ));
        }
        let properties = &feature["properties"];
        let cell = |field: &str| match properties.get(self.column_of(field)).or_else(|| {
            properties
                .as_object()?
                .iter()
                .find(|(k, _)| k.eq_ignore_ascii_case(self.column_of(field)))
                .map(|(_, v)| v)
        }) {
            Some(serde_json::Value::String(s)) if !s.is_empty() => Some(Cell::Text(s.clone())),
            Some(serde_json::Value::Number(n)) => n.as_f64().map(Cell::Number),
            Some(serde_json::Value::Array(items)) => Some(Cell::Text(
                items
                    .iter()
                    .map(|v| v.as_str().map_or(v.to_string(), str::to_string))
                    .collect::<Vec<_>>()
                    .join("|"),
            )),
            _ => None,
        };
        self.row(label, &cell, [coordinates[0], coordinates[1]], coordinates.get(2).copied())
    }

    /// A row from its cells; `z` from the geometry overrides a `z` cell.
    fn row(
        &self,
        label: &str,
        cell: &dyn Fn(&str) -> Option<Cell>,
        xy: [f64; 2],
        z: Option<f64>,
    ) -> Result<Row, String> {
        let name = match cell("name") {
            Some(Cell::Text(t)) => t.trim().to_string(),
            Some(Cell::Number(n)) => n.to_string(),
            None => return Err(format!("column {}: the name is empty", self.column_of("name"))),
        };
        let kind = match cell("kind") {
            Some(c) => parse_kind(&text(&c)).ok_or_else(|| {
                format!(
                    "column {}: \"{}\" is not sink, spring, waypoint or dead_end",
                    self.column_of("kind"),
                    text(&c)
                )
            })?,
            None => self.kind.ok_or_else(|| {
                format!(
                    "column {}: no kind (give the table a `kind`, or the file a kind column)",
                    self.column_of("kind")
                )
            })?,
        };
        let z = match z {
            Some(z) => Some(z),
            None => optional(self, cell, "z")?,
        };
        let weight = match optional(self, cell, "weight")? {
            Some(w) => Some(w),
            None => optional(self, cell, "recharge")?,
        };
        let order = match optional(self, cell, "order")? {
            Some(o) if o.fract() != 0.0 || o.abs() > 1e15 => {
                return Err(format!("column {}: {o} is not an integer", self.column_of("order")));
            }
            o => o.map_or(0, |o| o as i64),
        };
        let phases: Vec<String> = cell("phase")
            .map(|c| text(&c).split('|').map(|p| p.trim().to_string()).filter(|p| !p.is_empty()).collect())
            .unwrap_or_default();
        let point = KeyPoint {
            name,
            kind,
            position: [xy[0], xy[1], z.unwrap_or(f64::NAN)],
            weight: weight.unwrap_or(1.0),
            order,
            water_table: cell("water_table").map(|c| text(&c).trim().to_string()),
        };
        Ok(Row { label: label.into(), point, z, phases })
    }
}

fn text(cell: &Cell) -> String {
    match cell {
        Cell::Text(t) => t.clone(),
        Cell::Number(n) => n.to_string(),
    }
}

fn parse_kind(text: &str) -> Option<KeyPointKind> {
    match text.trim().to_ascii_lowercase().replace(['-', ' '], "_").as_str() {
        "sink" => Some(KeyPointKind::Sink),
        "spring" => Some(KeyPointKind::Spring),
        "waypoint" => Some(KeyPointKind::Waypoint),
        "dead_end" => Some(KeyPointKind::DeadEnd),
        _ => None,
    }
}

fn optional(
    table: &PointTable,
    cell: &dyn Fn(&str) -> Option<Cell>,
    field: &str,
) -> Result<Option<f64>, String> {
    match cell(field) {
        None => Ok(None),
        Some(Cell::Number(n)) => Ok(Some(n)),
        Some(Cell::Text(t)) => t
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map(Some)
            .ok_or_else(|| format!("column {}: \"{t}\" is not a number", table.column_of(field))),
    }
}

fn required(table: &PointTable, cell: &dyn Fn(&str) -> Option<Cell>, field: &str) -> Result<f64, String> {
    optional(table, cell, field)?
        .ok_or_else(|| format!("column {}: the value is empty", table.column_of(field)))
}

/// Where key point `i` came from: None for the scene's own `[[keypoints]]`, else the index of
/// its table and its row's label (`points.csv:7`).
pub(crate) fn source_of(scene: &Scene, i: usize) -> Option<(usize, &str)> {
    let from_tables: usize = scene.keypoints_from.iter().map(|t| t.rows.len()).sum();
    let mut k = i.checked_sub(scene.keypoints.len() - from_tables)?;
    for (t, table) in scene.keypoints_from.iter().enumerate() {
        if k < table.rows.len() {
            return Some((t, &table.rows[k]));
        }
        k -= table.rows.len();
    }
    None
}
