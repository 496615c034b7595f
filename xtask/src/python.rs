//! The Python package's part of `cargo xtask test`: build the `karstgen` wheel (python/, with
//! PyO3 and maturin) into `target/wheels`, install it into the test venv when it changed, and
//! run its pytest suite with the `karstgen` command of the same workspace (`KARSTGEN_BIN`).
//!
//! The wheel is built with maturin from the venv (pinned in tools/python-requirements.txt),
//! in the workspace's target folder and release profile, so the stage crates it links are
//! compiled once for the command line and the wheel alike.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::tools::Tools;

const WHEEL_STAMP: &str = ".venv/karstgen-wheel.blake3";

/// Builds and installs the wheel, then runs pytest on python/tests; true when it passed.
pub fn test(root: &Path, tools: &Tools) -> Result<bool, String> {
    let wheel = build_wheel(root, &tools.python)?;
    install(root, &tools.python, &wheel)?;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let built = Command::new(&cargo)
        .args(["build", "--release", "--quiet", "-p", "karstgen", "--bin", "karstgen"])
        .current_dir(root)
        .status()
        .map_err(|e| format!("cargo build: {e}"))?;
    if !built.success() {
        return Err("cannot build the karstgen command".into());
    }
    let status = Command::new(&tools.python)
        .args(["-m", "pytest", "python/tests", "-q", "-p", "no:cacheprovider"])
        .current_dir(root)
        .envs(tools.env())
        .env("KARSTGEN_BIN", target_dir(root).join("release/karstgen"))
        .status()
        .map_err(|e| format!("pytest: {e}"))?;
    Ok(status.success())
}

/// The workspace's target folder (`CARGO_TARGET_DIR` when set).
fn target_dir(root: &Path) -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => root.join(dir),
        None => root.join("target"),
    }
}

/// `maturin build --release` of python/; returns the wheel's path.
fn build_wheel(root: &Path, python: &Path) -> Result<PathBuf, String> {
    let out = target_dir(root).join("wheels");
    let maturin = python.with_file_name("maturin");
    eprintln!("building the karstgen wheel (python/) with maturin...");
    let start = std::time::Instant::now();
    let status = Command::new(&maturin)
        .args(["build", "--release", "-m", "python/Cargo.toml", "--out"])
        .arg(&out)
        .arg("--interpreter")
        .arg(python)
        .current_dir(root)
        .status()
        .map_err(|e| format!("{}: {e} (run `cargo xtask test`: it installs maturin)", maturin.display()))?;
    if !status.success() {
        return Err("maturin could not build the wheel".into());
    }
    eprintln!("built the karstgen wheel in {:.0} s", start.elapsed().as_secs_f64());
    newest_wheel(&out)
}

/// The most recently written `karstgen-*.whl` of `folder`.
fn newest_wheel(folder: &Path) -> Result<PathBuf, String> {
    let entries = std::fs::read_dir(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("karstgen-")))
        .filter(|p| p.extension().is_some_and(|x| x == "whl"))
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .ok_or_else(|| format!("maturin built no wheel into {}", folder.display()))
}

/// Installs `wheel` into the venv unless the same wheel is installed already.
fn install(root: &Path, python: &Path, wheel: &Path) -> Result<(), String> {
    let bytes = std::fs::read(wheel).map_err(|e| format!("{}: {e}", wheel.display()))?;
    let digest = karst_artifact::hash::hex(&bytes);
    let stamp = root.join(WHEEL_STAMP);
    if std::fs::read_to_string(&stamp).is_ok_and(|s| s.trim() == digest) {
        return Ok(());
    }
    let status = Command::new(python)
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--no-deps",
            "--force-reinstall",
        ])
        .arg(wheel)
        .current_dir(root)
        .status()
        .map_err(|e| format!("pip: {e}"))?;
    if !status.success() {
        return Err(format!("pip could not install {}", wheel.display()));
    }
    std::fs::write(&stamp, digest).map_err(|e| format!("{}: {e}", stamp.display()))
}
