//! The calibrated scene: the original scene text with the calibrated values written into their
//! sections (comments and layout kept, through `toml_edit`), its name suffixed `-calibrated` so
//! that running it does not overwrite the original's outputs, and the data files it names made
//! absolute so that it runs from the output folder. The result is parsed and validated as a
//! scene before it is written.

use std::path::Path;

use toml_edit::{DocumentMut, Item, Value, value};

use karst_scene::Scene;

use super::error::CalibrateError;

/// A calibrated value: the parameter (`section.field`), the value and whether it is an integer.
pub struct Setting<'a> {
    pub name: &'a str,
    pub value: f64,
    pub integer: bool,
}

/// The scene text `text` (read from `scene_path`) with `settings` applied and, when given, the
/// aim (`like` or `target` and its value) recorded in `[calibrate]` in place of the scene's own,
/// headed by `comment`.
pub fn calibrated_text(
    text: &str,
    scene_path: &Path,
    settings: &[Setting],
    aim: Option<&(&str, String)>,
    comment: &str,
) -> Result<String, CalibrateError> {
    let mut doc: DocumentMut = text.parse().map_err(|e| CalibrateError::Toml(format!("{e}")))?;
    let name = doc.get("name").and_then(Item::as_str).unwrap_or("scene").to_string();
    doc["name"] = value(format!("{name}-calibrated"));
    for s in settings {
        let (section, field) =
            s.name.split_once('.').ok_or_else(|| CalibrateError::NotSectionField(s.name.to_string()))?;
        let v = if s.integer { value(s.value.round() as i64) } else { value(s.value) };
        if doc.get(section).is_none() {
            doc[section] = toml_edit::table();
        }
        match &mut doc[section] {
            Item::Table(table) => table[field] = v,
            Item::Value(Value::InlineTable(table)) => {
                table.insert(
                    field,
                    v.into_value().map_err(|_| CalibrateError::NotATable(section.to_string()))?,
                );
            }
            _ => return Err(CalibrateError::NotATable(section.to_string())),
        }
    }
    if let Some((field, aim)) = aim
        && let Some(table) = doc.get_mut("calibrate").and_then(Item::as_table_like_mut)
    {
        table.remove("like");
        table.remove("target");
        table.insert(field, value(aim.as_str()));
    }
    let folder = scene_path.parent().unwrap_or(Path::new(""));
    absolute_data_files(&mut doc, folder);
    let out = format!("{comment}{doc}");
    Scene::parse(&out, scene_path).map_err(|e| CalibrateError::Invalid(e.to_string()))?;
    Ok(out)
}

/// Makes the data files the scene names (`terrain.file`, surfaces' `file`, `geology.grid.file`,
/// `calibrate.target`)
/// absolute, relative to `folder`.
fn absolute_data_files(doc: &mut DocumentMut, folder: &Path) {
    let absolute = |item: &mut Item| {
        if let Some(file) = item.as_str().filter(|f| Path::new(f).is_relative()) {
            let path = std::path::absolute(folder.join(file)).unwrap_or_else(|_| folder.join(file));
            *item = value(path.display().to_string());
        }
    };
    if let Some(terrain) = doc.get_mut("terrain").and_then(Item::as_table_like_mut)
        && let Some(file) = terrain.get_mut("file")
    {
        absolute(file);
    }
    if let Some(calibrate) = doc.get_mut("calibrate").and_then(Item::as_table_like_mut)
        && let Some(file) = calibrate.get_mut("target")
    {
        absolute(file);
    }
    let Some(geology) = doc.get_mut("geology").and_then(Item::as_table_like_mut) else { return };
    for list in ["water_tables", "horizons", "faults"] {
        if let Some(tables) = geology.get_mut(list).and_then(Item::as_array_of_tables_mut) {
            for table in tables.iter_mut() {
                if let Some(file) = table.get_mut("file") {
                    absolute(file);
                }
            }
        }
    }
    if let Some(grid) = geology.get_mut("grid").and_then(Item::as_table_like_mut)
        && let Some(file) = grid.get_mut("file")
    {
        absolute(file);
    }
}
