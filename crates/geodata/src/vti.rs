//! VTK ImageData files (`.vti`, the XML format GemPy, PyVista and ParaView write): one scalar
//! array of a regular grid, as integer codes.
//!
//! The file is `<VTKFile type="ImageData" byte_order=... header_type=... compressor=...>` with
//! `<ImageData WholeExtent="x0 x1 y0 y1 z0 z1" Origin="x y z" Spacing="dx dy dz">`, one
//! `<Piece>` whose `<PointData>` or `<CellData>` holds `<DataArray type=... Name=...
//! format=...>` elements. Point data stand at origin + (x0 + i)·spacing; cell data fill the
//! cells between points, so their centres are half a spacing further. Data arrays are read in
//! the three formats VTK writes: `ascii` (numbers in the element), `binary` (base64 in the
//! element) and `appended` (at `offset` in the `<AppendedData>` section, raw or base64). Binary
//! data start with a header of `header_type` integers: the byte count, or with
//! `compressor="vtkZLibDataCompressor"` the block count, block size, last block size and each
//! block's compressed size, then the zlib blocks; with base64 the header may be encoded apart
//! from the data (VTK does so) or with it. Rotated grids (a `Direction` other than the identity)
//! and several pieces are refused.

use std::io::Read;

use crate::voxels::{Lattice, Voxels};

/// Reads the array `name` (or the only array, or the `Scalars` one) of a `.vti` file's bytes.
pub fn parse(bytes: &[u8], name: Option<&str>) -> Result<Voxels, String> {
    let (xml, appended) = split_appended(bytes)?;
    let root = element(xml, "VTKFile").ok_or("has no <VTKFile> element: not a VTK XML file")?;
    let kind = attribute(root.attributes, "type").unwrap_or_default();
    if kind != "ImageData" {
        return Err(format!("is a VTK {kind} file, not ImageData (.vti)"));
    }
    let encoding = Encoding::of(root.attributes)?;
    let image = element(xml, "ImageData").ok_or("has no <ImageData> element")?;
    let extent: [i64; 6] = numbers(image.attributes, "WholeExtent")?;
    let origin: [f64; 3] = numbers(image.attributes, "Origin")?;
    let spacing: [f64; 3] = numbers(image.attributes, "Spacing")?;
    if let Ok(direction) = numbers::<f64, 9>(image.attributes, "Direction")
        && direction != [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    {
        return Err(format!("is rotated (Direction {direction:?}): karstgen reads axis-aligned grids"));
    }
    if spacing.iter().any(|s| !(s.is_finite() && *s > 0.0)) || origin.iter().any(|o| !o.is_finite()) {
        return Err(format!("Spacing {spacing:?} must be > 0 and Origin {origin:?} finite"));
    }
    let pieces = xml.matches("<Piece").count();
    if pieces != 1 {
        return Err(format!("has {pieces} pieces: karstgen reads single-piece ImageData"));
    }
    let (array, cells) = pick_array(xml, name)?;
    let points: Vec<usize> =
        (0..3).map(|a| (extent[2 * a + 1] - extent[2 * a] + 1).max(0) as usize).collect();
    if points.contains(&0) || (cells && points.iter().any(|n| *n < 2)) {
        return Err(format!("WholeExtent {extent:?} holds no {}", if cells { "cell" } else { "point" }));
    }
    let size: [usize; 3] = std::array::from_fn(|a| if cells { points[a] - 1 } else { points[a] });
    let count = size.iter().product::<usize>();
    let codes = array.codes(appended, &encoding, count)?;
    let shift = if cells { 0.5 } else { 0.0 };
    let first_centre = std::array::from_fn(|a| origin[a] + (extent[2 * a] as f64 + shift) * spacing[a]);
    Ok(Voxels { lattice: Lattice { first_centre, spacing, size }, codes })
}

/// The bytes after the `_` marker of `<AppendedData>`, and whether they are base64.
type Appended<'a> = (&'a [u8], bool);

/// The XML text before `<AppendedData`, and the bytes after its `_` marker.
fn split_appended(bytes: &[u8]) -> Result<(&str, Option<Appended<'_>>), String> {
    let marker = b"<AppendedData";
    let at = bytes.windows(marker.len()).position(|w| w == marker);
    let head = &bytes[..at.unwrap_or(bytes.len())];
    let xml = std::str::from_utf8(head).map_err(|e| format!("is not text before its appended data: {e}"))?;
    let Some(at) = at else { return Ok((xml, None)) };
    let rest = &bytes[at..];
    let close = rest.iter().position(|b| *b == b'>').ok_or("<AppendedData is not closed")?;
    let attributes =
        std::str::from_utf8(&rest[..close]).map_err(|_| "<AppendedData has non-text attributes")?;
    let base64 = match attribute(attributes, "encoding").as_deref() {
        Some("raw") => false,
        Some("base64") => true,
        other => return Err(format!("AppendedData encoding {other:?} is neither raw nor base64")),
    };
    let underscore = rest[close..].iter().position(|b| *b == b'_').ok_or("AppendedData has no `_` marker")?;
    Ok((xml, Some((&rest[close + underscore + 1..], base64))))
}

/// An element's attribute text and, unless it closes itself, its content.
struct Element<'a> {
    attributes: &'a str,
    body: &'a str,
}

/// The first `<name ...>` element in `xml`.
fn element<'a>(xml: &'a str, name: &str) -> Option<Element<'a>> {
    elements(xml, name).next()
}

/// Every `<name ...>` element of `xml`, in order.
fn elements<'a>(xml: &'a str, name: &str) -> impl Iterator<Item = Element<'a>> + use<'a> {
    let open = format!("<{name}");
    let close = format!("</{name}>");
    let mut rest = xml;
    std::iter::from_fn(move || {
        loop {
            let at = rest.find(&open)?;
            let after = &rest[at + open.len()..];
            if !after.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
                rest = after;
                continue;
            }
            let end = after.find('>')?;
            let attributes = after[..end].trim_end_matches('/');
            let self_closing = after[..end].ends_with('/');
            let content = &after[end + 1..];
            let body =
                if self_closing { "" } else { content.find(&close).map_or(content, |c| &content[..c]) };
            rest = &content[body.len()..];
            return Some(Element { attributes, body });
        }
    })
}

/// The value of `key="..."` (or single quotes) in an element's attribute text.
fn attribute(attributes: &str, key: &str) -> Option<String> {
    let mut rest = attributes;
    while let Some(at) = rest.find(key) {
        let before_ok = at == 0 || rest[..at].ends_with(char::is_whitespace);
        let after = rest[at + key.len()..].trim_start();
        if let Some(value) = after.strip_prefix('=').map(str::trim_start)
            && before_ok
        {
            let quote = value.chars().next()?;
            let value = &value[1..];
            return value.find(quote).map(|end| value[..end].to_string());
        }
        rest = &rest[at + key.len()..];
    }
    None
}

fn numbers<T: std::str::FromStr + Copy + Default, const N: usize>(
    attributes: &str,
    key: &str,
) -> Result<[T; N], String> {
    let text = attribute(attributes, key).ok_or(format!("has no {key}"))?;
    let values: Vec<T> = text
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{key} \"{text}\" is not {N} numbers"))?;
    <[T; N]>::try_from(values).map_err(|_| format!("{key} \"{text}\" is not {N} numbers"))
}

/// How binary data are laid out in this file.
struct Encoding {
    little_endian: bool,
    /// Bytes of a header integer (4 for UInt32, 8 for UInt64).
    header: usize,
    zlib: bool,
}

impl Encoding {
    fn of(root: &str) -> Result<Encoding, String> {
        let little_endian = attribute(root, "byte_order").as_deref() != Some("BigEndian");
        let header = match attribute(root, "header_type").as_deref() {
            None | Some("UInt32") => 4,
            Some("UInt64") => 8,
            Some(other) => return Err(format!("header_type \"{other}\" is neither UInt32 nor UInt64")),
        };
        let zlib = match attribute(root, "compressor").as_deref() {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => {
                return Err(format!(
                    "compressor {other} is not supported: write the file with zlib or no compression"
                ));
            }
        };
        Ok(Encoding { little_endian, header, zlib })
    }

    fn integer(&self, bytes: &[u8]) -> u64 {
        let mut v = 0u64;
        for k in 0..self.header {
            let b = if self.little_endian { bytes[self.header - 1 - k] } else { bytes[k] };
            v = (v << 8) | b as u64;
        }
        v
    }
}

/// One `<DataArray>`.
struct DataArray<'a> {
    name: String,
    kind: String,
    format: String,
    offset: Option<usize>,
    body: &'a str,
}

/// The array to read and whether it is cell data.
fn pick_array<'a>(xml: &'a str, name: Option<&str>) -> Result<(DataArray<'a>, bool), String> {
    let mut found = Vec::new();
    for (section, cells) in [("PointData", false), ("CellData", true)] {
        let Some(data) = element(xml, section) else { continue };
        let scalars = attribute(data.attributes, "Scalars");
        for a in elements(data.body, "DataArray") {
            let components = attribute(a.attributes, "NumberOfComponents").unwrap_or("1".into());
            let array = DataArray {
                name: attribute(a.attributes, "Name").unwrap_or_default(),
                kind: attribute(a.attributes, "type").unwrap_or_default(),
                format: attribute(a.attributes, "format").unwrap_or("ascii".into()),
                offset: attribute(a.attributes, "offset").and_then(|o| o.trim().parse().ok()),
                body: a.body,
            };
            let is_scalars = scalars.as_deref() == Some(array.name.as_str());
            found.push((array, cells, components, is_scalars));
        }
    }
    let names = found.iter().map(|(a, ..)| format!("\"{}\"", a.name)).collect::<Vec<_>>().join(", ");
    let index = match name {
        Some(n) => found
            .iter()
            .position(|(a, ..)| a.name == n)
            .ok_or(format!("has no array \"{n}\" (its arrays: {names})"))?,
        None if found.len() == 1 => 0,
        None => found
            .iter()
            .position(|f| f.3)
            .ok_or(format!("has {} arrays ({names}): name the lithology's with `array`", found.len()))?,
    };
    let (array, cells, components, _) = found.swap_remove(index);
    if components.trim() != "1" {
        return Err(format!("array \"{}\" has {components} components, not 1", array.name));
    }
    Ok((array, cells))
}

impl DataArray<'_> {
    /// The array's `count` values as integer codes.
    fn codes(
        &self,
        appended: Option<(&[u8], bool)>,
        encoding: &Encoding,
        count: usize,
    ) -> Result<Vec<i32>, String> {
        let width = match self.kind.as_str() {
            "Int8" | "UInt8" => 1,
            "Int16" | "UInt16" => 2,
            "Int32" | "UInt32" | "Float32" => 4,
            "Int64" | "UInt64" | "Float64" => 8,
            other => {
                return Err(format!(
                    "array \"{}\" has type {other}: lithology codes need integers or floats",
                    self.name
                ));
            }
        };
        let values: Vec<f64> = match self.format.as_str() {
            "ascii" => self
                .body
                .split_whitespace()
                .enumerate()
                .map(|(i, w)| {
                    w.parse::<f64>()
                        .map_err(|_| format!("array \"{}\": value {i} \"{w}\" is not a number", self.name))
                })
                .collect::<Result<_, _>>()?,
            "binary" => {
                let chars: Vec<u8> = self.body.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
                self.numbers(&block(Source::Base64(&chars), encoding)?, width, encoding)
            }
            "appended" => {
                let (data, base64) = appended
                    .ok_or(format!("array \"{}\" is appended but the file has no AppendedData", self.name))?;
                let offset =
                    self.offset.ok_or(format!("array \"{}\" is appended without an offset", self.name))?;
                let data = data
                    .get(offset..)
                    .ok_or(format!("array \"{}\": offset {offset} is beyond the appended data", self.name))?;
                let source = if base64 { Source::Base64(data) } else { Source::Raw(data) };
                self.numbers(&block(source, encoding)?, width, encoding)
            }
            other => return Err(format!("array \"{}\" has format \"{other}\"", self.name)),
        };
        if values.len() != count {
            return Err(format!("array \"{}\" has {} values, its extent {count}", self.name, values.len()));
        }
        values
            .iter()
            .enumerate()
            .map(|(i, v)| {
                if v.fract() == 0.0 && *v >= i32::MIN as f64 && *v <= i32::MAX as f64 {
                    Ok(*v as i32)
                } else {
                    Err(format!("array \"{}\": value {i} = {v} is not an integer code", self.name))
                }
            })
            .collect()
    }

    /// Binary values of `width` bytes, in the file's byte order, as f64.
    fn numbers(&self, bytes: &[u8], width: usize, encoding: &Encoding) -> Vec<f64> {
        bytes
            .chunks_exact(width)
            .map(|c| {
                let mut b = [0u8; 8];
                b[..width].copy_from_slice(c);
                if !encoding.little_endian {
                    b[..width].reverse();
                }
                match self.kind.as_str() {
                    "Int8" => b[0] as i8 as f64,
                    "UInt8" => b[0] as f64,
                    "Int16" => i16::from_le_bytes([b[0], b[1]]) as f64,
                    "UInt16" => u16::from_le_bytes([b[0], b[1]]) as f64,
                    "Int32" => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "UInt32" => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "Float32" => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "Int64" => i64::from_le_bytes(b) as f64,
                    "UInt64" => u64::from_le_bytes(b) as f64,
                    _ => f64::from_le_bytes(b),
                }
            })
            .collect()
    }
}

/// Where a binary block's bytes come from.
enum Source<'a> {
    Raw(&'a [u8]),
    /// base64 characters, without whitespace.
    Base64(&'a [u8]),
}

impl Source<'_> {
    /// The first `n` bytes.
    fn prefix(&self, n: usize) -> Result<Vec<u8>, String> {
        match self {
            Source::Raw(b) => b.get(..n).map(<[u8]>::to_vec).ok_or("the binary data end early".into()),
            Source::Base64(chars) => {
                let bytes = base64(chars.get(..4 * n.div_ceil(3)).ok_or("the base64 data end early")?)?;
                bytes.get(..n).map(<[u8]>::to_vec).ok_or("the base64 data end early".into())
            }
        }
    }

    /// The `n` bytes after a header of `header` bytes: with base64, the header is encoded on
    /// its own when its last group is padded (VTK's way), else with the data.
    fn after_header(&self, header: usize, n: usize) -> Result<Vec<u8>, String> {
        match self {
            Source::Raw(b) => {
                b.get(header..header + n).map(<[u8]>::to_vec).ok_or("the binary data end early".into())
            }
            Source::Base64(chars) => {
                let head = 4 * header.div_ceil(3);
                if chars.get(head - 1) == Some(&b'=') || header.is_multiple_of(3) {
                    let rest = chars.get(head..).ok_or("the base64 data end early")?;
                    Source::Base64(rest).prefix(n)
                } else {
                    Ok(self.prefix(header + n)?[header..].to_vec())
                }
            }
        }
    }
}

/// The data of one binary block: its header, then the data, inflated when compressed.
fn block(source: Source, e: &Encoding) -> Result<Vec<u8>, String> {
    let first = e.integer(&source.prefix(e.header)?) as usize;
    if !e.zlib {
        return source.after_header(e.header, first);
    }
    let header_len = (3 + first) * e.header;
    let header = source.prefix(header_len)?;
    let int = |k: usize| e.integer(&header[k * e.header..]) as usize;
    let (block_size, last) = (int(1), int(2));
    let compressed: Vec<usize> = (0..first).map(|k| int(3 + k)).collect();
    let packed = source.after_header(header_len, compressed.iter().sum())?;
    let mut out = Vec::new();
    let mut at = 0;
    for (k, size) in compressed.iter().enumerate() {
        let expected = if k + 1 == first && last != 0 { last } else { block_size };
        let mut inflated = Vec::with_capacity(expected);
        flate2::read::ZlibDecoder::new(&packed[at..at + size])
            .read_to_end(&mut inflated)
            .map_err(|e| format!("zlib block {k}: {e}"))?;
        if inflated.len() != expected {
            return Err(format!("zlib block {k} holds {} bytes, its header says {expected}", inflated.len()));
        }
        out.extend(inflated);
        at += size;
    }
    Ok(out)
}

/// Decodes standard base64 (`=` padding).
fn base64(chars: &[u8]) -> Result<Vec<u8>, String> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let mut out = Vec::with_capacity(chars.len() / 4 * 3);
    for group in chars.chunks(4) {
        let data: Vec<u8> = group
            .iter()
            .take_while(|c| **c != b'=')
            .map(|c| value(*c).ok_or(format!("'{}' is not base64", *c as char)))
            .collect::<Result<_, _>>()?;
        let bits = data.iter().fold(0u32, |acc, v| (acc << 6) | *v as u32) << (6 * (4 - data.len()));
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..data.len().max(1)]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b64(bytes: &[u8]) -> String {
        const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let mut b = [0u8; 3];
            b[..chunk.len()].copy_from_slice(chunk);
            let n = u32::from_be_bytes([0, b[0], b[1], b[2]]);
            for k in 0..4 {
                out.push(if k <= chunk.len() {
                    ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char
                } else {
                    '='
                });
            }
        }
        out
    }

    fn file(data_array: &str, appended: &str, root: &str) -> String {
        format!(
            r#"<?xml version="1.0"?>
<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" {root}>
  <ImageData WholeExtent="0 2 0 1 0 0" Origin="100 200 -50" Spacing="10 20 5">
    <Piece Extent="0 2 0 1 0 0">
      <PointData Scalars="lith">{data_array}</PointData>
      <CellData></CellData>
    </Piece>
  </ImageData>{appended}
</VTKFile>"#
        )
    }

    #[test]
    fn base64_round_trips() {
        for n in 0..10 {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 37 + 5) as u8).collect();
            assert_eq!(base64(b64(&bytes).as_bytes()).unwrap(), bytes);
        }
    }

    #[test]
    fn ascii_point_data() {
        let text =
            file(r#"<DataArray type="Int32" Name="lith" format="ascii">1 2 3 4 5 6</DataArray>"#, "", "");
        let v = parse(text.as_bytes(), None).unwrap();
        let l = v.lattice;
        assert_eq!(
            (l.size, l.first_centre, l.spacing),
            ([3, 2, 1], [100.0, 200.0, -50.0], [10.0, 20.0, 5.0])
        );
        assert_eq!(v.codes, [1, 2, 3, 4, 5, 6]);
    }

    #[test]
    fn binary_with_the_header_apart_or_together() {
        let data: Vec<u8> = [1i16, 2, 3, 4, 5, 6].iter().flat_map(|v| v.to_le_bytes()).collect();
        let header = (data.len() as u32).to_le_bytes();
        let apart = format!("{}{}", b64(&header), b64(&data));
        let together = b64(&[header.to_vec(), data.clone()].concat());
        for body in [apart, together] {
            let array = format!(r#"<DataArray type="Int16" Name="lith" format="binary">{body}</DataArray>"#);
            assert_eq!(parse(file(&array, "", "").as_bytes(), None).unwrap().codes, [1, 2, 3, 4, 5, 6]);
        }
    }

    #[test]
    fn appended_raw_zlib_with_64_bit_headers() {
        use std::io::Write;
        let data: Vec<u8> = [7.0f64, 8.0, 9.0, 7.0, 8.0, 9.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&data).unwrap();
        let packed = z.finish().unwrap();
        let header: Vec<u8> = [1u64, data.len() as u64, data.len() as u64, packed.len() as u64]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let array = r#"<DataArray type="Float64" Name="lith" format="appended" offset="0"/>"#;
        let mut bytes = file(
            array,
            "\n  <AppendedData encoding=\"raw\">\n   _",
            r#"header_type="UInt64" compressor="vtkZLibDataCompressor""#,
        )
        .into_bytes();
        let tail = bytes.split_off(bytes.len() - "\n</VTKFile>".len());
        bytes.extend(&header);
        bytes.extend(&packed);
        bytes.extend(b"\n  </AppendedData>");
        bytes.extend(tail);
        assert_eq!(parse(&bytes, Some("lith")).unwrap().codes, [7, 8, 9, 7, 8, 9]);
    }

    #[test]
    fn wrong_files_are_named() {
        let ascii = |values: &str| {
            file(
                &format!(r#"<DataArray type="Float32" Name="lith" format="ascii">{values}</DataArray>"#),
                "",
                "",
            )
        };
        assert!(parse(ascii("1 2 3").as_bytes(), None).unwrap_err().contains("has 3 values, its extent 6"));
        assert!(
            parse(ascii("1 2 3 4 5 6.5").as_bytes(), None)
                .unwrap_err()
                .contains("value 5 = 6.5 is not an integer code")
        );
        assert!(
            parse(ascii("1 2 3 4 5 6").as_bytes(), Some("rock"))
                .unwrap_err()
                .contains("has no array \"rock\" (its arrays: \"lith\")")
        );
        let poly = ascii("1 2 3 4 5 6").replace("type=\"ImageData\"", "type=\"PolyData\"");
        assert!(parse(poly.as_bytes(), None).unwrap_err().contains("is a VTK PolyData file, not ImageData"));
        let rotated = ascii("1 2 3 4 5 6")
            .replace("Spacing=\"10 20 5\"", "Spacing=\"10 20 5\" Direction=\"0 1 0 -1 0 0 0 0 1\"");
        assert!(parse(rotated.as_bytes(), None).unwrap_err().contains("is rotated"));
        let lz4 = file("", "", r#"compressor="vtkLZ4DataCompressor""#);
        assert!(
            parse(lz4.as_bytes(), None)
                .unwrap_err()
                .contains("compressor vtkLZ4DataCompressor is not supported")
        );
        assert!(parse(b"not xml", None).unwrap_err().contains("not a VTK XML file"));
    }
}
