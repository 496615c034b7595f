//! Payloads handed from one stage to the next within one pipeline run.
//!
//! `karstgen run` runs the stages one after the other in one process (a stage that reads nothing
//! of the one before it may run beside it: it then takes its payloads as that one's next stage). Each stage writes its
//! artifact, and the next one would read it back: open the file, hash the payload, decode it
//! and check it again, for a payload that is still in memory: on the large scenes a good part
//! of the skeleton's time, and a cost graph of gigabytes (BENCHMARKS.md). A
//! [`Handoff`] keeps the payload a stage wrote for the stage after it instead.
//!
//! What stays true:
//! - **The artifact is still written**, the same bytes, before the next stage starts: a run
//!   interrupted anywhere resumes from the files, and every artifact can be inspected.
//! - **The payload handed over is the one in the file.** The entry keeps the header the write
//!   returned; a stage takes the payload only when the header now in the file is that one (same
//!   key, same payload hash and length). Anything else reads the file, with all its checks.
//! - **Memory stays what the next stage needs anyway.** A payload is kept only while the stage
//!   about to run or the one after it reads it; it is moved, not copied, into the last of them.

use std::any::Any;
use std::path::Path;
use std::sync::Mutex;

use karst_artifact::{Header, Payload, StageId, read_header};

/// The payloads the last stages wrote, for the next ones in the same run.
#[derive(Default)]
pub struct Handoff {
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// The stage running now (None before the first).
    running: Option<StageId>,
    entries: Vec<Entry>,
}

impl State {
    /// Whether the stage after the running one reads the artifact of `input`.
    fn read_next(&self, input: StageId) -> bool {
        self.running.is_some_and(|running| read_next(running, input))
    }
}

/// One payload and the header of the artifact it was written to.
struct Entry {
    header: Header,
    payload: Box<dyn Any + Send>,
}

impl Handoff {
    pub fn new() -> Self {
        Handoff::default()
    }

    /// Called before `stage` runs (or is found up to date): drops every payload that neither
    /// it nor the stage after it reads.
    pub fn begin(&self, stage: StageId) {
        let mut state = self.lock();
        state.running = Some(stage);
        state.entries.retain(|e| read_by(stage, e.header.kind) || read_next(stage, e.header.kind));
    }

    /// Keeps `payload`, just written with `header`, when the stage after the running one reads
    /// it.
    pub fn keep<P: Payload + Send + 'static>(&self, header: Header, payload: P) {
        let mut state = self.lock();
        let wanted = state.read_next(P::STAGE);
        state.entries.retain(|e| e.header.kind != P::STAGE);
        if wanted {
            state.entries.push(Entry { header, payload: Box::new(payload) });
        }
    }

    /// The payload of `P`'s stage with its header, when one is kept and the artifact at `path`
    /// is still the one it was written to; moved out when the stage after the running one
    /// does not read it, copied otherwise.
    pub fn take<P: Payload + Clone + Send + 'static>(&self, path: &Path) -> Option<(Header, P)> {
        let mut state = self.lock();
        let at = state.entries.iter().position(|e| e.header.kind == P::STAGE)?;
        if read_header(path).ok().as_ref() != Some(&state.entries[at].header) {
            state.entries.remove(at);
            return None;
        }
        if state.read_next(P::STAGE) {
            let entry = &state.entries[at];
            let payload = entry.payload.downcast_ref::<P>()?.clone();
            return Some((entry.header.clone(), payload));
        }
        let entry = state.entries.remove(at);
        let payload = *entry.payload.downcast::<P>().ok()?;
        Some((entry.header, payload))
    }

    /// The stages whose payloads are kept now, in the order they were kept.
    pub fn kept(&self) -> Vec<StageId> {
        self.lock().entries.iter().map(|e| e.header.kind).collect()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        // A stage that panicked while holding the lock left no half-made entry: each update is
        // one push or remove.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl std::fmt::Debug for Handoff {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Handoff").field("kept", &self.kept()).finish()
    }
}

/// Whether `stage` reads the artifact of `input`.
fn read_by(stage: StageId, input: StageId) -> bool {
    stage.inputs().contains(&input)
}

/// Whether the stage after `stage` in the pipeline's order reads the artifact of `input`.
fn read_next(stage: StageId, input: StageId) -> bool {
    StageId::ALL.into_iter().skip_while(|s| *s != stage).nth(1).is_some_and(|next| read_by(next, input))
}

#[cfg(test)]
mod tests {
    use karst_artifact::{Frame, Provenance, write_artifact};
    use serde::{Deserialize, Serialize};

    use super::*;

    /// A stand-in for the samples: read by the cost graph and by the skeleton.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    struct Points(Vec<u32>);
    impl Payload for Points {
        const STAGE: StageId = StageId::Sampling;
        const SCHEMA: u32 = 1;
    }

    fn written(path: &Path, points: &Points) -> Header {
        let provenance = Provenance {
            producer: "test 0".into(),
            inputs: vec![],
            params: "p".into(),
            frame: Frame::default(),
        };
        write_artifact(path, &provenance, points).unwrap()
    }

    /// A scratch folder, the path of the samples' artifact in it and an empty handoff.
    fn setup(name: &str) -> (karst_testkit::Scratch, std::path::PathBuf, Handoff) {
        let dir = karst_testkit::scratch(name);
        let path = dir.join(StageId::Sampling.file_name());
        (dir, path, Handoff::new())
    }

    #[test]
    fn a_payload_is_copied_while_a_later_stage_reads_it_then_moved() {
        let (_dir, path, handoff) = setup("handoff-copied-then-moved");
        let points = Points(vec![3, 1, 4]);
        handoff.begin(StageId::Sampling);
        handoff.keep(written(&path, &points), points.clone());
        handoff.begin(StageId::Costgraph);
        let (header, taken) = handoff.take::<Points>(&path).expect("kept for the cost graph");
        assert_eq!((header, &taken), (read_header(&path).unwrap(), &points));
        assert_eq!(handoff.kept(), [StageId::Sampling], "the skeleton reads the samples too");
        handoff.begin(StageId::Skeleton);
        assert_eq!(handoff.take::<Points>(&path).map(|(_, p)| p), Some(points));
        assert!(handoff.kept().is_empty(), "the hydro stage does not read the samples");
    }

    #[test]
    fn a_rewritten_artifact_is_read_from_its_file() {
        let (dir, path, handoff) = setup("handoff-rewritten");
        handoff.begin(StageId::Sampling);
        handoff.keep(written(&path, &Points(vec![1, 2])), Points(vec![1, 2]));
        written(&path, &Points(vec![1, 2, 3]));
        handoff.begin(StageId::Costgraph);
        assert_eq!(handoff.take::<Points>(&path), None);
        assert!(handoff.kept().is_empty());
        let gone = dir.join("missing.bin");
        handoff.keep(written(&path, &Points(vec![5])), Points(vec![5]));
        assert_eq!(handoff.take::<Points>(&gone), None, "no artifact there: read it (and fail)");
    }

    #[test]
    fn only_what_the_next_stages_read_is_kept() {
        let (_dir, path, handoff) = setup("handoff-next-stages");
        // Written by a stage whose next one does not read it (the skeleton: hydro is next).
        handoff.begin(StageId::Skeleton);
        handoff.keep(written(&path, &Points(vec![7])), Points(vec![7]));
        assert!(handoff.kept().is_empty());
        // Kept for the cost graph, then dropped when a stage that reads neither comes.
        handoff.begin(StageId::Sampling);
        handoff.keep(written(&path, &Points(vec![7])), Points(vec![7]));
        handoff.begin(StageId::Hydro);
        assert!(handoff.kept().is_empty());
        assert_eq!(handoff.take::<Points>(&path), None);
    }
}
