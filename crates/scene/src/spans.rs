//! Finding where a field is written in the scene text: lines for problems found after
//! parsing, and the field path at the position of a parse error.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// 1-based line of byte `offset`.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].bytes().filter(|b| *b == b'\n').count() + 1
}

/// Line where the field at `path` (`keypoints[2].position`) is written, if it is written.
pub(crate) fn line_of_path(text: &str, path: &str) -> Option<usize> {
    let root = DeTable::parse(text).ok()?;
    let mut span = root.span();
    let mut value: Option<&DeValue> = None;
    let mut table = Some(root.get_ref());
    for segment in parse_path(path) {
        let next: &Spanned<DeValue> = match segment {
            Segment::Key(key) => table?.iter().find(|(k, _)| k.get_ref() == key).map(|(_, v)| v)?,
            Segment::Index(i) => match value? {
                DeValue::Array(items) => items.get(i)?,
                _ => return None,
            },
        };
        span = next.span();
        value = Some(next.get_ref());
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    Some(line_of(text, span.start))
}

/// Path of the innermost field whose key or value contains byte `offset`. Header tables
/// (`[costgraph]`, `[[keypoints]]`) do not span their contents, so every child is searched.
pub(crate) fn path_at(text: &str, offset: usize) -> String {
    let Ok(root) = DeTable::parse(text) else { return String::new() };
    search_table(root.get_ref(), offset).unwrap_or_default()
}

fn search_table(table: &DeTable, offset: usize) -> Option<String> {
    table.iter().find_map(|(key, value)| {
        let name = key.get_ref().to_string();
        match search_value(value, offset) {
            Some(rest) if rest.is_empty() => Some(name),
            Some(rest) if rest.starts_with('[') => Some(format!("{name}{rest}")),
            Some(rest) => Some(format!("{name}.{rest}")),
            None if contains(&key.span(), offset) => Some(name),
            None => None,
        }
    })
}

/// Some(path below this value) when `offset` is inside it ("" for the value itself).
fn search_value(value: &Spanned<DeValue>, offset: usize) -> Option<String> {
    match value.get_ref() {
        DeValue::Table(t) => search_table(t, offset),
        DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
            search_value(item, offset).map(|rest| match rest.as_str() {
                "" => format!("[{i}]"),
                r if r.starts_with('[') => format!("[{i}]{r}"),
                r => format!("[{i}].{r}"),
            })
        }),
        _ => contains(&value.span(), offset).then(String::new),
    }
    .or_else(|| contains(&value.span(), offset).then(String::new))
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.start <= offset && offset < span.end.max(span.start + 1)
}

enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn parse_path(path: &str) -> Vec<Segment<'_>> {
    let mut segments = Vec::new();
    for part in path.split('.') {
        let (key, rest) = part.split_once('[').unwrap_or((part, ""));
        segments.push(Segment::Key(key));
        for index in rest.split('[') {
            if let Ok(i) = index.trim_end_matches(']').parse() {
                segments.push(Segment::Index(i));
            }
        }
    }
    segments
}
