//! The module-graph check (`cargo xtask modules`): no import circles inside a crate.
//!
//! For every crate of the workspace (each package's `src/lib.rs`, `src/main.rs` and
//! `src/bin/*.rs` is a crate of its own), the modules are found by following the `mod`
//! declarations from the crate root (file modules and inline `mod x { ... }` alike), and each
//! module's source is parsed with `syn`. A path that starts with `crate::` — in a `use`, in
//! code, or in the tokens of a macro call or definition (`$crate::` too) — is an edge from the
//! module it is written in to the longest module its path names (`crate::view::part::json`
//! goes to `view::part`, and through it to `view`). Edges between a module and one that contains it are not counted
//! (a parent declares its children; a child reaches its parent's items), nor are paths to items
//! of the crate root (`crate::Scene`, whatever module re-exports it there). A circle is a
//! strongly connected component of more than one module: each of them reaches every other
//! through `crate::` paths, so none can be understood, moved or split out without the others.

use std::path::{Path, PathBuf};

use proc_macro2::{TokenStream, TokenTree};
use syn::visit::Visit;

/// Why a crate's modules cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ModuleError {
    #[error("cannot read {path}: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: module `{module}` has no file ({tried})")]
    MissingFile { path: PathBuf, module: String, tried: String },
}

/// One module of a crate: its path from the crate root (`view::part`; empty for the root) and the
/// file it is written in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Module {
    pub path: String,
    pub file: PathBuf,
}

/// A circle: modules of one crate each reaching every other through `crate::` paths.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Circle {
    /// The crate: its root file.
    pub root: PathBuf,
    /// The modules, by path, with the modules of the circle each one uses.
    pub modules: Vec<(Module, Vec<String>)>,
}

impl std::fmt::Display for Circle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}: a circle of {} modules:", self.root.display(), self.modules.len())?;
        for (module, uses) in &self.modules {
            writeln!(f, "  {} ({}) uses {}", module.path, module.file.display(), uses.join(", "))?;
        }
        Ok(())
    }
}

/// The circles of every crate of the workspace at `root` (its `[workspace] members`).
pub fn check_workspace(root: &Path) -> Result<Vec<Circle>, ModuleError> {
    let mut circles = Vec::new();
    for member in members(root)? {
        for crate_root in crate_roots(&root.join(member)) {
            circles.extend(check_crate(&crate_root)?);
        }
    }
    Ok(circles)
}

/// The circles of the crate whose root file is `crate_root`.
pub fn check_crate(crate_root: &Path) -> Result<Vec<Circle>, ModuleError> {
    let mut graph = Graph::default();
    let dir = crate_root.parent().unwrap_or(Path::new("")).to_path_buf();
    let file = parse(crate_root)?;
    graph.collect_items(String::new(), crate_root, &dir, &file.items)?;
    Ok(graph.circles(crate_root))
}

/// The member folders of the workspace's `Cargo.toml`.
fn members(root: &Path) -> Result<Vec<String>, ModuleError> {
    let path = root.join("Cargo.toml");
    let text = read(&path)?;
    let manifest: toml::Table = toml::from_str(&text)
        .map_err(|e| ModuleError::Parse { path: path.clone(), message: e.to_string() })?;
    let members =
        manifest.get("workspace").and_then(|w| w.get("members")).and_then(|m| m.as_array()).ok_or_else(
            || ModuleError::Parse { path: path.clone(), message: "has no [workspace] members".into() },
        )?;
    Ok(members.iter().filter_map(|m| m.as_str().map(str::to_string)).collect())
}

/// The crate roots of the package in `folder`: its library, its main binary and `src/bin/*.rs`.
fn crate_roots(folder: &Path) -> Vec<PathBuf> {
    let src = folder.join("src");
    let mut roots: Vec<PathBuf> =
        ["lib.rs", "main.rs"].iter().map(|f| src.join(f)).filter(|p| p.is_file()).collect();
    if let Ok(entries) = std::fs::read_dir(src.join("bin")) {
        let mut bins: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "rs"))
            .collect();
        bins.sort();
        roots.extend(bins);
    }
    roots
}

fn read(path: &Path) -> Result<String, ModuleError> {
    std::fs::read_to_string(path).map_err(|source| ModuleError::Read { path: path.to_path_buf(), source })
}

fn parse(path: &Path) -> Result<syn::File, ModuleError> {
    syn::parse_file(&read(path)?)
        .map_err(|e| ModuleError::Parse { path: path.to_path_buf(), message: e.to_string() })
}

/// The modules of one crate and the `crate::` paths written in each.
#[derive(Default)]
struct Graph {
    modules: Vec<Module>,
    /// Per module (same index), the paths after `crate::`, as segments.
    paths: Vec<Vec<Vec<String>>>,
}

impl Graph {
    /// Records module `path` (written in `file`, its child files in `dir`) with `items`.
    fn collect_items(
        &mut self,
        path: String,
        file: &Path,
        dir: &Path,
        items: &[syn::Item],
    ) -> Result<(), ModuleError> {
        let mut paths = CratePaths::default();
        for item in items {
            paths.visit_item(item);
        }
        self.modules.push(Module { path: path.clone(), file: file.to_path_buf() });
        self.paths.push(paths.found);
        for item in items {
            let syn::Item::Mod(m) = item else { continue };
            let name = m.ident.to_string();
            let child = if path.is_empty() { name.clone() } else { format!("{path}::{name}") };
            match &m.content {
                Some((_, inner)) => self.collect_items(child, file, &dir.join(&name), inner)?,
                None => {
                    let (child_file, child_dir) = child_file(file, dir, &name, &m.attrs)?;
                    let parsed = parse(&child_file)?;
                    self.collect_items(child, &child_file, &child_dir, &parsed.items)?;
                }
            }
        }
        Ok(())
    }

    /// The module a `crate::` path goes to: the longest module its segments name.
    fn target(&self, segments: &[String]) -> Option<usize> {
        (1..=segments.len()).rev().find_map(|n| {
            let path = segments[..n].join("::");
            self.modules.iter().position(|m| m.path == path)
        })
    }

    /// Module `m` and the modules that contain it (reaching `a::b` goes through `a`).
    fn with_ancestors(&self, m: usize) -> Vec<usize> {
        let path = &self.modules[m].path;
        let prefixes = path.match_indices("::").map(|(i, _)| &path[..i]);
        let mut found: Vec<usize> =
            prefixes.filter_map(|p| self.modules.iter().position(|o| o.path == p)).collect();
        found.push(m);
        found
    }

    /// The edges between modules neither of which contains the other.
    fn edges(&self) -> Vec<Vec<usize>> {
        let contains = |outer: &str, inner: &str| {
            outer.is_empty() || inner == outer || inner.starts_with(&format!("{outer}::"))
        };
        self.paths
            .iter()
            .enumerate()
            .map(|(from, paths)| {
                let mut to: Vec<usize> = paths
                    .iter()
                    .filter_map(|p| self.target(p))
                    .flat_map(|t| self.with_ancestors(t))
                    .filter(|&t| {
                        let (a, b) = (&self.modules[from].path, &self.modules[t].path);
                        !contains(a, b) && !contains(b, a)
                    })
                    .collect();
                to.sort_unstable();
                to.dedup();
                to
            })
            .collect()
    }

    fn circles(&self, root: &Path) -> Vec<Circle> {
        let edges = self.edges();
        strongly_connected(&edges)
            .into_iter()
            .filter(|c| c.len() > 1)
            .map(|mut component| {
                component.sort_by(|a, b| self.modules[*a].path.cmp(&self.modules[*b].path));
                let modules = component
                    .iter()
                    .map(|&m| {
                        let uses = edges[m]
                            .iter()
                            .filter(|t| component.contains(t))
                            .map(|&t| self.modules[t].path.clone())
                            .collect();
                        (self.modules[m].clone(), uses)
                    })
                    .collect();
                Circle { root: root.to_path_buf(), modules }
            })
            .collect()
    }
}

/// The file of `mod name;` declared in `file` (child files in `dir`): `#[path]`, `name.rs` or
/// `name/mod.rs`; and the folder of its own children.
fn child_file(
    file: &Path,
    dir: &Path,
    name: &str,
    attrs: &[syn::Attribute],
) -> Result<(PathBuf, PathBuf), ModuleError> {
    let explicit = attrs.iter().find(|a| a.path().is_ident("path")).and_then(|a| match &a.meta {
        syn::Meta::NameValue(nv) => match &nv.value {
            syn::Expr::Lit(syn::ExprLit { lit: syn::Lit::Str(s), .. }) => Some(s.value()),
            _ => None,
        },
        _ => None,
    });
    if let Some(relative) = explicit {
        let path = file.parent().unwrap_or(Path::new("")).join(relative);
        let children = path.with_extension("");
        return Ok((path, children));
    }
    let flat = dir.join(format!("{name}.rs"));
    if flat.is_file() {
        return Ok((flat, dir.join(name)));
    }
    let nested = dir.join(name).join("mod.rs");
    if nested.is_file() {
        return Ok((nested, dir.join(name)));
    }
    Err(ModuleError::MissingFile {
        path: file.to_path_buf(),
        module: name.into(),
        tried: format!("{} or {}", flat.display(), nested.display()),
    })
}

/// The `crate::` paths of one module's items, not descending into its inline modules (they are
/// modules of their own).
#[derive(Default)]
struct CratePaths {
    found: Vec<Vec<String>>,
}

impl CratePaths {
    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree);
                prefix.pop();
            }
            syn::UseTree::Name(n) => self.use_path(prefix, Some(n.ident.to_string())),
            syn::UseTree::Rename(r) => self.use_path(prefix, Some(r.ident.to_string())),
            syn::UseTree::Glob(_) => self.use_path(prefix, None),
            syn::UseTree::Group(g) => g.items.iter().for_each(|t| self.use_tree(prefix, t)),
        }
    }

    fn use_path(&mut self, prefix: &[String], last: Option<String>) {
        let mut segments: Vec<String> = prefix.to_vec();
        segments.extend(last.filter(|l| l != "self"));
        if segments.first().is_some_and(|s| s == "crate") {
            self.found.push(segments[1..].to_vec());
        }
    }

    /// `crate :: a :: b` sequences in macro tokens (`$crate` included: it is this crate).
    fn tokens(&mut self, tokens: TokenStream) {
        let tokens: Vec<TokenTree> = tokens.into_iter().collect();
        for (i, token) in tokens.iter().enumerate() {
            match token {
                TokenTree::Group(g) => self.tokens(g.stream()),
                TokenTree::Ident(id) if id == "crate" => {
                    let mut segments = Vec::new();
                    let mut j = i + 1;
                    while let [TokenTree::Punct(a), TokenTree::Punct(b), TokenTree::Ident(name), ..] =
                        &tokens[j..]
                    {
                        if a.as_char() != ':' || b.as_char() != ':' {
                            break;
                        }
                        segments.push(name.to_string());
                        j += 3;
                    }
                    if !segments.is_empty() {
                        self.found.push(segments);
                    }
                }
                _ => {}
            }
        }
    }
}

impl<'ast> Visit<'ast> for CratePaths {
    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {}

    fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
        self.use_tree(&mut Vec::new(), &item.tree);
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        if segments.len() > 1 && segments[0] == "crate" {
            self.found.push(segments[1..].to_vec());
        }
        syn::visit::visit_path(self, path);
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        self.tokens(mac.tokens.clone());
        syn::visit::visit_macro(self, mac);
    }
}

/// Tarjan's strongly connected components of the graph `edges` (node → its successors), each
/// component's nodes in the order they were completed.
fn strongly_connected(edges: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct Walk<'a> {
        edges: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        components: Vec<Vec<usize>>,
    }
    impl Walk<'_> {
        fn visit(&mut self, v: usize) {
            self.index[v] = Some(self.next);
            self.low[v] = self.next;
            self.next += 1;
            self.stack.push(v);
            self.on_stack[v] = true;
            for &w in &self.edges[v] {
                match self.index[w] {
                    None => {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    }
                    Some(i) if self.on_stack[w] => self.low[v] = self.low[v].min(i),
                    Some(_) => {}
                }
            }
            if Some(self.low[v]) == self.index[v] {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack[w] = false;
                    component.push(w);
                    if w == v {
                        break;
                    }
                }
                self.components.push(component);
            }
        }
    }
    let n = edges.len();
    let mut walk = Walk {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        components: Vec::new(),
    };
    for v in 0..n {
        if walk.index[v].is_none() {
            walk.visit(v);
        }
    }
    walk.components
}
