//! The command-line contract of a stage binary: bad scenes exit with code 2 and a message that
//! names the file, the line and the field; `inspect --json` prints header and payload.

use karst_testkit::{root, scratch};
use std::path::Path;
use std::process::{Command, Output};

fn sampling(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_karst-sampling")).args(args).arg("--out").arg(out).output().unwrap()
}

#[test]
fn bad_scenes_exit_2_naming_file_line_and_field() {
    let cases = [
        ("unknown_field.toml", ":5: colour: unknown field `colour`"),
        ("nan_radius.toml", "sampling.radius: NaN is not a finite number"),
        ("inverted_box.toml", ":8: domain.max: inverted box: max.z = -60"),
        ("syntax.toml", ":6: unclosed table, expected `]`"),
        ("wrong_type.toml", "costgraph.k: invalid type: string \"sixteen\""),
        ("sink_above_terrain.toml", "keypoints[0].position: \"sink-a\" at z = 59 is above the terrain"),
        ("heightfield_not_covering.toml", ":11: terrain.file: the heightfield covers x [100, 1100]"),
        ("tsurf_bad_index.toml", "bad_index.ts:10: TRGL uses vertex id 4, which no VRTX defines"),
        ("tsurf_degenerate.toml", "degenerate.ts: triangle 1 [0, 2, 3] is degenerate"),
        (
            "spring_without_water_table.toml",
            "keypoints[2].water_table: spring \"spring\" names no water table",
        ),
        (
            "keypoint_outside_domain.toml",
            "keypoints[1].position: \"sink-b\" at [40, 180, 54] is outside the domain",
        ),
        ("surface_radius_zero.toml", "sampling.surface_radius: must be > 0, got 0"),
        ("nan_in_horizon.toml", "geology.horizons[0].elevation: NaN is not a finite number"),
        ("nothing_to_sample.toml", "sampling.radius: no sample fits in the bedrock"),
        ("radius_negative.toml", ":41: sampling.radius: must be > 0, got -4"),
        ("tsurf_nan.toml", "nan.ts:7: coordinate NaN is not a finite number"),
        // Issue 15: work estimates, ranges and the validation gaps.
        ("radius_tiny.toml", "sampling.radius = 0.01 means about"),
        ("radius_tiny.toml", "sampling.radius = 0.21 would fit"),
        ("surface_radius_tiny.toml", "sampling.surface_radius = 1.00e-4 means about"),
        ("radius_denormal.toml", "sampling.radius = 4.94e-324 means about inf samples"),
        ("radius_denormal.toml", "sampling.radius = 0.21 would fit"),
        ("extent_huge.toml", "domain.max: 1e308 is beyond ±1e8 m"),
        ("extra_elements.toml", ":7: domain.max: has 5 elements, but only 3 are read"),
        ("keypoints_coincide.toml", "keypoints[1].position: \"sink-b\" lies where \"sink-a\" does"),
        ("keypoint_weight_huge.toml", "keypoints[1].weight: must be in [0, 1e9], got 1e308"),
        ("cost_floor_huge.toml", "costgraph.cost_floor: must be in [1e-6, 1e6], got 1e300"),
        ("noise_wavelength_tiny.toml", "terrain.wavelength: gives the terrain a steepest slope of"),
        ("radius_upper_nan.toml", "skeleton.radius: NaN is not a finite number"),
        ("octaves_huge.toml", "terrain.octaves: must be in [0, 24], got 4e9"),
        ("amplification_huge.toml", "skeleton.amplification_steps: must be at most 100, got 1000000"),
    ];
    let out = scratch("bad");
    for (file, expected) in cases {
        let scene = root().join("fixtures/bad").join(file);
        let result = sampling(&["run", scene.to_str().unwrap()], &out);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{file}: {stderr}");
        assert!(stderr.contains(file) && stderr.contains(expected), "{file}: {stderr}");
        assert!(!out.join("samples.bin").exists(), "{file}: nothing may be written");
    }
    let missing = sampling(&["run", "no/such/scene.toml"], &out);
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("no/such/scene.toml"));
}

#[test]
fn run_then_inspect_json() {
    let out = scratch("ok");
    let scene = root().join("fixtures/scenes/tiny.toml");
    let result = sampling(&["run", scene.to_str().unwrap()], &out);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let file = out.join("samples.bin");
    let json = Command::new(env!("CARGO_BIN_EXE_karst-sampling"))
        .args(["inspect", "--json"])
        .arg(&file)
        .output()
        .unwrap();
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["header"]["kind"], "samples");
    let n = value["payload"]["positions"].as_array().unwrap().len();
    assert!(n > 100, "{n} samples");
    let garbage = out.join("garbage.bin");
    std::fs::write(&garbage, b"not an artifact").unwrap();
    let bad =
        Command::new(env!("CARGO_BIN_EXE_karst-sampling")).arg("inspect").arg(&garbage).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("garbage.bin: not a karstgen artifact"));
}

#[test]
fn inspect_into_a_closed_pipe_ends_quietly() {
    let out = scratch("pipe");
    assert!(
        sampling(&["run", &root().join("fixtures/scenes/tiny.toml").to_string_lossy()], &out)
            .status
            .success()
    );
    // `inspect --json` prints far more than a pipe holds; the reader reads one byte and closes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_karst-sampling"))
        .args(["inspect", "--json"])
        .arg(out.join("samples.bin"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    std::io::Read::read_exact(&mut stdout, &mut [0u8; 1]).unwrap();
    drop(stdout);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}
