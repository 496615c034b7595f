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
//! `keypoints` section. Problems ([`PointTableError`]) name the scene's `keypoints_from[i].file`,
//! the file, its line (CSV) or feature (GeoJSON), the column and the value. The files' syntax is
//! `karst-geodata`'s ([`karst_geodata::csv`], [`karst_geodata::geojson`]); this module gives
//! their rows and properties the meaning of key points.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::{KeyPoint, KeyPointKind, Scene};
use karst_geodata::crs::Epsg;
use karst_geodata::csv::{CsvError, Table};
use karst_geodata::geojson::{FeatureError, GeoJsonError, PointCollection, PointFeature, Property};

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

/// Why a table, or one of its rows, cannot be read: each names the file and, for a row, its line
/// (CSV) or feature (GeoJSON), the column and the value.
#[derive(Debug, thiserror::Error)]
pub enum PointTableError {
    /// `columns` renames a field karstgen does not read.
    #[error("columns: \"{name}\" is not one of {}", FIELDS.join(", "))]
    UnknownField { name: String },
    /// The file cannot be opened or is not text.
    #[error("cannot read {file}: {source}")]
    Unreadable { file: String, source: std::io::Error },
    /// Not a delimited table (the CSV error starts with its line).
    #[error("{file}:{source}")]
    Csv { file: String, source: CsvError },
    /// Not a GeoJSON point collection.
    #[error("{file}{}{source}", after_file(.source))]
    GeoJson { file: String, source: GeoJsonError },
    /// Both synonyms of the weight.
    #[error("{file}: has both a weight and a recharge column; keep one")]
    WeightAndRecharge { file: String },
    /// A required column, or a renamed one, that the header lacks.
    #[error("{file}: has no column \"{column}\" (its columns: {})", columns.join(", "))]
    MissingColumn { file: String, column: String, columns: Vec<String> },
    /// One bad row; `row` is `file:line` or `file: feature n`.
    #[error("{row}: {problem}")]
    Row { row: String, problem: RowError },
}

/// What is wrong with one row's cells, naming the column (as the file names it) and the value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RowError {
    /// The name is empty.
    #[error("column {column}: the name is empty")]
    NoName { column: String },
    /// A kind karstgen does not know.
    #[error("column {column}: \"{value}\" is not sink, spring, waypoint or dead_end")]
    Kind { column: String, value: String },
    /// No kind in the row nor in the table.
    #[error("column {column}: no kind (give the table a `kind`, or the file a kind column)")]
    NoKind { column: String },
    /// A required number that is empty.
    #[error("column {column}: the value is empty")]
    Empty { column: String },
    /// Text where a finite number belongs.
    #[error("column {column}: \"{value}\" is not a number")]
    NotNumber { column: String, value: String },
    /// An order that is not an integer.
    #[error("column {column}: {value} is not an integer")]
    NotInteger { column: String, value: f64 },
    /// A GeoJSON feature that is not a point.
    #[error(transparent)]
    Feature(#[from] FeatureError),
}

/// The CRS a file declares and its rows; or the problems that stop it being read.
pub(crate) type Read = Result<(Option<Epsg>, Vec<Row>), Vec<PointTableError>>;

impl PointTable {
    /// The file's name for karstgen's `field` (the renamed column, or the field's own name).
    fn column_of<'a>(&'a self, field: &'a str) -> &'a str {
        self.columns.get(field).map_or(field, String::as_str)
    }

    /// Reads the rows of the file, or every problem found in it.
    pub(crate) fn read(&self, path: &Path) -> Read {
        let file = path.display().to_string();
        if let Some(bad) = self.columns.keys().find(|k| !FIELDS.contains(&k.as_str())) {
            return Err(vec![PointTableError::UnknownField { name: bad.clone() }]);
        }
        let text = std::fs::read_to_string(path)
            .map_err(|source| vec![PointTableError::Unreadable { file: file.clone(), source }])?;
        let lower = file.to_ascii_lowercase();
        if lower.ends_with(".geojson") || lower.ends_with(".json") {
            self.read_geojson(&file, &text)
        } else {
            self.read_csv(&file, &text).map(|rows| (None, rows))
        }
    }

    fn read_csv(&self, file: &str, text: &str) -> Result<Vec<Row>, Vec<PointTableError>> {
        let table =
            Table::parse(text).map_err(|source| vec![PointTableError::Csv { file: file.into(), source }])?;
        if table.column(self.column_of("weight")).is_some()
            && table.column(self.column_of("recharge")).is_some()
        {
            return Err(vec![PointTableError::WeightAndRecharge { file: file.into() }]);
        }
        let mut columns = BTreeMap::new();
        for field in FIELDS {
            match table.column(self.column_of(field)) {
                Some(c) => {
                    columns.insert(field, c);
                }
                None if ["name", "x", "y"].contains(&field) || self.columns.contains_key(field) => {
                    return Err(vec![PointTableError::MissingColumn {
                        file: file.into(),
                        column: self.column_of(field).into(),
                        columns: table.header.clone(),
                    }]);
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
                Err(problem) => problems.push(PointTableError::Row { row: label, problem }),
            }
        }
        if problems.is_empty() { Ok(rows) } else { Err(problems) }
    }

    fn read_geojson(&self, file: &str, text: &str) -> Read {
        let collection = PointCollection::parse(text)
            .map_err(|source| vec![PointTableError::GeoJson { file: file.into(), source }])?;
        let mut rows = Vec::new();
        let mut problems = Vec::new();
        for (n, feature) in collection.features.iter().enumerate() {
            let label = format!("{file}: feature {n}");
            match feature.clone().map_err(RowError::from).and_then(|f| self.feature(&label, &f)) {
                Ok(row) => rows.push(row),
                Err(problem) => problems.push(PointTableError::Row { row: label, problem }),
            }
        }
        if problems.is_empty() { Ok((collection.crs, rows)) } else { Err(problems) }
    }

    /// A row from a Point feature: its coordinates, and its properties as the cells.
    fn feature(&self, label: &str, feature: &PointFeature) -> Result<Row, RowError> {
        let cell = |field: &str| {
            feature.property(self.column_of(field)).map(|p| match p {
                Property::Text(t) => Cell::Text(t),
                Property::Number(n) => Cell::Number(n),
                Property::List(items) => Cell::Text(items.join("|")),
            })
        };
        self.row(label, &cell, feature.xy, feature.z)
    }

    /// A row from its cells; `z` from the geometry overrides a `z` cell.
    fn row(
        &self,
        label: &str,
        cell: &dyn Fn(&str) -> Option<Cell>,
        xy: [f64; 2],
        z: Option<f64>,
    ) -> Result<Row, RowError> {
        let column = |field: &str| self.column_of(field).to_string();
        let name = match cell("name") {
            Some(Cell::Text(t)) => t.trim().to_string(),
            Some(Cell::Number(n)) => n.to_string(),
            None => return Err(RowError::NoName { column: column("name") }),
        };
        let kind = match cell("kind") {
            Some(c) => parse_kind(&text(&c))
                .ok_or_else(|| RowError::Kind { column: column("kind"), value: text(&c) })?,
            None => self.kind.ok_or_else(|| RowError::NoKind { column: column("kind") })?,
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
                return Err(RowError::NotInteger { column: column("order"), value: o });
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

/// A syntax error goes `file:line: …`, the others `file: …`.
fn after_file(error: &GeoJsonError) -> &'static str {
    if matches!(error, GeoJsonError::Syntax { .. }) { ":" } else { ": " }
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
) -> Result<Option<f64>, RowError> {
    match cell(field) {
        None => Ok(None),
        Some(Cell::Number(n)) => Ok(Some(n)),
        Some(Cell::Text(t)) => {
            t.trim().parse::<f64>().ok().filter(|v| v.is_finite()).map(Some).ok_or_else(|| {
                RowError::NotNumber { column: table.column_of(field).into(), value: t.clone() }
            })
        }
    }
}

fn required(table: &PointTable, cell: &dyn Fn(&str) -> Option<Cell>, field: &str) -> Result<f64, RowError> {
    optional(table, cell, field)?.ok_or_else(|| RowError::Empty { column: table.column_of(field).into() })
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
