//! Readers of the network formats karstnet and karstgen exchange, each returning a [`Network`].
//!
//! * [`read_karstnet`]: karstnet's `{base}_nodes.dat` (one node per line, `x y z`; extra columns
//!   are properties and ignored; if the first line has only `x y` the whole network is 2D with
//!   z = 0) and `{base}_links.dat` (two **1-based** node indices per line). Blank lines and lines
//!   starting with `#` are skipped, as `numpy.loadtxt` does. The base may also be given as
//!   either file's name (`Huttes_nodes.dat`, `Huttes_links.dat`): see [`karstnet_base`].
//! * [`read_pline`]: GOCAD PLine (`.pl`): `VRTX id x y z` (or `PVRTX`, extra values ignored) adds
//!   a node, `ATOM id ref` makes `id` another name of `ref`'s node, `SEG a b` links two ids; ids are
//!   global to the file and must be defined before use; `ILINE` and other keywords are ignored.
//! * [`read_csv`]: a nodes table whose header names the columns `id,x,y` and optionally `z`
//!   (any order, other columns ignored, ids arbitrary integers; without `z` the network is 2D
//!   with z = 0) and an edges table whose header names `from,to`, `from_id,to_id` or
//!   `source,target`. Each file is delimited by `;` when its header line holds one, by `,`
//!   otherwise (the public KNdata survey tables use `id;x;y;z` and `from_id;to_id`); fields may
//!   be quoted with `"`.
//!
//! # Bad input policy
//! Errors name the file, the 1-based line number and the offending value.
//! * self-loops (a link from a node to itself, also through an ATOM) are errors: karstnet would
//!   silently corrupt its branches;
//! * duplicate links, also reversed, are accepted and collapse into one edge, as in karstnet;
//! * links to missing nodes (index out of range, undefined id) are errors;
//! * unparsable numbers and NaN / infinite coordinates are errors;
//! * a file with no link is an error (karstnet's graph would be empty);
//! * nodes in no link are kept in [`Network::nodes`] and ignored by the metrics, as in karstnet.

use std::collections::HashMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::network::Network;

/// Why a network file cannot be read.
#[derive(Debug, Error)]
pub enum ReadError {
    /// The file cannot be opened or is not UTF-8 text.
    #[error("{}: {source}", .path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A line holds a bad value.
    #[error("{}:{line}: {problem}: `{value}`", .path.display())]
    Line {
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The offending token (or the whole line).
        value: String,
        problem: String,
    },
    /// The file defines no link.
    #[error("{}: no link, the network is empty", .path.display())]
    NoLinks { path: PathBuf },
}

/// Reads karstnet's `{base}_nodes.dat` and `{base}_links.dat`; `base` may also name either
/// file.
pub fn read_karstnet(base: &Path) -> Result<Network, ReadError> {
    let base = karstnet_base(base);
    let base = base.as_path();
    let nodes_file = TextFile::open(&with_suffix(base, "_nodes.dat"))?;
    let links_file = TextFile::open(&with_suffix(base, "_links.dat"))?;
    let nodes = dat_nodes(&nodes_file)?;
    let mut links = Links::new(&links_file);
    for (line, text) in links_file.data_lines() {
        let [a, b] = links_file.fields::<2>(line, text)?;
        let [a, b] = [a, b].map(|t| links_file.one_based(line, t, nodes.len()));
        links.push(line, text, a?, b?)?;
    }
    Ok(Network { nodes, links: links.finish()? })
}

/// Reads a GOCAD PLine file.
pub fn read_pline(path: &Path) -> Result<Network, ReadError> {
    let file = TextFile::open(path)?;
    let mut nodes = Vec::new();
    let mut ids = Ids::default();
    let mut links = Links::new(&file);
    for (line, text) in file.data_lines() {
        match text.split_whitespace().next().unwrap_or_default() {
            "VRTX" | "PVRTX" => {
                let [_, id, x, y, z] = file.fields::<5>(line, text)?;
                ids.define(&file, line, id, nodes.len())?;
                nodes.push(file.point(line, [x, y, z])?);
            }
            "ATOM" | "PATOM" => {
                let [_, id, target] = file.fields::<3>(line, text)?;
                let node = ids.resolve(&file, line, target)?;
                ids.define(&file, line, id, node)?;
            }
            "SEG" => {
                let [_, a, b] = file.fields::<3>(line, text)?;
                let (a, b) = (ids.resolve(&file, line, a)?, ids.resolve(&file, line, b)?);
                links.push(line, text, a, b)?;
            }
            _ => {}
        }
    }
    Ok(Network { nodes, links: links.finish()? })
}

/// Reads a nodes CSV (`id,x,y[,z]` columns) and an edges CSV (`from,to`, `from_id,to_id` or
/// `source,target` columns), each delimited by `;` or `,`.
pub fn read_csv(nodes_path: &Path, edges_path: &Path) -> Result<Network, ReadError> {
    let nodes_file = TextFile::open(nodes_path)?;
    let edges_file = TextFile::open(edges_path)?;
    let mut nodes = Vec::new();
    let mut ids = Ids::default();
    let mut rows = nodes_file.data_lines();
    let table = CsvTable::header(&nodes_file, rows.next())?;
    let [id, x, y] = table.columns(&nodes_file, [&["id"], &["x"], &["y"]])?;
    let z = table.column(&["z"]);
    for (line, text) in rows {
        let [id_text] = table.fields(&nodes_file, line, text, [id])?;
        ids.define(&nodes_file, line, id_text, nodes.len())?;
        nodes.push(table.point(&nodes_file, line, text, [x, y], z)?);
    }
    let mut links = Links::new(&edges_file);
    let mut rows = edges_file.data_lines();
    let table = CsvTable::header(&edges_file, rows.next())?;
    let ends = table.edge_columns(&edges_file)?;
    for (line, text) in rows {
        let [a, b] = table.fields(&edges_file, line, text, ends)?;
        let (a, b) = (ids.resolve(&edges_file, line, a)?, ids.resolve(&edges_file, line, b)?);
        links.push(line, text, a, b)?;
    }
    Ok(Network { nodes, links: links.finish()? })
}

/// The base name of a karstnet network given as its base (`caves/Huttes`) or as either of its
/// files (`caves/Huttes_nodes.dat`, `caves/Huttes_links.dat`).
pub fn karstnet_base(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    match ["_nodes.dat", "_links.dat"].iter().find_map(|suffix| name.strip_suffix(suffix)) {
        Some(base) if !base.is_empty() => path.with_file_name(base),
        _ => path.to_path_buf(),
    }
}

/// `{base}{suffix}`, e.g. `caves/Sakany` + `_nodes.dat`.
fn with_suffix(base: &Path, suffix: &str) -> PathBuf {
    let mut name = OsString::from(base.as_os_str());
    name.push(suffix);
    PathBuf::from(name)
}

/// Nodes of a `_nodes.dat` file: 2 columns make a 2D network (z = 0), 3 or more a 3D one.
fn dat_nodes(file: &TextFile) -> Result<Vec<[f64; 3]>, ReadError> {
    let mut width = None;
    let mut nodes = Vec::new();
    for (line, text) in file.data_lines() {
        let tokens: Vec<&str> = text.split_whitespace().collect();
        let expected = *width.get_or_insert(tokens.len());
        if tokens.len() != expected || expected < 2 {
            let problem = format!("expected {} coordinates", expected.max(2));
            return Err(file.error(line, text, problem));
        }
        let z = if expected == 2 { "0" } else { tokens[2] };
        nodes.push(file.point(line, [tokens[0], tokens[1], z])?);
    }
    Ok(nodes)
}

/// The header of a CSV table: its delimiter and column names.
struct CsvTable {
    delimiter: char,
    names: Vec<String>,
    /// 1-based line of the header, and its text, for errors.
    line: usize,
    text: String,
}

/// Accepted names of the two ends of an edge, as pairs of columns.
const EDGE_ENDS: [[&str; 2]; 3] = [["from", "to"], ["from_id", "to_id"], ["source", "target"]];

impl CsvTable {
    fn header(file: &TextFile, header: Option<(usize, &str)>) -> Result<Self, ReadError> {
        let (line, text) = header.ok_or_else(|| file.error(1, "", "missing CSV header"))?;
        let delimiter = if text.contains(';') { ';' } else { ',' };
        let names = text.split(delimiter).map(|f| csv_unquote(f).to_ascii_lowercase()).collect();
        Ok(CsvTable { delimiter, names, line, text: text.to_string() })
    }

    /// Position of the first column named one of `names`.
    fn column(&self, names: &[&str]) -> Option<usize> {
        self.names.iter().position(|n| names.contains(&n.as_str()))
    }

    /// Positions of required columns, each named one of its alternatives.
    fn columns<const N: usize>(
        &self,
        file: &TextFile,
        wanted: [&[&str]; N],
    ) -> Result<[usize; N], ReadError> {
        let mut columns = [0; N];
        for (column, names) in columns.iter_mut().zip(wanted) {
            *column = self.column(names).ok_or_else(|| {
                let problem =
                    format!("header has no `{}` column (its columns: {})", names[0], self.names.join(", "));
                file.error(self.line, &self.text, problem)
            })?;
        }
        Ok(columns)
    }

    /// The `from`/`to` columns of an edges table, under any of the accepted names.
    fn edge_columns(&self, file: &TextFile) -> Result<[usize; 2], ReadError> {
        EDGE_ENDS.iter().find_map(|[a, b]| Some([self.column(&[a])?, self.column(&[b])?])).ok_or_else(|| {
            let accepted: Vec<String> = EDGE_ENDS.iter().map(|[a, b]| format!("`{a}`/`{b}`")).collect();
            let problem = format!(
                "header has none of the edge column pairs {} (its columns: {})",
                accepted.join(", "),
                self.names.join(", ")
            );
            file.error(self.line, &self.text, problem)
        })
    }

    /// The point of a row from its `x`, `y` and optional `z` columns (z = 0 without one).
    fn point(
        &self,
        file: &TextFile,
        line: usize,
        text: &str,
        [x, y]: [usize; 2],
        z: Option<usize>,
    ) -> Result<[f64; 3], ReadError> {
        let mut p = [0.0; 3];
        for (axis, column) in [Some(x), Some(y), z].into_iter().enumerate() {
            let Some(column) = column else { continue };
            let [token] = self.fields(file, line, text, [column])?;
            p[axis] = token.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                let problem =
                    format!("not a finite coordinate in column {} (`{}`)", column + 1, self.names[column]);
                file.error(line, token, problem)
            })?;
        }
        Ok(p)
    }

    /// The fields at `columns` of a row.
    fn fields<'a, const N: usize>(
        &self,
        file: &TextFile,
        line: usize,
        text: &'a str,
        columns: [usize; N],
    ) -> Result<[&'a str; N], ReadError> {
        let fields: Vec<&str> = text.split(self.delimiter).map(csv_unquote).collect();
        let mut picked = [""; N];
        for (slot, c) in picked.iter_mut().zip(columns) {
            *slot = fields.get(c).copied().ok_or_else(|| {
                let problem = format!(
                    "missing column {} (`{}`): the row has {} fields",
                    c + 1,
                    self.names[c],
                    fields.len()
                );
                file.error(line, text, problem)
            })?;
        }
        Ok(picked)
    }
}

fn csv_unquote(field: &str) -> &str {
    let field = field.trim();
    field.strip_prefix('"').and_then(|f| f.strip_suffix('"')).unwrap_or(field)
}

/// A text file kept in memory with its path, for line-numbered errors.
struct TextFile {
    path: PathBuf,
    text: String,
}

impl TextFile {
    fn open(path: &Path) -> Result<Self, ReadError> {
        let text = karst_artifact::files::read_regular_text(path, karst_artifact::files::MAX_DATA_BYTES)
            .map_err(|source| ReadError::Io { path: path.to_path_buf(), source })?;
        Ok(Self { path: path.to_path_buf(), text })
    }

    /// `(1-based line number, trimmed line)` of the non-blank, non-`#` lines.
    fn data_lines(&self) -> impl Iterator<Item = (usize, &str)> {
        self.text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
    }

    fn error(&self, line: usize, value: &str, problem: impl Into<String>) -> ReadError {
        ReadError::Line { path: self.path.clone(), line, value: value.to_string(), problem: problem.into() }
    }

    /// The first `N` whitespace-separated tokens of a line (more are allowed).
    fn fields<'a, const N: usize>(&self, line: usize, text: &'a str) -> Result<[&'a str; N], ReadError> {
        let mut tokens = text.split_whitespace();
        let mut fields = [""; N];
        for slot in &mut fields {
            *slot = tokens.next().ok_or_else(|| self.error(line, text, format!("expected {N} values")))?;
        }
        Ok(fields)
    }

    /// A point from three coordinate tokens, which must be finite numbers.
    fn point(&self, line: usize, tokens: [&str; 3]) -> Result<[f64; 3], ReadError> {
        let mut p = [0.0; 3];
        for (c, t) in p.iter_mut().zip(tokens) {
            *c = t
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| self.error(line, t, "not a finite coordinate"))?;
        }
        Ok(p)
    }

    /// A 1-based node index in `1..=n_nodes`, as a 0-based index.
    fn one_based(&self, line: usize, token: &str, n_nodes: usize) -> Result<usize, ReadError> {
        match token.parse::<usize>() {
            Ok(i) if (1..=n_nodes).contains(&i) => Ok(i - 1),
            Ok(_) => Err(self.error(line, token, format!("node index out of range 1..={n_nodes}"))),
            Err(_) => Err(self.error(line, token, "not a node index")),
        }
    }
}

/// Integer ids of a file mapped to node indices.
#[derive(Default)]
struct Ids(HashMap<i64, usize>);

impl Ids {
    fn define(&mut self, file: &TextFile, line: usize, id: &str, node: usize) -> Result<(), ReadError> {
        let key = Self::parse(file, line, id)?;
        match self.0.insert(key, node) {
            None => Ok(()),
            Some(_) => Err(file.error(line, id, "id defined twice")),
        }
    }

    fn resolve(&self, file: &TextFile, line: usize, id: &str) -> Result<usize, ReadError> {
        let key = Self::parse(file, line, id)?;
        self.0.get(&key).copied().ok_or_else(|| file.error(line, id, "undefined node id"))
    }

    fn parse(file: &TextFile, line: usize, id: &str) -> Result<i64, ReadError> {
        id.parse().map_err(|_| file.error(line, id, "not an integer id"))
    }
}

/// Links of one file, refusing self-loops.
struct Links<'f> {
    file: &'f TextFile,
    links: Vec<[usize; 2]>,
}

impl<'f> Links<'f> {
    fn new(file: &'f TextFile) -> Self {
        Self { file, links: Vec::new() }
    }

    fn push(&mut self, line: usize, text: &str, a: usize, b: usize) -> Result<(), ReadError> {
        if a == b {
            return Err(self.file.error(line, text, "self-loop (a link from a node to itself)"));
        }
        self.links.push([a, b]);
        Ok(())
    }

    fn finish(self) -> Result<Vec<[usize; 2]>, ReadError> {
        if self.links.is_empty() {
            return Err(ReadError::NoLinks { path: self.file.path.clone() });
        }
        Ok(self.links)
    }
}
