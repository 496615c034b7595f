//! The module-graph check: the workspace has no import circle, and a planted one is reported
//! with its modules and files (so the check can fail).

use std::path::Path;

use xtask::modules::{check_crate, check_workspace};
use xtask::temp_folder::TempFolder;

#[test]
fn the_workspace_has_no_import_circle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let circles = check_workspace(&root).unwrap_or_else(|e| panic!("{e}"));
    let report: String = circles.iter().map(ToString::to_string).collect();
    assert!(circles.is_empty(), "{report}");
}

fn write(folder: &Path, file: &str, text: &str) {
    let path = folder.join(file);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A crate where `a` and `b/mod.rs` use each other (`a` through `b`'s child, `b` through a path
/// in a macro's tokens), the inline module `e::inner` and `g` use each other, `c` uses `a` and
/// `b` without being used, `d`'s inline child and `d` use each other (parent and child: not a
/// circle), and `f` uses an item of the root only.
#[test]
fn a_planted_circle_is_reported_with_its_files() {
    let folder = TempFolder::new("modules-test");
    write(
        &folder,
        "src/lib.rs",
        "mod a;\nmod b;\nmod c;\nmod d;\nmod e;\nmod f;\nmod g;\npub struct Root;\n",
    );
    write(&folder, "src/a.rs", "use crate::b::inner::Thing;\npub struct A(pub Thing);\n");
    write(&folder, "src/b/mod.rs", "pub mod inner;\npub fn f() { println!(\"{}\", crate::a::A::NAME); }\n");
    write(&folder, "src/b/inner.rs", "pub struct Thing;\n");
    write(&folder, "src/c.rs", "use crate::{a::A, b};\npub fn g(_: A) { b::f() }\n");
    write(
        &folder,
        "src/d.rs",
        "pub mod nested {\n    pub fn h() { crate::d::top() }\n}\npub fn top() { crate::d::nested::h() }\n",
    );
    write(&folder, "src/e.rs", "pub mod inner {\n    pub fn k() { crate::g::z() }\n}\n");
    write(&folder, "src/f.rs", "pub fn m(_: crate::Root) {}\n");
    write(&folder, "src/g.rs", "pub fn z() { crate::e::inner::k() }\n");
    let circles = check_crate(&folder.join("src/lib.rs")).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<Vec<&str>> =
        circles.iter().map(|c| c.modules.iter().map(|(m, _)| m.path.as_str()).collect()).collect();
    assert_eq!(names.len(), 2, "{names:?}");
    assert!(names.contains(&vec!["a", "b"]), "{names:?}");
    assert!(names.contains(&vec!["e::inner", "g"]), "{names:?}");
    let report: String = circles.iter().map(ToString::to_string).collect();
    for file in ["src/a.rs", "src/b/mod.rs", "src/e.rs", "src/g.rs"] {
        assert!(report.contains(file), "{file} missing from {report}");
    }
    for file in ["src/c.rs", "src/d.rs", "src/f.rs", "src/b/inner.rs"] {
        assert!(!report.contains(file), "{file} in {report}");
    }
    assert!(report.contains("a.rs) uses b\n"), "{report}");
}
