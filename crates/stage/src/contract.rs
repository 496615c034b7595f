//! The [`Stage`] trait and how a stage's error says whose fault it is.

use std::path::Path;

use karst_artifact::{Header, Payload, StageId};
use karst_scene::{SceneView, Section};

use crate::inputs::Inputs;
use crate::streamed::{ArtifactOut, Written};

/// One stage of the pipeline. Implemented by a unit type in each stage crate's `stage.rs`;
/// [`crate::runner::run`] does the rest.
pub trait Stage: 'static {
    /// The stage's row of the stage table: name, binary, artifact file, encoding, inputs.
    const ID: StageId;
    /// What the stage reads of the scene ([`karst_scene::view!`]): its artifact key hashes
    /// exactly the view's sections ([`sections`]).
    type View<'s>: SceneView<'s>;
    /// The upstream payloads it reads, in the row's order.
    type Inputs: Inputs;
    /// The payload of its artifact (handed to the next stage of a pipeline run: [`crate::Handoff`]).
    type Output: Payload + Send;
    /// Its typed error.
    type Error: Failure;

    /// The stage's algorithm: its view of the scene and the inputs in, the payload out.
    fn build(view: &Self::View<'_>, inputs: &Self::Inputs) -> Result<Self::Output, Self::Error>;

    /// The figures printed after a run, one line ("33 nodes, 3 conduits, 376 m").
    fn headline(view: &Self::View<'_>, output: &Self::Output) -> String;

    /// What the stage corrected or could not do in this run (a lowered control point, a lake),
    /// printed under the headline: the user's input was usable, but not as given.
    fn notes(_output: &Self::Output) -> Vec<String> {
        Vec::new()
    }

    /// The lines `inspect` prints under the artifact's first line.
    fn summary(header: &Header, output: &Self::Output) -> Vec<String>;

    /// Files written into the output folder beside the artifact (tables for other programs,
    /// previews, exports). The runner writes them before the artifact, so a run interrupted
    /// between the two leaves a stale artifact and the stage runs again next time. A stage may
    /// record in its payload what it wrote (the export stage's manifest of files and hashes).
    fn side_files(
        _out: &Path,
        _view: &Self::View<'_>,
        _inputs: &Self::Inputs,
        _output: &mut Self::Output,
    ) -> std::io::Result<()> {
        Ok(())
    }

    /// For a stage whose payload is too large to hold in memory: builds the payload and writes
    /// it itself through `artifact` ([`ArtifactOut::write`]: the same header, key and atomic
    /// write as the runner's), then returns the headline and notes. None, the default, when
    /// the stage returns its payload from [`Stage::build`] for the runner to validate and write
    /// (a stage may decide per scene: the mesher keeps its surfaces in memory to simplify them).
    /// A streamed stage writes no side files, and checks what [`karst_artifact::Payload::validate`]
    /// would as it writes; its timing covers the build and the write.
    fn write_streamed(
        _view: &Self::View<'_>,
        _inputs: &Self::Inputs,
        _artifact: &mut ArtifactOut<'_, Self::Output>,
    ) -> Option<Result<Written, Self::Error>> {
        None
    }
}

/// The scene sections stage `S` reads: its view's, in the order its key hashes them.
pub fn sections<S: Stage>() -> &'static [Section] {
    <S::View<'static> as SceneView<'static>>::SECTIONS
}

/// Whose fault an error is, so that the runner can name the file and give the exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blame {
    /// The scene file (or a data file it names) is wrong: exit 2, naming the scene.
    Scene,
    /// An upstream artifact is inconsistent: exit 2, naming it and the stage to rerun.
    Artifact(StageId),
    /// karstgen or the machine failed: exit 1.
    Internal,
}

/// A stage's typed error.
pub trait Failure: std::error::Error + Send + Sync + 'static {
    /// Whose fault it is.
    fn blame(&self) -> Blame;
}
