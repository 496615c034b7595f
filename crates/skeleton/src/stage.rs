//! The skeleton stage's contract: its view of the scene, `samples.bin` and `costgraph.bin` in,
//! `skeleton.json` and karstnet's node/link files out; `render` draws the network.

use std::path::{Path, PathBuf};

use karst_artifact::{Header, StageId, read_artifact};
use karst_costgraph::CostGraph;
use karst_sampling::Samples;
use karst_scene::params::SkeletonMode;
use karst_stage::{Stage, StageError};

use crate::build::build;
use crate::error::SkeletonError;
use crate::output::karstnet;
use crate::payload::{ConduitType, Skeleton, Zone};
use crate::view::SkeletonView;

/// The base name of the karstnet export in the output folder.
pub const KARSTNET_BASE: &str = "network";

/// Stage 3: the conduit network.
pub struct SkeletonStage;

impl Stage for SkeletonStage {
    const ID: StageId = StageId::Skeleton;
    type Inputs = (Samples, CostGraph);
    type Output = Skeleton;
    type Error = SkeletonError;
    type View<'s> = SkeletonView<'s>;

    fn build(
        view: &SkeletonView,
        (samples, graph): &(Samples, CostGraph),
    ) -> Result<Skeleton, SkeletonError> {
        build(view, samples, graph)
    }

    fn headline(view: &SkeletonView, skeleton: &Skeleton) -> String {
        // Least-cost distances obey the triangle inequality, so γ ≤ 1 prunes nothing
        // (docs/skeleton.md): say so, since Paris et al.'s Table 1 suggests 0.8 for mazes.
        let p = view.skeleton;
        let complete = p.mode == SkeletonMode::Gamma && p.gamma <= 1.0;
        format!(
            "{} nodes, {} conduits, {:.0} m{}",
            skeleton.nodes.len(),
            skeleton.conduits.len(),
            skeleton.total_length(),
            if complete { " (skeleton.gamma ≤ 1 keeps every pair of key points)" } else { "" }
        )
    }

    fn summary(_: &Header, skeleton: &Skeleton) -> Vec<String> {
        let phreatic = skeleton.nodes.iter().filter(|n| n.zone == Zone::Phreatic).count();
        let mut lines = vec![
            format!(
                "nodes     {} ({} vadose, {phreatic} phreatic)",
                skeleton.nodes.len(),
                skeleton.nodes.len() - phreatic
            ),
            format!("conduits  {}", skeleton.conduits.len()),
            format!("length    {:.1} m", skeleton.total_length()),
        ];
        for kind in ConduitType::ALL {
            let length = skeleton.length_of_type(kind);
            if length > 0.0 {
                lines.push(format!("{:<9} {length:.1} m", kind.name()));
            }
        }
        for route in &skeleton.routes {
            lines.push(format!(
                "route     {} → {}: {} nodes, cost {:.1}",
                route.sink,
                route.spring,
                route.nodes.len(),
                route.cost
            ));
        }
        lines
    }

    /// karstnet's `network_nodes.dat` / `network_links.dat`, and `resolved.toml`: the defaults
    /// derived from the scene, as scene sections (none: no file).
    fn side_files(
        out: &Path,
        _: &SkeletonView,
        _: &Self::Inputs,
        skeleton: &mut Skeleton,
    ) -> std::io::Result<()> {
        karstnet::write(skeleton, &out.join(KARSTNET_BASE))?;
        let resolved = out.join(RESOLVED_FILE);
        match resolved_toml(skeleton) {
            Some(text) => std::fs::write(resolved, text),
            None => match std::fs::remove_file(resolved) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
                _ => Ok(()),
            },
        }
    }
}

/// The file beside the artifacts that holds the derived defaults.
pub const RESOLVED_FILE: &str = "resolved.toml";

/// The derived defaults of `skeleton` as the scene sections they belong to; None when the scene
/// gave every value.
pub fn resolved_toml(skeleton: &Skeleton) -> Option<String> {
    if skeleton.derived.is_empty() {
        return None;
    }
    let mut text = String::from(
        "# Defaults karstgen derived from the scene for the values it left out (docs/skeleton.md,\n\
         # \"Defaults from the scene\"). Copy them into the scene to pin them.\n",
    );
    let mut section = "";
    for (field, value) in &skeleton.derived {
        let (table, name) = field.split_once('.').unwrap_or(("skeleton", field));
        if let Some(tables) = array_of_tables(value) {
            for entries in tables {
                text += &format!("\n[[{table}.{name}]]\n");
                text.extend(entries.iter().map(|(key, v)| format!("{key} = {v}\n")));
            }
            section = "";
            continue;
        }
        if table != section {
            text += &format!("\n[{table}]\n");
            section = table;
        }
        text += &format!("{name} = {value}\n");
    }
    Some(text)
}

/// The objects of `value` when it is a non-empty array of objects (written as TOML's array of
/// tables, `[[geology.fractures]]`); their scalar values print the same in JSON and TOML.
fn array_of_tables(value: &serde_json::Value) -> Option<Vec<&serde_json::Map<String, serde_json::Value>>> {
    let items = value.as_array().filter(|a| !a.is_empty())?;
    items.iter().map(serde_json::Value::as_object).collect()
}

/// `karst-skeleton render FILE --png PNG`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The skeleton artifact.
    pub file: PathBuf,
    /// The picture to write.
    #[arg(long)]
    pub png: PathBuf,
    /// Title written on the picture (default: the artifact's file name).
    #[arg(long)]
    pub title: Option<String>,
}

/// `karst-skeleton render`.
pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let (_, skeleton) = read_artifact::<Skeleton>(&args.file)?;
    let title = args.title.clone().unwrap_or_else(|| args.file.display().to_string());
    crate::output::render::render(&skeleton, &title)
        .write_png(&args.png)
        .map_err(|e| StageError::failure(format!("{}: cannot write the picture: {e}", args.png.display())))
}
