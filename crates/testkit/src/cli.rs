//! The command-line contract every stage binary keeps, checked on the tiny scene: `run` on the
//! upstream goldens (fixtures/golden/tiny) exits 0 and writes the stage's golden artifact byte
//! for byte, `inspect` reads it; a truncated input artifact and a scene that does not parse
//! exit 2 with a message naming the file.

use std::path::Path;
use std::process::{Command, Output};

use crate::{Scratch, fixture, scratch};

/// One stage binary: its path (`env!("CARGO_BIN_EXE_karst-…")`), the artifact files it reads
/// and the one it writes.
pub struct StageBinary<'a> {
    pub path: &'a str,
    pub inputs: &'a [&'a str],
    pub artifact: &'a str,
}

impl StageBinary<'_> {
    /// Runs the binary with `args`.
    pub fn command(&self, args: &[&str]) -> Output {
        Command::new(self.path).args(args).output().unwrap_or_else(|e| panic!("{}: {e}", self.path))
    }

    /// A scratch folder holding the tiny scene's golden inputs of the stage.
    fn with_inputs(&self, name: &str) -> Scratch {
        let out = scratch(name);
        for input in self.inputs {
            std::fs::copy(fixture(&format!("fixtures/golden/tiny/{input}")), out.join(input)).unwrap();
        }
        out
    }

    /// `run SCENE --out DIR` on the tiny scene.
    fn run_tiny(&self, out: &Path) -> Output {
        let scene = fixture("fixtures/scenes/tiny.toml");
        self.command(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
    }

    /// `run` writes the golden artifact, `inspect` reads it.
    pub fn assert_runs_on_the_tiny_scene(&self) {
        let out = self.with_inputs("cli-run");
        let result = self.run_tiny(&out);
        assert!(result.status.success(), "{}: {}", self.path, String::from_utf8_lossy(&result.stderr));
        let written = std::fs::read(out.join(self.artifact)).unwrap();
        let golden = std::fs::read(fixture(&format!("fixtures/golden/tiny/{}", self.artifact))).unwrap();
        assert!(written == golden, "{}: {} differs from its golden", self.path, self.artifact);
        let inspect = self.command(&["inspect", out.join(self.artifact).to_str().unwrap()]);
        assert!(inspect.status.success() && !inspect.stdout.is_empty(), "{}: inspect", self.path);
    }

    /// A truncated input artifact and a scene that does not parse: exit 2, the file named.
    pub fn assert_bad_inputs_exit_2(&self) {
        let out = self.with_inputs("cli-bad");
        if let Some(input) = self.inputs.first() {
            let path = out.join(input);
            let bytes = std::fs::read(&path).unwrap();
            std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
            let result = self.run_tiny(&out);
            let stderr = String::from_utf8_lossy(&result.stderr);
            assert_eq!(result.status.code(), Some(2), "{}, {input} truncated: {stderr}", self.path);
            assert!(stderr.contains(input), "{}: the message names {input}: {stderr}", self.path);
            assert!(!out.join(self.artifact).exists(), "{}: nothing written", self.path);
        }
        let bad = fixture("fixtures/bad/syntax.toml");
        let result = self.command(&["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{}, bad scene: {stderr}", self.path);
        assert!(stderr.contains("syntax.toml"), "{}: {stderr}", self.path);
    }
}
