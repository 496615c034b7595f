//! Recovery and concurrency (issue 15): one run per output folder, side files committed with
//! their stage, leftovers of killed runs swept, stale inputs refused, and decoded payloads
//! that are wrong refused by every reader (run, inspect, render) with exit code 2, never a
//! panic.

use std::fs;
use std::path::Path;

use karst_artifact::{Payload, Provenance, StageId, read_artifact, write_artifact};
use karst_pipeline::make::{Outcome, Selection};
use karst_stage::StageError;
use karstgen_tests::{root, run, scratch};

fn tiny_in(out: &Path) -> std::path::PathBuf {
    let scene = out.join("scene.toml");
    fs::copy(root().join("fixtures/scenes/tiny.toml"), &scene).unwrap();
    scene
}

#[test]
fn a_second_run_into_the_same_folder_is_refused_while_the_first_writes() {
    let out = scratch("busy");
    let scene = tiny_in(&out);
    let first = karst_artifact::lock_output(&out).unwrap();
    let err = run(&scene, &out, &Selection::default()).unwrap_err();
    assert!(err.to_string().contains(&format!("another run is writing to {}", out.display())), "{err}");
    assert_eq!(err.exit_code(), 1);
    assert!(!out.join("samples.bin").exists());
    // Exports on demand and the viewer write into the run folder too: they wait their turn.
    let args = karst_export::stage::ExportArgs {
        dir: out.to_path_buf(),
        format: vec!["csv".into()],
        scene: None,
        json: false,
        budget: None,
    };
    let err = karst_export::stage::export_run(&args).unwrap_err();
    assert!(err.to_string().contains("another run is writing to"), "{err}");
    drop(first);
    run(&scene, &out, &Selection { to: Some(StageId::Sampling), ..Selection::default() }).unwrap();
    let second = karst_artifact::lock_output(&out).unwrap();
    let err = karst_view::write_view(&out, Some(&scene)).unwrap_err();
    assert!(err.to_string().contains("another run is writing to"), "{err}");
    drop(second);
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn a_stage_whose_side_files_fail_leaves_no_artifact_that_claims_them() {
    let out = scratch("sides");
    let scene = tiny_in(&out);
    run(&scene, &out, &Selection::default()).unwrap();
    // Another mesh is asked for, and the export's VTK file cannot be written (a folder stands
    // in its way), as if the disk filled up or the run was killed while exporting.
    let text = fs::read_to_string(&scene).unwrap();
    fs::write(&scene, text.replace("cell_size = 3.0", "cell_size = 3.5")).unwrap();
    let vtk = out.join("export/network.vtp");
    fs::remove_file(&vtk).unwrap();
    fs::create_dir_all(vtk.join("blocked")).unwrap();
    let err = run(&scene, &out, &Selection::default()).unwrap_err();
    assert!(err.to_string().contains("cannot write the export stage's files"), "{err}");
    assert!(!out.join("export.json").exists(), "the old export.json would claim the half-written exports");
    // Back to the first scene: the export runs again instead of being "up to date" over
    // exports of another mesh.
    fs::remove_dir_all(&vtk).unwrap();
    fs::write(&scene, &text).unwrap();
    let reports = run(&scene, &out, &Selection::default()).unwrap();
    let export = reports.iter().find(|r| r.stage == StageId::Export).unwrap();
    assert!(matches!(export.outcome, Outcome::Ran { .. }), "{:?}", export.outcome);
    assert!(vtk.is_file());
    assert!(!out.join(".export.json.previous").exists());
    fs::remove_dir_all(&out).unwrap();
}

/// A process id that runs no more: a finished child's.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

#[test]
fn leftovers_of_killed_runs_are_swept_and_live_writers_kept() {
    let out = scratch("leftovers");
    let scene = tiny_in(&out);
    let dead = dead_pid();
    fs::create_dir_all(out.join("export")).unwrap();
    let stale = [out.join(format!(".mesh.bin.tmp-{dead}")), out.join(format!("export/.cave.obj.tmp-{dead}"))];
    for file in &stale {
        fs::write(file, b"torn").unwrap();
    }
    // Another process writing a picture into the folder (its pid is alive: our parent's).
    let live = out.join(format!(".render.png.tmp-{}", std::os::unix::process::parent_id()));
    fs::write(&live, b"in progress").unwrap();
    run(&scene, &out, &Selection { to: Some(StageId::Sampling), ..Selection::default() }).unwrap();
    for file in &stale {
        assert!(!file.exists(), "{} was left behind", file.display());
    }
    assert!(live.exists());
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn previous_artifacts_left_by_a_killed_run_are_removed_by_the_next() {
    let out = scratch("previous");
    let scene = tiny_in(&out);
    let to_costgraph = Selection { to: Some(StageId::Costgraph), ..Selection::default() };
    run(&scene, &out, &to_costgraph).unwrap();
    // Killed after the new costgraph.bin replaced the old one, before the old one was deleted;
    // a temporary file of the killed writer too, and files of the user's that look alike.
    let previous = out.join(".costgraph.bin.previous");
    fs::copy(out.join("costgraph.bin"), &previous).unwrap();
    let temporary = out.join(format!(".costgraph.bin.tmp-{}", dead_pid()));
    fs::write(&temporary, b"torn").unwrap();
    let users = [out.join(".notes.txt.previous"), out.join("costgraph.bin.previous")];
    for file in &users {
        fs::write(file, b"mine").unwrap();
    }
    let reports = run(&scene, &out, &to_costgraph).unwrap();
    let costgraph = reports.iter().find(|r| r.stage == StageId::Costgraph).unwrap();
    assert!(matches!(costgraph.outcome, Outcome::UpToDate), "{:?}", costgraph.outcome);
    assert!(!previous.exists(), "the stale .previous was left behind");
    assert!(!temporary.exists(), "the stale temporary file was left behind");
    for file in &users {
        assert!(file.exists(), "{} is not karstgen's to delete", file.display());
    }
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn inputs_made_from_another_upstream_artifact_are_refused() {
    let out = scratch("mixed");
    let scene = tiny_in(&out);
    run(&scene, &out, &Selection { to: Some(StageId::Costgraph), ..Selection::default() }).unwrap();
    // Resample with another seed only: costgraph.bin now belongs to the old samples.
    let text = fs::read_to_string(&scene).unwrap();
    fs::write(&scene, text.replace("seed = 7", "seed = 8")).unwrap();
    run(&scene, &out, &Selection { only: Some(StageId::Sampling), ..Selection::default() }).unwrap();
    let err =
        run(&scene, &out, &Selection { only: Some(StageId::Skeleton), ..Selection::default() }).unwrap_err();
    let message = err.to_string();
    assert!(message.contains("costgraph.bin: was made from another samples.bin"), "{message}");
    assert!(message.contains("--from costgraph"), "{message}");
    assert_eq!(err.exit_code(), 2);
    fs::remove_dir_all(&out).unwrap();
}

/// A forger of the artifact at `path`: each forgery is its good payload with `edit` applied,
/// written with a right checksum.
fn forger<P: Payload + Clone>(path: &Path) -> impl Fn(&dyn Fn(&mut P)) {
    let (header, good) = read_artifact::<P>(path).unwrap();
    let frame = header.frame();
    let provenance =
        Provenance { producer: header.producer, inputs: header.inputs, params: header.params, frame };
    let path = path.to_path_buf();
    move |edit| {
        let mut payload = good.clone();
        edit(&mut payload);
        write_artifact(&path, &provenance, &payload).unwrap();
    }
}

fn bad_input(result: Result<impl std::fmt::Debug, StageError>) -> String {
    match result {
        Err(e @ StageError::BadInput(_)) => e.to_string(),
        other => panic!("expected bad input, got {other:?}"),
    }
}

#[test]
fn wrong_payloads_with_right_checksums_are_refused_by_every_reader() {
    let out = scratch("forged");
    let scene = tiny_in(&out);
    run(&scene, &out, &Selection::default()).unwrap();
    let skeleton = out.join("skeleton.json");
    forger::<karst_skeleton::Skeleton>(&skeleton)(&|s| s.conduits[0].nodes[1] = 1_000_000_000);
    let message = bad_input(karst_pipeline::registry::inspect(&skeleton));
    assert!(message.contains("skeleton.json: conduits[0].nodes[1]: 1000000000 is out of range"), "{message}");
    let args =
        karst_skeleton::stage::RenderArgs { file: skeleton.clone(), png: out.join("s.png"), title: None };
    bad_input(karst_skeleton::stage::render(&args));
    let message =
        bad_input(run(&scene, &out, &Selection { only: Some(StageId::Hydro), ..Selection::default() }));
    assert!(message.contains("rerun the pipeline from skeleton"), "{message}");

    let mesh = out.join("mesh.bin");
    let forge = forger::<karst_mesher::Mesh>(&mesh);
    forge(&|m| m.cave.triangles[3][2] = u32::MAX);
    let message = bad_input(karst_pipeline::registry::inspect(&mesh));
    assert!(message.contains("mesh.bin: cave.triangles[3]: 4294967295 is out of range"), "{message}");
    let args = karst_mesher::stage::RenderArgs {
        file: mesh.clone(),
        png: out.join("m.png"),
        surface: "cave".into(),
        width: 64,
        height: 64,
    };
    bad_input(karst_mesher::stage::render(&args));
    let args = karst_export::stage::ExportArgs {
        dir: out.to_path_buf(),
        format: vec!["obj".into()],
        scene: None,
        json: false,
        budget: None,
    };
    let message = bad_input(karst_export::stage::export_run(&args));
    assert!(message.contains("cave.triangles[3]"), "{message}");
    forge(&|m| m.terrain = Default::default());
    let message = bad_input(karst_pipeline::registry::inspect(&mesh));
    assert!(message.contains("terrain.triangles: is empty"), "{message}");

    let graph = out.join("costgraph.bin");
    let forge = forger::<karst_costgraph::CostGraph>(&graph);
    forge(&|g| g.cost_sets.clear());
    let message = bad_input(karst_pipeline::registry::inspect(&graph));
    assert!(message.contains("cost_sets: is empty"), "{message}");
    forge(&|g| g.cost_sets[0].min_cost_per_metre = Some(f64::NAN));
    let message = bad_input(karst_pipeline::registry::inspect(&graph));
    assert!(message.contains("cost_sets[0].min_cost_per_metre: NaN"), "{message}");
    forge(&|g| g.targets[5] = 9_999_999);
    bad_input(karst_pipeline::registry::inspect(&graph));

    let samples = out.join("samples.bin");
    let forge = forger::<karst_sampling::Samples>(&samples);
    forge(&|s| s.positions[7] = [f64::NAN, 0.0, 0.0]);
    let message = bad_input(karst_pipeline::registry::inspect(&samples));
    assert!(message.contains("positions[7]: [NaN, 0.0, 0.0] is not a finite position"), "{message}");
    forge(&|s| s.tags.truncate(5));
    bad_input(karst_pipeline::registry::inspect(&samples));
    // Two samples, the key points only: nothing for a conduit to run through.
    forge(&|s| {
        s.positions.truncate(2);
        s.tags.truncate(2);
        assert!(s.tags.iter().all(|t| matches!(t, karst_sampling::Tag::KeyPoint(_))));
    });
    let message = bad_input(karst_pipeline::registry::inspect(&samples));
    assert!(message.contains("samples.bin: tags: all 2 samples are key points"), "{message}");

    let sdf = out.join("sdf.bin");
    let forge = forger::<karst_sdf::SdfModel>(&sdf);
    forge(&|m| m.domain.max[2] = f64::NAN);
    let message = bad_input(karst_pipeline::registry::inspect(&sdf));
    assert!(message.contains("domain.max"), "{message}");
    forge(&|m| m.domain.max[0] = m.domain.min[0] - 1.0);
    let message = bad_input(karst_pipeline::registry::inspect(&sdf));
    assert!(message.contains("is not a box of positive extent"), "{message}");

    let hydro = out.join("hydro.json");
    forger::<karst_hydro::Hydro>(&hydro)(&|h| h.conduits[0].segments[0].depth = -1.0);
    let message = bad_input(karst_pipeline::registry::inspect(&hydro));
    assert!(message.contains("conduits[0].segments[0].depth: -1 is not a finite number"), "{message}");
    fs::remove_dir_all(&out).unwrap();
}

/// Rewrites the postcard artifact at `path` with `extra` bytes after its payload and a header
/// whose `payload_len` and digest cover them: a length one too large, checksum and all right.
fn lengthen_payload(path: &Path, extra: &[u8]) {
    let bytes = fs::read(path).unwrap();
    let end = bytes.iter().position(|&b| b == b'\n').unwrap();
    let mut header: serde_json::Value = serde_json::from_slice(&bytes[..end]).unwrap();
    let mut payload = bytes[end + 1..].to_vec();
    payload.extend_from_slice(extra);
    header["payload_len"] = payload.len().into();
    header["payload_blake3"] = karst_artifact::hash::hex(&payload).into();
    let mut forged = serde_json::to_vec(&header).unwrap();
    forged.push(b'\n');
    forged.extend_from_slice(&payload);
    fs::write(path, forged).unwrap();
}

#[test]
fn samples_of_another_scene_and_an_sdf_longer_than_its_fields_are_refused_naming_the_file() {
    let out = scratch("foreign");
    let scene = tiny_in(&out);
    run(&scene, &out, &Selection { to: Some(StageId::Sdf), ..Selection::default() }).unwrap();
    // A surface tag naming a fault the scene does not have (tag 99), checksums right.
    let samples = out.join("samples.bin");
    forger::<karst_sampling::Samples>(&samples)(&|s| {
        let volume = s.tags.iter().position(|t| *t == karst_sampling::Tag::Volume).unwrap();
        s.tags[volume] = karst_sampling::Tag::Fault(99);
    });
    let (_, forged) = read_artifact::<karst_sampling::Samples>(&samples).unwrap();
    let foreign = forged.tags.iter().position(|t| *t == karst_sampling::Tag::Fault(99)).unwrap();
    let only = |stage| Selection { only: Some(stage), ..Selection::default() };
    let err = run(&scene, &out, &only(StageId::Costgraph)).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    let expected = format!("samples.bin: tags[{foreign}] is fault 99, which the scene does not have");
    assert!(message.contains(&expected), "{message}");

    // An sdf.bin whose payload is one byte longer than its fields.
    let sdf = out.join("sdf.bin");
    lengthen_payload(&sdf, &[0]);
    let err = run(&scene, &out, &only(StageId::Mesher)).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    // A zero byte decodes as a tag of the trailing full-detail field, which refuses it.
    let past_the_fields = ["the payload's fields end at byte", "cannot decode the sdf payload"];
    assert!(message.contains("sdf.bin") && past_the_fields.iter().any(|m| message.contains(m)), "{message}");
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn the_export_removes_only_files_its_previous_manifest_lists_and_refuses_forged_ones() {
    let out = scratch("manifest");
    let scene = tiny_in(&out);
    let text = fs::read_to_string(&scene).unwrap();
    run(&scene, &out, &Selection::default()).unwrap();
    assert!(out.join("export/nodes.csv").is_file());
    // Fewer formats: the files of the last export that this one does not write go, found in
    // its manifest (moved aside while the export is rewritten, deleted after).
    fs::write(&scene, format!("{text}\n[export]\nformats = [\"vtk\"]\n")).unwrap();
    run(&scene, &out, &Selection::default()).unwrap();
    assert!(out.join("export/network.vtp").is_file());
    assert!(!out.join("export/nodes.csv").exists());
    assert!(!out.join(".export.json.previous").exists());

    let manifest = out.join("export.json");
    forger::<karst_export::Manifest>(&manifest)(&|m| m.files[0].name = "../scene.toml".into());
    let message = bad_input(karst_pipeline::registry::inspect(&manifest));
    assert!(message.contains("files[0].name: \"../scene.toml\" is not a file name"), "{message}");
    // The next export reads the forged manifest for the files to remove: refused, nothing
    // outside export/ is touched.
    fs::write(&scene, &text).unwrap();
    run(&scene, &out, &Selection::default()).unwrap();
    assert!(scene.is_file());
    assert!(out.join("export/nodes.csv").is_file());
    fs::remove_dir_all(&out).unwrap();
}
