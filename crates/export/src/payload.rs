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

    fn validate(&self) -> Result<(), Invalid> {
        for (i, file) in self.files.iter().enumerate() {
            let plain = !file.name.is_empty() && !file.name.contains(['/', '\\']) && file.name != "..";
            if !plain {
                return Err(Invalid::new(
                    format!("files[{i}].name"),
                    format!("{:?} is not a file name", file.name),
                ));
            }
            if self.files[..i].iter().any(|f| f.name == file.name) {
                return Err(Invalid::new(
                    format!("files[{i}].name"),
                    format!("{} is listed twice", file.name),
                ));
            }
        }
        Ok(())
    }
}
