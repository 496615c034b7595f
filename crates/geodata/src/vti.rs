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

use base64::Engine;
use base64::engine::DecodePaddingMode;
use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use quick_xml::XmlVersion;
use quick_xml::events::{BytesStart, Event};

use crate::voxels::{Lattice, Voxels};

/// Why a `.vti` file was refused; the caller puts the file's name in front.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum VtiError {
    #[error("is not well-formed XML at byte {position}: {reason}")]
    Xml { position: u64, reason: String },
    #[error("has no <VTKFile> element: not a VTK XML file")]
    NotVtk,
    #[error("is a VTK {0} file, not ImageData (.vti)")]
    NotImageData(String),
    #[error("has no <{0}> element")]
    MissingElement(&'static str),
    #[error("has no {0}")]
    MissingAttribute(&'static str),
    #[error("{field} \"{value}\" is not {count} numbers")]
    NotNumbers { field: &'static str, value: String, count: usize },
    #[error("{field} \"{value}\" is neither {allowed}")]
    Choice { field: &'static str, value: String, allowed: &'static str },
    #[error("compressor {0} is not supported: write the file with zlib or no compression")]
    Compressor(String),
    #[error("is rotated (Direction {0:?}): karstgen reads axis-aligned grids")]
    Rotated([f64; 9]),
    #[error("Spacing {spacing:?} must be > 0 and Origin {origin:?} finite")]
    Placement { spacing: [f64; 3], origin: [f64; 3] },
    #[error("has {0} pieces: karstgen reads single-piece ImageData")]
    Pieces(usize),
    #[error("WholeExtent {extent:?} holds no {what}")]
    EmptyExtent { extent: [i64; 6], what: &'static str },
    #[error("<AppendedData> {0}")]
    Appended(&'static str),
    #[error("has no array \"{name}\" (its arrays: {arrays})")]
    NoSuchArray { name: String, arrays: String },
    #[error("has {count} arrays ({arrays}): name the lithology's with `array`")]
    AmbiguousArray { count: usize, arrays: String },
    #[error("array \"{array}\": {reason}")]
    Array { array: String, reason: ArrayError },
}

/// What is wrong with the lithology's data array: its type, format, encoding or values.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum ArrayError {
    #[error("has {0} components, not 1")]
    Components(String),
    #[error("has type {0}: lithology codes need integers or floats")]
    Type(String),
    #[error("has format \"{0}\"")]
    Format(String),
    #[error("value {index} \"{word}\" is not a number")]
    NotNumber { index: usize, word: String },
    #[error("value {index} = {value} is not an integer code")]
    NotCode { index: usize, value: f64 },
    #[error("has {found} values, its extent {count}")]
    Count { found: usize, count: usize },
    #[error("is appended but the file has no AppendedData")]
    NoAppendedData,
    #[error("is appended without an offset")]
    NoOffset,
    #[error("offset {0} is beyond the appended data")]
    Offset(usize),
    #[error("bad base64 data: {0}")]
    Base64(#[from] base64::DecodeError),
    #[error("the {} data end early", if *.base64 { "base64" } else { "binary" })]
    Truncated { base64: bool },
    #[error("zlib block {block}: {reason}")]
    Zlib { block: usize, reason: String },
    #[error("zlib block {block} holds {found} bytes, its header says {expected}")]
    BlockSize { block: usize, found: usize, expected: usize },
}

/// Reads the array `name` (or the only array, or the `Scalars` one) of a `.vti` file's bytes.
pub fn parse(bytes: &[u8], name: Option<&str>) -> Result<Voxels, VtiError> {
    let (xml, appended) = split_appended(bytes)?;
    let tree = Node::parse(xml)?;
    let root = tree.find("VTKFile").ok_or(VtiError::NotVtk)?;
    let kind = root.attribute("type").unwrap_or_default();
    if kind != "ImageData" {
        return Err(VtiError::NotImageData(kind.to_string()));
    }
    let encoding = Encoding::of(root)?;
    let image = root.find("ImageData").ok_or(VtiError::MissingElement("ImageData"))?;
    let extent: [i64; 6] = numbers(image, "WholeExtent")?;
    let origin: [f64; 3] = numbers(image, "Origin")?;
    let spacing: [f64; 3] = numbers(image, "Spacing")?;
    if let Ok(direction) = numbers::<f64, 9>(image, "Direction")
        && direction != [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    {
        return Err(VtiError::Rotated(direction));
    }
    if spacing.iter().any(|s| !(s.is_finite() && *s > 0.0)) || origin.iter().any(|o| !o.is_finite()) {
        return Err(VtiError::Placement { spacing, origin });
    }
    let pieces = tree.count("Piece");
    if pieces != 1 {
        return Err(VtiError::Pieces(pieces));
    }
    let (array, cells) = pick_array(&tree, name)?;
    let points: Vec<usize> =
        (0..3).map(|a| (extent[2 * a + 1] - extent[2 * a] + 1).max(0) as usize).collect();
    if points.contains(&0) || (cells && points.iter().any(|n| *n < 2)) {
        return Err(VtiError::EmptyExtent { extent, what: if cells { "cell" } else { "point" } });
    }
    let size: [usize; 3] = std::array::from_fn(|a| if cells { points[a] - 1 } else { points[a] });
    let count = size.iter().product::<usize>();
    let codes = array
        .codes(appended, &encoding, count)
        .map_err(|reason| VtiError::Array { array: array.name.to_string(), reason })?;
    let shift = if cells { 0.5 } else { 0.0 };
    let first_centre = std::array::from_fn(|a| origin[a] + (extent[2 * a] as f64 + shift) * spacing[a]);
    Ok(Voxels { lattice: Lattice { first_centre, spacing, size }, codes })
}

/// The bytes after the `_` marker of `<AppendedData>`, and whether they are base64.
type Appended<'a> = (&'a [u8], bool);

/// The XML text before `<AppendedData` (raw appended data are not XML), and the bytes after its
/// `_` marker.
fn split_appended(bytes: &[u8]) -> Result<(&str, Option<Appended<'_>>), VtiError> {
    let marker = b"<AppendedData";
    let at = bytes.windows(marker.len()).position(|w| w == marker);
    let head = &bytes[..at.unwrap_or(bytes.len())];
    let xml = std::str::from_utf8(head).map_err(|e| VtiError::Xml {
        position: e.valid_up_to() as u64,
        reason: format!("not UTF-8 text before the appended data: {e}"),
    })?;
    let Some(at) = at else { return Ok((xml, None)) };
    let rest = &bytes[at..];
    let close = rest.iter().position(|b| *b == b'>').ok_or(VtiError::Appended("is not closed"))?;
    let tag =
        std::str::from_utf8(&rest[..=close]).map_err(|_| VtiError::Appended("has non-text attributes"))?;
    let element = Node::parse(tag)?;
    let encoding = element.find("AppendedData").and_then(|e| e.attribute("encoding"));
    let base64 = match encoding {
        Some("raw") => false,
        Some("base64") => true,
        other => {
            return Err(VtiError::Choice {
                field: "AppendedData encoding",
                value: other.unwrap_or_default().to_string(),
                allowed: "raw nor base64",
            });
        }
    };
    let underscore =
        rest[close..].iter().position(|b| *b == b'_').ok_or(VtiError::Appended("has no `_` marker"))?;
    Ok((xml, Some((&rest[close + underscore + 1..], base64))))
}

/// One XML element: its name, attributes, text and child elements.
#[derive(Default)]
struct Node {
    name: String,
    attributes: Vec<(String, String)>,
    text: String,
    children: Vec<Node>,
}

impl Node {
    /// The elements of `xml` under a nameless root. Elements still open at the end (the text
    /// stops where the appended data start) are closed there.
    fn parse(xml: &str) -> Result<Node, VtiError> {
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut open = vec![Node::default()];
        loop {
            let malformed = |reason: String, reader: &quick_xml::Reader<&[u8]>| VtiError::Xml {
                position: reader.error_position(),
                reason,
            };
            let event = reader.read_event().map_err(|e| malformed(e.to_string(), &reader))?;
            match event {
                Event::Start(start) => open.push(Node::of(&start).map_err(|e| malformed(e, &reader))?),
                Event::Empty(start) => {
                    let node = Node::of(&start).map_err(|e| malformed(e, &reader))?;
                    open.last_mut().expect("the root stays open").children.push(node);
                }
                Event::Text(text) => {
                    open.last_mut().expect("the root stays open").text.push_str(&text.xml10_content())
                }
                Event::CData(data) => {
                    open.last_mut().expect("the root stays open").text.push_str(&data.xml10_content())
                }
                Event::End(_) => close_last(&mut open),
                Event::Eof => break,
                _ => {}
            }
        }
        while open.len() > 1 {
            close_last(&mut open);
        }
        Ok(open.pop().expect("the root stays open"))
    }

    /// A node for an opening tag, with its attributes unescaped.
    fn of(start: &BytesStart) -> Result<Node, String> {
        let name = start.name().as_ref().to_string();
        let attributes = start
            .attributes()
            .map(|a| {
                let a = a.map_err(|e| e.to_string())?;
                let value = a.normalized_value(XmlVersion::Implicit1_0).map_err(|e| e.to_string())?;
                Ok((a.key.as_ref().to_string(), value.into_owned()))
            })
            .collect::<Result<_, String>>()?;
        Ok(Node { name, attributes, ..Node::default() })
    }

    fn attribute(&self, key: &str) -> Option<&str> {
        self.attributes.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// The first element named `name` below this one, depth first.
    fn find(&self, name: &str) -> Option<&Node> {
        self.children.iter().find_map(|c| if c.name == name { Some(c) } else { c.find(name) })
    }

    /// Every element named `name` below this one, depth first.
    fn all<'a>(&'a self, name: &str, out: &mut Vec<&'a Node>) {
        for c in &self.children {
            if c.name == name {
                out.push(c);
            }
            c.all(name, out);
        }
    }

    fn count(&self, name: &str) -> usize {
        let mut found = Vec::new();
        self.all(name, &mut found);
        found.len()
    }
}

/// Closes the innermost open element into its parent.
fn close_last(open: &mut Vec<Node>) {
    if open.len() > 1 {
        let node = open.pop().expect("more than the root is open");
        open.last_mut().expect("the root stays open").children.push(node);
    }
}

fn numbers<T: std::str::FromStr + Copy + Default, const N: usize>(
    element: &Node,
    field: &'static str,
) -> Result<[T; N], VtiError> {
    let text = element.attribute(field).ok_or(VtiError::MissingAttribute(field))?;
    let wrong = || VtiError::NotNumbers { field, value: text.to_string(), count: N };
    let values: Vec<T> =
        text.split_whitespace().map(str::parse).collect::<Result<_, _>>().map_err(|_| wrong())?;
    <[T; N]>::try_from(values).map_err(|_| wrong())
}

/// How binary data are laid out in this file.
struct Encoding {
    little_endian: bool,
    /// Bytes of a header integer (4 for UInt32, 8 for UInt64).
    header: usize,
    zlib: bool,
}

impl Encoding {
    fn of(root: &Node) -> Result<Encoding, VtiError> {
        let little_endian = root.attribute("byte_order") != Some("BigEndian");
        let header = match root.attribute("header_type") {
            None | Some("UInt32") => 4,
            Some("UInt64") => 8,
            Some(other) => {
                return Err(VtiError::Choice {
                    field: "header_type",
                    value: other.to_string(),
                    allowed: "UInt32 nor UInt64",
                });
            }
        };
        let zlib = match root.attribute("compressor") {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => return Err(VtiError::Compressor(other.to_string())),
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
    name: &'a str,
    kind: &'a str,
    format: &'a str,
    offset: Option<usize>,
    body: &'a str,
}

/// The array to read and whether it is cell data.
fn pick_array<'a>(tree: &'a Node, name: Option<&str>) -> Result<(DataArray<'a>, bool), VtiError> {
    let mut found = Vec::new();
    for (section, cells) in [("PointData", false), ("CellData", true)] {
        let Some(data) = tree.find(section) else { continue };
        let scalars = data.attribute("Scalars");
        let mut arrays = Vec::new();
        data.all("DataArray", &mut arrays);
        for a in arrays {
            let components = a.attribute("NumberOfComponents").unwrap_or("1");
            let array = DataArray {
                name: a.attribute("Name").unwrap_or_default(),
                kind: a.attribute("type").unwrap_or_default(),
                format: a.attribute("format").unwrap_or("ascii"),
                offset: a.attribute("offset").and_then(|o| o.trim().parse().ok()),
                body: &a.text,
            };
            let is_scalars = scalars == Some(array.name);
            found.push((array, cells, components, is_scalars));
        }
    }
    let arrays = found.iter().map(|(a, ..)| format!("\"{}\"", a.name)).collect::<Vec<_>>().join(", ");
    let index = match name {
        Some(n) => found
            .iter()
            .position(|(a, ..)| a.name == n)
            .ok_or(VtiError::NoSuchArray { name: n.to_string(), arrays })?,
        None if found.len() == 1 => 0,
        None => {
            found.iter().position(|f| f.3).ok_or(VtiError::AmbiguousArray { count: found.len(), arrays })?
        }
    };
    let (array, cells, components, _) = found.swap_remove(index);
    if components.trim() != "1" {
        return Err(VtiError::Array {
            array: array.name.to_string(),
            reason: ArrayError::Components(components.to_string()),
        });
    }
    Ok((array, cells))
}

impl DataArray<'_> {
    /// The array's `count` values as integer codes; errors say what is wrong with the array.
    fn codes(
        &self,
        appended: Option<Appended>,
        encoding: &Encoding,
        count: usize,
    ) -> Result<Vec<i32>, ArrayError> {
        let width = match self.kind {
            "Int8" | "UInt8" => 1,
            "Int16" | "UInt16" => 2,
            "Int32" | "UInt32" | "Float32" => 4,
            "Int64" | "UInt64" | "Float64" => 8,
            other => return Err(ArrayError::Type(other.into())),
        };
        let values: Vec<f64> = match self.format {
            "ascii" => self
                .body
                .split_whitespace()
                .enumerate()
                .map(|(index, w)| {
                    w.parse::<f64>().map_err(|_| ArrayError::NotNumber { index, word: w.into() })
                })
                .collect::<Result<_, _>>()?,
            "binary" => {
                let chars: Vec<u8> = self.body.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
                self.numbers(&block(Source::Base64(&chars), encoding)?, width, encoding)
            }
            "appended" => {
                let (data, base64) = appended.ok_or(ArrayError::NoAppendedData)?;
                let offset = self.offset.ok_or(ArrayError::NoOffset)?;
                let data = data.get(offset..).ok_or(ArrayError::Offset(offset))?;
                let source = if base64 { Source::Base64(data) } else { Source::Raw(data) };
                self.numbers(&block(source, encoding)?, width, encoding)
            }
            other => return Err(ArrayError::Format(other.into())),
        };
        if values.len() != count {
            return Err(ArrayError::Count { found: values.len(), count });
        }
        values
            .iter()
            .enumerate()
            .map(|(index, v)| {
                if v.fract() == 0.0 && *v >= i32::MIN as f64 && *v <= i32::MAX as f64 {
                    Ok(*v as i32)
                } else {
                    Err(ArrayError::NotCode { index, value: *v })
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
                match self.kind {
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

/// Standard base64 as VTK writes it: `=` padding where a group ends early (also inside the
/// data, where the header was encoded apart), trailing bits tolerated.
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_decode_padding_mode(DecodePaddingMode::Indifferent)
        .with_decode_allow_trailing_bits(true),
);

/// Decodes base64 characters (without whitespace).
fn decode_base64(chars: &[u8]) -> Result<Vec<u8>, ArrayError> {
    Ok(BASE64.decode(chars)?)
}

/// Where a binary block's bytes come from.
enum Source<'a> {
    Raw(&'a [u8]),
    /// base64 characters, without whitespace.
    Base64(&'a [u8]),
}

impl Source<'_> {
    /// The first `n` bytes.
    fn prefix(&self, n: usize) -> Result<Vec<u8>, ArrayError> {
        let end = ArrayError::Truncated { base64: matches!(self, Source::Base64(_)) };
        match self {
            Source::Raw(b) => b.get(..n).map(<[u8]>::to_vec).ok_or(end),
            Source::Base64(chars) => {
                let bytes = decode_base64(chars.get(..4 * n.div_ceil(3)).ok_or(end.clone())?)?;
                bytes.get(..n).map(<[u8]>::to_vec).ok_or(end)
            }
        }
    }

    /// The `n` bytes after a header of `header` bytes: with base64, the header is encoded on
    /// its own when its last group is padded (VTK's way), else with the data.
    fn after_header(&self, header: usize, n: usize) -> Result<Vec<u8>, ArrayError> {
        match self {
            Source::Raw(b) => {
                b.get(header..header + n).map(<[u8]>::to_vec).ok_or(ArrayError::Truncated { base64: false })
            }
            Source::Base64(chars) => {
                let head = 4 * header.div_ceil(3);
                if chars.get(head - 1) == Some(&b'=') || header.is_multiple_of(3) {
                    let rest = chars.get(head..).ok_or(ArrayError::Truncated { base64: true })?;
                    Source::Base64(rest).prefix(n)
                } else {
                    Ok(self.prefix(header + n)?[header..].to_vec())
                }
            }
        }
    }
}

/// The data of one binary block: its header, then the data, inflated when compressed.
fn block(source: Source, e: &Encoding) -> Result<Vec<u8>, ArrayError> {
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
            .map_err(|e| ArrayError::Zlib { block: k, reason: e.to_string() })?;
        if inflated.len() != expected {
            return Err(ArrayError::BlockSize { block: k, found: inflated.len(), expected });
        }
        out.extend(inflated);
        at += size;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b64(bytes: &[u8]) -> String {
        base64::engine::general_purpose::STANDARD.encode(bytes)
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
        assert!(
            parse(ascii("1 2 3").as_bytes(), None)
                .unwrap_err()
                .to_string()
                .contains("has 3 values, its extent 6")
        );
        assert!(
            parse(ascii("1 2 3 4 5 6.5").as_bytes(), None)
                .unwrap_err()
                .to_string()
                .contains("value 5 = 6.5 is not an integer code")
        );
        assert!(
            parse(ascii("1 2 3 4 5 6").as_bytes(), Some("rock"))
                .unwrap_err()
                .to_string()
                .contains("has no array \"rock\" (its arrays: \"lith\")")
        );
        let poly = ascii("1 2 3 4 5 6").replace("type=\"ImageData\"", "type=\"PolyData\"");
        assert!(
            parse(poly.as_bytes(), None)
                .unwrap_err()
                .to_string()
                .contains("is a VTK PolyData file, not ImageData")
        );
        let rotated = ascii("1 2 3 4 5 6")
            .replace("Spacing=\"10 20 5\"", "Spacing=\"10 20 5\" Direction=\"0 1 0 -1 0 0 0 0 1\"");
        assert!(parse(rotated.as_bytes(), None).unwrap_err().to_string().contains("is rotated"));
        let lz4 = file("", "", r#"compressor="vtkLZ4DataCompressor""#);
        assert!(
            parse(lz4.as_bytes(), None)
                .unwrap_err()
                .to_string()
                .contains("compressor vtkLZ4DataCompressor is not supported")
        );
        assert!(parse(b"not xml", None).unwrap_err().to_string().contains("not a VTK XML file"));
    }

    #[test]
    fn malformed_xml_and_bad_base64_are_named() {
        let ascii = r#"<DataArray type="Int32" Name="lith" format="ascii">1 2 3 4 5 6</DataArray>"#;
        let mismatched = file(ascii, "", "").replace("</PointData>", "</CellData>");
        let error = parse(mismatched.as_bytes(), None).unwrap_err();
        assert!(matches!(error, VtiError::Xml { .. }), "{error}");
        assert!(error.to_string().contains("is not well-formed XML at byte"), "{error}");
        let unquoted = file(ascii, "", "").replace("Name=\"lith\"", "Name=lith");
        assert!(matches!(parse(unquoted.as_bytes(), None).unwrap_err(), VtiError::Xml { .. }));

        let data: Vec<u8> = [1i16, 2, 3, 4, 5, 6].iter().flat_map(|v| v.to_le_bytes()).collect();
        let body = format!("{}{}", b64(&(data.len() as u32).to_le_bytes()), b64(&data)).replace('C', "*");
        let array = format!(r#"<DataArray type="Int16" Name="lith" format="binary">{body}</DataArray>"#);
        let error = parse(file(&array, "", "").as_bytes(), None).unwrap_err().to_string();
        assert!(error.starts_with("array \"lith\": bad base64 data: Invalid symbol 42"), "{error}");
    }
}
