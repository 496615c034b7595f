//! The GIS exports checked by the users' tools: the geotiff example (Lambert-93) run through
//! every stage writes `karst.gpkg` and the conduit rasters; GDAL (`ogrinfo`, `ogr2ogr`,
//! `gdalinfo`, `gdallocationinfo` of Debian's gdal-bin) reads every layer and raster with the
//! scene's CRS, the artifacts' feature counts and the depth under known conduits; QGIS
//! (Debian's python3-qgis on /usr/bin/python3, headless) opens them over the DEM with the
//! GeoPackage's default styles and draws the conduits in their type's colour; the key points
//! written out equal the CSV read in; an ensemble writes probability.tif and mean-depth.tif.
//! Every tool is installed by `cargo xtask test` (tools/apt-packages.txt); a missing one fails.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use karst_testkit::gdal::gdal;
use std::sync::OnceLock;

use common::{read, root, scratch};
use karst_export::NetworkView;
use karst_export::gpkg::style::CONDUIT_COLOURS;
use karst_hydro::Hydro;
use karst_pipeline::ensemble::{self, Keep, Plan};
use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::SceneFile;
use karst_skeleton::{ConduitType, Skeleton};

const EPSG: &str = "ID[\"EPSG\",2154]]";

fn scene_path() -> PathBuf {
    root().join("fixtures/scenes/geotiff.toml")
}

/// The geotiff example run through every stage, once per test binary.
fn run() -> &'static Path {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let out = scratch("gis-run").keep();
        let scene = SceneFile::load(&scene_path()).unwrap();
        make::run(&scene, &out, &Selection::default(), &mut |_| {})
            .unwrap_or_else(|e| panic!("geotiff: {e}"));
        out
    })
}

fn export_file(name: &str) -> String {
    run().join("export").join(name).to_str().unwrap().to_string()
}

/// `gdalinfo -json` of a raster (no statistics file left behind).
fn gdalinfo(path: &str) -> serde_json::Value {
    serde_json::from_str(&gdal("gdalinfo", &["-json", path], None)).unwrap()
}

/// The raster's value at each world point, as GDAL reads it.
fn values_at(path: &str, points: &[[f64; 2]]) -> Vec<f64> {
    let input: String = points.iter().map(|[x, y]| format!("{x} {y}\n")).collect();
    let out = gdal("gdallocationinfo", &["-valonly", "-geoloc", path], Some(&input));
    out.lines().map(|l| l.trim().parse().unwrap_or_else(|_| panic!("{path}: {l:?}"))).collect()
}

/// Feature count and SRS of a layer, as `ogrinfo -so` reports them.
fn layer_summary(gpkg: &str, layer: &str) -> (usize, String) {
    let text = gdal("ogrinfo", &["-ro", "-so", gpkg, layer], None);
    let count = text
        .lines()
        .find_map(|l| l.strip_prefix("Feature Count: "))
        .unwrap_or_else(|| panic!("{layer}: no feature count in\n{text}"))
        .trim()
        .parse()
        .unwrap();
    (count, text)
}

#[test]
fn ogr_reads_every_layer_in_the_scene_crs_with_the_artifacts_counts() {
    let gpkg = export_file("karst.gpkg");
    let skeleton: Skeleton = read(run(), "skeleton.json");
    let streams: karst_streams::Streams = read(run(), "streams.json");
    let segments: usize = skeleton.conduits.iter().map(|c| c.nodes.len() - 1).sum();
    let expected = [
        ("segments", segments, "3D Line String"),
        ("conduits", skeleton.conduits.len(), "3D Line String"),
        ("passages", skeleton.conduits.len(), "Multi Polygon"),
        ("key_points", 5, "3D Point"),
        ("streams", streams.segments.len(), "3D Line String"),
        ("routes", skeleton.routes.len(), "3D Line String"),
    ];
    for (layer, count, geometry) in expected {
        let (found, text) = layer_summary(&gpkg, layer);
        assert_eq!(found, count, "{layer}");
        assert!(text.contains(&format!("Geometry: {geometry}")), "{layer}: {text}");
        assert!(text.trim_end().ends_with(EPSG) || text.contains(&format!("    {EPSG}")), "{layer}: {text}");
        assert!(text.contains("RGF93"), "{layer}: not in Lambert-93:\n{text}");
    }
    // 1-based ids, and the spatial index answers a window query around the first segment.
    let first = gdal("ogrinfo", &["-ro", "-fid", "1", &gpkg, "segments"], None);
    assert!(
        first.contains("OGRFeature(segments):1") && first.contains("conduit (Integer")
            || first.contains("conduit (Integer64) = 1")
    );
    let sql =
        gdal("ogrinfo", &["-ro", "-q", &gpkg, "-sql", "SELECT count(*) AS n FROM rtree_segments_geom"], None);
    assert!(
        sql.contains(&format!("n (Integer) = {segments}"))
            || sql.contains(&format!("n (Integer64) = {segments}")),
        "{sql}"
    );
}

#[test]
fn key_points_written_out_equal_the_csv_read_in() {
    let csv = gdal(
        "ogr2ogr",
        &["-f", "CSV", "/vsistdout/", &export_file("karst.gpkg"), "key_points", "-lco", "GEOMETRY=AS_XYZ"],
        None,
    );
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column =
        |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("{name}: {header:?}"));
    let (x, y, z, name) = (column("X"), column("Y"), column("Z"), column("name"));
    let written: Vec<(String, [f64; 3])> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[name].trim_matches('"').to_string(), [f[x], f[y], f[z]].map(|v| v.parse().unwrap()))
        })
        .collect();
    let scene = SceneFile::load(&scene_path()).unwrap().scene;
    let origin = scene.frame().origin;
    let table = std::fs::read_to_string(root().join("fixtures/scenes/data/geotiff/field.csv")).unwrap();
    let mut read_in = 0;
    for row in table.lines().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        let (label, cx, cy) = (f[0], f[1].parse::<f64>().unwrap(), f[2].parse::<f64>().unwrap());
        let (_, p) =
            written.iter().find(|(n, _)| n == label).unwrap_or_else(|| panic!("{label} not written"));
        assert!((p[0] - cx).abs() < 5e-4 && (p[1] - cy).abs() < 5e-4, "{label}: {p:?} vs ({cx}, {cy})");
        let z = match f[3] {
            "" => scene.terrain().height(cx - origin[0], cy - origin[1]) + origin[2],
            given => given.parse().unwrap(),
        };
        assert!((p[2] - z).abs() < 5e-4, "{label}: z {} vs {z}", p[2]);
        read_in += 1;
    }
    assert_eq!((read_in, written.len()), (5, 5));
}

/// The geotransform of a raster.
fn transform(info: &serde_json::Value) -> [f64; 6] {
    let gt = info["geoTransform"].as_array().unwrap();
    std::array::from_fn(|i| gt[i].as_f64().unwrap())
}

#[test]
fn gdal_reads_the_rasters_on_the_dem_grid_with_the_depth_under_known_conduits() {
    let dem = root().join("fixtures/scenes/data/geotiff/dem.tif").to_str().unwrap().to_string();
    let dem_gt = transform(&gdalinfo(&dem));
    let depth_path = export_file("conduit-depth.tif");
    for name in ["conduit-depth.tif", "conduit-density.tif"] {
        let info = gdalinfo(&export_file(name));
        assert!(info["coordinateSystem"]["wkt"].as_str().unwrap().ends_with(EPSG), "{name}: {info}");
        assert_eq!(info["bands"][0]["noDataValue"], -9999.0, "{name}");
        assert_eq!(info["metadata"]["IMAGE_STRUCTURE"]["COMPRESSION"], "DEFLATE", "{name}");
        let gt = transform(&info);
        assert_eq!((gt[1], gt[5]), (dem_gt[1], dem_gt[5]), "{name}: the DEM's pixel size");
        for (corner, dem_corner) in [(gt[0], dem_gt[0]), (gt[3], dem_gt[3])] {
            let shift = (corner - dem_corner) / gt[1];
            assert!((shift - shift.round()).abs() < 1e-9, "{name}: not on the DEM's pixel grid");
        }
    }
    // The depth at the pixels of the network's nodes: the DEM under the pixel's centre minus
    // the highest roof over the pixel, found here by sampling every segment's discs.
    let skeleton: Skeleton = read(run(), "skeleton.json");
    let hydro: Hydro = read(run(), "hydro.json");
    let net = NetworkView::new(&skeleton, &hydro).unwrap();
    let origin = karst_artifact::read_header(&run().join("skeleton.json")).unwrap().origin;
    let gt = transform(&gdalinfo(&depth_path));
    let cell = gt[1];
    let centres: Vec<[f64; 2]> = net
        .nodes
        .iter()
        .step_by(7)
        .map(|n| {
            let [x, y] = [n.position[0] + origin[0], n.position[1] + origin[1]];
            [
                gt[0] + ((x - gt[0]) / cell).floor() * cell + cell / 2.0,
                gt[3] - ((gt[3] - y) / cell).floor() * cell - cell / 2.0,
            ]
        })
        .collect();
    let depths = values_at(&depth_path, &centres);
    let ground = values_at(&dem, &centres);
    for ((centre, depth), ground) in centres.iter().zip(&depths).zip(&ground) {
        let local = [centre[0] - origin[0], centre[1] - origin[1]];
        let roof =
            highest_roof(&net, local, cell / 2.0).expect("a node's pixel is under its conduit") + origin[2];
        assert!(
            (depth - (ground - roof)).abs() < 0.05,
            "at {centre:?}: depth {depth}, DEM {ground} − roof {roof}"
        );
    }
    let density = values_at(&export_file("conduit-density.tif"), &centres);
    assert!(density.iter().all(|&d| d > 0.0), "a node's pixel holds conduit length: {density:?}");
}

/// The highest roof of the network's tubes over the square pixel of `centre` and half edge
/// `half` (local coordinates): for 2001 discs along each segment, the roof over the square's
/// point nearest to the disc's centre.
fn highest_roof(net: &NetworkView, centre: [f64; 2], half: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for s in &net.segments {
        let [a, b] = s.nodes.map(|n| net.nodes[n as usize].position);
        for k in 0..=2000 {
            let t = k as f64 / 2000.0;
            let c: [f64; 3] = std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t);
            let r = s.radius[0] + (s.radius[1] - s.radius[0]) * t;
            let q = [
                c[0].clamp(centre[0] - half, centre[0] + half),
                c[1].clamp(centre[1] - half, centre[1] + half),
            ];
            let d2 = (q[0] - c[0]).powi(2) + (q[1] - c[1]).powi(2);
            if d2 <= r * r {
                let roof = c[2] + (r * r - d2).sqrt();
                best = Some(best.map_or(roof, |b| b.max(roof)));
            }
        }
    }
    best
}

/// Debian's Python with QGIS; a machine without it fails, saying how to install it.
fn qgis_python() -> &'static str {
    let python = "/usr/bin/python3";
    let found = Command::new(python).args(["-c", "import qgis.core"]).output();
    assert!(
        found.is_ok_and(|o| o.status.success()),
        "QGIS's Python bindings are missing: install python3-qgis (tools/apt-packages.txt) with `cargo xtask test`"
    );
    python
}

#[test]
fn qgis_draws_the_conduits_in_their_style_colour_over_the_dem() {
    let python = qgis_python();
    let dir = scratch("gis-qgis");
    let png = dir.join("map.png");
    let dem = root().join("fixtures/scenes/data/geotiff/dem.tif");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/qgis_map.py");
    let out = Command::new(python)
        .arg(&script)
        .arg(&dem)
        .arg(export_file("karst.gpkg"))
        .arg(export_file("conduit-depth.tif"))
        .arg(&png)
        .env("QT_QPA_PLATFORM", "offscreen")
        .output()
        .unwrap();
    assert!(out.status.success(), "qgis_map.py: {}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let report: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    for (layer, facts) in report["layers"].as_object().unwrap() {
        assert_eq!(facts["valid"], true, "{layer}: {report}");
        assert_eq!(facts["crs"], "EPSG:2154", "{layer}");
    }
    for layer in ["segments", "conduits", "passages"] {
        assert_eq!(
            report["layers"][layer]["renderer"], "categorizedSymbol",
            "{layer}: the GeoPackage's style"
        );
    }
    assert_eq!(report["map_extent"], report["extent"], "the map is the DEM's extent");
    // The image covers the DEM's extent: the conduits' colours must be in it.
    let skeleton: Skeleton = read(run(), "skeleton.json");
    let (width, height, pixels) = decode_rgba(&png);
    assert_eq!([width, height], [800, 640]);
    let mut found = 0;
    // Each segment's type and length on the map (shafts have next to none).
    let on_map: Vec<(ConduitType, f64)> = skeleton
        .conduits
        .iter()
        .flat_map(|c| c.nodes.windows(2).zip(&c.types))
        .map(|(pair, ty)| {
            let [a, b] = [pair[0], pair[1]].map(|n| skeleton.nodes[n as usize].position);
            (*ty, (b[0] - a[0]).hypot(b[1] - a[1]))
        })
        .collect();
    let total: f64 = on_map.iter().map(|(_, l)| l).sum();
    for (ty, [r, g, b]) in CONDUIT_COLOURS {
        // A type of a tenth of the map length or more shows between the markers and routes.
        let length: f64 = on_map.iter().filter(|(t, _)| *t == ty).map(|(_, l)| l).sum();
        let common = length >= total / 10.0;
        let drawn = pixels.chunks(4).filter(|p| p[..3] == [r, g, b]).count();
        assert!(!common || drawn > 0, "{}: common in the network, not drawn in its colour", ty.name());
        found += drawn;
    }
    assert!(found > 200, "the conduits cover {found} pixels of their type colours");
}

fn decode_rgba(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buffer).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba, "QGIS writes RGBA");
    buffer.truncate(info.buffer_size());
    (info.width, info.height, buffer)
}

#[test]
fn an_ensemble_writes_the_probability_rasters_gdal_reads() {
    let scene = SceneFile::load(&scene_path()).unwrap();
    let plan =
        Plan::new(scene, Some(karst_artifact::StageId::Hydro), 10.0, Keep::Stages(Vec::new())).unwrap();
    let dir = scratch("gis-ensemble");
    ensemble::run(&plan, &dir, &[2154, 2155], None).unwrap();
    let probability = dir.join("probability.tif").to_str().unwrap().to_string();
    let info = gdalinfo(&probability);
    assert!(info["coordinateSystem"]["wkt"].as_str().unwrap().ends_with(EPSG), "{info}");
    // Seed 2154 is the single run: its nodes' pixels have a conduit in one realization at least.
    let skeleton: Skeleton = read(run(), "skeleton.json");
    let origin = karst_artifact::read_header(&run().join("skeleton.json")).unwrap().origin;
    let points: Vec<[f64; 2]> =
        skeleton.nodes.iter().map(|n| [n.position[0] + origin[0], n.position[1] + origin[1]]).collect();
    let any = values_at(&probability, &points);
    assert!(any.iter().all(|&p| p == 0.5 || p == 1.0), "shares of 2 realizations: {any:?}");
    let mean_depth = values_at(dir.join("mean-depth.tif").to_str().unwrap(), &points);
    assert!(mean_depth.iter().all(|&d| d > -10.0 && d < 250.0), "{mean_depth:?}");
    // No conduit lies 1 km below ground.
    ensemble::merge(std::slice::from_ref(&dir.to_path_buf()), &dir, Some([1000.0, 2000.0])).unwrap();
    assert!(values_at(&probability, &points).iter().all(|&p| p == 0.0));
}
