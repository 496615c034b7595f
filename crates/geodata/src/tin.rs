//! Triangulated surface files: GOCAD TSurf (`.ts`, what SKUA-Gocad exports) and a plain text
//! of vertices and triangles, read into vertices and triangles (the surface and its queries are
//! `karst_geology::tin`).
//!
//! TSurf: `VRTX`/`PVRTX id x y z [properties]` define vertices, `ATOM`/`PATOM id ref` reuse one,
//! `TRGL a b c` are triangles over those ids; several `TFACE` parts are merged; with
//! `ZPOSITIVE Depth` z is negated so that z stays up. Other keywords (HEADER, properties,
//! BSTONE, BORDER, ...) are skipped. Plain text: `v x y z` lines and `f a b c` lines with
//! 1-based vertex numbers (OBJ's convention, so a triangulated OBJ reads too); `#` starts a
//! comment.

use std::path::Path;

/// Why a triangulated surface cannot be used.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TinError {
    #[error("cannot read {file}: {message}")]
    Read { file: String, message: String },
    #[error("{file}:{line}: {message}")]
    Syntax { file: String, line: usize, message: String },
    #[error("{file}: triangle {index} {message}")]
    Triangle { file: String, index: usize, message: String },
    #[error("{file}: has no triangles")]
    Empty { file: String },
}

/// Reads a `.ts` TSurf or a plain vertices/triangles text, by extension: its vertices and its
/// triangles (indices into the vertices), as the file gives them.
pub fn read(path: &Path) -> Result<Parsed, TinError> {
    let file = path.display().to_string();
    let text = karst_artifact::files::read_regular_text(path, karst_artifact::files::MAX_DATA_BYTES)
        .map_err(|e| TinError::Read { file: file.clone(), message: e.to_string() })?;
    let is_tsurf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("ts"));
    if is_tsurf { parse_tsurf(&text, &file) } else { parse_plain(&text, &file) }
}

/// Vertices `[x, y, z]` and triangles (three indices into the vertices).
pub type Parsed = (Vec<[f64; 3]>, Vec<[u32; 3]>);

fn syntax(file: &str, line: usize, message: String) -> TinError {
    TinError::Syntax { file: file.into(), line, message }
}

fn numbers<T: std::str::FromStr>(
    words: &[&str],
    n: usize,
    file: &str,
    line: usize,
) -> Result<Vec<T>, TinError> {
    if words.len() < n {
        return Err(syntax(file, line, format!("expected {n} numbers, found {}", words.len())));
    }
    words[..n]
        .iter()
        .map(|w| w.parse().map_err(|_| syntax(file, line, format!("\"{w}\" is not a valid number"))))
        .collect()
}

fn finite_vertex(xyz: Vec<f64>, file: &str, line: usize) -> Result<[f64; 3], TinError> {
    let limit = crate::MAX_COORDINATE;
    if let Some(v) = xyz.iter().find(|v| v.is_nan() || v.abs() > limit) {
        return Err(syntax(file, line, format!("coordinate {v} is not a finite number within ±{limit:e}")));
    }
    Ok([xyz[0], xyz[1], xyz[2]])
}

fn parse_tsurf(text: &str, file: &str) -> Result<Parsed, TinError> {
    let mut vertices = Vec::new();
    let mut ids: std::collections::BTreeMap<i64, u32> = std::collections::BTreeMap::new();
    let mut triangles = Vec::new();
    let mut depth_positive = false;
    if !text.trim_start().starts_with("GOCAD TSurf") {
        return Err(syntax(file, 1, "not a GOCAD TSurf file (it must start with \"GOCAD TSurf\")".into()));
    }
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let words: Vec<&str> = raw.split_whitespace().collect();
        let Some((&key, rest)) = words.split_first() else { continue };
        match key {
            "ZPOSITIVE" => depth_positive = rest.first().is_some_and(|w| w.eq_ignore_ascii_case("depth")),
            "VRTX" | "PVRTX" => {
                let id: Vec<i64> = numbers(rest, 1, file, line)?;
                let mut xyz = finite_vertex(numbers(&rest[1..], 3, file, line)?, file, line)?;
                if depth_positive {
                    xyz[2] = -xyz[2];
                }
                if ids.insert(id[0], vertices.len() as u32).is_some() {
                    return Err(syntax(file, line, format!("vertex id {} is defined twice", id[0])));
                }
                vertices.push(xyz);
            }
            "ATOM" | "PATOM" => {
                let v: Vec<i64> = numbers(rest, 2, file, line)?;
                let target = *ids.get(&v[1]).ok_or_else(|| {
                    syntax(file, line, format!("ATOM {} refers to undefined vertex {}", v[0], v[1]))
                })?;
                ids.insert(v[0], target);
            }
            "TRGL" => {
                let v: Vec<i64> = numbers(rest, 3, file, line)?;
                let mut t = [0u32; 3];
                for (k, id) in v.iter().enumerate() {
                    t[k] = *ids.get(id).ok_or_else(|| {
                        syntax(file, line, format!("TRGL uses vertex id {id}, which no VRTX defines"))
                    })?;
                }
                triangles.push(t);
            }
            _ => {}
        }
    }
    Ok((vertices, triangles))
}

fn parse_plain(text: &str, file: &str) -> Result<Parsed, TinError> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let content = raw.split('#').next().unwrap_or("");
        let words: Vec<&str> = content.split_whitespace().collect();
        let Some((&key, rest)) = words.split_first() else { continue };
        match key {
            "v" => vertices.push(finite_vertex(numbers(rest, 3, file, line)?, file, line)?),
            "f" => {
                let v: Vec<i64> = numbers(rest, 3, file, line)?;
                if v.len() != 3 || rest.len() != 3 {
                    return Err(syntax(
                        file,
                        line,
                        format!("a face must have 3 vertices, found {}", rest.len()),
                    ));
                }
                let mut t = [0u32; 3];
                for (k, i) in v.iter().enumerate() {
                    if *i < 1 || *i as usize > vertices.len() {
                        return Err(syntax(
                            file,
                            line,
                            format!(
                                "vertex number {i} is not in 1..={} (vertices read so far)",
                                vertices.len()
                            ),
                        ));
                    }
                    t[k] = (*i - 1) as u32;
                }
                triangles.push(t);
            }
            other => return Err(syntax(file, line, format!("unknown record \"{other}\" (expected v or f)"))),
        }
    }
    Ok((vertices, triangles))
}

/// Writes a TIN as a GOCAD TSurf.
pub fn write_tsurf(
    path: &Path,
    name: &str,
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> std::io::Result<()> {
    let mut text = format!("GOCAD TSurf 1\nHEADER {{\nname: {name}\n}}\nTFACE\n");
    for (i, v) in vertices.iter().enumerate() {
        text.push_str(&format!("VRTX {} {} {} {}\n", i + 1, v[0], v[1], v[2]));
    }
    for t in triangles {
        text.push_str(&format!("TRGL {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    text.push_str("END\n");
    std::fs::write(path, text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tsurf_round_trip_and_bad_files() {
        let dir = std::env::temp_dir().join(format!("karst-tin-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("h.ts");
        let vertices = vec![[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [0.0, 1.0, 3.0]];
        write_tsurf(&path, "h", &vertices, &[[0, 1, 2]]).unwrap();
        assert_eq!(read(&path).unwrap(), (vertices, vec![[0, 1, 2]]));
        let bad = dir.join("bad.ts");
        std::fs::write(&bad, "GOCAD TSurf 1\nTFACE\nVRTX 1 0 0 0\nVRTX 2 1 0 0\nTRGL 1 2 9\nEND\n").unwrap();
        let e = read(&bad).unwrap_err().to_string();
        assert!(e.contains("bad.ts:5: TRGL uses vertex id 9"), "{e}");
        let depth = dir.join("depth.ts");
        std::fs::write(
            &depth,
            "GOCAD TSurf 1\nZPOSITIVE Depth\nVRTX 1 0 0 10\nVRTX 2 1 0 10\nVRTX 3 0 1 10\nTRGL 1 2 3\n",
        )
        .unwrap();
        assert_eq!(read(&depth).unwrap().0[0][2], -10.0);
        let plain = dir.join("p.txt");
        std::fs::write(&plain, "# a triangle\nv 0 0 1\nv 1 0 1\nv 0 1 nan\nf 1 2 3\n").unwrap();
        assert!(read(&plain).unwrap_err().to_string().contains("p.txt:4: coordinate NaN"));
        std::fs::write(&plain, "v 0 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 4\n").unwrap();
        assert!(read(&plain).unwrap_err().to_string().contains("vertex number 4 is not in 1..=3"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
