//! The outside tools the test suite checks karstgen's outputs with, installed on first use.
//!
//! The suite tests exports with the programs users open them in (karstnet, VTK, EPA SWMM,
//! Survex, the glTF validator, a browser), so `cargo xtask test` installs them when missing:
//!
//! - Python packages pinned in `tools/python-requirements.txt`, into `.venv` (a stamp file
//!   holding the requirements' hash makes a changed list reinstall);
//! - Debian packages listed in `tools/apt-packages.txt`, with `apt-get` (as root, or through
//!   `sudo` when it is there);
//! - npm packages pinned by `tools/node/package-lock.json`, into `tools/node/node_modules`
//!   with `npm ci`.
//!
//! The tests find them through environment variables that [`Tools::env`] sets:
//! `KARSTNET_PYTHON` (the venv's Python) and `KARSTGEN_NODE_MODULES`; Debian programs are on
//! the `PATH`. A test whose tool is missing fails rather than passing silently.

use std::path::{Path, PathBuf};
use std::process::Command;

const PYTHON_REQUIREMENTS: &str = "tools/python-requirements.txt";
const APT_PACKAGES: &str = "tools/apt-packages.txt";
const NODE_DIR: &str = "tools/node";
const VENV: &str = ".venv";

/// Where the installed tools are.
#[derive(Debug, Clone)]
pub struct Tools {
    /// The venv's Python, with every package of the requirements.
    pub python: PathBuf,
    /// `tools/node/node_modules`.
    pub node_modules: PathBuf,
}

impl Tools {
    /// Installs what is missing, under `root` (the workspace).
    pub fn ensure(root: &Path) -> Result<Tools, String> {
        let python = ensure_python(root)?;
        ensure_apt(root)?;
        let node_modules = ensure_node(root)?;
        Ok(Tools { python, node_modules })
    }

    /// The environment variables the tests read.
    pub fn env(&self) -> [(&'static str, &Path); 2] {
        [("KARSTNET_PYTHON", &self.python), ("KARSTGEN_NODE_MODULES", &self.node_modules)]
    }
}

fn ensure_python(root: &Path) -> Result<PathBuf, String> {
    ensure_venv(root, PYTHON_REQUIREMENTS, VENV)
}

/// The Python of the venv `venv` (under `root`), created and filled with the pinned packages of
/// `requirements` when they changed (a stamp file in the venv holds their hash). The path stays
/// a path into the venv: resolving its symlink would name the base interpreter, without the
/// packages.
pub fn ensure_venv(root: &Path, requirements: &str, venv: &str) -> Result<PathBuf, String> {
    let list = read(&root.join(requirements))?;
    let digest = karst_artifact::hash::hex(list.as_bytes());
    let python = root.join(venv).join("bin/python");
    let stamp = root.join(venv).join("karstgen-requirements.blake3");
    if python.exists() && std::fs::read_to_string(&stamp).is_ok_and(|s| s.trim() == digest) {
        return Ok(python);
    }
    eprintln!("installing the Python packages of {requirements} into {venv}...");
    if !python.exists() {
        run(root, &["python3", "-m", "venv", venv])?;
    }
    let pip = root.join(venv).join("bin/pip");
    let pip = pip.to_string_lossy();
    run(root, &[&pip, "install", "--quiet", "--disable-pip-version-check", "-r", requirements])?;
    std::fs::write(&stamp, digest).map_err(|e| format!("{}: {e}", stamp.display()))?;
    Ok(python)
}

/// Installs the Debian packages that are not installed yet.
fn ensure_apt(root: &Path) -> Result<(), String> {
    let list = read(&root.join(APT_PACKAGES))?;
    let missing: Vec<&str> = packages(&list).filter(|p| !dpkg_installed(p)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    eprintln!("installing the Debian test tools {} (apt-get)...", missing.join(" "));
    let sudo: &[&str] = if is_root() { &[] } else { &["sudo", "-n"] };
    let mut update = sudo.to_vec();
    update.extend(["apt-get", "update", "-qq"]);
    run(root, &update)?;
    let mut install = sudo.to_vec();
    install.extend(["apt-get", "install", "-y", "-qq", "--no-install-recommends"]);
    install.extend(&missing);
    run(root, &install).map_err(|e| {
        format!("{e}\ninstall them yourself (`apt-get install {}`) and rerun", missing.join(" "))
    })
}

/// `npm ci` in tools/node unless node_modules was installed from this very lock file (a stamp
/// holds the lock's hash: npm's own `.package-lock.json` is rewritten by `npm install
/// --package-lock-only` without installing anything).
fn ensure_node(root: &Path) -> Result<PathBuf, String> {
    let dir = root.join(NODE_DIR);
    let modules = dir.join("node_modules");
    let lock = read(&dir.join("package-lock.json"))?;
    let digest = karst_artifact::hash::hex(lock.as_bytes());
    let stamp = modules.join(".karstgen-lock.blake3");
    if std::fs::read_to_string(&stamp).is_ok_and(|s| s.trim() == digest) {
        return Ok(modules);
    }
    eprintln!("installing the npm test tools of {NODE_DIR}/package-lock.json...");
    run(&dir, &["npm", "ci", "--silent", "--no-audit", "--no-fund"])?;
    std::fs::write(&stamp, digest).map_err(|e| format!("{}: {e}", stamp.display()))?;
    Ok(modules)
}

/// The package names of a list file: one per line, `#` starts a comment.
fn packages(list: &str) -> impl Iterator<Item = &str> {
    list.lines().map(|l| l.split('#').next().unwrap_or("").trim()).filter(|l| !l.is_empty())
}

fn dpkg_installed(package: &str) -> bool {
    Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", package])
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("install ok installed"))
}

fn is_root() -> bool {
    Command::new("id").arg("-u").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

fn run(dir: &Path, command: &[&str]) -> Result<(), String> {
    let status = Command::new(command[0])
        .args(&command[1..])
        .current_dir(dir)
        .status()
        .map_err(|e| format!("`{}`: {e}", command.join(" ")))?;
    if status.success() { Ok(()) } else { Err(format!("`{}` failed ({status})", command.join(" "))) }
}

#[cfg(test)]
mod tests {
    use super::packages;

    #[test]
    fn package_lists_skip_comments_and_blank_lines() {
        let list = "# tools\nsurvex  # cavern\n\n  gdal-bin\n";
        assert_eq!(packages(list).collect::<Vec<_>>(), ["survex", "gdal-bin"]);
    }
}
