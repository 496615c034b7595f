//! `cargo xtask bless [--accept --why REASON]`: the tiny scene's artifacts against the goldens
//! of `fixtures/golden/tiny`, reviewed before they are replaced.
//!
//! Without `--accept` it runs the pipeline into a scratch folder and prints the semantic diff
//! of every artifact (`karstgen diff`'s, tolerance 1e-9): nothing is written. With `--accept
//! --why REASON` it replaces the goldens and appends an entry to `fixtures/golden/CHANGES.md`:
//! the date, the reason, the diff and the BLAKE3 of every golden file as written. A test
//! (tests/tests/golden.rs) checks the last entry's hashes against the files, so a golden
//! changed by hand or by a tool that skips this record fails it.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use karst_artifact::StageId;
use karst_pipeline::diff;
use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::SceneFile;
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

/// The scene the goldens pin.
pub const GOLDEN_SCENE: &str = "fixtures/scenes/tiny.toml";
/// Where its artifacts are pinned.
pub const GOLDEN_DIR: &str = "fixtures/golden/tiny";
/// The record of every bless.
pub const CHANGES: &str = "fixtures/golden/CHANGES.md";

const CHANGES_HEADER: &str = "# Changes of the golden artifacts\n\n\
    Appended by `cargo xtask bless --accept --why REASON`, one entry per bless: when, why, the \
    semantic diff of each artifact against the previous golden, and the BLAKE3 of every file of \
    `fixtures/golden/tiny` as written. `tests/tests/golden.rs` checks the last entry's hashes \
    against the files.\n";

/// Runs the pipeline on the golden scene, prints the diff against the goldens, and with
/// `accept` (the reason) replaces them and records the change in [`CHANGES`].
pub fn bless(accept: Option<&str>) -> Result<(), StageError> {
    let scratch = TempFolder::new("bless");
    let selection = Selection { force: true, ..Selection::default() };
    make::run(&SceneFile::load(Path::new(GOLDEN_SCENE))?, &scratch, &selection, &mut |_| {})?;
    let golden = Path::new(GOLDEN_DIR);
    let mut report = String::new();
    let mut changed = false;
    for stage in StageId::ALL {
        let (new, old) = (scratch.join(stage.file_name()), golden.join(stage.file_name()));
        let line = match diff::diff(&old, &new, 1e-9) {
            Ok(d) if !d.differs() => format!("{}: unchanged\n", stage.file_name()),
            Ok(d) => format!("{}: changed\n{}\n", stage.file_name(), d.summary()),
            Err(e) => format!("{}: replaced ({e})\n", stage.file_name()),
        };
        changed |= !line.ends_with(": unchanged\n");
        report += &line;
    }
    print!("{report}");
    let Some(why) = accept else {
        println!("nothing written: review the diff, then `cargo xtask bless --accept --why \"REASON\"`");
        return Ok(());
    };
    let fail = |p: &Path, e: std::io::Error| StageError::failure(format!("{}: {e}", p.display()));
    std::fs::create_dir_all(golden).map_err(|e| fail(golden, e))?;
    for stage in StageId::ALL {
        let (new, old) = (scratch.join(stage.file_name()), golden.join(stage.file_name()));
        std::fs::copy(&new, &old).map_err(|e| fail(&old, e))?;
    }
    let changes = Path::new(CHANGES);
    let previous = std::fs::read_to_string(changes).unwrap_or_else(|_| CHANGES_HEADER.to_string());
    let now = hashes(golden)?;
    let recorded = previous.rsplit("\n## ").next().is_some_and(|last| last.ends_with(&hash_rows(&now)));
    if !changed && previous.contains("\n## ") && recorded {
        println!("the goldens are unchanged and recorded: {CHANGES} not extended");
        return Ok(());
    }
    let text = previous + &entry(&utc_now(), why, &report, &now);
    std::fs::write(changes, text).map_err(|e| fail(changes, e))?;
    println!("goldens replaced; {CHANGES} records why");
    Ok(())
}

/// The BLAKE3 of every file of the golden folder, by name, sorted.
pub fn hashes(golden: &Path) -> Result<Vec<(String, String)>, StageError> {
    let fail = |e: std::io::Error| StageError::failure(format!("{}: {e}", golden.display()));
    let mut hashes = Vec::new();
    for entry in std::fs::read_dir(golden).map_err(fail)? {
        let path = entry.map_err(fail)?.path();
        let bytes = std::fs::read(&path).map_err(fail)?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        hashes.push((name, blake3::hash(&bytes).to_hex().to_string()));
    }
    hashes.sort();
    Ok(hashes)
}

/// One entry of [`CHANGES`]: a heading with the date and the reason, the diff, the hashes.
pub fn entry(date: &str, why: &str, report: &str, hashes: &[(String, String)]) -> String {
    format!("\n## {date}: {}\n\n```text\n{report}```\n\n| golden | BLAKE3 |\n|---|---|\n", why.trim())
        + &hash_rows(hashes)
}

/// The hash table's rows of an entry, one per golden file.
fn hash_rows(hashes: &[(String, String)]) -> String {
    let mut rows = String::new();
    for (name, hash) in hashes {
        let _ = writeln!(rows, "| `tiny/{name}` | `{hash}` |");
    }
    rows
}

/// The current time in UTC, to the minute ("2026-12-06 02:50 UTC").
fn utc_now() -> String {
    let seconds = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (year, month, day) = civil_date(seconds / 86_400);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", seconds / 3600 % 24, seconds / 60 % 60)
}

/// The proleptic Gregorian date of a day count since 1970-01-01 (Hinnant's days-to-civil).
fn civil_date(days: u64) -> (u64, u64, u64) {
    let z = days + 719_468;
    let era = z / 146_097;
    let day_of_era = z % 146_097;
    let year_of_era = (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = year_of_era + era * 400 + u64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(civil_date(0), (1970, 1, 1));
        assert_eq!(civil_date(11_016), (2000, 2, 29));
        assert_eq!(civil_date(20_793), (2026, 12, 6));
    }

    #[test]
    fn an_entry_has_the_reason_the_diff_and_the_hashes() {
        let e = entry(
            "2026-12-06 02:50 UTC",
            " a reason\n",
            "a.bin: unchanged\n",
            &[("a.bin".into(), "ab12".into())],
        );
        assert_eq!(
            e,
            "\n## 2026-12-06 02:50 UTC: a reason\n\n```text\na.bin: unchanged\n```\n\n\
             | golden | BLAKE3 |\n|---|---|\n| `tiny/a.bin` | `ab12` |\n"
        );
    }
}
