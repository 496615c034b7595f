//! Reading a run folder: the artifacts the viewer shows (skeleton, hydro, streams, mesh, metrics) and the
//! scene (key points, water tables, horizons).
//!
//! A folder with none of the pipeline's artifacts is not a run (an error). A run that lacks a
//! stage, or whose artifact cannot be read or no longer matches its inputs, is still shown:
//! each such artifact becomes a [`Problem`] that the page lists instead of the layers it would
//! have fed. An ensemble's probability grid (`cargo xtask ensemble SCENE --out DIR`) in the
//! folder adds the ensemble colouring ([`ensemble`]). The scene is `--scene` when given, else the one `karstgen run` recorded in the run
//! folder (karst_stage::run_dir), else absent (a problem too).

use std::path::{Path, PathBuf};

use serde::Serialize;

use karst_artifact::{Header, Payload, StageId, read_artifact};
use karst_hydro::Hydro;
use karst_mesher::Mesh;
use karst_metrics::MetricsReport;
use karst_scene::Scene;
use karst_skeleton::Skeleton;
use karst_streams::Streams;

use crate::ViewError;
use crate::ensemble::{self, EnsembleView};

/// Something the view cannot show, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Problem {
    /// The file concerned (`mesh.bin`, `scene.toml`).
    pub file: String,
    /// What is wrong and what to do, one sentence.
    pub message: String,
    /// The layers and panels it leaves empty.
    pub affects: Vec<String>,
}

/// The parts of a run the viewer reads; each is absent when its file is missing or unusable.
pub struct Run {
    pub dir: PathBuf,
    pub scene: Option<Scene>,
    pub skeleton: Option<Skeleton>,
    pub hydro: Option<Hydro>,
    /// The surface streams.
    pub streams: Option<Streams>,
    pub mesh: Option<Mesh>,
    pub metrics: Option<MetricsReport>,
    /// The ensemble probability of every segment, when the folder holds an ensemble's grid.
    pub ensemble: Option<EnsembleView>,
    pub problems: Vec<Problem>,
}

/// The stages whose artifacts the view reads, and what each feeds.
const SHOWN: [(StageId, &[&str]); 5] = [
    (StageId::Skeleton, &["network", "key points", "routes", "walk"]),
    (StageId::Hydro, &["water colouring", "flow", "spring discharges"]),
    (StageId::Streams, &["surface streams"]),
    (StageId::Mesher, &["terrain", "cave", "water"]),
    (StageId::Metrics, &["metrics panel"]),
];

impl Run {
    /// Reads the run in `dir`; `scene` overrides the run's own `scene.toml`.
    pub fn load(dir: &Path, scene: Option<&Path>) -> Result<Run, ViewError> {
        if !dir.is_dir() {
            return Err(ViewError::NoFolder { dir: dir.to_path_buf() });
        }
        if !StageId::ALL.iter().any(|s| dir.join(s.file_name()).is_file()) {
            let expected: Vec<&str> = StageId::ALL.iter().map(|s| s.file_name()).collect();
            return Err(ViewError::NotARun { dir: dir.to_path_buf(), expected: expected.join(", ") });
        }
        let mut run = Run {
            dir: dir.to_path_buf(),
            scene: None,
            skeleton: None,
            hydro: None,
            streams: None,
            mesh: None,
            metrics: None,
            ensemble: None,
            problems: Vec::new(),
        };
        run.scene = run.load_scene(scene)?;
        let skeleton = run.artifact::<Skeleton>(StageId::Skeleton);
        let hydro = run.artifact::<Hydro>(StageId::Hydro);
        let streams = run.artifact::<Streams>(StageId::Streams);
        let mesh = run.artifact::<Mesh>(StageId::Mesher);
        let metrics = run.artifact::<MetricsReport>(StageId::Metrics);
        run.check_inputs(header(&skeleton), header(&hydro), header(&metrics));
        run.check_streams(header(&hydro), header(&streams));
        run.skeleton = skeleton.map(|(_, s)| s);
        run.hydro = hydro.map(|(_, h)| h).and_then(|h| run.matching_hydro(h));
        run.streams = streams.map(|(_, s)| s);
        run.mesh = mesh.map(|(_, m)| m);
        run.metrics = metrics.map(|(_, m)| m);
        run.ensemble = run.load_ensemble();
        Ok(run)
    }

    /// The run folder's name, for the page title.
    pub fn name(&self) -> String {
        let dir = self.dir.canonicalize().unwrap_or_else(|_| self.dir.clone());
        dir.file_name().map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into_owned())
    }

    fn load_scene(&mut self, given: Option<&Path>) -> Result<Option<Scene>, ViewError> {
        if let Some(path) = given {
            return Ok(Some(Scene::load(path)?));
        }
        if let Some(recorded) = karst_stage::run_dir::scene_of(&self.dir) {
            return Ok(Some(Scene::load(&recorded)?));
        }
        self.problems.push(Problem {
            file: karst_stage::run_dir::SCENE_PATH_FILE.into(),
            message:
                "the run folder does not say which scene made it: give the scene (`--scene SCENE.toml`) \
                      to see its water tables, horizons and domain"
                    .into(),
            affects: vec!["water tables".into(), "horizons".into()],
        });
        Ok(None)
    }

    /// The ensemble probability, or a problem when the folder's ensemble cannot be read.
    fn load_ensemble(&mut self) -> Option<EnsembleView> {
        match ensemble::load(&self.dir, self.skeleton.as_ref()?)? {
            Ok(view) => Some(view),
            Err(message) => {
                self.problems.push(Problem {
                    file: "probability/grid.json".into(),
                    message: format!("{message}: rerun `cargo xtask ensemble SCENE --out DIR`"),
                    affects: vec!["ensemble probability".into()],
                });
                None
            }
        }
    }

    /// Reads the artifact of `stage`, or records why it cannot be shown.
    fn artifact<P: Payload>(&mut self, stage: StageId) -> Option<(Header, P)> {
        let file = stage.file_name();
        let path = self.dir.join(file);
        let message = if !path.is_file() {
            format!("{file} is missing: run the {} stage (`karstgen run SCENE --out DIR`)", stage.name())
        } else {
            match read_artifact::<P>(&path) {
                Ok(artifact) => return Some(artifact),
                Err(e) => e.to_string(),
            }
        };
        self.problem(stage, message);
        None
    }

    fn problem(&mut self, stage: StageId, message: String) {
        let affects = SHOWN.iter().find(|(s, _)| *s == stage).map_or(&[][..], |(_, a)| *a);
        self.problems.push(Problem {
            file: stage.file_name().into(),
            message,
            affects: affects.iter().map(|a| a.to_string()).collect(),
        });
    }

    /// Records the artifacts made from another skeleton than the one in the folder (a stage
    /// rerun without its successors): they are still shown, with a warning.
    fn check_inputs(&mut self, skeleton: Option<&Header>, hydro: Option<&Header>, metrics: Option<&Header>) {
        let Some(skeleton) = skeleton else { return };
        for (header, stage) in [(hydro, StageId::Hydro), (metrics, StageId::Metrics)] {
            let stale = header.is_some_and(|h| {
                h.inputs.iter().any(|i| i.name == "skeleton" && i.payload_blake3 != skeleton.payload_blake3)
            });
            if stale {
                self.problem(
                    stage,
                    format!(
                        "{} was made from another skeleton.json: rerun `karstgen run SCENE --from {}`",
                        stage.file_name(),
                        stage.name()
                    ),
                );
            }
        }
    }

    /// Records a streams.json made from another hydro.json than the one in the folder: it is
    /// still shown, with a warning.
    fn check_streams(&mut self, hydro: Option<&Header>, streams: Option<&Header>) {
        let (Some(hydro), Some(streams)) = (hydro, streams) else { return };
        if streams.inputs.iter().any(|i| i.name == "hydro" && i.payload_blake3 != hydro.payload_blake3) {
            self.problem(
                StageId::Streams,
                "streams.json was made from another hydro.json: rerun `karstgen run SCENE --from streams`"
                    .into(),
            );
        }
    }

    /// The hydro artifact when it describes the conduits of the skeleton (same counts).
    fn matching_hydro(&mut self, hydro: Hydro) -> Option<Hydro> {
        let skeleton = self.skeleton.as_ref()?;
        let matches = hydro.conduits.len() == skeleton.conduits.len()
            && hydro.nodes.len() == skeleton.nodes.len()
            && hydro
                .conduits
                .iter()
                .zip(&skeleton.conduits)
                .all(|(w, c)| w.segments.len() + 1 == c.nodes.len());
        if matches {
            return Some(hydro);
        }
        self.problem(
            StageId::Hydro,
            "hydro.json does not describe the conduits of skeleton.json: rerun `karstgen run SCENE --from hydro`".into(),
        );
        None
    }
}

fn header<P>(artifact: &Option<(Header, P)>) -> Option<&Header> {
    artifact.as_ref().map(|(h, _)| h)
}
