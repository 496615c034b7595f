//! The export stage's artifact, `export.json`: the manifest of every file it wrote into
//! `export/`, with sizes and BLAKE3 digests, so that a user (or a test) can check the folder.

use serde::{Deserialize, Serialize};

use karst_artifact::{Invalid, Payload, StageId};

/// Every file an export wrote, in writing order.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    pub files: Vec<ExportedFile>,
}

/// One file of the export folder.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExportedFile {
    /// File name inside `export/`.
    pub name: String,
    /// The format that wrote it (`vtk`, `swmm`, ...).
    pub format: String,
    pub bytes: u64,
    /// BLAKE3 of the file, hex.
    pub blake3: String,
}

impl Payload for Manifest {
    const STAGE: StageId = StageId::Export;
    const SCHEMA: u32 = 1;

    /// Plain, distinct file names (the stage removes the files of the previous manifest: a
    /// path there would delete outside `export/`), sizes within what a disk holds and BLAKE3
    /// digests of 64 hex digits.
    fn validate(&self) -> Result<(), Invalid> {
        let mut seen = std::collections::HashSet::with_capacity(self.files.len());
        for (i, file) in self.files.iter().enumerate() {
            let plain = !file.name.is_empty()
                && !file.name.contains(['/', '\\', '\0'])
                && file.name != ".."
                && file.name != ".";
            if !plain {
                return Err(Invalid::new(
                    format!("files[{i}].name"),
                    format!("{:?} is not a file name", file.name),
                ));
            }
            if !seen.insert(file.name.as_str()) {
                return Err(Invalid::new(
                    format!("files[{i}].name"),
                    format!("{} is listed twice", file.name),
                ));
            }
            if file.bytes > 1 << 50 {
                return Err(Invalid::new(
                    format!("files[{i}].bytes"),
                    format!("{} is not a file size", file.bytes),
                ));
            }
            let hex = file.blake3.len() == 64 && file.blake3.bytes().all(|b| b.is_ascii_hexdigit());
            if !hex {
                return Err(Invalid::new(
                    format!("files[{i}].blake3"),
                    format!("{:?} is not a BLAKE3 digest (64 hex digits)", file.blake3),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forged_manifests_name_the_field() {
        let file = |name: &str| ExportedFile {
            name: name.into(),
            format: "csv".into(),
            bytes: 10,
            blake3: blake3::hash(name.as_bytes()).to_hex().to_string(),
        };
        let field = |files: Vec<ExportedFile>| Manifest { files }.validate().map_err(|e| e.field);
        assert_eq!(field(vec![file("nodes.csv"), file("links.csv")]), Ok(()));
        for bad in ["", ".", "..", "../scene.toml", "a\\b", "a\0b"] {
            assert_eq!(field(vec![file("ok.csv"), file(bad)]), Err("files[1].name".into()), "{bad:?}");
        }
        assert_eq!(field(vec![file("a.csv"), file("a.csv")]), Err("files[1].name".into()));
        let mut short = file("a.csv");
        short.blake3.pop();
        assert_eq!(field(vec![short]), Err("files[0].blake3".into()));
        let mut huge = file("a.csv");
        huge.bytes = u64::MAX;
        assert_eq!(field(vec![huge]), Err("files[0].bytes".into()));
    }
}
