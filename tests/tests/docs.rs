//! Docs that cannot drift: every repository path, Rust file, local link and crate that
//! docs/*.md and the README name exists, and every workspace member has its place in
//! docs/architecture.md's code map. The checker is shown to fail on planted bad references.

use karst_artifact::StageId;
use karstgen_tests::docs::Repository;
use karstgen_tests::root;

/// docs/*.md and the README, as (path from the root, text).
fn pages() -> Vec<(String, String)> {
    let mut pages: Vec<String> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|name| name.ends_with(".md"))
        .map(|name| format!("docs/{name}"))
        .collect();
    pages.sort();
    pages.push("README.md".into());
    pages
        .into_iter()
        .map(|page| (page.clone(), std::fs::read_to_string(root().join(&page)).unwrap()))
        .collect()
}

#[test]
fn every_reference_of_the_docs_exists() {
    let repository = Repository::read(&root());
    let pages = pages();
    assert!(pages.len() > 10, "docs/ has its pages");
    let stale: Vec<String> =
        pages.iter().flat_map(|(page, text)| repository.stale_references(page, text)).collect();
    assert!(stale.is_empty(), "the docs name what the repository does not hold:\n{}", stale.join("\n"));
}

#[test]
fn every_workspace_member_is_in_the_code_map() {
    let repository = Repository::read(&root());
    assert!(repository.members.len() > 10, "{:?}", repository.members);
    let architecture = std::fs::read_to_string(root().join("docs/architecture.md")).unwrap();
    let missing = repository.missing_from_code_map(&architecture);
    assert!(missing.is_empty(), "docs/architecture.md's code map leaves out {missing:?}");
}

#[test]
fn the_checker_finds_planted_bad_references() {
    let repository = Repository::read(&root());
    let planted = "See `crates/raster/src/lib.rs` and crates/skeleton/src/nowhere.rs. The search is in \
                   `search.rs`, the radii in `radius.rs`; [scene](scene-gone.md); the `karst-raster` \
                   binary and `karst_nowhere::Thing`. Fine: crates/skeleton/src/route/search.rs, \
                   `crates/<stage>/src/view.rs`, [scene](scene.md), `karst-sampling`, https://x.invalid/src/a.rs.";
    let stale = repository.stale_references("docs/skeleton.md", planted);
    let expected = [
        "docs/skeleton.md: crate karst-nowhere",
        "docs/skeleton.md: crate karst-raster",
        "docs/skeleton.md: file radius.rs (searched crates/skeleton/)",
        "docs/skeleton.md: link scene-gone.md",
        "docs/skeleton.md: path crates/raster/src/lib.rs",
        "docs/skeleton.md: path crates/skeleton/src/nowhere.rs",
    ];
    assert_eq!(stale, expected);
    let map = "# A\n\n## Code map\n\n**`crates/artifact`**, **`xtask`**\n\n## Invariants\n\n`crates/plot`\n";
    let missing = repository.missing_from_code_map(map);
    assert!(
        missing.contains(&"crates/plot".to_string()) && !missing.contains(&"xtask".to_string()),
        "{missing:?}"
    );
}

/// docs/images/stage-graph.svg draws one arrow per input of the stage table, titled
/// "upstream → stage", and a box per stage.
#[test]
fn the_stage_graph_picture_is_the_stage_table() {
    let svg = std::fs::read_to_string(root().join("docs/images/stage-graph.svg")).unwrap();
    let mut drawn: Vec<String> = svg
        .split("<title>")
        .skip(2)
        .filter_map(|t| t.split_once("</title>").map(|(title, _)| title.to_string()))
        .collect();
    let mut table: Vec<String> = StageId::ALL
        .into_iter()
        .flat_map(|s| s.inputs().iter().map(move |i| format!("{} → {}", i.name(), s.name())))
        .collect();
    drawn.sort();
    table.sort();
    assert_eq!(drawn, table, "the arrows of docs/images/stage-graph.svg");
    for stage in StageId::ALL {
        assert!(svg.contains(&format!(">{}</text>", stage.name())), "no box for {}", stage.name());
    }
}
