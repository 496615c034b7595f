//! Real data in a scene: a GeoTIFF terrain and water table in Lambert-93, key points from CSV
//! and GeoJSON tables, connectivity by name, and the scene's CRS; every bad input refused with
//! the file, the row or pixel, the field and the value.

use std::path::{Path, PathBuf};

use karst_testkit::{SceneText, scratch};

use karst_geodata::geotiff::testing::{Encoding, write};
use karst_scene::{KeyPointKind, Link, Scene, SceneError};

/// The scene's folder: the rasters of every test, and the files a test writes.
struct Folder(PathBuf);

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl Folder {
    fn new(test: &str) -> Folder {
        let s = Folder(scratch(test).keep());
        s.rasters();
        s
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    fn file(&self, name: &str, text: &str) {
        std::fs::write(self.path(name), text).unwrap();
    }

    /// dem.tif: 32 × 28 pixels of 10 m from (650990, 6862260), ground 250 m falling 0.1 m per
    /// pixel eastwards; wt.tif: a water table at 120 m rising 0.2 m per row southwards.
    fn rasters(&self) {
        let (w, h) = (32, 28);
        let dem: Vec<f32> = (0..h).flat_map(|_| (0..w).map(|c| 250.0 - 0.1 * c as f32)).collect();
        let wt: Vec<f32> = (0..h).flat_map(|r| (0..w).map(move |_| 120.0 + 0.2 * r as f32)).collect();
        let enc = Encoding { corner: [650_990.0, 6_862_260.0], ..Encoding::default() };
        write(&self.path("dem.tif"), w, h, &dem, &enc).unwrap();
        write(&self.path("wt.tif"), w, h, &wt, &enc).unwrap();
        let mut holed = dem.clone();
        holed[5 * w as usize + 7] = -9999.0;
        write(
            &self.path("holed.tif"),
            w,
            h,
            &holed,
            &Encoding { nodata: Some("-9999".into()), ..enc.clone() },
        )
        .unwrap();
        write(&self.path("utm.tif"), w, h, &dem, &Encoding { epsg: Some((1, 32631)), ..enc.clone() })
            .unwrap();
        write(&self.path("small.tif"), 10, 10, &dem[..100], &enc).unwrap();
    }

    fn scene(&self, text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, &self.path("scene.toml"))
    }

    /// The problems of a scene that must not load, as printed (`scene.toml:LINE: field: ...`).
    fn problems(&self, text: &str) -> Vec<String> {
        match self.scene(text) {
            Ok(_) => panic!("the scene loads"),
            Err(SceneError::Invalid { path, problems }) => problems
                .iter()
                .map(|p| format!("{}{p}", path.file_name().unwrap().to_str().unwrap()))
                .collect(),
            Err(e) => panic!("{e}"),
        }
    }
}

const SCENE: &str = r#"name = "lambert"
crs = "EPSG:2154"

[domain]
min = [651000, 6862000, 0]
max = [651300, 6862250, 300]

[terrain]
kind = "heightfield"
file = "dem.tif"

[[geology.water_tables]]
name = "wt"
file = "wt.tif"

[[keypoints]]
name = "A"
kind = "sink"
position = [651010, 6862010, 240]
"#;

const TABLE: &str = "\n[[keypoints_from]]\nfile = \"points.csv\"\n";

const POINTS: &str = "name,x,y,z,kind,recharge,water_table,phase\n\
                      B,651100.5,6862200,,sink,2.5,,\n\
                      S1,651290,6862100,123,spring,,wt,young|old\n";

fn with(text: &str, extra: &str) -> String {
    format!("{text}{extra}")
}

#[test]
fn geotiff_terrain_and_water_table_in_lambert_93() {
    let s = Folder::new("rasters");
    s.file("points.csv", POINTS);
    let phases =
        "\n[skeleton]\nmode = \"karstnsim\"\n\n[[phases]]\nname = \"old\"\n\n[[phases]]\nname = \"young\"\n";
    let base = with(&with(SCENE, TABLE), phases);
    let scene = s.scene(&base).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.crs(), Some("EPSG:2154"));
    // Coordinates are local once loaded: relative to the domain's min corner.
    assert_eq!(scene.origin(), [651_000.0, 6_862_000.0, 0.0]);
    assert_eq!(scene.domain().min, [0.0; 3]);
    assert_eq!(scene.domain().max, [300.0, 250.0, 300.0]);
    // Pixel centres at 650995 + 10 c: the ground at x = 651100 is halfway between columns 10
    // and 11, 250 − 0.1 · 10.5.
    assert!((scene.terrain().height(100.0, 100.0) - 248.95).abs() < 1e-5);
    let wt = scene.geology().water_table("wt").unwrap();
    // Row r's centre is at 6862255 − 10 r: at y = 6862100, r = 15.5.
    assert!((wt.elevation_at(123.0, 100.0) - (120.0 + 0.2 * 15.5)).abs() < 1e-4);
    let names: Vec<&str> = scene.keypoints().iter().map(|k| k.name.as_str()).collect();
    assert_eq!(names, ["A", "B", "S1"]);
    let b = &scene.keypoints()[1];
    assert_eq!(b.kind, KeyPointKind::Sink);
    assert_eq!(b.weight, 2.5, "recharge is the weight");
    assert!((b.position[2] - scene.terrain().height(100.5, 200.0)).abs() < 1e-12, "z from the terrain");
    assert_eq!(scene.keypoints()[2].water_table.as_deref(), Some("wt"));
    assert!(scene.phases().iter().all(|p| p.springs == ["S1"]), "the spring joins both phases");
    assert!(!scene.keypoints_from()[0].content.is_empty());
    let named = with(&base, "\n[connectivity.named]\nB = { S1 = 1 }\nA = { S1 = 2 }\n");
    let scene = s.scene(&named).unwrap();
    assert_eq!(
        (scene.connectivity().link(0, 0), scene.connectivity().link(1, 0)),
        (Link::Uncertain, Link::Connected)
    );
}

#[test]
fn tables_rename_columns_and_read_geojson_points() {
    let s = Folder::new("tables");
    s.file("field.csv", "ID;X_L93;Y_L93;type\nP1;651200;6862100;dead-end\nP2;651150;6862050;Spring\n");
    s.file(
        "springs.geojson",
        r#"{"type": "FeatureCollection",
            "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}},
            "features": [
              {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651290, 6862100, 123.5]},
               "properties": {"name": "S1", "kind": "spring", "water_table": "wt"}},
              {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651200, 6862200]},
               "properties": {"Name": 17, "weight": "3"}}]}"#,
    );
    let tables = "\n[[keypoints_from]]\nfile = \"springs.geojson\"\nkind = \"sink\"\n\n\
                  [[keypoints_from]]\nfile = \"field.csv\"\nkind = \"waypoint\"\n\
                  columns = { name = \"ID\", x = \"X_L93\", y = \"Y_L93\", kind = \"type\" }\n";
    let problems = s.problems(&with(SCENE, tables));
    // P2 is a spring without a water table: the message names the file, its line and column.
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(problems[0].contains("keypoints_from[1].file: "), "{problems:?}");
    assert!(
        problems[0].ends_with("field.csv:3: water_table: spring \"P2\" names no water table"),
        "{problems:?}"
    );
    s.file("field.csv", "ID;X_L93;Y_L93;type\nP1;651200;6862100;dead-end\n");
    let scene = s.scene(&with(SCENE, tables)).unwrap_or_else(|e| panic!("{e}"));
    let kinds: Vec<(&str, KeyPointKind, f64)> =
        scene.keypoints().iter().map(|k| (k.name.as_str(), k.kind, k.position[2])).collect();
    assert_eq!(kinds[1], ("S1", KeyPointKind::Spring, 123.5));
    assert_eq!((kinds[2].0, kinds[2].1), ("17", KeyPointKind::Sink));
    assert_eq!(scene.keypoints()[2].weight, 3.0);
    assert_eq!((kinds[3].0, kinds[3].1), ("P1", KeyPointKind::DeadEnd));
}

#[test]
fn bad_rasters_and_crs_are_refused_naming_file_field_and_value() {
    let s = Folder::new("bad-rasters");
    let cases: [(String, &str); 7] = [
        (
            SCENE.replace("file = \"dem.tif\"", "file = \"dem.tif\"\norigin = [0, 0]"),
            ":11: terrain.origin: dem.tif is a GeoTIFF",
        ),
        (SCENE.replace("EPSG:2154", "EPSG:2056"), "dem.tif is in EPSG:2154, the scene in EPSG:2056 (crs)"),
        (
            SCENE.replace("crs = \"EPSG:2154\"\n", ""),
            "dem.tif is in EPSG:2154, but the scene declares no crs: add `crs = \"EPSG:2154\"`",
        ),
        (SCENE.replace("EPSG:2154", "Lambert93"), ":2: crs: \"Lambert93\" is not of the form \"EPSG:NNNN\""),
        (SCENE.replace("\"dem.tif\"", "\"utm.tif\""), ":10: terrain.file: "),
        (
            SCENE.replace("\"dem.tif\"", "\"small.tif\""),
            "small.tif: its pixel centres cover x [650995, 651085], y [6862165, 6862255], not the domain's x [651000, 651300]",
        ),
        (
            SCENE.replace("\"dem.tif\"", "\"holed.tif\""),
            "holed.tif: pixel (column 7, row 5) at (651065, 6862205) has no data (value -9999, the no-data value)",
        ),
    ];
    for (text, expected) in cases {
        let p = s.problems(&text);
        assert!(p.iter().any(|m| m.contains(expected)), "{expected}: {p:?}");
    }
    let wt = SCENE.replace("file = \"wt.tif\"", "file = \"holed.tif\"");
    let p = s.problems(&wt);
    assert!(
        p.iter().any(|m| m.contains(":14: geology.water_tables[0].file: ") && m.contains("column 7, row 5")),
        "{p:?}"
    );
}

#[test]
fn bad_tables_are_refused_naming_file_row_column_and_value() {
    let s = Folder::new("bad-tables");
    let cases: [(&str, &str, &str); 8] = [
        (
            "points.csv",
            "name,x,kind\nB,651100,sink\n",
            "points.csv: has no column \"y\" (its columns: name, x, kind)",
        ),
        (
            "points.csv",
            "name,x,y,kind\nB,651100,north,sink\n",
            "points.csv:2: column y: \"north\" is not a number",
        ),
        ("points.csv", "name,x,y,kind\nA,651100,6862100,sink\n", "points.csv:2: name: \"A\" is used twice"),
        (
            "points.csv",
            "name,x,y,z,kind\nB,651100,6863100,100,sink\n",
            "points.csv:2: x, y, z: \"B\" at [651100, 6863100, 100] is outside the domain",
        ),
        (
            "points.csv",
            "name,x,y,kind\nB,651100,6862100,swallet\n",
            "points.csv:2: column kind: \"swallet\" is not sink, spring, waypoint or dead_end",
        ),
        (
            "points.csv",
            "name,x,y,kind,phase\nB,651100,6862100,sink,old\n",
            "points.csv:2: phase: only springs have phases",
        ),
        (
            "points.csv",
            "name,x,y,kind,weight,recharge\nB,651100,6862100,sink,1,1\n",
            "points.csv: has both a weight and a recharge column",
        ),
        (
            "points.csv",
            "name,x,y,z,kind\nB,651100,6862100,260,sink\n",
            "points.csv:2: x, y, z: \"B\" at z = 260 is above the terrain",
        ),
    ];
    for (file, content, expected) in cases {
        s.file(file, content);
        let p = s.problems(&with(SCENE, TABLE));
        assert!(
            p.iter().any(|m| m.contains(":22: keypoints_from[0].file: ") && m.contains(expected)),
            "{expected}: {p:?}"
        );
    }
    let geojson = "\n[[keypoints_from]]\nfile = \"points.geojson\"\nkind = \"sink\"\n";
    let collection = |features: &str, crs: &str| {
        format!(r#"{{"type": "FeatureCollection", {crs} "features": [{features}]}}"#)
    };
    let line = r#"{"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}, "properties": {"name": "L"}}"#;
    let point = r#"{"type": "Feature", "geometry": {"type": "Point", "coordinates": [651100, 6862100]}, "properties": {"name": "P"}}"#;
    let utm = r#""crs": {"type": "name", "properties": {"name": "EPSG:32631"}},"#;
    let cases = [
        (
            collection(&format!("{point}, {line}"), ""),
            "points.geojson: feature 1: is a LineString: karstgen reads Point features only",
        ),
        (collection(point, utm), "points.geojson is in EPSG:32631, the scene in EPSG:2154"),
        (
            r#"{"type": "Feature"}"#.to_string(),
            "points.geojson: is a \"Feature\", not a GeoJSON FeatureCollection",
        ),
        ("{\"type\": ".to_string(), "points.geojson:1: EOF while parsing"),
    ];
    for (content, expected) in cases {
        s.file("points.geojson", &content);
        let p = s.problems(&with(SCENE, geojson));
        assert!(p.iter().any(|m| m.contains(expected)), "{expected}: {p:?}");
    }
    // The CSV's first lines are fine, the third is not: every bad row is named.
    s.file("points.csv", "name,x,y,kind\nB,651100,6862100,sink\nC,abc,6862100,sink\nD,651100,,sink\n");
    let p = s.problems(&with(SCENE, TABLE));
    assert!(p.iter().any(|m| m.contains("points.csv:3: column x: \"abc\" is not a number")), "{p:?}");
    assert!(p.iter().any(|m| m.contains("points.csv:4: column y: the value is empty")), "{p:?}");
}

/// A scene of two sinks ("a", "b") and two springs ("s", "s2") with `extra` appended.
fn two_by_two(extra: &str) -> String {
    SceneText::new("named")
        .with("[[keypoints]]\nname = \"b\"\nkind = \"sink\"\nposition = [20, 10, 40]")
        .with(
            "[[keypoints]]\nname = \"s2\"\nkind = \"spring\"\nposition = [90, 10, 10]\nwater_table = \"wt\"",
        )
        .with(extra)
        .text()
}

#[test]
fn connectivity_by_name_becomes_the_matrix() {
    let scene = Scene::parse(&two_by_two("[connectivity.named]\na = { s = 1, s2 = 0 }"), Path::new("s.toml"))
        .unwrap();
    assert_eq!(scene.connectivity().matrix, Some(vec![vec![1, 0], vec![2, 2]]));
    assert_eq!(scene.connectivity().link(0, 1), Link::None);
    assert_eq!(scene.connectivity().link(1, 0), Link::Uncertain);
}

#[test]
fn connectivity_by_unknown_names_bad_values_or_both_forms_is_refused() {
    let problems = |extra: &str| match Scene::parse(&two_by_two(extra), Path::new("s.toml")) {
        Err(SceneError::Invalid { problems, .. }) => {
            problems.iter().map(|p| p.to_string()).collect::<Vec<_>>()
        }
        other => panic!("{other:?}"),
    };
    let text = two_by_two("[connectivity.named]\nz = { s = 1 }\na = { s9 = 1, s2 = 3 }");
    let line = text.lines().position(|l| l == "[connectivity.named]").unwrap() + 1;
    let p = problems("[connectivity.named]\nz = { s = 1 }\na = { s9 = 1, s2 = 3 }");
    assert!(
        p.iter().any(|m| m.contains(&format!(":{line}: connectivity.named: \"z\" is not a sink"))),
        "{p:?}"
    );
    assert!(p.iter().any(|m| m.contains("\"a\": \"s9\" is not a spring")), "{p:?}");
    assert!(p.iter().any(|m| m.contains("\"a\": \"s2\": value 3 is not 0, 1 or 2")), "{p:?}");
    let p = problems("[connectivity]\nmatrix = [[1, 1], [1, 1]]\nnamed = { a = { s = 0 } }");
    assert!(p.iter().any(|m| m.contains("not both")), "{p:?}");
    let p = problems("[connectivity.named]\na = { s = 0, s2 = 0 }");
    assert!(p.iter().any(|m| m.contains("sink \"a\" may drain to no spring")), "{p:?}");
}
