//! The scene file: its structure, loading, validation and the hashes of its sections.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::field::{self, FieldNode, GridSpec, Layer, NoKarst};
use crate::params::{
    CalibrateParams, CostgraphParams, ExportParams, HydroParams, MesherParams, SamplingParams, SdfParams,
    SkeletonParams, StreamsParams,
};
use crate::sections::{Reads, Section};
use crate::validate::{self, Problem};
use crate::{Domain, FractureFamily, KeyPoint, KeyPointKind, Surface, Terrain};

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
    /// `[calibrate]`: the box `karstgen calibrate` searches; read by no stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) calibrate: Option<CalibrateParams>,
    /// The world position of the local frame's origin (the domain's `min` as written in the
    /// file); every coordinate above is relative to it once loaded ([`crate::localize`]).
    #[serde(skip)]
    pub(crate) origin: [f64; 3],
    /// Which sections were read, when auditing (see [`Scene::audited`]).
    #[serde(skip)]
    pub(crate) reads: Reads,
    /// The memory the stages may plan to use: set by the command line, in no key.
    #[serde(skip)]
    pub(crate) budget: crate::budget::Budget,
}

/// `[geology]`: the surfaces that guide karstification.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Geology {
    /// Water tables, one per spring (springs name theirs). Below it is the phreatic zone.
    pub water_tables: Vec<Surface>,
    /// Inception horizons: bedding surfaces along which conduits preferentially develop.
    pub horizons: Vec<Surface>,
    /// Faults: inception surfaces that may be vertical.
    pub faults: Vec<Surface>,
    /// Fracture families: directions conduits tend to follow.
    pub fractures: Vec<FractureFamily>,
    /// Layers of rock with their own potential and sampling radius (first match wins).
    pub layers: Vec<Layer>,
    /// The potential's construction tree; the last node is the root.
    pub potential: Vec<FieldNode>,
    /// Volumes where no sample (no conduit) may lie.
    pub no_karst: Vec<NoKarst>,
    /// Background grid of potentials read from a file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridSpec>,
    /// A voxel model of lithology codes mapped to layers of rock.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lithology: Option<crate::lithology::Lithology>,
}

impl Geology {
    /// Intrinsic karstification potential P(p) in [0, 1] (KarstNSim §1.3: 1 = the most
    /// karstifiable rock, Paris et al.'s relative resistance to flow is 1 − P): the product of
    /// the layer's potential, the potential tree and the background grid ([`crate::field`]).
    pub fn potential(&self, p: crate::Point) -> f64 {
        let layer = self.layer_at(p).map_or(1.0, |l| l.potential);
        let grid = self.grid.as_ref().map_or(1.0, |g| g.values.at(p));
        (layer * field::tree_value(&self.potential, p, self) * grid).clamp(0.0, 1.0)
    }

    /// The layer containing `p`: the lithology grid's unit there, else the first layer (scene
    /// order) containing `p`.
    pub fn layer_at(&self, p: crate::Point) -> Option<&Layer> {
        let unit = self.lithology.as_ref().and_then(|l| l.grid.layer_at(p));
        unit.or_else(|| self.layers.iter().find(|l| l.contains(p, self)))
    }

    /// True when `p` lies in a no-karst volume or a no-karst lithology unit.
    #[inline]
    pub fn in_no_karst(&self, p: crate::Point) -> bool {
        self.no_karst.iter().any(|v| v.shape().is_some_and(|s| s.signed_distance(p, self) <= 0.0))
            || self.lithology.as_ref().is_some_and(|l| l.grid.no_karst_at(p).is_some())
    }

    /// The sampling radii the layers and lithology units set.
    pub fn layer_radii(&self) -> impl Iterator<Item = f64> + '_ {
        self.layers.iter().filter_map(|l| l.radius).chain(self.lithology.iter().flat_map(|l| l.radii()))
    }

    /// True when the potential is 1 everywhere (no layer, tree, grid or lithology).
    pub fn uniform_potential(&self) -> bool {
        self.layers.is_empty() && self.grid.is_none() && self.potential.is_empty() && self.lithology.is_none()
    }

    /// Inception surfaces: horizons and faults.
    pub fn inception_surfaces(&self) -> impl Iterator<Item = &Surface> {
        self.horizons.iter().chain(&self.faults)
    }
}

impl field::Surfaces for Geology {
    fn surface(&self, name: &str) -> Option<&Surface> {
        self.horizons.iter().chain(&self.faults).chain(&self.water_tables).find(|s| s.name == name)
    }
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
        self.reads.note(Section::Seed);
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
        self.origin
    }

    /// The local frame (origin and CRS) every artifact of this scene records.
    pub fn frame(&self) -> karst_artifact::Frame {
        karst_artifact::Frame { origin: self.origin, crs: self.crs.clone() }
    }

    /// `[[keypoints_from]]`: the tables key points were read from; their points are already
    /// in [`Scene::keypoints`], so reading them is reading the key points.
    pub fn keypoints_from(&self) -> &[crate::point_table::PointTable] {
        self.reads.note(Section::Keypoints);
        &self.keypoints_from
    }

    /// `skeleton.forced_links`, read on its own by the cost graph.
    pub fn forced_links(&self) -> &[[String; 2]] {
        self.reads.note(Section::ForcedLinks);
        &self.skeleton.forced_links
    }

    /// `hydro.total_discharge`, read on its own by the streams (the springs' discharge in m³/s).
    pub fn total_discharge(&self) -> f64 {
        self.reads.note(Section::TotalDischarge);
        self.hydro.total_discharge
    }

    /// The key points of `kind`, with their index in `keypoints`, in scene order.
    pub fn keypoints_of(&self, kind: KeyPointKind) -> impl Iterator<Item = (usize, &KeyPoint)> {
        self.keypoints().iter().enumerate().filter(move |(_, k)| k.kind == kind)
    }

    /// True inside the domain and below the ground (no-karst volumes included).
    pub fn in_bedrock(&self, p: crate::Point) -> bool {
        self.domain().contains(p) && p.z < self.terrain().height(p.x, p.y)
    }

    /// The water table named `name`.
    pub fn water_table(&self, name: &str) -> Option<&Surface> {
        self.geology().water_tables.iter().find(|w| w.name == name)
    }

    /// Connectivity between the `sink`-th sink and the `spring`-th spring (scene order).
    pub fn link(&self, sink: usize, spring: usize) -> Link {
        match &self.connectivity().matrix {
            None => Link::Uncertain,
            Some(rows) => match rows[sink][spring] {
                0 => Link::None,
                1 => Link::Connected,
                _ => Link::Uncertain,
            },
        }
    }

    /// Hash of the named top-level sections (defaults applied), or of one field of a section
    /// when the name is dotted, for artifact keys.
    pub fn sections_hash(&self, sections: &[&str]) -> String {
        let value = serde_json::to_value(self).expect("a scene always serializes");
        let texts: Vec<String> = sections
            .iter()
            .map(|name| {
                // A dotted name ("skeleton.forced_links") hashes one field of a section.
                let field = name.split('.').try_fold(&value, |v, key| v.get(key));
                format!("{name}={}", field.cloned().unwrap_or_default())
            })
            .collect();
        karst_artifact::hash::hex_of_parts(texts.iter().map(|t| t.as_bytes()))
    }

    /// A copy that records which sections it hands out ([`Scene::sections_read`]).
    pub fn audited(&self) -> Scene {
        Scene { reads: Reads::auditing(), ..self.clone() }
    }

    /// The sections read from an [`audited`](Scene::audited) scene so far.
    pub fn sections_read(&self) -> Vec<Section> {
        self.reads.read()
    }
}

/// A read accessor per section, noting the read, and a write accessor without the note.
macro_rules! section_accessors {
    ($($(#[$doc:meta])* $field:ident, $field_mut:ident: $ty:ty => $section:ident;)*) => {
        impl Scene {
            $(
                $(#[$doc])*
                #[inline]
                pub fn $field(&self) -> &$ty {
                    self.reads.note(Section::$section);
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
    domain, domain_mut: Domain => Domain;
    /// `[terrain]`: the ground surface.
    terrain, terrain_mut: Terrain => Terrain;
    /// `[geology]`: water tables, horizons, faults, fractures, layers, potential, no-karst.
    geology, geology_mut: Geology => Geology;
    /// `[[keypoints]]`: sinks, springs, waypoints, dead ends, in scene order.
    keypoints, keypoints_mut: Vec<KeyPoint> => Keypoints;
    /// `[connectivity]`: which sink may drain to which spring.
    connectivity, connectivity_mut: Connectivity => Connectivity;
    /// `[[phases]]`: speleogenetic phases, oldest first.
    phases, phases_mut: Vec<Phase> => Phases;
    /// `[sampling]`.
    sampling, sampling_mut: SamplingParams => Sampling;
    /// `[costgraph]`.
    costgraph, costgraph_mut: CostgraphParams => Costgraph;
    /// `[skeleton]`.
    skeleton, skeleton_mut: SkeletonParams => Skeleton;
    /// `[hydro]`.
    hydro, hydro_mut: HydroParams => Hydro;
    /// `[streams]`: the surface streams and their controller curves.
    streams, streams_mut: StreamsParams => Streams;
    /// `[sdf]`.
    sdf, sdf_mut: SdfParams => Sdf;
    /// `[mesher]`.
    mesher, mesher_mut: MesherParams => Mesher;
    /// `[export]`: which formats the export stage writes.
    export, export_mut: ExportParams => Export;
    /// `[calibrate]`: the parameter box of `karstgen calibrate`, when the scene has one.
    calibrate, calibrate_mut: Option<CalibrateParams> => Calibrate;
}
