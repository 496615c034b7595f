//! NumPy `.npy` arrays (format versions 1 to 3): a 3D array of integer codes, as GemPy's
//! `lith_block` saved with `numpy.save` after `reshape(nx, ny, nz)`.
//!
//! The file is the magic `\x93NUMPY`, a version, the length of a header, the header (a Python
//! dict literal: `{'descr': '<i4', 'fortran_order': False, 'shape': (nx, ny, nz), }`), then the
//! values. Axis 0 is x (east), 1 is y (north), 2 is z (up); C order has z fastest, Fortran
//! order x fastest. Signed and unsigned integers and floats of any width and byte order are
//! read; floats must hold whole numbers (GemPy stores its codes as floats).

/// Why a `.npy` file was refused; the caller puts the file's name in front.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum NpyError {
    #[error("does not start with \\x93NUMPY: not a .npy file")]
    NotNpy,
    #[error("format version {0} is not 1, 2 or 3")]
    Version(u8),
    #[error("the header {0}")]
    Header(String),
    #[error("shape {0} is not a tuple of sizes")]
    Shape(String),
    #[error("has {0} dimensions, not 3 (nx, ny, nz)")]
    Dimensions(usize),
    #[error("dtype '{0}' is not an integer, boolean or float array")]
    Dtype(String),
    #[error("holds {found} bytes of data, its shape {shape:?} of {descr} needs {needed}")]
    Short { found: usize, shape: [usize; 3], descr: String, needed: usize },
    #[error("value {value} at index {index:?} is not an integer code")]
    NotACode { value: f64, index: [usize; 3] },
}

/// The codes of a 3D array, x fastest, then y, then z, and the array's shape.
pub fn parse(bytes: &[u8]) -> Result<([usize; 3], Vec<i32>), NpyError> {
    let rest = bytes.strip_prefix(b"\x93NUMPY").ok_or(NpyError::NotNpy)?;
    let (major, rest) = (rest.first().copied().unwrap_or(0), rest.get(2..).unwrap_or_default());
    let (length, rest) = match major {
        1 => (rest.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]]) as usize), rest.get(2..)),
        2 | 3 => {
            (rest.get(..4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize), rest.get(4..))
        }
        v => return Err(NpyError::Version(v)),
    };
    let early = || NpyError::Header("ends early".into());
    let (length, rest) = (length.ok_or_else(early)?, rest.ok_or_else(early)?);
    let header = std::str::from_utf8(rest.get(..length).ok_or_else(early)?)
        .map_err(|_| NpyError::Header("is not text".into()))?;
    let data = &rest[length..];
    let descr = value(header, "descr")?;
    let descr = descr.trim_matches(|c| c == '\'' || c == '"');
    let fortran = value(header, "fortran_order")?.starts_with("True");
    let shape = value(header, "shape")?;
    let dims: Vec<usize> = shape
        .trim_matches(|c| c == '(' || c == ')')
        .split(',')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .map(|d| d.parse().map_err(|_| NpyError::Shape(shape.into())))
        .collect::<Result<_, _>>()?;
    let shape: [usize; 3] = dims.try_into().map_err(|d: Vec<usize>| NpyError::Dimensions(d.len()))?;
    let count = shape.iter().product::<usize>();
    let (order, kind, width) = dtype(descr)?;
    if data.len() < count * width {
        return Err(NpyError::Short { found: data.len(), shape, descr: descr.into(), needed: count * width });
    }
    let mut codes = vec![0i32; count];
    for (k, chunk) in data.chunks_exact(width).take(count).enumerate() {
        let v = number(chunk, order, kind);
        if !(v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64) {
            return Err(NpyError::NotACode { value: v, index: index_of(k, shape, fortran) });
        }
        let [i, j, l] = index_of(k, shape, fortran);
        codes[(l * shape[1] + j) * shape[0] + i] = v as i32;
    }
    Ok((shape, codes))
}

/// The (i, j, k) of the `k`-th stored value.
fn index_of(k: usize, [nx, ny, nz]: [usize; 3], fortran: bool) -> [usize; 3] {
    if fortran { [k % nx, k / nx % ny, k / (nx * ny)] } else { [k / (ny * nz), k / nz % ny, k % nz] }
}

/// The text of `'key': value` in the header dict, up to the next top-level comma.
fn value<'a>(header: &'a str, key: &str) -> Result<&'a str, NpyError> {
    let at = header.find(&format!("'{key}'")).ok_or_else(|| NpyError::Header(format!("has no '{key}'")))?;
    let rest = header[at + key.len() + 2..]
        .trim_start()
        .strip_prefix(':')
        .ok_or_else(|| NpyError::Header(format!("gives '{key}' no value")))?
        .trim_start();
    let end = if rest.starts_with('(') { rest.find(')').map(|e| e + 1) } else { rest.find([',', '}']) };
    Ok(rest[..end.unwrap_or(rest.len())].trim())
}

/// Byte order (true: little-endian), kind (`i`, `u`, `f`, `b`) and width of a dtype string.
fn dtype(descr: &str) -> Result<(bool, char, usize), NpyError> {
    let wrong = || NpyError::Dtype(descr.into());
    let mut chars = descr.chars();
    let order = chars.next().ok_or_else(wrong)?;
    let kind = chars.next().ok_or_else(wrong)?;
    let width: usize = chars.as_str().parse().map_err(|_| wrong())?;
    let ok = match kind {
        'i' | 'u' => matches!(width, 1 | 2 | 4 | 8),
        'f' => matches!(width, 4 | 8),
        'b' => width == 1,
        _ => false,
    };
    if !ok || !matches!(order, '<' | '>' | '|' | '=') {
        return Err(wrong());
    }
    Ok((order != '>', kind, width))
}

fn number(chunk: &[u8], little: bool, kind: char) -> f64 {
    let mut b = [0u8; 8];
    b[..chunk.len()].copy_from_slice(chunk);
    if !little {
        b[..chunk.len()].reverse();
    }
    match (kind, chunk.len()) {
        ('i', 1) => b[0] as i8 as f64,
        ('i', 2) => i16::from_le_bytes([b[0], b[1]]) as f64,
        ('i', 4) => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        ('i', _) => i64::from_le_bytes(b) as f64,
        ('f', 4) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        ('f', _) => f64::from_le_bytes(b),
        _ => u64::from_le_bytes(b) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let mut header = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
            if fortran { "True" } else { "False" }
        );
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        out.extend(data);
        out
    }

    #[test]
    fn c_and_fortran_orders_give_x_fastest() {
        // value = 100 i + 10 j + k on a 2 × 3 × 2 array.
        let c: Vec<u8> = (0..2)
            .flat_map(|i| (0..3).flat_map(move |j| (0..2).map(move |k| 100 * i + 10 * j + k)))
            .flat_map(i32::to_le_bytes)
            .collect();
        let (shape, codes) = parse(&npy("<i4", false, "(2, 3, 2)", &c)).unwrap();
        assert_eq!(shape, [2, 3, 2]);
        assert_eq!(&codes[..4], &[0, 100, 10, 110]);
        assert_eq!(codes[11], 121, "(i, j, k) = (1, 2, 1) at (k·ny + j)·nx + i");
        let f: Vec<u8> = (0..2)
            .flat_map(|k| (0..3).flat_map(move |j| (0..2).map(move |i| (100 * i + 10 * j + k) as f64)))
            .flat_map(|v: f64| v.to_be_bytes())
            .collect();
        assert_eq!(parse(&npy(">f8", true, "(2, 3, 2)", &f)).unwrap().1, codes);
    }

    #[test]
    fn wrong_arrays_are_named() {
        let two_d = npy("<i4", false, "(2, 2)", &[0; 16]);
        assert!(parse(&two_d).unwrap_err().to_string().contains("has 2 dimensions, not 3"));
        let short = npy("<i4", false, "(2, 2, 2)", &[0; 16]);
        assert!(
            parse(&short)
                .unwrap_err()
                .to_string()
                .contains("holds 16 bytes of data, its shape [2, 2, 2] of <i4 needs 32")
        );
        let half = npy("<f8", false, "(1, 1, 2)", &[0.0f64.to_le_bytes(), 1.5f64.to_le_bytes()].concat());
        assert!(
            parse(&half)
                .unwrap_err()
                .to_string()
                .contains("value 1.5 at index [0, 0, 1] is not an integer code")
        );
        assert!(
            parse(&npy("<U4", false, "(1, 1, 1)", &[0; 16])).unwrap_err().to_string().contains("dtype '<U4'")
        );
        assert!(parse(b"PK\x03\x04").unwrap_err().to_string().contains("not a .npy file"));
    }
}
