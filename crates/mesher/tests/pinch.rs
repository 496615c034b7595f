//! A pinch never closes the cave mesh: the mesher meshes its field with every conduit at least
//! a cave cell thick on each side ([`meshed_field`]), so a passage at the passage profiles'
//! smallest half-width stays open between two larger passages at the automatic cave cell,
//! wherever the pinch lies relative to the lattice.

use karst_geology::Domain;
use karst_mesher::{Cave, cave_cell, components, meshed_field, polygonize, watertight};
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};

/// The passage profiles' smallest half-width and half-height, metres (docs/skeleton.md,
/// "Passages").
const SMALLEST_PASSAGE: f64 = 0.5;

/// A 2 m passage, a 10 m long pinch of half-width `pinch`, and another 2 m passage, the axis at
/// `offset` from the lattice's planes.
fn pinched(pinch: f64, offset: f64) -> SdfModel {
    let (y, z) = (20.0 + offset, 10.0 + 0.7 * offset);
    SdfModel {
        capsules: vec![
            Capsule { a: [5.0, y, z], b: [23.0, y, z], radius: 2.0 },
            Capsule { a: [23.0, y, z], b: [37.0, y + 0.3, z - 0.2], radius: pinch },
            Capsule { a: [37.0, y + 0.3, z - 0.2], b: [55.0, y, z], radius: 2.0 },
        ],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [60.0, 40.0, 30.0] },
            TerrainField::Plane { elevation: 25.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
        )
    }
}

#[test]
fn the_smallest_passage_stays_open_at_the_automatic_cave_cell() {
    let half_width = SMALLEST_PASSAGE;
    for cell_size in [2.0, 3.0, 4.0, 6.0, 10.0] {
        for offset in [0.0, 0.13, 0.29, 0.41] {
            let model = pinched(half_width, offset);
            let cave_cell = cave_cell(&model, cell_size, 0.0);
            let cave = polygonize(&Cave(&meshed_field(&model, cave_cell)), cave_cell);
            assert!(watertight::check(&cave).is_ok(), "cell {cell_size}, offset {offset}");
            assert_eq!(
                components::count(&cave),
                1,
                "a pinch of half-width {half_width} m closed at mesher.cell_size {cell_size} \
                 (cave cell {cave_cell}), offset {offset}"
            );
        }
    }
}

#[test]
fn a_pinch_thinner_than_the_cave_cell_can_close() {
    // The check above can fail: unthickened, at a fixed cell four times the pinch's
    // half-width, some offset splits the passage in two.
    let closed = [0.0, 0.13, 0.29, 0.41, 0.5, 0.77, 1.0].iter().any(|&offset| {
        let cave = polygonize(&Cave(&CarvedTerrain::new(pinched(0.25, offset))), 1.0);
        components::count(&cave) > 1
    });
    assert!(closed);
}
