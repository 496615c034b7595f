//! GDAL's command-line programs (Debian's gdal-bin, installed by `cargo xtask test`), the users'
//! tool the tests read karstgen's rasters and GeoPackages with.

use std::io::Write;
use std::process::{Command, Stdio};

/// Runs the GDAL `program` with `args`, feeding it `stdin`; its standard output. A missing
/// program fails with how to install it; a failing one with its standard error.
pub fn gdal(program: &str, args: &[&str], stdin: Option<&str>) -> String {
    let mut child = Command::new(program)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| {
            panic!("{program}: {e}: install gdal-bin (tools/apt-packages.txt) with `cargo xtask test`")
        });
    child.stdin.take().unwrap().write_all(stdin.unwrap_or("").as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{program} {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}
