//! The page: `crates/view/app/` (index.html, the app's ES modules, its stylesheet and the
//! vendored three.js of `app/vendor/three/`, refreshed by `scripts/vendor-three.sh`), embedded
//! into the binary so that `karst-view` writes a complete, offline view from any folder.

use std::path::Path;

use crate::ViewError;

macro_rules! embed {
    ($($path:literal),* $(,)?) => {
        &[$(($path, include_bytes!(concat!("../app/", $path)))),*]
    };
}

/// Every file of the app, by path relative to view/.
pub const FILES: &[(&str, &[u8])] = embed![
    "index.html",
    "style.css",
    "js/main.js",
    "js/viewer.js",
    "js/meshes.js",
    "js/network.js",
    "js/streams.js",
    "js/colours.js",
    "js/surfaces.js",
    "js/keypoints.js",
    "js/panels.js",
    "js/metrics.js",
    "js/overlay.js",
    "js/walk.js",
    "vendor/three/LICENSE",
    "vendor/three/VERSION",
    "vendor/three/build/three.module.js",
    "vendor/three/build/three.core.js",
    "vendor/three/addons/controls/OrbitControls.js",
    "vendor/three/addons/libs/meshopt_decoder.module.js",
    "vendor/three/addons/loaders/GLTFLoader.js",
    "vendor/three/addons/utils/BufferGeometryUtils.js",
    "vendor/three/addons/utils/SkeletonUtils.js",
];

/// Writes the app's files into `view_dir`.
pub fn write(view_dir: &Path) -> Result<(), ViewError> {
    for (name, bytes) in FILES {
        let path = view_dir.join(name);
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder)
                .map_err(|source| ViewError::Write { path: folder.into(), source })?;
        }
        std::fs::write(&path, bytes).map_err(|source| ViewError::Write { path, source })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::FILES;
    use std::path::{Path, PathBuf};

    fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() { files_under(&path, out) } else { out.push(path) }
        }
    }

    #[test]
    fn every_file_of_the_app_folder_is_embedded() {
        let app = Path::new(env!("CARGO_MANIFEST_DIR")).join("app");
        let mut found = Vec::new();
        files_under(&app, &mut found);
        let mut found: Vec<String> =
            found.iter().map(|p| p.strip_prefix(&app).unwrap().to_string_lossy().into_owned()).collect();
        let mut embedded: Vec<String> = FILES.iter().map(|(n, _)| n.to_string()).collect();
        found.sort();
        embedded.sort();
        assert_eq!(found, embedded);
    }

    #[test]
    fn the_app_loads_nothing_from_another_host() {
        for (name, bytes) in FILES.iter().filter(|(n, _)| !n.starts_with("vendor/")) {
            let text = std::str::from_utf8(bytes).unwrap();
            for scheme in ["http://", "https://", "//cdn", "ws://"] {
                assert!(!text.contains(scheme), "{name} names {scheme}");
            }
        }
    }
}
