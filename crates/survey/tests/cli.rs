//! The command-line contract of `karst-survey` (karst_testkit::cli): `run` on the tiny scene's
//! golden inputs writes its golden artifact, `inspect` reads it, a truncated input and a bad
//! scene exit 2 naming the file.

use karst_testkit::cli::StageBinary;

const BINARY: StageBinary = StageBinary {
    path: env!("CARGO_BIN_EXE_karst-survey"),
    inputs: &["sdf.bin", "skeleton.json"],
    artifact: "survey.json",
};

#[test]
fn runs_on_the_tiny_scene() {
    BINARY.assert_runs_on_the_tiny_scene();
}

#[test]
fn bad_inputs_exit_2() {
    BINARY.assert_bad_inputs_exit_2();
}
