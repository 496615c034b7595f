//! The metrics stage's contract: `skeleton.json`, `hydro.json`, `streams.json` and `survey.json` in,
//! `metrics.json` and three pictures (DIR/preview/) out; and the statistics of any network file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Serialize;

use karst_artifact::{Header, StageId};
use karst_hydro::Hydro;
use karst_skeleton::Skeleton;
use karst_stage::{Stage, StageError};
use karst_streams::Streams;
use karst_survey::Survey;

use crate::build::{build, network_of};
use crate::error::ReportError;
use crate::payload::MetricsReport;
use crate::ranges::Compared;
use crate::readers::{self, ReadError};
use crate::view::MetricsView;
use crate::{Metrics, Network, aim, characterize, distributions, hints, plots, ranges};
use karst_scene::params::Aim;

/// Stage 8: karstnet's statistics of the network against real caves.
pub struct MetricsStage;

impl Stage for MetricsStage {
    const ID: StageId = StageId::Metrics;
    type Inputs = (Skeleton, Hydro, Streams, Survey);
    type Output = MetricsReport;
    type Error = ReportError;
    type View<'s> = MetricsView<'s>;

    fn build(
        view: &MetricsView,
        (skeleton, hydro, streams, survey): &(Skeleton, Hydro, Streams, Survey),
    ) -> Result<MetricsReport, ReportError> {
        let mut report = build(skeleton, hydro, streams, survey)?;
        let parameters = hints::Parameters {
            skeleton: view.skeleton,
            sampling: view.sampling,
            derived: &skeleton.derived,
        };
        match view.aim.map(resolve).transpose()? {
            Some(target) => {
                let verdict = hints::against(&report.karstnet, &target);
                report.hints = hints::target_hints(&report.karstnet, &verdict, &parameters);
                report.target = Some(verdict);
            }
            None => report.hints = hints::hints(&report.karstnet, &parameters),
        }
        Ok(report)
    }

    fn headline(_: &MetricsView, report: &MetricsReport) -> String {
        let m = &report.network;
        format!(
            "{} nodes, {} branches, {:.0} m, {}",
            m.n_nodes_full,
            m.n_branches,
            m.total_length,
            hints::verdict_of(report)
        )
    }

    /// The hints of the metrics outside the real-cave ranges.
    fn notes(report: &MetricsReport) -> Vec<String> {
        report.hints.clone()
    }

    fn summary(_: &Header, report: &MetricsReport) -> Vec<String> {
        let mut lines = Vec::new();
        for (key, c) in &report.karstnet {
            let verdict = if c.inside { "inside" } else { "OUTSIDE" };
            let r = &c.real_caves;
            lines.push(format!("{key:<28} {:>12.5}  {verdict:<7} [{:.4}, {:.4}]", c.value, r.min, r.max));
        }
        for (key, value) in report.network.to_pairs().into_iter().skip(ranges::CHARACTERIZE_KEYS.len()) {
            lines.push(format!("{key:<28} {value:>12.5}"));
        }
        lines.push(format!(
            "vadose length {:.1} m, phreatic length {:.1} m",
            report.zones.vadose, report.zones.phreatic
        ));
        for (kind, length) in
            report.conduit_types.iter().chain(&report.water_types).filter(|(_, l)| **l > 0.0)
        {
            lines.push(format!("{kind} {length:.1} m"));
        }
        let surface: Vec<String> = report
            .surface
            .water_types
            .iter()
            .filter(|(_, l)| **l > 0.0)
            .map(|(kind, length)| format!("{kind} {length:.1} m"))
            .collect();
        for (name, s) in &report.passages {
            let verdict = if s.inside { "inside" } else { "OUTSIDE" };
            let value = s.value.map_or("undefined".to_string(), |v| format!("{v:.4}"));
            lines.push(format!("passages {name:<19} {value:>12}  {verdict:<7} [{}, {}]", s.min, s.max));
        }
        if !surface.is_empty() {
            lines.push(format!("surface: {}, {} falls", surface.join(", "), report.surface.falls));
        }
        lines
    }

    /// The rose diagram, the branch-length histogram and the range chart, in DIR/preview/.
    fn side_files(
        out: &Path,
        _: &MetricsView,
        (skeleton, ..): &(Skeleton, Hydro, Streams, Survey),
        report: &mut MetricsReport,
    ) -> std::io::Result<()> {
        write_plots(&out.join("preview"), &network_of(skeleton), &report.network)
    }
}

/// The network the scene's `[calibrate]` aims at, its statistics.
pub fn resolve(aim: Aim) -> Result<aim::Target, ReportError> {
    match aim {
        Aim::Like(name) => aim::like(name).map_err(|e| ReportError::Aim {
            field: "like",
            value: name.into(),
            message: e.to_string(),
        }),
        Aim::Target { file, path, .. } => aim::cave(&[path.to_path_buf()])
            .map(|target| aim::Target { name: file.to_string(), ..target })
            .map_err(|e| ReportError::Aim { field: "target", value: file.into(), message: e.to_string() }),
    }
}

/// Writes the rose diagram, the branch-length histogram and the range chart of a network.
pub fn write_plots(dir: &Path, net: &Network, metrics: &Metrics) -> std::io::Result<()> {
    let d = distributions(net).map_err(std::io::Error::other)?;
    plots::write_all(dir, &d.azimuth_lengths, &d.branch_lengths, &ranges::compare(metrics))
}

/// A network file to characterize.
#[derive(Debug, Clone, clap::Args)]
#[group(multiple = false)]
pub struct NetworkFile {
    /// karstnet's BASE_nodes.dat and BASE_links.dat (BASE, or either file's name).
    #[arg(long, value_name = "BASE")]
    pub karstnet: Option<PathBuf>,
    /// A GOCAD PLine file.
    #[arg(long, value_name = "FILE.pl")]
    pub pline: Option<PathBuf>,
    /// CSV node table (id,x,y[,z]) and edge table (from,to | from_id,to_id | source,target),
    /// delimited by `,` or `;`.
    #[arg(long, num_args = 2, value_names = ["NODES", "EDGES"])]
    pub csv: Option<Vec<PathBuf>>,
}

/// What the command prints for a network file.
#[derive(Serialize)]
struct FileReport<'a> {
    karstnet: BTreeMap<&'a str, Compared>,
    network: &'a Metrics,
}

/// Prints the metrics of a network file as JSON (karstnet's keys, each `characterize_graph()`
/// metric beside its real-cave range), and draws its plots into `plots` when given.
pub fn characterize_file(file: &NetworkFile, plots: Option<&Path>) -> Result<(), StageError> {
    let (network, name) = read(file)?;
    let metrics = characterize(&network).map_err(|e| StageError::input(format!("{name}: {e}")))?;
    let report = FileReport { karstnet: ranges::compare(&metrics).into_iter().collect(), network: &metrics };
    let text = serde_json::to_string_pretty(&report).map_err(|e| StageError::failure(e.to_string()))?;
    println!("{text}");
    if let Some(dir) = plots {
        write_plots(dir, &network, &metrics)
            .map_err(|e| StageError::failure(format!("{}: cannot write the plots: {e}", dir.display())))?;
    }
    Ok(())
}

fn read(file: &NetworkFile) -> Result<(Network, String), StageError> {
    let bad = |e: ReadError| StageError::input(e.to_string());
    let show = |p: &Path| p.display().to_string();
    if let Some(base) = &file.karstnet {
        return Ok((readers::read_karstnet(base).map_err(bad)?, show(base)));
    }
    if let Some(path) = &file.pline {
        return Ok((readers::read_pline(path).map_err(bad)?, show(path)));
    }
    if let Some([nodes, edges]) = file.csv.as_deref() {
        return Ok((readers::read_csv(nodes, edges).map_err(bad)?, show(nodes)));
    }
    Err(StageError::input(
        "give a subcommand (run, inspect) or a network: --karstnet BASE, --pline FILE.pl or --csv NODES EDGES",
    ))
}
