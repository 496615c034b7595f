//! The streams stage's contract: `hydro.json` in, `streams.json` out; `render` draws the map.

use std::path::PathBuf;

use karst_artifact::{Header, StageId, read_artifact};
use karst_hydro::Hydro;
use karst_scene::Scene;
use karst_stage::human::round;
use karst_stage::{Stage, StageError};

use crate::build::build;
use crate::error::StreamsError;
use crate::payload::{Motion, PoolKind, Role, Streams};
use crate::render;
use crate::view::StreamsView;

/// Stage 5: the surface waterfall network fed by the springs.
pub struct StreamsStage;

impl Stage for StreamsStage {
    const ID: StageId = StageId::Streams;
    type Inputs = (Hydro,);
    type Output = Streams;
    type Error = StreamsError;
    type View<'s> = StreamsView<'s>;

    fn build(view: &StreamsView, (hydro,): &(Hydro,)) -> Result<Streams, StreamsError> {
        build(view, hydro)
    }

    fn headline(_: &StreamsView, streams: &Streams) -> String {
        let running: f64 =
            streams.segments.iter().filter(|s| s.motion == Motion::Contact).map(|s| streams.length(s)).sum();
        let lakes = streams.pools.iter().filter(|p| p.kind == PoolKind::Lake).count();
        format!(
            "{} segments ({} m running), {} falls, {} pools ({lakes} lakes), {} m³/s leaving",
            streams.segments.len(),
            round(running),
            streams.falls(),
            streams.pools.len(),
            round(leaving(streams))
        )
    }

    /// Lowered control points, lakes, springs whose water leaves by the domain's side,
    /// implausible types.
    fn notes(streams: &Streams) -> Vec<String> {
        streams.reports.clone()
    }

    fn summary(_: &Header, streams: &Streams) -> Vec<String> {
        let mut lines = vec![format!(
            "network   {} nodes, {} segments, {} falls, {} m³/s leaving",
            streams.nodes.len(),
            streams.segments.len(),
            streams.falls(),
            round(leaving(streams))
        )];
        for (w, metres) in streams.lengths() {
            lines.push(format!("{:<9} {} m", w.name(), round(metres)));
        }
        for s in &streams.springs {
            let mouth = s.mouth.map_or("outside the domain".to_string(), |m| {
                format!("mouth at [{}, {}, {}]", round(m[0]), round(m[1]), round(m[2]))
            });
            lines.push(format!("spring    {}: {} m³/s, {mouth}", s.name, round(s.discharge)));
        }
        for p in &streams.pools {
            lines.push(format!(
                "pool      {:?} at z {}, {} m², {} m deep",
                p.kind,
                round(p.level),
                round(p.area),
                round(p.depth)
            ));
        }
        lines.extend(streams.reports.iter().map(|r| format!("report    {r}")));
        lines
    }
}

/// Water leaving the network at its wells, m³/s.
fn leaving(streams: &Streams) -> f64 {
    streams.nodes.iter().filter(|n| n.role == Role::Well).map(|n| n.inflow).sum()
}

/// `karst-streams render SCENE DIR [--png FILE]`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The scene file (for its terrain).
    pub scene: PathBuf,
    /// Folder holding streams.json.
    pub dir: PathBuf,
    /// The picture to write; default DIR/streams.png.
    #[arg(long)]
    pub png: Option<PathBuf>,
}

/// `karst-streams render`: the map of DIR/streams.json over the scene's terrain.
pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let scene = Scene::load(&args.scene)?;
    let (_, streams) = read_artifact::<Streams>(&args.dir.join(StageId::Streams.file_name()))?;
    let png = args.png.clone().unwrap_or_else(|| args.dir.join("streams.png"));
    render::map(scene.domain(), scene.terrain(), &streams)
        .write_png(&png)
        .map_err(|e| StageError::failure(format!("cannot write {}: {e}", png.display())))?;
    println!("{}", png.display());
    Ok(())
}
