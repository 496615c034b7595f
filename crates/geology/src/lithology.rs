//! Lithology grids (`[geology.lithology]`): a 3D voxel model from a geomodeller (GemPy, GOCAD)
//! whose integer codes the scene maps to layers of rock: karstification potential, sampling
//! radius, no-karst.
//!
//! The grid is a VTK ImageData file ([`karst_geodata::vti`]; its origin and spacing are the file's) or
//! a NumPy array ([`karst_geodata::npy`]; `origin`, the centre of voxel [0, 0, 0], and `spacing` are
//! given in the scene). Each voxel is a box centred on its sample; a point takes the code of
//! the voxel containing it (nearest sample, no interpolation: codes are categories). Where the
//! grid has a unit, that unit is the point's layer ([`crate::Geology::layer_at`]) — the voxel
//! model is the finer description — and elsewhere the `[[geology.layers]]` rule applies; a
//! unit with `no_karst = true` is a no-karst volume. The voxels must cover the domain, and
//! every code found in a voxel that meets the domain must have a unit.

use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use karst_geodata::voxels::{Lattice, Voxels};

use crate::field::Layer;
use crate::file_error::FileError;
use crate::{Domain, Point};

/// `[geology.lithology]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lithology {
    /// `.vti` or `.npy`, relative to the scene's folder.
    pub file: String,
    /// `.vti`: the name of the data array (default: the file's only array, or its Scalars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub array: Option<String>,
    /// `.npy`: `[x, y, z]` of the centre of voxel [0, 0, 0].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<[f64; 3]>,
    /// `.npy`: voxel size `[dx, dy, dz]`, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<[f64; 3]>,
    /// What each code means.
    pub units: Vec<LithologyUnit>,
    /// BLAKE3 of the file, filled when loaded.
    #[serde(default, skip_deserializing)]
    pub content: String,
    /// The voxels, filled when loaded.
    #[serde(skip)]
    pub grid: Arc<LithologyGrid>,
}

/// One code of the grid (`[[geology.lithology.units]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LithologyUnit {
    /// The integer in the grid.
    pub code: i32,
    /// The rock's name (limestone, marl, granite).
    pub name: String,
    /// Karstification potential in [0, 1]; default 1.
    #[serde(default = "one")]
    pub potential: f64,
    /// Sampling radius in the unit (units of `[sampling]`); default `sampling.radius`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// No sample, hence no conduit, in this unit; default false.
    #[serde(default)]
    pub no_karst: bool,
}

fn one() -> f64 {
    1.0
}

/// The loaded grid: each voxel's unit.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LithologyGrid {
    lattice: Lattice,
    /// Index into `layers` per voxel; [`UNMAPPED`] for codes without a unit (outside the domain).
    units: Vec<u16>,
    /// One layer (name, potential, radius) per unit, in scene order.
    layers: Vec<Layer>,
    no_karst: Vec<bool>,
}

const UNMAPPED: u16 = u16::MAX;

/// Largest grid, in bytes of the file and of its voxels' units: 1 GiB.
const BUDGET_BYTES: u64 = 1 << 30;

impl LithologyGrid {
    /// Moves the voxels by `by`.
    pub fn translate(&mut self, by: [f64; 3]) {
        for (c, d) in self.lattice.first_centre.iter_mut().zip(by) {
            *c += d;
        }
    }

    /// The unit at `p`, if the grid has one there.
    fn unit_at(&self, p: Point) -> Option<usize> {
        self.units.get(self.lattice.index(p.to_array())).filter(|u| **u != UNMAPPED).map(|u| *u as usize)
    }

    /// The layer of the unit at `p`.
    pub fn layer_at(&self, p: Point) -> Option<&Layer> {
        self.unit_at(p).map(|u| &self.layers[u])
    }

    /// The name of the no-karst unit at `p`, if `p` is in one.
    pub fn no_karst_at(&self, p: Point) -> Option<&str> {
        self.unit_at(p).filter(|u| self.no_karst[*u]).map(|u| self.layers[u].name.as_str())
    }
}

impl Lithology {
    /// The radii the units set.
    pub fn radii(&self) -> impl Iterator<Item = f64> + '_ {
        self.units.iter().filter_map(|u| u.radius)
    }

    /// Reads the grid (relative to `folder`) and maps its codes over `domain`.
    pub fn load(&self, folder: &Path, domain: &Domain) -> Result<LithologyGrid, FileError> {
        let path = folder.join(&self.file);
        let file = path.display();
        let size = std::fs::metadata(&path).map_err(|e| FileError::read(&file, e))?.len();
        if size > BUDGET_BYTES {
            let problem =
                format!("{} MiB, more than the {} MiB lithology budget", size >> 20, BUDGET_BYTES >> 20);
            return Err(FileError::content(&file, problem));
        }
        let bytes = std::fs::read(&path).map_err(|e| FileError::read(&file, e))?;
        let wrong = |problem: GridProblem| FileError::content(&file, problem);
        let voxels = self.voxels(&bytes).map_err(wrong)?;
        covers(&voxels.lattice, domain).map_err(wrong)?;
        let units = self.map_codes(&voxels, domain).map_err(wrong)?;
        Ok(self.grid(voxels.lattice, units))
    }

    fn voxels(&self, bytes: &[u8]) -> Result<Voxels, GridProblem> {
        let lower = self.file.to_ascii_lowercase();
        if lower.ends_with(".vti") {
            if self.origin.is_some() || self.spacing.is_some() {
                return Err(GridProblem::PlacedVti);
            }
            Ok(karst_geodata::vti::parse(bytes, self.array.as_deref())?)
        } else if lower.ends_with(".npy") {
            let (Some(first_centre), Some(spacing)) = (self.origin, self.spacing) else {
                return Err(GridProblem::UnplacedNpy);
            };
            if self.array.is_some() {
                return Err(GridProblem::ArrayInNpy);
            }
            let (size, codes) = karst_geodata::npy::parse(bytes)?;
            Ok(Voxels { lattice: Lattice { first_centre, spacing, size }, codes })
        } else {
            Err(GridProblem::Format)
        }
    }

    /// The grid of `units` (one per voxel of `lattice`), each unit a layer of rock.
    fn grid(&self, lattice: Lattice, units: Vec<u16>) -> LithologyGrid {
        let layer = |u: &LithologyUnit| Layer {
            name: u.name.clone(),
            top: None,
            bottom: None,
            potential: u.potential,
            radius: u.radius,
        };
        LithologyGrid {
            lattice,
            units,
            layers: self.units.iter().map(layer).collect(),
            no_karst: self.units.iter().map(|u| u.no_karst).collect(),
        }
    }

    /// Each voxel's unit; a code without a unit in a voxel that meets the domain is an error.
    fn map_codes(&self, voxels: &Voxels, domain: &Domain) -> Result<Vec<u16>, GridProblem> {
        if self.units.len() >= UNMAPPED as usize {
            return Err(GridProblem::TooManyUnits { units: self.units.len() });
        }
        let by_code: std::collections::BTreeMap<i32, u16> =
            self.units.iter().enumerate().rev().map(|(u, unit)| (unit.code, u as u16)).collect();
        let lattice = &voxels.lattice;
        let [nx, ny, _] = lattice.size;
        let mut units = Vec::with_capacity(voxels.codes.len());
        for (k, code) in voxels.codes.iter().enumerate() {
            let unit = by_code.get(code).copied().unwrap_or(UNMAPPED);
            let index = [k % nx, k / nx % ny, k / (nx * ny)];
            if unit == UNMAPPED && meets(lattice, index, domain) {
                let centre: [f64; 3] =
                    std::array::from_fn(|a| lattice.first_centre[a] + index[a] as f64 * lattice.spacing[a]);
                let more = voxels.codes.iter().filter(|c| *c == code).count() - 1;
                return Err(GridProblem::NoUnit { code: *code, index, centre, more });
            }
            units.push(unit);
        }
        Ok(units)
    }
}

/// Does voxel `index`'s box meet the domain?
fn meets(lattice: &Lattice, index: [usize; 3], domain: &Domain) -> bool {
    (0..3).all(|a| {
        let centre = lattice.first_centre[a] + index[a] as f64 * lattice.spacing[a];
        let half = 0.5 * lattice.spacing[a];
        centre + half > domain.min[a] && centre - half < domain.max[a]
    })
}

/// The voxels' boxes must hold the domain.
fn covers(lattice: &Lattice, domain: &Domain) -> Result<(), GridProblem> {
    let b = lattice.bounds();
    let tolerance = |a: usize| 1e-9 * (domain.max[a] - domain.min[a]).abs().max(1.0);
    if (0..3).all(|a| b[a][0] <= domain.min[a] + tolerance(a) && b[a][1] >= domain.max[a] - tolerance(a)) {
        return Ok(());
    }
    Err(GridProblem::Uncovered { voxels: b, domain: std::array::from_fn(|a| [domain.min[a], domain.max[a]]) })
}

/// What is wrong with a lithology file or its units, in the file's or the scene's terms.
#[derive(Debug, thiserror::Error)]
enum GridProblem {
    #[error(transparent)]
    Vti(#[from] karst_geodata::vti::VtiError),
    #[error(transparent)]
    Npy(#[from] karst_geodata::npy::NpyError),
    #[error("a .vti file carries its origin and spacing: remove them from the scene")]
    PlacedVti,
    #[error("a .npy array needs `origin` and `spacing` in the scene")]
    UnplacedNpy,
    #[error("`array` names a .vti file's array; a .npy file holds one")]
    ArrayInNpy,
    #[error("is neither a VTK ImageData (.vti) nor a NumPy (.npy) file")]
    Format,
    #[error("{units} units, more than {}", UNMAPPED - 1)]
    TooManyUnits { units: usize },
    #[error(
        "code {code} (voxel {index:?} centred at {centre:?}, and {more} more voxels) has no unit in geology.lithology.units"
    )]
    NoUnit { code: i32, index: [usize; 3], centre: [f64; 3], more: usize },
    #[error(
        "its voxels cover x [{}, {}], y [{}, {}], z [{}, {}], not the domain's x [{}, {}], y [{}, {}], z [{}, {}]",
        voxels[0][0], voxels[0][1], voxels[1][0], voxels[1][1], voxels[2][0], voxels[2][1],
        domain[0][0], domain[0][1], domain[1][0], domain[1][1], domain[2][0], domain[2][1]
    )]
    Uncovered { voxels: [[f64; 2]; 3], domain: [[f64; 2]; 3] },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(units: &[(i32, &str, f64, bool)]) -> Lithology {
        Lithology {
            file: "l.npy".into(),
            array: None,
            origin: Some([5.0, 5.0, 5.0]),
            spacing: Some([10.0; 3]),
            units: units
                .iter()
                .map(|&(code, name, potential, no_karst)| LithologyUnit {
                    code,
                    name: name.into(),
                    potential,
                    radius: None,
                    no_karst,
                })
                .collect(),
            content: String::new(),
            grid: Arc::default(),
        }
    }

    /// 3 × 2 × 2 voxels of 10 m from the origin: code 1 below z = 10, 2 above; 9 in one voxel
    /// at x > 20.
    fn voxels() -> Voxels {
        let codes = (0..12)
            .map(|k| {
                if k == 2 {
                    9
                } else if k / 6 == 0 {
                    1
                } else {
                    2
                }
            })
            .collect();
        Voxels { lattice: Lattice { first_centre: [5.0; 3], spacing: [10.0; 3], size: [3, 2, 2] }, codes }
    }

    #[test]
    fn points_take_their_voxels_unit() {
        let s = spec(&[(1, "limestone", 1.0, false), (2, "granite", 0.0, true), (9, "marl", 0.3, false)]);
        let domain = Domain { min: [0.0; 3], max: [30.0, 20.0, 20.0] };
        let units = s.map_codes(&voxels(), &domain).unwrap();
        let grid = s.grid(voxels().lattice, units);
        assert_eq!(grid.layer_at(Point::new(3.0, 3.0, 3.0)).unwrap().name, "limestone");
        assert_eq!(grid.layer_at(Point::new(25.0, 3.0, 9.99)).unwrap().potential, 0.3);
        assert_eq!(
            grid.no_karst_at(Point::new(3.0, 3.0, 10.0)),
            Some("granite"),
            "a boundary belongs to the upper voxel"
        );
        assert_eq!(grid.no_karst_at(Point::new(3.0, 3.0, 9.0)), None);
    }

    #[test]
    fn codes_without_units_and_short_grids_are_refused() {
        let s = spec(&[(1, "limestone", 1.0, false), (2, "granite", 0.0, true)]);
        let domain = Domain { min: [0.0; 3], max: [30.0, 20.0, 20.0] };
        let e = s.map_codes(&voxels(), &domain).unwrap_err();
        assert!(matches!(e, GridProblem::NoUnit { code: 9, index: [2, 0, 0], more: 0, .. }), "{e}");
        assert_eq!(
            e.to_string(),
            "code 9 (voxel [2, 0, 0] centred at [25.0, 5.0, 5.0], and 0 more voxels) has no unit in geology.lithology.units"
        );
        let away = Domain { min: [0.0; 3], max: [19.0, 20.0, 20.0] };
        assert!(s.map_codes(&voxels(), &away).is_ok(), "the unmapped voxel is outside the domain");
        let e = covers(&voxels().lattice, &Domain { min: [0.0; 3], max: [30.0, 20.0, 25.0] })
            .unwrap_err()
            .to_string();
        assert!(e.contains("z [0, 20], not the domain's") && e.contains("z [0, 25]"), "{e}");
    }
}
