//! The scene file: its structure, loading, validation and the hashes of its sections.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::params::{
    CalibrateParams, CostgraphParams, ExportParams, HydroParams, MesherParams, SamplingParams, SdfParams,
    SkeletonParams, StreamsParams,
};
use crate::sections::Section;
use crate::validate::{self, Problem};
use crate::view::Frame;
use karst_geology::{Domain, Geology, Terrain};

use crate::KeyPoint;

/// A whole scene, as read from its TOML file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name of the scene; `cargo xtask run` writes into `out/<name>` by default.
    pub(crate) name: String,
    /// Seed of every random choice; same scene and seed give byte-identical artifacts.
    #[serde(default)]
    pub(crate) seed: u64,
    /// The coordinate reference system, `"EPSG:NNNN"` (a projected CRS in metres); every data
    /// file that carries a CRS must be in it. Absent: local coordinates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) crs: Option<String>,
    pub(crate) domain: Domain,
    pub(crate) terrain: Terrain,
    #[serde(default)]
    pub(crate) geology: Geology,
    #[serde(default)]
    pub(crate) keypoints: Vec<KeyPoint>,
    /// Tables of key points (CSV, GeoJSON), appended to `keypoints` when the scene is loaded.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) keypoints_from: Vec<crate::point_table::PointTable>,
    #[serde(default)]
    pub(crate) connectivity: Connectivity,
    /// Speleogenetic phases, oldest first (`[[phases]]`); none: one phase with every spring.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) phases: Vec<Phase>,
    #[serde(default)]
    pub(crate) sampling: SamplingParams,
    #[serde(default)]
    pub(crate) costgraph: CostgraphParams,
    #[serde(default)]
    pub(crate) skeleton: SkeletonParams,
    #[serde(default)]
    pub(crate) hydro: HydroParams,
    /// The surface streams and waterfalls fed by the springs (docs/streams.md).
    #[serde(default)]
    pub(crate) streams: StreamsParams,
    #[serde(default)]
    pub(crate) sdf: SdfParams,
    #[serde(default)]
    pub(crate) mesher: MesherParams,
    #[serde(default)]
    pub(crate) export: ExportParams,
    /// `[calibrate]`: the box `karstgen calibrate` searches (read by no stage) and its target
    /// (`like` or `target`, read by the metrics stage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) calibrate: Option<CalibrateParams>,
    /// The local frame: the world position of its origin (the domain's `min` as written in the
    /// file; every coordinate above is relative to it once loaded, [`crate::localize`]) and the
    /// CRS.
    #[serde(skip)]
    pub(crate) frame: Frame,
    /// The memory the stages may plan to use: set by the command line, in no key.
    #[serde(skip)]
    pub(crate) budget: crate::budget::Budget,
    /// The bytes the run's meshes and exports may take, when a run holds them to it (`karstgen
    /// run --budget`): set by the command line, in no key.
    #[serde(skip)]
    pub(crate) output_budget: Option<crate::output_budget::OutputBudget>,
}

/// `[connectivity]`: which sink may drain to which spring.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Connectivity {
    /// One row per sink, one column per spring, both in scene order. 0: not connected,
    /// 1: connected, 2: uncertain (the cheapest of the row's uncertain springs is kept).
    /// Absent: every entry is 2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub matrix: Option<Vec<Vec<u8>>>,
    /// The same by name: sink → spring → 0/1/2, unlisted pairs 2; turned into `matrix` when
    /// the scene is loaded ([`crate::links`]).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub named: std::collections::BTreeMap<String, std::collections::BTreeMap<String, u8>>,
}

impl Connectivity {
    /// How the `sink`-th sink relates to the `spring`-th spring (scene order).
    pub fn link(&self, sink: usize, spring: usize) -> Link {
        match &self.matrix {
            None => Link::Uncertain,
            Some(rows) => match rows[sink][spring] {
                0 => Link::None,
                1 => Link::Connected,
                _ => Link::Uncertain,
            },
        }
    }
}

/// One speleogenetic phase (`[[phases]]`, KarstNSim §2.6): the springs active during it (each
/// with its water table), the sinks' weights then, and how much cheaper the conduits of the
/// earlier phases are to reuse.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Phase {
    pub name: String,
    /// Names of the springs that drain the network during the phase (springs read from tables
    /// join the phases their `phase` column names).
    #[serde(default)]
    pub springs: Vec<String>,
    /// Factor in (0, 1] on the cost of the edges the earlier phases' conduits use (default 1).
    #[serde(default = "one")]
    pub inherited_cost: f64,
    /// Sink weights during the phase, by sink name; sinks not listed keep their own weight.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub weights: std::collections::BTreeMap<String, f64>,
}

fn one() -> f64 {
    1.0
}

/// How sink `s` relates to spring `t` in the connectivity matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Link {
    None,
    Connected,
    Uncertain,
}

/// A scene that cannot be used, with every reason.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: cannot read the scene")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{}", format_problems(path, problems))]
    Invalid { path: PathBuf, problems: Vec<Problem> },
}

fn format_problems(path: &Path, problems: &[Problem]) -> String {
    let mut text = String::new();
    for (i, p) in problems.iter().enumerate() {
        if i > 0 {
            text.push('\n');
        }
        text.push_str(&format!("{}{p}", path.display()));
    }
    text
}

impl Scene {
    /// Reads, parses and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = karst_artifact::files::read_regular_text(path, karst_artifact::files::MAX_SCENE_BYTES)
            .map_err(|source| SceneError::Read { path: path.to_path_buf(), source })?;
        Scene::parse(&text, path)
    }

    /// Parses and validates scene text; `path` names it in messages, and the data files it
    /// names (heightfield, TIN surfaces, potential grid) are read relative to its folder.
    pub fn parse(text: &str, path: &Path) -> Result<Scene, SceneError> {
        let invalid = |problems| SceneError::Invalid { path: path.to_path_buf(), problems };
        let mut scene: Scene =
            toml::from_str(text).map_err(|e| invalid(vec![validate::from_toml(text, &e)]))?;
        let extra = validate::extra_elements(text, &scene);
        if !extra.is_empty() {
            return Err(invalid(extra));
        }
        let folder = path.parent().unwrap_or(Path::new(""));
        let mut problems = crate::load::attach_files(&mut scene, folder, text);
        problems.extend(validate::check(&scene, text));
        if !problems.is_empty() {
            return Err(invalid(problems));
        }
        crate::localize::localize(&mut scene);
        Ok(scene)
    }

    /// The scene's name; `karstgen run` writes into `out/<name>` by default.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The seed of every random choice.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Sets the seed (an ensemble's realizations differ only by it).
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
    }

    /// The memory budget the stages check their work estimates against.
    pub fn budget(&self) -> crate::budget::Budget {
        self.budget
    }

    /// Sets the memory budget (`--max-memory`).
    pub fn set_budget(&mut self, budget: crate::budget::Budget) {
        self.budget = budget;
    }

    /// The output budget the mesher holds its estimate to, when the run has one.
    pub fn output_budget(&self) -> Option<crate::output_budget::OutputBudget> {
        self.output_budget
    }

    /// Sets the output budget (`karstgen run --budget`): the mesher then prints its estimate
    /// before it starts and refuses work beyond it.
    pub fn set_output_budget(&mut self, budget: crate::output_budget::OutputBudget) {
        self.output_budget = Some(budget);
    }

    /// The coordinate reference system (`crs = "EPSG:2154"`), when the scene names one. Like
    /// the name, it is the scene's identity, not an input of any stage's computation.
    pub fn crs(&self) -> Option<&str> {
        self.crs.as_deref()
    }

    /// The world coordinates of the local frame's origin: the domain's `min` as the scene file
    /// gives it. Every coordinate the scene hands out is local (world − origin); artifacts
    /// record the origin and exports add it back. Like the CRS, it is not an input of any
    /// stage's computation: a scene moved by any offset gives the same payloads.
    pub fn origin(&self) -> [f64; 3] {
        self.frame.origin
    }

    /// The local frame (origin and CRS) every artifact of this scene records.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// `[[keypoints_from]]`: the tables key points were read from; their points are already
    /// in [`Scene::keypoints`].
    pub fn keypoints_from(&self) -> &[crate::point_table::PointTable] {
        &self.keypoints_from
    }

    /// Hash of `sections` (defaults applied; a field of a section, such as
    /// [`Section::ForcedLinks`], on its own), for artifact keys: what
    /// [`SceneView::sections_hash`](crate::view::SceneView::sections_hash) gives for a view of
    /// those sections.
    pub fn sections_hash(&self, sections: &[Section]) -> String {
        let values: Vec<_> = sections.iter().map(|&s| (s, crate::view::part::json(self, s))).collect();
        crate::view::hash(&values)
    }
}

/// A read and a write accessor per section (stages read theirs through their view,
/// [`crate::view`]).
macro_rules! section_accessors {
    ($($(#[$doc:meta])* $field:ident, $field_mut:ident: $ty:ty;)*) => {
        impl Scene {
            $(
                $(#[$doc])*
                #[inline]
                pub fn $field(&self) -> &$ty {
                    &self.$field
                }

                #[doc = concat!("`[", stringify!($field), "]`, to change it.")]
                pub fn $field_mut(&mut self) -> &mut $ty {
                    &mut self.$field
                }
            )*
        }
    };
}

section_accessors! {
    /// `[domain]`: the box of the model.
    domain, domain_mut: Domain;
    /// `[terrain]`: the ground surface.
    terrain, terrain_mut: Terrain;
    /// `[geology]`: water tables, horizons, faults, fractures, layers, potential, no-karst.
    geology, geology_mut: Geology;
    /// `[[keypoints]]`: sinks, springs, waypoints, dead ends, in scene order.
    keypoints, keypoints_mut: Vec<KeyPoint>;
    /// `[connectivity]`: which sink may drain to which spring.
    connectivity, connectivity_mut: Connectivity;
    /// `[[phases]]`: speleogenetic phases, oldest first.
    phases, phases_mut: Vec<Phase>;
    /// `[sampling]`.
    sampling, sampling_mut: SamplingParams;
    /// `[costgraph]`.
    costgraph, costgraph_mut: CostgraphParams;
    /// `[skeleton]`.
    skeleton, skeleton_mut: SkeletonParams;
    /// `[hydro]`.
    hydro, hydro_mut: HydroParams;
    /// `[streams]`: the surface streams and their controller curves.
    streams, streams_mut: StreamsParams;
    /// `[sdf]`.
    sdf, sdf_mut: SdfParams;
    /// `[mesher]`.
    mesher, mesher_mut: MesherParams;
    /// `[export]`: which formats the export stage writes.
    export, export_mut: ExportParams;
    /// `[calibrate]`: the parameter box of `karstgen calibrate`, when the scene has one.
    calibrate, calibrate_mut: Option<CalibrateParams>;
}
