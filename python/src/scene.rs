//! A scene from Python: a TOML file, or a dict with the file's structure, plus overrides of
//! single fields (`("sampling.radius", 4.0)`), checked as `karstgen run` checks a file.
//!
//! The result is the scene's text and the path that names it in messages and anchors its data
//! files (a dict's path is `<folder>/<scene dict>`, its data files relative to `folder`). A
//! file without overrides keeps its own text, so that messages cite its lines; otherwise the
//! text is the TOML of the changed table, named `<file> (with overrides)`.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;

use karst_scene::Scene;
use karst_stage::StageError;

use crate::errors::{SceneError, to_py};

/// The name a dict scene gets in messages.
pub const DICT_NAME: &str = "<scene dict>";

/// `(path, text, name, seed)` of the scene given by `path` or `table_json` (a JSON object),
/// with `overrides_json` (a JSON list of `[dotted field, value]`) applied.
#[pyfunction]
#[pyo3(signature = (path, table_json, overrides_json, folder))]
pub fn scene_source(
    py: Python<'_>,
    path: Option<PathBuf>,
    table_json: Option<String>,
    overrides_json: String,
    folder: PathBuf,
) -> PyResult<(PathBuf, String, String, u64)> {
    py.detach(|| source(path, table_json, &overrides_json, &folder))
}

fn source(
    path: Option<PathBuf>,
    table_json: Option<String>,
    overrides_json: &str,
    folder: &Path,
) -> PyResult<(PathBuf, String, String, u64)> {
    let overrides: Vec<(String, serde_json::Value)> =
        serde_json::from_str(overrides_json).map_err(|e| SceneError::new_err(format!("overrides: {e}")))?;
    let (path, text) = match (path, table_json) {
        (Some(path), _) => {
            let text = std::fs::read_to_string(&path).map_err(|e| {
                SceneError::new_err(format!("{}: cannot read the scene: {e}", path.display()))
            })?;
            if overrides.is_empty() {
                (path, text)
            } else {
                let table = text.parse::<toml::Table>().map_err(|_| invalid(&text, &path))?;
                let text = with_overrides(table, &overrides).map_err(|e| scene_error(&path, e))?;
                // Lines of messages are those of the changed text, not of the file.
                let mut changed = path.into_os_string();
                changed.push(" (with overrides)");
                (PathBuf::from(changed), text)
            }
        }
        (None, Some(json)) => {
            let path = folder.join(DICT_NAME);
            let value: serde_json::Value = serde_json::from_str(&json).map_err(|e| scene_error(&path, e))?;
            let table = toml::Table::try_from(value)
                .map_err(|e| scene_error(&path, format!("not a TOML table: {e} (None has no TOML value)")))?;
            (path.clone(), with_overrides(table, &overrides).map_err(|e| scene_error(&path, e))?)
        }
        (None, None) => return Err(SceneError::new_err("no scene: give a path or a dict")),
    };
    let scene = Scene::parse(&text, &path).map_err(|e| to_py(StageError::from(e)))?;
    let (name, seed) = (scene.name().to_string(), scene.seed());
    Ok((path, text, name, seed))
}

fn scene_error(path: &Path, e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(format!("{}: {e}", path.display()))
}

/// The scene parser's own message for text that is not TOML (it names the line).
fn invalid(text: &str, path: &Path) -> PyErr {
    match Scene::parse(text, path) {
        Err(e) => to_py(StageError::from(e)),
        Ok(_) => scene_error(path, "not a TOML table"),
    }
}

/// The TOML text of `table` with every override applied.
fn with_overrides(
    mut table: toml::Table,
    overrides: &[(String, serde_json::Value)],
) -> Result<String, String> {
    for (field, value) in overrides {
        let value = toml::Value::try_from(value)
            .map_err(|e| format!("override {field}: {value} has no TOML value ({e})"))?;
        set(&mut table, field, value)?;
    }
    toml::to_string(&table).map_err(|e| format!("cannot write the scene as TOML: {e}"))
}

/// Sets the dotted `field` (`skeleton.gamma`, `keypoints.0.position`) of `table`, creating the
/// tables on the way.
fn set(table: &mut toml::Table, field: &str, value: toml::Value) -> Result<(), String> {
    let parts: Vec<&str> = field.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(format!("override \"{field}\": an empty part in the field name"));
    }
    let mut node = table.entry(parts[0]).or_insert_with(|| toml::Value::Table(toml::Table::new()));
    for part in &parts[1..] {
        node = child(node, part, field)?;
    }
    *node = value;
    Ok(())
}

/// The entry `part` of a table (created when missing) or the element `part` of a list.
fn child<'a>(node: &'a mut toml::Value, part: &str, field: &str) -> Result<&'a mut toml::Value, String> {
    match node {
        toml::Value::Table(t) => Ok(t.entry(part).or_insert_with(|| toml::Value::Table(toml::Table::new()))),
        toml::Value::Array(list) => {
            let len = list.len();
            let i: usize =
                part.parse().map_err(|_| format!("override {field}: \"{part}\" is not a list index"))?;
            list.get_mut(i).ok_or_else(|| format!("override {field}: no element {i} in a list of {len}"))
        }
        _ => Err(format!("override {field}: \"{part}\" is inside a value that is not a table")),
    }
}
