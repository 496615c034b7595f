//! The small scene the parameter sections' tests append their section to: a plane terrain, one
//! water table, a sink and a spring.

use std::path::Path;

use crate::{Scene, SceneError};

const SCENE: &str = "name = \"t\"\nseed = 1\n[domain]\nmin = [0, 0, 0]\nmax = [100, 100, 50]\n\
    [terrain]\nkind = \"plane\"\nelevation = 40\n[[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
    [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 40]\n\
    [[keypoints]]\nname = \"s\"\nkind = \"spring\"\nposition = [90, 90, 10]\nwater_table = \"wt\"\n";

/// The problems of the scene with `extra` (TOML) appended, as text (none when it is valid).
pub(crate) fn problems(extra: &str) -> Vec<String> {
    match Scene::parse(&format!("{SCENE}{extra}\n"), Path::new("s.toml")) {
        Ok(_) => vec![],
        Err(SceneError::Invalid { problems, .. }) => problems.iter().map(|p| p.to_string()).collect(),
        Err(e) => vec![e.to_string()],
    }
}
