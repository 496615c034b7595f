//! The docs' references to the repository, checked against it, so that docs/*.md and the README
//! cannot drift from the code without a test failing.
//!
//! What a page may name, and what must then exist:
//! - a repository path (`crates/…`, `docs/…`, `fixtures/…`, `xtask/…`, `tools/…`, `src/…`,
//!   `python/…`, `tests/…`): the path from the root, or for `src/…` and `tests/…` inside some
//!   crate (a crate's page says `tests/modes.rs` for its own tests). A placeholder (`<stage>`,
//!   `*`, `{…}`) ends the path: what comes before it must exist;
//! - a bare Rust file (`search.rs`): a file of that name in the crate the page documents
//!   (docs/skeleton.md: crates/skeleton), anywhere in the code otherwise;
//! - a Markdown link to a local file, relative to the page;
//! - a crate (`karst-sampling`, `karst_geology::…`): a package or binary of the workspace.
//!
//! And every workspace member must appear in docs/architecture.md's code map.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The prefixes of repository paths.
const ROOTS: [&str; 8] = ["crates/", "docs/", "fixtures/", "xtask/", "tools/", "src/", "python/", "tests/"];

/// Paths the docs may name that a checkout does not hold: installed or generated, not tracked.
pub const GENERATED: [(&str, &str); 1] =
    [("tools/node/node_modules/", "installed by `cargo xtask test` from tools/node/package.json")];

/// The folders of code searched for a bare Rust file name.
const CODE: [&str; 5] = ["crates", "xtask", "tests", "src", "python"];

/// What the docs are checked against: the workspace's members, crate names and Rust files.
pub struct Repository {
    root: PathBuf,
    /// Workspace members, as paths from the root ("." for the root package).
    pub members: Vec<String>,
    /// Package and binary names of every member.
    pub crates: BTreeSet<String>,
    /// Every Rust file of the code, as paths from the root.
    rust_files: Vec<String>,
}

impl Repository {
    /// Reads the workspace at `root` (its Cargo.toml's members and theirs).
    pub fn read(root: &Path) -> Repository {
        let manifest = |dir: &Path| -> toml::Table {
            let path = dir.join("Cargo.toml");
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            text.parse().unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        };
        let workspace = manifest(root);
        let members: Vec<String> = workspace["workspace"]["members"]
            .as_array()
            .expect("[workspace] members")
            .iter()
            .filter_map(|m| m.as_str().map(str::to_string))
            .collect();
        let mut crates = BTreeSet::new();
        for member in &members {
            let table = manifest(&root.join(member));
            let names = table.get("package").and_then(|p| p.get("name")).into_iter().chain(
                table
                    .get("bin")
                    .and_then(|b| b.as_array())
                    .into_iter()
                    .flatten()
                    .filter_map(|b| b.get("name")),
            );
            crates.extend(names.filter_map(|n| n.as_str().map(str::to_string)));
        }
        let mut rust_files = Vec::new();
        for dir in CODE {
            walk(root, &root.join(dir), &mut rust_files);
        }
        Repository { root: root.to_path_buf(), members, crates, rust_files }
    }

    /// What `text`, the page at `page` (from the root), names that the repository does not
    /// hold, one line each ("page: reference").
    pub fn stale_references(&self, page: &str, text: &str) -> Vec<String> {
        let mut stale = BTreeSet::new();
        for path in repository_paths(text) {
            if !self.path_exists(&path) {
                stale.insert(format!("{page}: path {path}"));
            }
        }
        let crate_dir = Path::new(page).file_stem().map(|s| format!("crates/{}/", s.to_string_lossy()));
        let crate_dir = crate_dir.filter(|d| self.root.join(d).is_dir());
        for file in bare_rust_files(text) {
            let scope = crate_dir.as_deref().unwrap_or("");
            let found =
                self.rust_files.iter().any(|f| f.starts_with(scope) && f.ends_with(&format!("/{file}")));
            if !found {
                stale.insert(format!(
                    "{page}: file {file} (searched {})",
                    if scope.is_empty() { "the code" } else { scope }
                ));
            }
        }
        let dir = Path::new(page).parent().unwrap_or(Path::new(""));
        for link in local_links(text) {
            if !self.root.join(dir).join(&link).exists() {
                stale.insert(format!("{page}: link {link}"));
            }
        }
        for name in crate_names(text) {
            if !self.crates.contains(&name) {
                stale.insert(format!("{page}: crate {name}"));
            }
        }
        stale.into_iter().collect()
    }

    /// The workspace members `architecture` (docs/architecture.md) leaves out of its code map:
    /// each must be named in backticks there (`crates/plot`, `xtask`; the root package as
    /// `karstgen`).
    pub fn missing_from_code_map(&self, architecture: &str) -> Vec<String> {
        let map = section(architecture, "## Code map");
        self.members
            .iter()
            .filter(|member| {
                let name = if member.as_str() == "." { "karstgen" } else { member.trim_end_matches('/') };
                !map.contains(&format!("`{name}`")) && !map.contains(&format!("`{name}/`"))
            })
            .cloned()
            .collect()
    }

    fn path_exists(&self, path: &str) -> bool {
        if GENERATED.iter().any(|(prefix, _)| path.starts_with(prefix)) || self.root.join(path).exists() {
            return true;
        }
        (path.starts_with("src/") || path.starts_with("tests/"))
            && self.members.iter().any(|m| self.root.join(m).join(path).exists())
    }
}

/// The Rust files under `dir`, as paths from `root` (skipping build output and installed tools).
fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if path.is_dir() && !matches!(name.to_str(), Some("target" | "node_modules" | ".venv")) {
            walk(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(root).expect("under the root");
            out.push(relative.to_string_lossy().replace('\\', "/"));
        }
    }
}

/// The text of the section of `text` that starts at the heading `heading`, up to the next
/// heading of the same level.
fn section<'a>(text: &'a str, heading: &str) -> &'a str {
    let Some(start) = text.find(&format!("{heading}\n")) else { return "" };
    let body = &text[start + heading.len()..];
    let level = format!("\n{} ", &heading[..heading.find(' ').unwrap_or(heading.len())]);
    &body[..body.find(&level).unwrap_or(body.len())]
}

fn is_path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-')
}

/// Whether `text[at..]` starts a word: the character before is not part of a path or a name
/// (a URL's `/src/…`, `out/crates/…` and `docs/../x` are not repository paths).
fn starts_word(text: &str, at: usize) -> bool {
    text[..at]
        .chars()
        .next_back()
        .is_none_or(|c| !is_path_char(c) && !matches!(c, ':' | '<' | '>' | '$' | '~'))
}

/// Every repository path named in `text`, up to a placeholder, without a sentence's full stop.
pub fn repository_paths(text: &str) -> Vec<String> {
    let mut paths = Vec::new();
    for root in ROOTS {
        for (at, _) in text.match_indices(root) {
            if !starts_word(text, at) {
                continue;
            }
            let rest = &text[at..];
            let end = rest.find(|c: char| !is_path_char(c)).unwrap_or(rest.len());
            let mut path = &rest[..end];
            if rest[end..].starts_with(['<', '*', '{', '$']) {
                path = &path[..path.rfind('/').map_or(0, |i| i + 1)];
            }
            paths.push(path.trim_end_matches('.').to_string());
        }
    }
    paths
}

/// Every bare Rust file name in `text` (`search.rs`, not `src/search.rs`).
pub fn bare_rust_files(text: &str) -> Vec<String> {
    let mut files = Vec::new();
    for (at, _) in text.match_indices(".rs") {
        let after = text[at + 3..].chars().next();
        if after.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let start = text[..at].rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let before = text[..start].chars().next_back();
        if start < at && !before.is_some_and(|c| matches!(c, '/' | '.' | '-' | '<' | '*')) {
            files.push(text[start..at + 3].to_string());
        }
    }
    files
}

/// The targets of Markdown links to local files (not URLs, not anchors), without their anchor.
pub fn local_links(text: &str) -> Vec<String> {
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            let target = &rest[..rest.find([')', ' ', '#'])?];
            let local = !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:");
            local.then(|| target.to_string())
        })
        .collect()
}

/// Every crate named in `text`: `karst-…` and the `karst_…` of a Rust path, as package names.
pub fn crate_names(text: &str) -> Vec<String> {
    let mut names = Vec::new();
    for prefix in ["karst-", "karst_"] {
        for (at, _) in text.match_indices(prefix) {
            if !starts_word(text, at) {
                continue;
            }
            let rest = &text[at..];
            let end = rest
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '_'))
                .unwrap_or(rest.len());
            if rest[end..].starts_with(['<', '*', '{']) {
                continue;
            }
            let name = rest[..end].trim_end_matches(['-', '_']).replace('_', "-");
            if name.len() > prefix.len() {
                names.push(name);
            }
        }
    }
    names
}
