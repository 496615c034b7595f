//! Every export format checked by the tool it targets: VTK's reader, karstnet 1.2.5, Survex's
//! cavern, EPA SWMM 5.2's engine, the Khronos glTF-Validator; the TSurf by karstgen's own
//! reader (the one that reads users' horizons) and the CSV tables by karst-metrics' reader.

mod common;

use std::path::Path;

use common::{Run, export_run, export_with, network_run, python_json, run_tool, tiny, validate_gltf};
use karst_export::ExportFormat;
use karst_hydro::WaterType;
use karst_skeleton::ConduitType;

fn values(report: &serde_json::Value, section: &str, name: &str) -> Vec<f64> {
    let array = &report[section][name]["values"];
    array
        .as_array()
        .unwrap_or_else(|| panic!("{section}.{name} missing: {report}"))
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

#[test]
fn vtk_reads_the_network_with_the_artifacts_counts_and_arrays() {
    for scene in ["default", "karstnsim"] {
        let run = Run::load(&network_run(scene));
        let (_scratch, dir, _) = export_run(&run, &[ExportFormat::Vtk], &format!("vtk-{scene}"));
        let file = dir.join("network.vtp");
        let report = python_json("read_vtp.py", &[file.to_str().unwrap()]);
        assert_eq!(report["log"], "", "{scene}: VTK wrote errors or warnings");
        let (skeleton, hydro) = (&run.skeleton, &run.hydro);
        assert_eq!(report["points"], skeleton.nodes.len());
        let segments: Vec<_> = hydro.conduits.iter().flat_map(|c| &c.segments).collect();
        assert_eq!(report["lines"], segments.len());
        assert_eq!(report["point_type"], "double");
        let z: Vec<f64> = skeleton.nodes.iter().map(|n| n.position[2]).collect();
        assert_eq!(values(&report, "point_data", "elevation"), z);
        let flows: Vec<f64> = segments.iter().map(|s| s.flow).collect();
        assert_eq!(values(&report, "cell_data", "flow"), flows);
        let depths: Vec<f64> = segments.iter().map(|s| s.depth).collect();
        assert_eq!(values(&report, "cell_data", "water_depth"), depths);
        let water: Vec<f64> = segments
            .iter()
            .map(|s| WaterType::ALL.iter().position(|w| *w == s.water).unwrap() as f64)
            .collect();
        assert_eq!(values(&report, "cell_data", "water_type"), water);
        let types: Vec<f64> = skeleton
            .conduits
            .iter()
            .flat_map(|c| &c.types)
            .map(|t| ConduitType::ALL.iter().position(|k| k == t).unwrap() as f64)
            .collect();
        assert_eq!(values(&report, "cell_data", "conduit_type"), types);
        let conduit_ids: Vec<f64> = skeleton
            .conduits
            .iter()
            .enumerate()
            .flat_map(|(i, c)| std::iter::repeat_n((i + 1) as f64, c.nodes.len() - 1))
            .collect();
        assert_eq!(values(&report, "cell_data", "conduit_id"), conduit_ids);
        let mut radius = vec![0.0f64; skeleton.nodes.len()];
        for c in &skeleton.conduits {
            for (n, r) in c.nodes.iter().zip(&c.radius) {
                radius[*n as usize] = radius[*n as usize].max(*r);
            }
        }
        assert_eq!(values(&report, "point_data", "radius"), radius);
        let orders = values(&report, "cell_data", "strahler_order");
        for (s, order) in segments.iter().zip(&orders) {
            assert_eq!(s.flow > 0.0, *order >= 1.0, "{scene}: wet segments and only they have an order");
        }
        let sinks = hydro.sinks.len() as f64;
        let max_order = orders.iter().copied().fold(0.0, f64::max);
        assert!(max_order >= 1.0 && max_order <= sinks.log2().floor() + 1.0, "{scene}: order {max_order}");
    }
}

#[test]
fn vtk_and_csv_carry_the_surface_streams_with_types_flows_and_falls() {
    let run = Run::load(&network_run("waterfall"));
    let streams = &run.streams;
    assert!(streams.falls() >= 3, "the waterfall preset has falls");
    let (_scratch, dir, _) = export_run(&run, &[ExportFormat::Vtk, ExportFormat::Csv], "streams");
    let report = python_json("read_vtp.py", &[dir.join("streams.vtp").to_str().unwrap()]);
    assert_eq!(report["log"], "", "VTK wrote errors or warnings");
    assert_eq!(report["points"], streams.nodes.len());
    assert_eq!(report["lines"], streams.segments.len());
    let code = |w: WaterType| WaterType::ALL.iter().position(|k| *k == w).unwrap() as f64;
    let water: Vec<f64> = streams.segments.iter().map(|s| code(s.water)).collect();
    assert_eq!(values(&report, "cell_data", "water_type"), water);
    let flows = values(&report, "cell_data", "flow");
    for (s, flow) in streams.segments.iter().zip(&flows) {
        assert!((s.flow - flow).abs() <= 1e-12 * flow, "{flow} vs {}", s.flow);
    }
    // The report's JSON is parsed without exact float round trips: the last bit may differ.
    let lengths = values(&report, "cell_data", "length");
    for (s, length) in streams.segments.iter().zip(&lengths) {
        assert!((streams.length(s) - length).abs() <= 1e-12 * length, "{length} vs {}", streams.length(s));
    }
    let drops = values(&report, "cell_data", "drop");
    for (s, drop) in streams.segments.iter().zip(&drops) {
        let expected = s.fall.as_ref().map_or(0.0, |f| f.drop);
        assert!((expected - drop).abs() <= 1e-12 * drop, "{drop} vs {expected}");
    }
    let inflow = values(&report, "point_data", "inflow");
    for (n, q) in streams.nodes.iter().zip(&inflow) {
        assert!((n.inflow - q).abs() <= 1e-12 * q, "{q} vs {}", n.inflow);
    }

    let table = std::fs::read_to_string(dir.join("stream_segments.csv")).unwrap();
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), streams.segments.len());
    for (row, s) in rows.iter().zip(&streams.segments) {
        assert_eq!(row.len(), header.len());
        assert_eq!(row[column("water")], s.water.name());
        assert_eq!(row[column("flow")].parse::<f64>().unwrap(), s.flow);
        let from = row[column("from")].parse::<usize>().unwrap();
        assert_eq!(from, s.from as usize + 1, "1-based ids");
        assert_eq!(row[column("motion")] == "free_fall", s.fall.is_some());
    }
    let nodes = std::fs::read_to_string(dir.join("stream_nodes.csv")).unwrap();
    assert_eq!(nodes.lines().count(), 1 + streams.nodes.len());
}

#[test]
fn vtk_reads_the_meshes_with_their_normals() {
    let run = Run::load(&tiny());
    let (_scratch, dir, _) = export_run(&run, &[ExportFormat::VtkMeshes], "vtk-meshes");
    let mesh = run.mesh.as_ref().unwrap();
    for (name, surface) in mesh.surfaces() {
        let file = dir.join(format!("{name}.vtp"));
        let report = python_json("read_vtp.py", &[file.to_str().unwrap(), "--counts"]);
        assert_eq!(report["log"], "", "{name}");
        assert_eq!(report["points"], surface.vertices.len(), "{name}");
        assert_eq!(report["polys"], surface.triangles.len(), "{name}");
        if !surface.triangles.is_empty() {
            assert_eq!(report["has_normals"], true, "{name}");
            let first: Vec<f64> = surface.vertices[0].iter().map(|&c| f64::from(c)).collect();
            assert_eq!(
                report["first_points"][0]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect::<Vec<_>>(),
                first
            );
        }
    }
}

#[test]
fn karstnet_reads_the_pline_and_finds_metrics_json() {
    for scene in ["default", "karstnsim", "branchwork"] {
        let run = Run::load(&network_run(scene));
        let (_scratch, dir, _) = export_run(&run, &[ExportFormat::Gocad], &format!("pline-{scene}"));
        let oracle = common::root().join("crates/metrics/tests/karstnet_oracle.py");
        let out = std::process::Command::new(common::python())
            .arg(oracle)
            .arg(dir.join("network.pl"))
            .output()
            .expect("run karstnet (cargo xtask test installs it)");
        assert!(out.status.success(), "{scene}: karstnet failed: {}", String::from_utf8_lossy(&out.stderr));
        let theirs: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(run.metrics.karstnet.len(), 10);
        for (key, ours) in &run.metrics.karstnet {
            let theirs = theirs[key].as_f64().unwrap_or_else(|| panic!("{scene}: karstnet has no {key}"));
            assert!(
                (ours.value - theirs).abs() <= 1e-9 * theirs.abs().max(1.0),
                "{scene}: {key}: {} vs {theirs}",
                ours.value
            );
        }
        let vset = std::fs::read_to_string(dir.join("samples.vs")).unwrap();
        assert_eq!(vset.lines().filter(|l| l.starts_with("PVRTX ")).count(), run.samples.len());
    }
}

#[test]
fn tsurfs_read_back_to_the_same_vertices() {
    let run = Run::load(&tiny());
    let (_scratch, dir, _) = export_run(&run, &[ExportFormat::GocadMeshes], "tsurf");
    for (name, surface) in run.mesh.as_ref().unwrap().surfaces() {
        if surface.triangles.is_empty() {
            continue;
        }
        let tin =
            karst_geology::tin::Tin::read(&dir.join(format!("{name}.ts"))).unwrap_or_else(|e| panic!("{e}"));
        let back: Vec<[f32; 3]> = tin.vertices.iter().map(|v| v.map(|c| c as f32)).collect();
        assert_eq!(back, surface.vertices, "{name}");
        assert_eq!(tin.triangles, surface.triangles, "{name}");
    }
}

/// Legs and their total length in a `dump3d` listing: every LINE from the point before it.
fn legs_of_dump(dump: &str) -> (usize, f64) {
    let (mut legs, mut length, mut at) = (0, 0.0, [0.0f64; 3]);
    for line in dump.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if matches!(words.first(), Some(&"MOVE") | Some(&"LINE")) && words.len() >= 4 {
            let p: [f64; 3] = std::array::from_fn(|i| words[i + 1].parse().unwrap());
            if words[0] == "LINE" {
                legs += 1;
                length += (0..3).map(|i| (p[i] - at[i]).powi(2)).sum::<f64>().sqrt();
            }
            at = p;
        }
    }
    (legs, length)
}

#[test]
fn cavern_processes_the_survey_without_warning_with_every_leg() {
    for scene in ["default", "karstnsim", "branchwork"] {
        let run = Run::load(&network_run(scene));
        let (_scratch, dir, _) = export_run(&run, &[ExportFormat::Survex], &format!("survex-{scene}"));
        let out = run_tool("cavern", &["network.svx"], &dir);
        let text =
            format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "{scene}: cavern failed:\n{text}");
        let lower = text.to_lowercase();
        assert!(!lower.contains("warning") && !lower.contains("error"), "{scene}: cavern said:\n{text}");
        let dump = run_tool("dump3d", &["network.3d"], &dir);
        assert!(dump.status.success());
        let (legs, length) = legs_of_dump(&String::from_utf8_lossy(&dump.stdout));
        let segments =
            run.skeleton.conduits.iter().flat_map(|c| c.nodes.windows(2)).filter(|w| w[0] != w[1]).count();
        assert_eq!(legs, segments, "{scene}");
        let expected = run.skeleton.total_length();
        assert!(
            (length - expected).abs() <= 1e-3 * expected,
            "{scene}: {length} m of legs, skeleton {expected} m"
        );
    }
}

/// One spring in the engine's run: SWMM's outfall inflow over the last tenth of the run, over
/// the tenth before it, its range over the last tenth, and hydro's discharge (m³/s).
struct Outfall {
    name: String,
    last: f64,
    before: f64,
    range: [f64; 2],
    hydro: f64,
}

/// The SWMM model of a run, run by the real engine: (continuity error %, springs, notes).
fn swmm_run(scene: &str) -> (f64, Vec<Outfall>, Vec<String>) {
    let run = Run::load(&network_run(scene));
    let (_scratch, dir, _) = export_run(&run, &[ExportFormat::Swmm], &format!("swmm-{scene}"));
    let view = karst_export::NetworkView::new(&run.skeleton, &run.hydro).unwrap();
    let names: Vec<String> = view.springs.iter().map(|s| s.name.clone()).collect();
    let model = dir.join("network.inp");
    let mut args = vec![model.to_str().unwrap()];
    args.extend(names.iter().map(String::as_str));
    let report = python_json("run_swmm.py", &args);
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{scene}: {report}"));
    let springs = view
        .springs
        .iter()
        .map(|s| Outfall {
            name: s.name.clone(),
            last: number(&report["outfalls"][&s.name]),
            before: number(&report["outfalls_before"][&s.name]),
            range: [0, 1].map(|i| number(&report["outfalls_range"][&s.name][i])),
            hydro: s.discharge,
        })
        .collect();
    let notes = report["notes"].as_array().unwrap().iter().map(|n| n.as_str().unwrap().to_string()).collect();
    std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
    (number(&report["continuity_error"]), springs, notes)
}

#[test]
fn swmm_runs_steadily_to_what_hydro_says_with_a_continuity_error_under_one_percent() {
    swmm_is_steady(&["default", "karstnsim", "branchwork"]);
}

/// The default runs have passage profiles (`passage_detail = "full"`): rooms and pinches along
/// the chains, short full conduits of a room's section, which the engine routes steadily only
/// with its conduit lengthening and enough trials per step (docs/exports.md). Without them
/// (`off`) the chains are smooth tubes, steady too.
#[test]
fn swmm_runs_steadily_without_passage_profiles() {
    swmm_is_steady(&["default:off", "branchwork:off"]);
}

fn swmm_is_steady(scenes: &[&str]) {
    for &scene in scenes {
        let (continuity, springs, notes) = swmm_run(scene);
        // WARNING 04 says a conduit drops less than SWMM's 0.001 ft and the engine used that
        // minimum drop: horizontal passages (tributaries in the bedding plane) are real geometry,
        // not a fault of the model. Every other warning fails the test.
        let notes: Vec<&String> = notes.iter().filter(|n| !n.starts_with("WARNING 04:")).collect();
        assert!(notes.is_empty(), "{scene}: the engine warned: {notes:?}");
        assert!(continuity.abs() < 1.0, "{scene}: flow-routing continuity error {continuity} %");
        // A spring hydro leaves dry may get what SWMM lets through a closed conduit: its
        // MaxFlow, 0.000001 m³/s (SWMM reads 0 as no limit; docs/exports.md).
        const CLOSED_FLOW: f64 = 1e-6;
        for s in springs {
            let (name, hydro) = (&s.name, s.hydro);
            assert!(
                (s.last - hydro).abs() <= 0.02 * hydro + CLOSED_FLOW,
                "{scene}: spring {name}: SWMM {} m³/s at the end, hydro {hydro} m³/s",
                s.last
            );
            assert!(
                (s.last - s.before).abs() <= 0.002 * hydro + CLOSED_FLOW
                    && s.range[1] - s.range[0] <= 0.02 * hydro + CLOSED_FLOW,
                "{scene}: spring {name} not steady: {} then {} m³/s, range {:?} at the end",
                s.before,
                s.last,
                s.range
            );
        }
    }
}

#[test]
fn gltf_validator_accepts_the_scene_with_named_nodes_and_typed_lines() {
    let run = Run::load(&tiny());
    let (_scratch, dir, manifest) = export_run(&run, &[ExportFormat::Gltf], "gltf");
    assert_eq!(manifest.files.len(), 1);
    let file = dir.join("karst.glb");
    let report = validate_gltf(&file);
    let issues = &report["issues"];
    assert_eq!(
        (issues["numErrors"].as_u64(), issues["numWarnings"].as_u64()),
        (Some(0), Some(0)),
        "{issues}"
    );
    let bytes = std::fs::read(&file).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let names: Vec<&str> =
        doc["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["terrain", "cave", "water", "network", "karst"]);
    assert_eq!(doc["scenes"][0]["nodes"], serde_json::json!([4]));
    assert_eq!(doc["nodes"][4]["children"], serde_json::json!([0, 1, 2, 3]));
    assert_eq!(doc["nodes"][4]["translation"], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(doc["scenes"][0]["extras"]["origin"], serde_json::json!([0.0, 0.0, 0.0]));
    let network = &doc["meshes"][doc["nodes"][3]["mesh"].as_u64().unwrap() as usize];
    let used: std::collections::BTreeSet<&str> =
        run.skeleton.conduits.iter().flat_map(|c| &c.types).map(|t| t.name()).collect();
    let primitives = network["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), used.len());
    for p in primitives {
        assert_eq!(p["mode"], 1, "line primitives");
        let material = &doc["materials"][p["material"].as_u64().unwrap() as usize];
        assert!(used.contains(material["name"].as_str().unwrap()));
    }
}

#[test]
fn gltf_over_its_bound_is_simplified_within_it_and_validates() {
    let run = Run::load(&tiny());
    let full = karst_export::ExportParams {
        formats: vec![ExportFormat::Gltf],
        gltf_full: true,
        ..karst_export::ExportParams::default()
    };
    let (_full_scratch, _, whole) = export_with(&run, &full, "gltf-full");
    // A bound of a third of the full file: the surfaces must lose about two thirds of their bytes.
    let bound_mb = whole.files[0].bytes as f64 / 3.0 / (1u64 << 20) as f64;
    let bounded = karst_export::ExportParams { gltf_full: false, gltf_max_mb: Some(bound_mb), ..full };
    let (_scratch, dir, manifest) = export_with(&run, &bounded, "gltf-bounded");
    let bytes = manifest.files[0].bytes as f64;
    let bound = bound_mb * (1u64 << 20) as f64;
    assert!(bytes <= bound && bytes >= 0.5 * bound, "{bytes} bytes for a bound of {bound}");
    let file = dir.join("karst.glb");
    let issues = &validate_gltf(&file)["issues"];
    assert_eq!(
        (issues["numErrors"].as_u64(), issues["numWarnings"].as_u64()),
        (Some(0), Some(0)),
        "{issues}"
    );
    let glb = std::fs::read(&file).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let mesh = run.mesh.as_ref().unwrap();
    for (i, surface) in [&mesh.terrain, &mesh.cave, &mesh.water].into_iter().enumerate() {
        let simplified = &doc["nodes"][i]["extras"]["simplified"];
        if surface.triangles.is_empty() {
            continue;
        }
        assert_eq!(simplified["full_triangles"].as_u64(), Some(surface.triangles.len() as u64));
        let kept = simplified["triangles"].as_u64().unwrap() as usize;
        assert!(kept < surface.triangles.len() / 2, "node {i}: {kept} of {}", surface.triangles.len());
    }
}

#[test]
fn csv_tables_read_back_with_karst_metrics() {
    let dir = network_run("karstnsim");
    let run = Run::load(&dir);
    let (_scratch, export_dir, _) = export_run(&run, &[ExportFormat::Csv], "csv");
    // Links come in another order than the skeleton's: sums may differ in the last digit.
    let expected = run.metrics.network.to_pairs();
    let check = |nodes: &Path, links: &Path| {
        let net = karst_metrics::readers::read_csv(nodes, links).unwrap_or_else(|e| panic!("{e}"));
        let found = karst_metrics::characterize(&net).unwrap().to_pairs();
        for ((key, a), (_, b)) in found.iter().zip(&expected) {
            assert!(a == b || (a - b).abs() <= 1e-12 * b.abs(), "{}: {key}: {a} vs {b}", nodes.display());
        }
    };
    check(&export_dir.join("nodes.csv"), &export_dir.join("segments.csv"));
    // The hydro stage's tables and the skeleton's node table share the 1-based ids.
    check(&dir.join("hydro_nodes.csv"), &dir.join("hydro_links.csv"));
    check(&dir.join("network_nodes.csv"), &dir.join("hydro_links.csv"));
    let metrics = std::fs::read_to_string(export_dir.join("metrics.csv")).unwrap();
    assert_eq!(metrics.lines().count(), 1 + run.metrics.karstnet.len());
}

#[test]
fn manifest_names_every_file_with_its_size_and_digest_and_repeats_exactly() {
    let run = Run::load(&tiny()).with_scene("tiny");
    let all = karst_export::ExportFormat::ALL;
    let (_scratch, dir, first) = export_run(&run, &all, "manifest-a");
    let (_second_scratch, _, second) = export_run(&run, &all, "manifest-b");
    assert_eq!(first, second, "the same run exports the same bytes");
    let mut names: Vec<&str> = first.files.iter().map(|f| f.name.as_str()).collect();
    names.sort();
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    assert_eq!(names, on_disk);
    for f in &first.files {
        let bytes = std::fs::read(dir.join(&f.name)).unwrap();
        assert_eq!(bytes.len() as u64, f.bytes, "{}", f.name);
        assert_eq!(blake3::hash(&bytes).to_hex().to_string(), f.blake3, "{}", f.name);
    }
}
