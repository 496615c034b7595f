//! The stages by their row of the table: the one place that names the type implementing each
//! stage, so that everything else (make, inspect, diff) works from a [`StageId`].

use std::marker::PhantomData;
use std::path::Path;

use karst_artifact::{Payload, StageId};
use karst_scene::Section;
use karst_stage::{Job, Ran, Stage, StageError, cli, runner};

/// A stage, seen through its id.
pub trait DynStage: Sync {
    /// Runs the stage (see [`runner::run`]).
    fn run(&self, job: &Job) -> Result<Ran, StageError>;
    /// The payload schema this build writes.
    fn schema(&self) -> u32;
    /// The `inspect` lines of an artifact of this stage.
    fn inspect(&self, path: &Path) -> Result<Vec<String>, StageError>;
    /// Prints the whole artifact as JSON.
    fn print_json(&self, path: &Path) -> Result<(), StageError>;
    /// The artifact's payload, read and checked, as a JSON value.
    fn payload_value(&self, path: &Path) -> Result<serde_json::Value, StageError>;
    /// The stages whose payloads the implementation reads, in order.
    fn input_stages(&self) -> Vec<StageId>;
    /// The scene sections the stage reads: its view's ([`karst_stage::sections`]), in the order
    /// its key hashes them.
    fn sections(&self) -> &'static [Section];
}

/// The dynamic face of stage `S` (a `fn` marker, so it is `Sync` whatever `S` is).
struct Entry<S>(PhantomData<fn() -> S>);

impl<S: Stage> DynStage for Entry<S> {
    fn run(&self, job: &Job) -> Result<Ran, StageError> {
        runner::run::<S>(job)
    }

    fn schema(&self) -> u32 {
        <S::Output as Payload>::SCHEMA
    }

    fn inspect(&self, path: &Path) -> Result<Vec<String>, StageError> {
        runner::inspect::<S>(path)
    }

    fn print_json(&self, path: &Path) -> Result<(), StageError> {
        cli::print_json::<S::Output>(path)
    }

    fn payload_value(&self, path: &Path) -> Result<serde_json::Value, StageError> {
        let (_, payload) = karst_artifact::read_artifact::<S::Output>(path)?;
        serde_json::to_value(&payload).map_err(|e| StageError::failure(format!("{}: {e}", path.display())))
    }

    fn input_stages(&self) -> Vec<StageId> {
        <S::Inputs as karst_stage::Inputs>::stages()
    }

    fn sections(&self) -> &'static [Section] {
        karst_stage::sections::<S>()
    }
}

/// The implementation of stage `id`.
pub fn stage(id: StageId) -> &'static dyn DynStage {
    match id {
        StageId::Sampling => &Entry::<karst_sampling::SamplingStage>(PhantomData),
        StageId::Costgraph => &Entry::<karst_costgraph::CostgraphStage>(PhantomData),
        StageId::Skeleton => &Entry::<karst_skeleton::SkeletonStage>(PhantomData),
        StageId::Hydro => &Entry::<karst_hydro::HydroStage>(PhantomData),
        StageId::Streams => &Entry::<karst_streams::StreamsStage>(PhantomData),
        StageId::Sdf => &Entry::<karst_sdf::SdfStage>(PhantomData),
        StageId::Mesher => &Entry::<karst_mesher::MesherStage>(PhantomData),
        StageId::Metrics => &Entry::<karst_metrics::MetricsStage>(PhantomData),
        StageId::Export => &Entry::<karst_export::ExportStage>(PhantomData),
    }
}

/// `inspect` of any artifact: its kind is read from its header.
pub fn inspect(path: &Path) -> Result<Vec<String>, StageError> {
    let header = karst_artifact::read_header(path)?;
    stage(header.kind).inspect(path)
}

/// `inspect --json` of any artifact.
pub fn print_json(path: &Path) -> Result<(), StageError> {
    let header = karst_artifact::read_header(path)?;
    stage(header.kind).print_json(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_reads_the_inputs_its_row_declares() {
        for id in StageId::ALL {
            assert_eq!(stage(id).input_stages(), id.inputs(), "{}", id.name());
        }
    }
}
