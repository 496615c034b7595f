//! Artifacts written by their stage, for payloads too large to hold in memory
//! ([`crate::Stage::write_streamed`]): the runner hands the stage an [`ArtifactOut`] that
//! knows the artifact's path and provenance, the stage streams the payload's bytes into it.

use std::io::Write;
use std::marker::PhantomData;
use std::path::Path;

use karst_artifact::{Payload, Provenance, write_artifact_with};

/// Where a streamed stage writes its artifact: the path and the provenance the runner would
/// write with, so that the header, its key and the atomic replacement are the runner's.
pub struct ArtifactOut<'a, P> {
    path: &'a Path,
    provenance: &'a Provenance,
    written: bool,
    payload: PhantomData<P>,
}

/// What a streamed stage reports once its artifact is written.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The headline figures ([`crate::Stage::headline`]).
    pub headline: String,
    /// What the stage corrected or could not do ([`crate::Stage::notes`]).
    pub notes: Vec<String>,
}

impl<'a, P: Payload> ArtifactOut<'a, P> {
    /// The artifact of `provenance` at `path` (the runner makes it).
    pub(crate) fn new(path: &'a Path, provenance: &'a Provenance) -> Self {
        ArtifactOut { path, provenance, written: false, payload: PhantomData }
    }

    /// The artifact's path: a stage's temporary files go beside it.
    pub fn path(&self) -> &Path {
        self.path
    }

    /// Writes the artifact whose payload bytes `encode` writes (twice, the same bytes:
    /// [`write_artifact_with`]).
    pub fn write(
        &mut self,
        encode: impl FnMut(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<(), karst_artifact::Error> {
        write_artifact_with::<P>(self.path, self.provenance, encode)?;
        self.written = true;
        Ok(())
    }

    /// Whether [`ArtifactOut::write`] succeeded.
    pub(crate) fn written(&self) -> bool {
        self.written
    }
}
