//! The one runner: everything around a stage's `build`, the same way for every stage.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_artifact::stages::{producer, stage_key};
use karst_artifact::{
    Header, InputRef, Payload, Provenance, StageId, read_artifact, read_header, write_artifact,
};
use karst_scene::{Scene, SceneView};

use crate::contract::{Blame, Failure, Stage, sections};
use crate::error::StageError;
use crate::handoff::Handoff;
use crate::inputs::Inputs;
use crate::streamed::ArtifactOut;

/// One run of one stage: the scene (and the file it came from, named in messages) and the
/// output folder holding the upstream artifacts, where this stage's artifact goes too.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a> {
    pub scene_path: &'a Path,
    pub scene: &'a Scene,
    pub out: &'a Path,
    /// Within a pipeline run, the payloads the previous stages handed over ([`Handoff`]);
    /// None for a stage run alone, which reads every input from its file.
    pub handoff: Option<&'a Handoff>,
}

impl<'a> Job<'a> {
    /// A stage run alone: every input is read from its file.
    pub fn new(scene_path: &'a Path, scene: &'a Scene, out: &'a Path) -> Self {
        Job { scene_path, scene, out, handoff: None }
    }

    /// The path of `stage`'s artifact in the output folder.
    pub fn artifact(&self, stage: karst_artifact::StageId) -> PathBuf {
        self.out.join(stage.file_name())
    }
}

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct Ran {
    /// The stage's headline figures.
    pub headline: String,
    /// Seconds spent in `build`.
    pub seconds: f64,
    /// What the stage corrected or could not do ([`Stage::notes`]).
    pub notes: Vec<String>,
}

/// Runs stage `S`: reads and checks its inputs, builds, writes the side files (after removing
/// an artifact of other parameters that would claim them), checks the payload, then writes the
/// artifact (atomically, keyed by the scene sections it reads and its inputs' hashes). A stage
/// that writes its artifact itself ([`Stage::write_streamed`]) gets its path and provenance
/// instead, and the runner reports what it returns.
pub fn run<S: Stage>(job: &Job) -> Result<Ran, StageError> {
    debug_assert_eq!(S::Inputs::stages(), S::ID.inputs(), "{}: inputs differ from its row", S::ID.name());
    let mut headers = Vec::new();
    let frame = job.scene.frame().clone();
    let inputs = S::Inputs::read(job.out, &frame, job.handoff, &mut headers)?;
    consistent(job, &headers)?;
    let refs = headers
        .iter()
        .map(|h| InputRef { name: h.kind.row().kind.into(), payload_blake3: h.payload_blake3.clone() })
        .collect();
    let provenance = Provenance {
        producer: producer(S::ID),
        inputs: refs,
        params: job.scene.sections_hash(sections::<S>()),
        frame,
    };
    let path = job.artifact(S::ID);
    // The stage sees its view of the scene, nothing else.
    let view = S::View::of(job.scene);
    let start = Instant::now();
    if let Some(ran) = run_streamed::<S>(job, &view, &inputs, &path, &provenance, start) {
        return ran;
    }
    let mut output = S::build(&view, &inputs).map_err(|e| blame(job, &e))?;
    invalidate_other(
        &path,
        &stage_key(
            S::ID,
            &provenance.producer,
            S::Output::SCHEMA,
            &provenance.params,
            &provenance.frame,
            &provenance.inputs,
        ),
    )?;
    S::side_files(job.out, &view, &inputs, &mut output).map_err(|e| {
        StageError::failure(format!(
            "{}: cannot write the {} stage's files: {e}",
            job.out.display(),
            S::ID.name()
        ))
    })?;
    let seconds = start.elapsed().as_secs_f64();
    output.validate().map_err(|invalid| {
        StageError::failure(format!(
            "{} built an invalid {} payload ({}: {}): this is a bug in karstgen",
            S::ID.name(),
            S::ID.row().kind,
            invalid.field,
            invalid.problem
        ))
    })?;
    let header = write_artifact(&path, &provenance, &output)?;
    let _ = std::fs::remove_file(previous_artifact(&path));
    let ran = Ran { headline: S::headline(&view, &output), seconds, notes: S::notes(&output) };
    if let Some(handoff) = job.handoff {
        handoff.keep(header, output);
    }
    Ok(ran)
}

/// Runs a stage that writes its own artifact ([`Stage::write_streamed`]); None when `S`
/// returns its payload instead. No side files: nothing to invalidate before the atomic write.
fn run_streamed<S: Stage>(
    job: &Job,
    view: &S::View<'_>,
    inputs: &S::Inputs,
    path: &Path,
    provenance: &Provenance,
    start: Instant,
) -> Option<Result<Ran, StageError>> {
    let mut artifact = ArtifactOut::new(path, provenance);
    let written = S::write_streamed(view, inputs, &mut artifact)?;
    Some(written.map_err(|e| blame(job, &e)).and_then(|written| {
        if !artifact.written() {
            return Err(StageError::failure(format!(
                "{} did not write {}: this is a bug in karstgen",
                S::ID.name(),
                path.display()
            )));
        }
        let _ = std::fs::remove_file(previous_artifact(path));
        Ok(Ran { headline: written.headline, seconds: start.elapsed().as_secs_f64(), notes: written.notes })
    }))
}

/// Checks that the inputs were made from one another: a costgraph.bin made from another
/// samples.bin than the one beside it (a stage rerun alone with `--only`) is refused, naming
/// the stage to rerun.
fn consistent(job: &Job, headers: &[Header]) -> Result<(), StageError> {
    for header in headers {
        for input in &header.inputs {
            let Some(used) = headers.iter().find(|h| h.kind.row().kind == input.name) else { continue };
            if used.payload_blake3 != input.payload_blake3 {
                let stage = header.kind.name();
                return Err(StageError::input(format!(
                    "{}: was made from another {} than {}: rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)",
                    job.artifact(header.kind).display(),
                    used.kind.file_name(),
                    job.artifact(used.kind).display(),
                )));
            }
        }
    }
    Ok(())
}

/// Moves the artifact at `path` aside (to [`previous_artifact`]) when its key is not `key`,
/// before the side files are rewritten: an interrupted run then leaves no artifact that claims
/// side files it did not write, and the stage runs again next time. The stage may still read
/// what the previous artifact recorded (the export stage removes the files it no longer
/// writes); the runner deletes it once the new artifact is written. (With the same key, the
/// side files written are the same bytes: nothing to invalidate.)
fn invalidate_other(path: &Path, key: &str) -> Result<(), StageError> {
    if path.exists() && !path.is_file() {
        // Never move aside what is not an artifact (a user's folder of that name).
        return Err(StageError::failure(format!(
            "{}: is not a file: cannot write the stage's artifact there",
            path.display()
        )));
    }
    match read_header(path) {
        Ok(header) if header.key == key => Ok(()),
        Err(karst_artifact::Error::Open { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
            Ok(())
        }
        _ => std::fs::rename(path, previous_artifact(path)).map_err(|e| {
            StageError::failure(format!("{}: cannot move the stale artifact aside: {e}", path.display()))
        }),
    }
}

/// Where the runner keeps the artifact at `path` of a previous run while the stage rewrites its
/// side files: `.NAME.previous` beside it.
pub fn previous_artifact(path: &Path) -> PathBuf {
    let name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.previous"))
}

/// Removes what killed runs left in the output folder `out`: temporary files of processes that
/// are gone ([`karst_artifact::atomic::remove_stale_temporaries`]) and the `.NAME.previous`
/// of every artifact NAME of karstgen's stages that exists again (a run killed after a stage
/// wrote its new artifact, before it deleted the old one). Without its artifact, a previous one
/// stays: the stage reads it when it runs again (the export removes the files it no longer
/// writes) and deletes it then. Other files, a user's too, are never touched. Returns how many
/// were removed.
pub fn sweep_leftovers(out: &Path) -> usize {
    let previous = StageId::ALL
        .iter()
        .map(|stage| out.join(stage.file_name()))
        .filter(|artifact| artifact.is_file())
        .filter(|artifact| std::fs::remove_file(previous_artifact(artifact)).is_ok())
        .count();
    previous + karst_artifact::atomic::remove_stale_temporaries(out)
}

/// The error a user sees for a stage's typed error: the file at fault named first.
pub fn blame(job: &Job, e: &impl Failure) -> StageError {
    match e.blame() {
        Blame::Scene => StageError::scene(format!("{}: {e}", job.scene_path.display())),
        Blame::Artifact(stage) => StageError::artifact(format!(
            "{}: {e}: rerun the pipeline from {} (`karstgen run SCENE --from {}`)",
            job.artifact(stage).display(),
            stage.name(),
            stage.name()
        )),
        Blame::Internal => StageError::failure(e),
    }
}

/// The lines `inspect` prints for an artifact of stage `S`: what it is, then its summary.
pub fn inspect<S: Stage>(path: &Path) -> Result<Vec<String>, StageError> {
    let (header, output) = read_artifact::<S::Output>(path)?;
    let mut lines = vec![format!(
        "{}: {}, schema {}, by {}",
        path.display(),
        S::ID.row().kind,
        header.schema,
        header.producer
    )];
    // The frame, when the coordinates are not world coordinates already.
    if header.origin != [0.0; 3] || header.crs.is_some() {
        lines.push(format!(
            "  local frame: world = local + {:?} ({})",
            header.origin,
            header.crs.as_deref().unwrap_or("no CRS")
        ));
    }
    lines.extend(S::summary(&header, &output).into_iter().map(|l| format!("  {l}")));
    Ok(lines)
}
