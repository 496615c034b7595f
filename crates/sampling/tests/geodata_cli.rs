//! Bad real-world data files exit with code 2 and a message naming the file, the row, pixel or
//! field and the value, never a panic, and write nothing: each case is a small scene in a
//! scratch folder with the data files karstgen's readers refuse.

use std::path::Path;
use std::process::Command;

use karst_geodata::geotiff::testing::{Encoding, write};
use karst_testkit::scratch;

const SCENE: &str = r#"name = "bad"
crs = "EPSG:2154"
[domain]
min = [651000, 6862000, 0]
max = [651100, 6862080, 300]
[terrain]
kind = "heightfield"
file = "TERRAIN"
[[geology.water_tables]]
name = "wt"
elevation = 100
[[keypoints]]
name = "s"
kind = "spring"
position = [651090, 6862040, 100]
water_table = "wt"
"#;

/// Writes the scene with `terrain` and `extra`, runs karst-sampling, returns its stderr.
fn refused(dir: &Path, terrain: &str, extra: &str) -> String {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, format!("{}{extra}", SCENE.replace("TERRAIN", terrain))).unwrap();
    let out = dir.join("out");
    let result = Command::new(env!("CARGO_BIN_EXE_karst-sampling"))
        .args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!out.join("samples.bin").exists());
    stderr
}

#[test]
fn bad_geodata_exits_2_naming_file_field_and_value() {
    let dir = scratch("geodata-cli");
    let dem: Vec<f32> = (0..12 * 10).map(|k| 250.0 + (k % 12) as f32).collect();
    let enc = Encoding { corner: [650_990.0, 6_862_090.0], ..Encoding::default() };
    write(&dir.join("dem.tif"), 12, 10, &dem, &enc).unwrap();
    write(&dir.join("bare.tif"), 12, 10, &dem, &Encoding { scale: None, ..enc.clone() }).unwrap();
    let sink = "\n[[keypoints_from]]\nfile = \"points.FORMAT\"\nkind = \"sink\"\n";
    let cases: [(&str, &str, &str, &str); 6] = [
        ("bare.tif", "", "", "bare.tif: has no georeferencing"),
        ("dem.tif", "", "", "the scene needs at least one sink"),
        ("dem.tif", "csv", "name,x\nA,651010\n", "points.csv: has no column \"y\" (its columns: name, x)"),
        ("dem.tif", "csv", "name,x,y\nA,651010,north\n", "points.csv:2: column y: \"north\" is not a number"),
        (
            "dem.tif",
            "geojson",
            r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": []}, "properties": {"name": "A"}}]}"#,
            "points.geojson: feature 0: is a Polygon",
        ),
        (
            "dem.tif",
            "csv",
            "name,x,y\nA,651010,6862500\n",
            "points.csv:2: x, y, z: \"A\" at [651010, 6862500",
        ),
    ];
    for (terrain, format, table, expected) in cases {
        let extra = if format.is_empty() {
            String::new()
        } else {
            std::fs::write(dir.join(format!("points.{format}")), table).unwrap();
            sink.replace("FORMAT", format)
        };
        let stderr = refused(&dir, terrain, &extra);
        assert!(stderr.contains("scene.toml:") && stderr.contains(expected), "{expected}: {stderr}");
    }
    let lithology =
        "\n[geology.lithology]\nfile = \"rock.vti\"\nunits = [{ code = 1, name = \"limestone\" }]\n";
    std::fs::write(dir.join("rock.vti"), "<VTKFile type=\"PolyData\"></VTKFile>").unwrap();
    let stderr = refused(&dir, "dem.tif", &format!("{lithology}{}", sink.replace("FORMAT", "csv")));
    assert!(
        stderr.contains("geology.lithology.file: ")
            && stderr.contains("rock.vti: is a VTK PolyData file, not ImageData"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
