//! Where `full` passage detail goes: the breakdown chambers and their blocks, the speleothems
//! and the sediment fills placed on a built model's own walls. Apart from the features' types
//! ([`super`]) because placing evaluates the carved field, which evaluates those types.

use karst_hydro::Hydro;
use karst_scene::params::SdfParams;
use karst_scene::rng::Random;
use karst_skeleton::Skeleton;

use super::rock::Piece;
use super::walls::{Relief, ReliefNoise};
use super::{Features, FullDetail, breakdown, sediment, speleothems};
use crate::SdfModel;
use crate::field::carved::CarvedTerrain;

/// Adds `full` passage detail to a built model: the relief of every wall, the breakdown
/// chambers and their blocks, the speleothems. Placement sphere-traces the model's own walls
/// (relief and chambers included), so what is placed sits on them.
pub fn add(model: &mut SdfModel, p: &SdfParams, seed: u64, skeleton: &Skeleton, hydro: &Hydro) {
    let noise = ReliefNoise::draw(&mut Random::stream(seed, "sdf", "relief"), p.wall_wavelength);
    let relief = Relief { fraction: p.wall_relief, max: p.wall_relief_max, noise };
    model.full = FullDetail(Some(Features { relief, pieces: Vec::new() }));
    let collapses = breakdown::collapses(&CarvedTerrain::new(model.clone()), skeleton, p);
    model.spheres.extend(collapses.iter().map(breakdown::chamber));
    let field = CarvedTerrain::new(model.clone());
    let mut random = Random::stream(seed, "sdf", "breakdown");
    let mut pieces: Vec<Piece> = collapses
        .iter()
        .flat_map(|c| breakdown::blocks(&field, c, p.breakdown_blocks, &mut random))
        .collect();
    let mut random = Random::stream(seed, "sdf", "speleothems");
    pieces.extend(speleothems::place(&field, skeleton, hydro, p, &mut random));
    pieces.extend(sediment::fills(&field, skeleton, p));
    if let Some(features) = &mut model.full.0 {
        features.pieces = pieces;
    }
}
