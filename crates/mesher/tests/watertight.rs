//! The mesher's promises on a small carved terrain: closed, 2-manifold, consistently oriented,
//! no degenerate triangle, the right volume, and the same bytes whatever the thread count.

use std::collections::HashMap;

use karst_geology::Domain;
use karst_mesher::Mesh;
use karst_mesher::polygonize::polygonize;
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};

fn model() -> SdfModel {
    SdfModel {
        capsules: vec![
            Capsule { a: [10.0, 20.0, 28.0], b: [15.0, 20.0, 12.0], radius: 2.5 },
            Capsule { a: [15.0, 20.0, 12.0], b: [50.0, 22.0, 10.0], radius: 3.0 },
            // A sealed pocket, entirely in rock.
            Capsule { a: [40.0, 8.0, 5.0], b: [44.0, 8.0, 5.0], radius: 2.0 },
        ],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [60.0, 40.0, 30.0] },
            TerrainField::Plane { elevation: 25.0, origin: [0.0, 0.0], gradient: [0.05, 0.02] },
        )
    }
}

fn mesh_with_threads(threads: usize, cell: f64) -> Mesh {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| polygonize(&CarvedTerrain::new(model()), cell))
}

#[test]
fn closed_oriented_manifold_without_degenerate_triangles() {
    let mesh = mesh_with_threads(2, 1.0);
    assert!(!mesh.triangles.is_empty());
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for e in 0..3 {
            *directed.entry((t[e], t[(e + 1) % 3])).or_default() += 1;
        }
        let [a, b, c] = t.map(|i| glam::Vec3::from_array(mesh.vertices[i as usize]).as_dvec3());
        assert!((b - a).cross(c - a).length() > 1e-9, "degenerate triangle {t:?}");
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge {a}→{b} used {n} times in one direction");
        assert_eq!(directed.get(&(b, a)), Some(&1), "edge {a}→{b} has no twin");
    }
}

#[test]
fn volume_is_the_rock_volume() {
    let mesh = mesh_with_threads(2, 0.5);
    // Rock under the tilted plane, minus the caves (the sealed pocket and the conduits).
    let under_terrain: f64 = 60.0 * 40.0 * (25.0 + 0.05 * 30.0 + 0.02 * 20.0);
    let pocket = std::f64::consts::PI * 4.0 * 4.0 + 4.0 / 3.0 * std::f64::consts::PI * 8.0;
    let volume = mesh.enclosed_volume();
    assert!(volume < under_terrain - pocket, "{volume}");
    assert!(volume > under_terrain - pocket - 2000.0, "{volume}: the conduits are far smaller");
}

#[test]
fn obj_reads_back_with_tobj() {
    let mesh = mesh_with_threads(2, 2.0);
    let path = std::env::temp_dir().join(format!("karst-mesher-{}.obj", std::process::id()));
    mesh.write_obj(&path).unwrap();
    let (models, _) = tobj::load_obj(&path, &tobj::LoadOptions::default()).unwrap();
    let m = &models[0].mesh;
    assert_eq!(m.positions.len(), mesh.vertices.len() * 3);
    assert_eq!(m.indices.len(), mesh.triangles.len() * 3);
    assert_eq!(m.indices[..3], mesh.triangles[0]);
    std::fs::remove_file(path).unwrap();
}

#[test]
fn same_mesh_with_one_or_two_threads() {
    assert_eq!(mesh_with_threads(1, 1.5), mesh_with_threads(2, 1.5));
}
