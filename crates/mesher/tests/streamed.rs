//! The stage writes `mesh.bin` streamed (spill files, cleanup from them, payload copied into the
//! artifact): the file must be byte-identical to the artifact of the mesh built in memory, for
//! cells where the cleanup keeps everything, removes islands and pockets, and asks the sinks
//! and springs; and no spill file may be left behind.

use karst_mesher::MesherView;
use karst_scene::SceneView;
use std::fs;

use karst_artifact::{Provenance, read_artifact, read_header, write_artifact};
use karst_mesher::{Mesh, MesherStage};
use karst_scene::Scene;
use karst_sdf::SdfModel;
use karst_stage::Stage;
use karst_testkit::{fixture, scratch};

/// Runs the stage on the tiny scene with `mesher` as its `[mesher]` section, streamed, and
/// compares its artifact with the in-memory mesh's; returns that mesh.
fn streamed_equals_in_memory(mesher: &str) -> Mesh {
    let out = scratch("streamed");
    fs::copy(fixture("fixtures/golden/tiny/sdf.bin"), out.join("sdf.bin")).unwrap();
    let text = fs::read_to_string(fixture("fixtures/scenes/tiny.toml")).unwrap();
    let scene_path = out.join("tiny.toml");
    fs::write(&scene_path, text.replace("[mesher]\ncell_size = 3.0\n", mesher)).unwrap();
    let ran = karst_testkit::run::<MesherStage>(&scene_path, &out).unwrap();
    let streamed = out.join("mesh.bin");

    let scene = Scene::load(&scene_path).unwrap();
    let (_, model) = read_artifact::<SdfModel>(&out.join("sdf.bin")).unwrap();
    let mesh = MesherStage::build(&MesherView::of(&scene), &(model,)).unwrap();
    let header = read_header(&streamed).unwrap();
    let provenance = Provenance {
        producer: header.producer.clone(),
        inputs: header.inputs.clone(),
        params: header.params.clone(),
        frame: header.frame(),
    };
    let in_memory = out.join("in-memory.bin");
    write_artifact(&in_memory, &provenance, &mesh).unwrap();
    assert!(fs::read(&streamed).unwrap() == fs::read(&in_memory).unwrap(), "{mesher}: the artifacts differ");
    assert_eq!(ran.headline, MesherStage::headline(&MesherView::of(&scene), &mesh));
    let left: Vec<_> = fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 4, "only the scene, sdf.bin and the two artifacts: {left:?}");
    fs::remove_dir_all(&out).unwrap();
    mesh
}

#[test]
fn the_streamed_artifact_is_the_in_memory_one() {
    // The tiny scene's own cells.
    let tiny = streamed_equals_in_memory("[mesher]\ncell_size = 3.0\n");
    // A finer cave cell: the cave's cleanup removes islands of rock between conduits, the
    // terrain's removes pockets.
    let fine = streamed_equals_in_memory("[mesher]\ncell_size = 3.0\ncave_cell_size = 1.0\n");
    assert!(fine.cave.removed.islands > 0, "{:?}", fine.cave.removed);
    assert!(fine.terrain.removed.pockets > 0, "{:?}", fine.terrain.removed);
    let golden = fs::read(fixture("fixtures/golden/tiny/mesh.bin")).unwrap();
    let payload = |bytes: &[u8]| bytes[bytes.iter().position(|&b| b == b'\n').unwrap() + 1..].to_vec();
    assert!(payload(&golden) == postcard::to_stdvec(&tiny).unwrap(), "the golden mesh changed");
    // A coarse terrain misses conduits: sealed pockets, whose verdict asks the sink and spring.
    let coarse = streamed_equals_in_memory("[mesher]\ncell_size = 6.0\ncave_cell_size = 2.0\n");
    let removed = coarse.terrain.removed.pockets + coarse.cave.removed.pockets + coarse.cave.removed.islands;
    assert!(removed > 0, "{:?} {:?}", coarse.terrain.removed, coarse.cave.removed);
}

#[test]
fn a_failed_write_leaves_no_spill_file() {
    // The artifact's path is a folder: the spills are written, cleaned, then the write fails.
    let out = scratch("streamed-failure");
    fs::copy(fixture("fixtures/golden/tiny/sdf.bin"), out.join("sdf.bin")).unwrap();
    fs::create_dir(out.join("mesh.bin")).unwrap();
    let scene = fixture("fixtures/scenes/tiny.toml");
    let err = karst_testkit::run::<MesherStage>(&scene, &out).unwrap_err();
    assert!(format!("{err:#}").contains("mesh.bin: cannot write"), "{err:#}");
    assert_eq!(err.exit_code(), 1, "the machine's fault, not the scene's");
    let left: Vec<_> = fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    fs::remove_dir_all(&out).unwrap();
}
