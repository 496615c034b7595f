//! The fuzz targets: what each reads, the real inputs its mutations start from, and the check
//! (read, then use what was read as the next consumer would; never panic).

use std::path::{Path, PathBuf};

use karst_artifact::stages::producer;
use karst_artifact::{Encoding, Header, Payload, StageId, decode_payload, read_artifact};
use karst_geology::heightfield::{Georeference, HeightGrid};
use karst_geology::tin::Tin;
use karst_scene::Scene;
use karst_stage::Stage;
use karst_testkit::root;

/// One fuzz target.
pub struct Target {
    /// Its name, also the folder of its regression cases in `fixtures/bad/fuzz/`.
    pub name: &'static str,
    /// The real inputs mutations start from.
    pub seeds: fn() -> Vec<Vec<u8>>,
    /// Whether the input is text (number tokens and lines are mutated too).
    pub text: bool,
    /// Reads one input and uses what it read; returns whatever the input, panics on a bug.
    pub check: fn(&[u8]),
}

/// Every target.
pub fn targets() -> Vec<Target> {
    vec![
        Target { name: "scene", seeds: scene_seeds, text: true, check: check_scene },
        Target {
            name: "samples",
            seeds: payload_seeds::<karst_sampling::SamplingStage>,
            text: false,
            check: check_payload::<karst_sampling::SamplingStage>,
        },
        Target {
            name: "costgraph",
            seeds: payload_seeds::<karst_costgraph::CostgraphStage>,
            text: false,
            check: check_payload::<karst_costgraph::CostgraphStage>,
        },
        Target {
            name: "skeleton",
            seeds: payload_seeds::<karst_skeleton::SkeletonStage>,
            text: true,
            check: check_payload::<karst_skeleton::SkeletonStage>,
        },
        Target {
            name: "hydro",
            seeds: payload_seeds::<karst_hydro::HydroStage>,
            text: true,
            check: check_payload::<karst_hydro::HydroStage>,
        },
        Target { name: "sdf", seeds: payload_seeds::<karst_sdf::SdfStage>, text: false, check: check_sdf },
        Target {
            name: "mesh",
            seeds: mesh_seeds,
            text: false,
            check: check_payload::<karst_mesher::MesherStage>,
        },
        Target {
            name: "metrics",
            seeds: payload_seeds::<karst_metrics::MetricsStage>,
            text: true,
            check: check_payload::<karst_metrics::MetricsStage>,
        },
        Target {
            name: "manifest",
            seeds: payload_seeds::<karst_export::ExportStage>,
            text: true,
            check: check_payload::<karst_export::ExportStage>,
        },
        Target { name: "network-out", seeds: network_out_seeds, text: true, check: check_network_out },
        Target { name: "view-mesh", seeds: mesh_seeds, text: false, check: check_view_mesh },
        Target { name: "ensemble-grid", seeds: grid_seeds, text: true, check: check_grid },
        Target { name: "karstnet", seeds: karstnet_seeds, text: true, check: check_karstnet },
        Target { name: "pline", seeds: pline_seeds, text: true, check: check_pline },
        Target { name: "csv", seeds: csv_seeds, text: true, check: check_csv },
        Target { name: "tsurf", seeds: tsurf_seeds, text: true, check: check_tsurf },
        Target { name: "tin", seeds: tin_seeds, text: true, check: check_tin },
        Target { name: "png", seeds: png_seeds, text: false, check: check_png },
    ]
}

fn read(relative: &str) -> Vec<u8> {
    std::fs::read(root().join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

thread_local! {
    /// This thread's scratch folder, removed when the thread ends.
    static SCRATCH: karst_testkit::Scratch = karst_testkit::scratch("fuzz");
}

/// A scratch folder of this thread, for the readers that take files.
fn scratch() -> PathBuf {
    SCRATCH.with(|dir| dir.to_path_buf())
}

// ---- scenes ----------------------------------------------------------------------------

fn scene_seeds() -> Vec<Vec<u8>> {
    ["tiny", "default", "karstnsim-2phase", "looping", "layered"]
        .iter()
        .map(|name| read(&format!("fixtures/scenes/{name}.toml")))
        .collect()
}

/// Parses and validates a scene as if it were a file of `fixtures/scenes` (its data files
/// resolve there).
fn check_scene(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    let _ = Scene::parse(&text, &root().join("fixtures/scenes/fuzz.toml"));
}

// ---- artifacts -------------------------------------------------------------------------

/// The payload of the tiny golden artifact of stage `S`, encoded as in its file.
fn payload_seeds<S: Stage>() -> Vec<Vec<u8>> {
    let (_, payload) =
        read_artifact::<S::Output>(&root().join("fixtures/golden/tiny").join(S::ID.file_name()))
            .expect("the goldens read");
    vec![encode(&payload)]
}

fn encode<P: Payload>(payload: &P) -> Vec<u8> {
    match P::STAGE.row().encoding {
        Encoding::Postcard => postcard::to_stdvec(payload).expect("a payload encodes"),
        Encoding::Json => serde_json::to_vec_pretty(payload).expect("a payload encodes"),
    }
}

/// The tiny mesh cut to its first 300 triangles per surface: a small seed, so that a case
/// is quick, not the whole golden mesh's work.
fn mesh_seeds() -> Vec<Vec<u8>> {
    let (_, mut mesh) = read_artifact::<karst_mesher::Mesh>(&root().join("fixtures/golden/tiny/mesh.bin"))
        .expect("the golden reads");
    for surface in [&mut mesh.terrain, &mut mesh.cave, &mut mesh.water] {
        surface.triangles.truncate(300);
        let mut used: Vec<u32> = surface.triangles.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        surface.vertices = used.iter().map(|&v| surface.vertices[v as usize]).collect();
        for t in &mut surface.triangles {
            *t = t.map(|v| used.binary_search(&v).expect("listed") as u32);
        }
    }
    vec![encode(&mesh)]
}

/// A header for `inspect`'s summary of a payload read from bytes.
fn header(stage: StageId, len: usize) -> Header {
    Header {
        format: karst_artifact::envelope::FORMAT.into(),
        kind: stage,
        schema: 0,
        producer: producer(stage),
        encoding: stage.row().encoding,
        key: String::new(),
        inputs: Vec::new(),
        params: String::new(),
        origin: [0.0; 3],
        crs: None,
        payload_len: len as u64,
        payload_blake3: String::new(),
    }
}

/// Decodes and validates a payload of stage `S`; when it passes, computes `inspect`'s summary.
fn check_payload<S: Stage>(input: &[u8]) {
    let path = Path::new("fuzz");
    if let Ok(payload) = decode_payload::<S::Output>(path, S::ID.row().encoding, input) {
        let _ = S::summary(&header(S::ID, input.len()), &payload);
    }
}

/// An sdf model that passes is evaluated as the mesher and the slices do.
fn check_sdf(input: &[u8]) {
    check_payload::<karst_sdf::SdfStage>(input);
    if let Ok(model) = decode_payload::<karst_sdf::SdfModel>(Path::new("fuzz"), Encoding::Postcard, input) {
        let (lo, hi) = (model.domain.min(), model.domain.max());
        let field = karst_sdf::CarvedTerrain::new(model);
        for t in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let p = lo.lerp(hi, t);
            let _ = (field.eval(p), field.cave(p), field.water(p));
        }
    }
}

// ---- what the export and the viewer make of the artifacts ------------------------------

/// The tiny goldens' skeleton and hydro payloads, one after the other.
fn network_out_seeds() -> Vec<Vec<u8>> {
    let (skeleton, hydro) =
        (payload_seeds::<karst_skeleton::SkeletonStage>(), payload_seeds::<karst_hydro::HydroStage>());
    vec![[skeleton[0].as_slice(), SPLIT.as_bytes(), hydro[0].as_slice()].concat()]
}

/// The tiny goldens the network formats read besides the skeleton and hydro.
struct Others {
    samples: karst_sampling::Samples,
    mesh: karst_mesher::Mesh,
    metrics: karst_metrics::MetricsReport,
    streams: karst_streams::Streams,
    scene: Scene,
    frame: karst_artifact::Frame,
}

fn others() -> &'static Others {
    static OTHERS: std::sync::OnceLock<Others> = std::sync::OnceLock::new();
    OTHERS.get_or_init(|| {
        let golden = |stage: StageId| root().join("fixtures/golden/tiny").join(stage.file_name());
        let mesh = decode_payload(Path::new("seed"), Encoding::Postcard, &mesh_seeds()[0])
            .expect("the seed mesh reads");
        Others {
            samples: read_artifact(&golden(StageId::Sampling)).expect("the goldens read").1,
            mesh,
            metrics: read_artifact(&golden(StageId::Metrics)).expect("the goldens read").1,
            streams: read_artifact(&golden(StageId::Streams)).expect("the goldens read").1,
            frame: karst_artifact::Frame::default(),
            scene: Scene::load(&root().join("fixtures/scenes/tiny.toml")).expect("the tiny scene loads"),
        }
    })
}

/// A skeleton and a hydro payload that pass their checks are exported in every format and
/// turned into the viewer's run.json.
fn check_network_out(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    let (a, b) = text.split_once(SPLIT).unwrap_or((&text, ""));
    let path = Path::new("fuzz");
    let Ok(skeleton) = decode_payload::<karst_skeleton::Skeleton>(path, Encoding::Json, a.as_bytes()) else {
        return;
    };
    let Ok(hydro) = decode_payload::<karst_hydro::Hydro>(path, Encoding::Json, b.as_bytes()) else { return };
    let o = others();
    let inputs = karst_export::Inputs {
        skeleton: Some(&skeleton),
        hydro: Some(&hydro),
        streams: Some(&o.streams),
        mesh: Some(&o.mesh),
        metrics: Some(&o.metrics),
        samples: Some(&o.samples),
        geology: Some(o.scene.geology()),
        keypoints: Some(o.scene.keypoints()),
        terrain: Some(o.scene.terrain()),
        domain: Some(o.scene.domain()),
        frame: &o.frame,
    };
    let params = karst_export::ExportParams {
        formats: karst_export::ExportFormat::ALL.to_vec(),
        ..karst_export::ExportParams::default()
    };
    let _ = karst_export::export(&inputs, &params, &scratch());
    let run = karst_view::Run {
        dir: scratch(),
        scene: Some(o.scene.clone()),
        skeleton: Some(skeleton),
        hydro: Some(hydro),
        streams: Some(o.streams.clone()),
        mesh: None,
        metrics: Some(o.metrics.clone()),
        ensemble: None,
        problems: Vec::new(),
    };
    let _ = serde_json::to_vec(&karst_view::data::view_data(&run, &[]));
}

/// A mesh that passes its checks is chunked, simplified and written as the viewer's glb files.
fn check_view_mesh(input: &[u8]) {
    if let Ok(mesh) = decode_payload::<karst_mesher::Mesh>(Path::new("fuzz"), Encoding::Postcard, input) {
        let dir = scratch().join("view");
        let _ = karst_view::meshes::write(&dir, &mesh);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

fn grid_seeds() -> Vec<Vec<u8>> {
    vec![br#"{"min": [0.0, 0.0, -50.0], "cell": 10.0, "dims": [40, 30, 8], "realizations": 5}"#.to_vec()]
}

/// An ensemble's grid.json beside the tiny skeleton, read as the viewer reads it.
fn check_grid(input: &[u8]) {
    let run = scratch().join("run");
    std::fs::create_dir_all(run.join("probability")).expect("scratch is writable");
    std::fs::write(run.join("probability/grid.json"), input).expect("scratch is writable");
    let skeleton = &others_skeleton();
    let _ = karst_view::ensemble::load(&run, skeleton);
}

fn others_skeleton() -> &'static karst_skeleton::Skeleton {
    static SKELETON: std::sync::OnceLock<karst_skeleton::Skeleton> = std::sync::OnceLock::new();
    SKELETON.get_or_init(|| {
        read_artifact(&root().join("fixtures/golden/tiny/skeleton.json")).expect("the goldens read").1
    })
}

// ---- network files ---------------------------------------------------------------------

/// The line separating the two files of a two-file input.
const SPLIT: &str = "\n%% next file %%\n";

fn two_files(input: &[u8], first: &Path, second: &Path) {
    let text = String::from_utf8_lossy(input);
    let (a, b) = text.split_once(SPLIT).unwrap_or((&text, ""));
    std::fs::write(first, a).expect("scratch is writable");
    std::fs::write(second, b).expect("scratch is writable");
}

/// A small cave-like network: a chain with a loop and a branch.
fn small_network() -> (String, String) {
    let nodes = "0 0 0\n10 0 -1\n20 5 -2\n30 0 -2\n20 -5 -3\n40 10 -4\n";
    let links = "1 2\n2 3\n3 4\n4 5\n5 2\n4 6\n";
    (nodes.into(), links.into())
}

fn karstnet_seeds() -> Vec<Vec<u8>> {
    let (nodes, links) = small_network();
    let sakany = [
        read("fixtures/caves/Sakany_nodes.dat"),
        SPLIT.as_bytes().to_vec(),
        read("fixtures/caves/Sakany_links.dat"),
    ];
    vec![format!("{nodes}{SPLIT}{links}").into_bytes(), sakany.concat()]
}

fn metrics_of(network: Result<karst_metrics::Network, karst_metrics::ReadError>) {
    if let Ok(network) = network {
        let _ = karst_metrics::characterize(&network);
    }
}

fn check_karstnet(input: &[u8]) {
    let base = scratch().join("net");
    two_files(input, &base.with_file_name("net_nodes.dat"), &base.with_file_name("net_links.dat"));
    metrics_of(karst_metrics::readers::read_karstnet(&base));
}

fn pline_seeds() -> Vec<Vec<u8>> {
    let small = "GOCAD PLine 1\nILINE\nVRTX 1 0 0 0\nVRTX 2 10 0 -1\nVRTX 3 20 5 -2\nATOM 4 2\nVRTX 5 20 -5 -3\nSEG 1 2\nSEG 2 3\nSEG 3 5\nSEG 5 4\nEND\n";
    vec![small.as_bytes().to_vec(), read("fixtures/caves/Monachou.pl")]
}

fn check_pline(input: &[u8]) {
    let file = scratch().join("net.pl");
    std::fs::write(&file, input).expect("scratch is writable");
    metrics_of(karst_metrics::readers::read_pline(&file));
}

fn csv_seeds() -> Vec<Vec<u8>> {
    let nodes = "id,x,y,z\n10,0,0,0\n11,10,0,-1\n12,20,5,-2\n13,30,0,-2\n14,20,-5,-3\n";
    let edges = "from,to\n10,11\n11,12\n12,13\n13,14\n14,11\n";
    vec![format!("{nodes}{SPLIT}{edges}").into_bytes()]
}

fn check_csv(input: &[u8]) {
    let dir = scratch();
    let (nodes, edges) = (dir.join("nodes.csv"), dir.join("edges.csv"));
    two_files(input, &nodes, &edges);
    metrics_of(karst_metrics::readers::read_csv(&nodes, &edges));
}

// ---- data files ------------------------------------------------------------------------

fn tsurf_seeds() -> Vec<Vec<u8>> {
    vec![read("fixtures/scenes/data/marl-parting.ts"), read("fixtures/bad/data/bad_index.ts")]
}

/// A surface that reads is queried as the geology and the sampling query it.
fn use_tin(tin: Result<Tin, karst_geodata::tin::TinError>) {
    if let Ok(tin) = tin {
        let _ = tin.elevation_at(0.0, 0.0);
        let _ = tin.elevation_at(1e5, -1e5);
        let _ = tin.closest_within(glam::DVec3::new(10.0, 20.0, 30.0), 1e3);
        let _ = tin.mean_normal();
    }
}

fn check_tsurf(input: &[u8]) {
    let file = scratch().join("surface.ts");
    std::fs::write(&file, input).expect("scratch is writable");
    use_tin(Tin::read(&file));
}

fn tin_seeds() -> Vec<Vec<u8>> {
    vec![b"# a tilted square\nv 0 0 10\nv 100 0 12\nv 100 100 14\nv 0 100 12\nf 1 2 3\nf 1 3 4\n".to_vec()]
}

fn check_tin(input: &[u8]) {
    let file = scratch().join("surface.txt");
    std::fs::write(&file, input).expect("scratch is writable");
    use_tin(Tin::read(&file));
}

fn png_seeds() -> Vec<Vec<u8>> {
    let heights = (0..12).map(|i| 100.0 + (i * 7 % 5) as f64).collect();
    let grid = HeightGrid::new([0.0, 0.0], 10.0, 4, 3, heights);
    let file = scratch().join("seed.png");
    karst_geology::heightfield::write_png(&file, &grid, 0.0, 1.0).expect("scratch is writable");
    vec![std::fs::read(&file).expect("just written"), read("fixtures/scenes/data/plateau.png")]
}

/// A heightfield that decodes is evaluated as the terrain is.
fn check_png(input: &[u8]) {
    let geo = Georeference {
        origin: [0.0, 0.0],
        cell_size: 10.0,
        vertical_scale: 0.1,
        offset: 0.0,
        nodata: Some(0.0),
    };
    if let Ok(grid) = HeightGrid::decode_png(input, "fuzz.png", &geo) {
        let _ = grid.height(15.0, 5.0);
        let _ = grid.slope_bound();
        let _ = grid.first_hole([0.0, 30.0], [0.0, 20.0]);
    }
}
