//! The geological model of a scene (`[geology]`): the surfaces that guide karstification
//! (water tables, inception horizons, faults), fracture families, layers of rock, the
//! karstification potential (layers, construction tree, background grid, lithology voxels) and
//! the volumes where no conduit may lie, with the queries every stage asks of them.

use serde::{Deserialize, Serialize};

use crate::field::{self, FieldNode, GridSpec, Layer, NoKarst};
use crate::lithology::Lithology;
use crate::{FractureFamily, Point, Surface};

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
    pub lithology: Option<Lithology>,
}

impl Geology {
    /// Intrinsic karstification potential P(p) in [0, 1] (KarstNSim §1.3: 1 = the most
    /// karstifiable rock, Paris et al.'s relative resistance to flow is 1 − P): the product of
    /// the layer's potential, the potential tree and the background grid ([`crate::field`]).
    pub fn potential(&self, p: Point) -> f64 {
        let layer = self.layer_at(p).map_or(1.0, |l| l.potential);
        let grid = self.grid.as_ref().map_or(1.0, |g| g.values.at(p));
        (layer * field::tree_value(&self.potential, p, self) * grid).clamp(0.0, 1.0)
    }

    /// The layer containing `p`: the lithology grid's unit there, else the first layer (scene
    /// order) containing `p`.
    pub fn layer_at(&self, p: Point) -> Option<&Layer> {
        let unit = self.lithology.as_ref().and_then(|l| l.grid.layer_at(p));
        unit.or_else(|| self.layers.iter().find(|l| l.contains(p, self)))
    }

    /// True when `p` lies in a no-karst volume or a no-karst lithology unit.
    #[inline]
    pub fn in_no_karst(&self, p: Point) -> bool {
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

    /// The water table named `name`.
    pub fn water_table(&self, name: &str) -> Option<&Surface> {
        self.water_tables.iter().find(|w| w.name == name)
    }
}

impl field::Surfaces for Geology {
    fn surface(&self, name: &str) -> Option<&Surface> {
        self.horizons.iter().chain(&self.faults).chain(&self.water_tables).find(|s| s.name == name)
    }
}
