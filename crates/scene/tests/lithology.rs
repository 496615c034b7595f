//! Lithology grids written by the real writers: VTK's vtkXMLImageDataWriter (the writer behind
//! GemPy's and PyVista's `.vti`) in every data mode, encoding, compressor, header type and
//! scalar type, as point and as cell data, and NumPy's `numpy.save` in C and Fortran order; a
//! scene reading each must give every voxel centre of the domain its code's unit. Needs
//! `KARSTNET_PYTHON` with `vtk` and `numpy` (tools/python-requirements.txt), set by `cargo xtask
//! test`.

use std::process::Command;

use karst_geology::Point;
use karst_scene::{Scene, SceneError};
use karst_testkit::scratch;

/// Writes the grids: code(i, j, k) = 1 + (i + 2j + k) mod 3 on 4 × 3 × 2 voxels of 25 × 25 ×
/// 10 m centred from (651012.5, 6862012.5, 105).
const WRITER: &str = r#"
import sys, itertools
import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk

folder = sys.argv[1]
nx, ny, nz = 4, 3, 2
codes = np.array([[[1 + (i + 2 * j + k) % 3 for k in range(nz)] for j in range(ny)] for i in range(nx)])
first = (651012.5, 6862012.5, 105.0)
spacing = (25.0, 25.0, 10.0)
flat = codes.ravel(order="F")  # VTK: x fastest

def image(cells):
    img = vtk.vtkImageData()
    if cells:
        img.SetDimensions(nx + 1, ny + 1, nz + 1)
        img.SetOrigin(*[f - s / 2 for f, s in zip(first, spacing)])
    else:
        img.SetDimensions(nx, ny, nz)
        img.SetOrigin(*first)
    img.SetSpacing(*spacing)
    return img

names = []
types = {"int8": np.int8, "uint8": np.uint8, "int32": np.int32, "float64": np.float64}
for mode, encode, compressor, header, dtype, cells in itertools.product(
        ["ascii", "binary", "appended"], [0, 1], ["none", "zlib"], ["UInt32", "UInt64"], list(types), [False, True]):
    if (mode != "appended" and encode) or (mode == "ascii" and (compressor != "none" or header != "UInt32")):
        continue
    img = image(cells)
    array = numpy_to_vtk(flat.astype(types[dtype]), deep=True)
    array.SetName("lith")
    data = img.GetCellData() if cells else img.GetPointData()
    data.SetScalars(array)
    other = numpy_to_vtk(np.zeros(flat.size), deep=True)
    other.SetName("other")
    data.AddArray(other)
    w = vtk.vtkXMLImageDataWriter()
    w.SetInputData(img)
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary, "appended": w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(encode)
    if compressor == "none":
        w.SetCompressorTypeToNone()
    else:
        w.SetCompressorTypeToZLib()
        w.SetBlockSize(16)  # several blocks, the last one partial
    w.SetHeaderType(vtk.vtkXMLWriter.UInt64 if header == "UInt64" else vtk.vtkXMLWriter.UInt32)
    name = f"{mode}-{'base64' if encode else 'raw'}-{compressor}-{header}-{dtype}-{'cells' if cells else 'points'}.vti"
    w.SetFileName(f"{folder}/{name}")
    assert w.Write() == 1, name
    names.append(name)
np.save(f"{folder}/c.npy", codes.astype(np.float64))
np.save(f"{folder}/f.npy", np.asfortranarray(codes.astype(np.int8)))
print("\n".join(names + ["c.npy", "f.npy"]))
"#;

fn python() -> String {
    std::env::var("KARSTNET_PYTHON")
        .unwrap_or_else(|_| panic!("KARSTNET_PYTHON is not set: run the tests with `cargo xtask test`"))
}

fn scene(file: &str, extra: &str) -> String {
    format!(
        r#"name = "lithology"

[domain]
min = [651000, 6862000, 100]
max = [651100, 6862075, 120]

[terrain]
kind = "plane"
elevation = 200

[geology.lithology]
file = "{file}"
{extra}
units = [
  {{ code = 1, name = "limestone", potential = 1.0, radius = 4 }},
  {{ code = 2, name = "marl", potential = 0.5 }},
  {{ code = 3, name = "granite", potential = 0.25, no_karst = true }},
]

[[geology.water_tables]]
name = "wt"
elevation = 110

[[keypoints]]
name = "a"
kind = "sink"
position = [651010, 6862010, 119]

[[keypoints]]
name = "s"
kind = "spring"
position = [651090, 6862060, 104]
water_table = "wt"
"#
    )
}

fn code(i: usize, j: usize, k: usize) -> usize {
    1 + (i + 2 * j + k) % 3
}

/// Every voxel centre takes its code's unit: potential 1, 0.5 or 0.25, granite no-karst.
fn check(scene: &Scene, what: &str) {
    // The scene is local once loaded: world − the domain's min corner.
    let origin = Point::from_array(scene.origin());
    assert_eq!(origin, Point::new(651_000.0, 6_862_000.0, 100.0));
    for (i, j, k) in (0..4).flat_map(|i| (0..3).flat_map(move |j| (0..2).map(move |k| (i, j, k)))) {
        let world =
            Point::new(651_012.5 + 25.0 * i as f64, 6_862_012.5 + 25.0 * j as f64, 105.0 + 10.0 * k as f64);
        let p = world - origin;
        let expected = [1.0, 0.5, 0.25][code(i, j, k) - 1];
        assert_eq!(scene.geology().potential(p), expected, "{what}: voxel ({i}, {j}, {k})");
        assert_eq!(scene.geology().in_no_karst(p), code(i, j, k) == 3, "{what}: voxel ({i}, {j}, {k})");
    }
    assert_eq!(scene.geology().layer_radii().collect::<Vec<_>>(), [4.0]);
}

#[test]
fn every_vtk_and_numpy_layout_reads_as_written() {
    let dir = scratch("lithology");
    let out = Command::new(python()).args(["-c", WRITER]).arg(dir.as_os_str()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let files: Vec<String> = String::from_utf8(out.stdout).unwrap().lines().map(str::to_string).collect();
    assert!(files.len() > 40, "{files:?}");
    for file in &files {
        let extra = if file.ends_with(".npy") {
            "origin = [651012.5, 6862012.5, 105]\nspacing = [25, 25, 10]"
        } else {
            "" // the writer's Scalars array
        };
        std::fs::write(dir.join("scene.toml"), scene(file, extra)).unwrap();
        let scene = Scene::load(&dir.join("scene.toml")).unwrap_or_else(|e| panic!("{file}: {e}"));
        check(&scene, file);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn wrong_grids_are_refused_naming_file_and_value() {
    let dir = scratch("lithology-bad");
    let out = Command::new(python()).args(["-c", WRITER]).arg(dir.as_os_str()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let vti = "appended-base64-zlib-UInt64-int32-points.vti";
    let problems = |text: String| {
        std::fs::write(dir.join("scene.toml"), text).unwrap();
        match Scene::load(&dir.join("scene.toml")) {
            Err(SceneError::Invalid { problems, .. }) => {
                problems.iter().map(|p| p.to_string()).collect::<Vec<_>>()
            }
            other => panic!("{other:?}"),
        }
    };
    let cases = [
        (
            scene(vti, "array = \"rock\""),
            "has no array \"rock\" (its arrays: \"lith\", \"other\")".to_string(),
        ),
        (
            scene(vti, "array = \"lith\"")
                .replace("max = [651100, 6862075, 120]", "max = [651100, 6862075, 130]"),
            "z [100, 120], not the domain's".into(),
        ),
        (
            scene(vti, "array = \"lith\"")
                .replace("  { code = 3, name = \"granite\", potential = 0.25, no_karst = true },\n", ""),
            "code 3 (voxel [2, 0, 0] centred at [651062.5, 6862012.5, 105.0], and 7 more voxels) has no unit"
                .into(),
        ),
        (
            scene(vti, "array = \"lith\"").replace("code = 2,", "code = 1,"),
            "geology.lithology.units[1].code: code 1 is mapped twice".into(),
        ),
        (
            scene(vti, "array = \"lith\"").replace("potential = 0.5", "potential = 1.5"),
            "units[1].potential: must be in [0, 1], got 1.5".into(),
        ),
        (
            scene(vti, "array = \"lith\"")
                .replace("position = [651010, 6862010, 119]", "position = [651062, 6862010, 105]"),
            "\"a\" at [651062, 6862010, 105] is in no-karst lithology unit \"granite\"".into(),
        ),
        (scene("c.npy", ""), "a .npy array needs `origin` and `spacing` in the scene".into()),
        (scene(vti, "origin = [0, 0, 0]"), "a .vti file carries its origin and spacing".into()),
        (scene("scene.toml", ""), "is neither a VTK ImageData (.vti) nor a NumPy (.npy) file".into()),
    ];
    for (text, expected) in cases {
        let p = problems(text);
        assert!(p.iter().any(|m| m.contains(&expected)), "{expected}: {p:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
