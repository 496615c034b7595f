//! The GLB container: a 12-byte header, the JSON chunk (padded with spaces) and the binary
//! chunk (padded with zeros), every length known before the first byte is written.

use std::io::{self, Write};

use serde_json::Value;

use crate::GltfError;

/// A deferred writer of some bytes of the buffer.
pub type Fill<'a> = Box<dyn Fn(&mut dyn Write) -> io::Result<()> + 'a>;

const MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// A laid-out .glb, ready to be written.
pub struct Glb<'a> {
    json: Vec<u8>,
    blocks: Vec<Fill<'a>>,
    /// Bytes the blocks write (a multiple of 4).
    bin: usize,
}

impl<'a> Glb<'a> {
    pub(crate) fn new(document: &Value, blocks: Vec<Fill<'a>>, bin: usize) -> Result<Glb<'a>, GltfError> {
        let mut json = serde_json::to_vec(document).expect("a JSON value serializes");
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let glb = Glb { json, blocks, bin };
        if glb.len() > u32::MAX as usize {
            return Err(GltfError::TooLarge { bytes: glb.len() });
        }
        Ok(glb)
    }

    /// Bytes of the file.
    pub fn len(&self) -> usize {
        12 + 8 + self.json.len() + if self.bin > 0 { 8 + self.bin } else { 0 }
    }

    /// Always false: a file has at least its header.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Streams the file into `w`.
    pub fn write_to(&self, w: &mut dyn Write) -> io::Result<()> {
        w.write_all(MAGIC)?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&(self.len() as u32).to_le_bytes())?;
        w.write_all(&(self.json.len() as u32).to_le_bytes())?;
        w.write_all(&JSON_CHUNK.to_le_bytes())?;
        w.write_all(&self.json)?;
        if self.bin > 0 {
            w.write_all(&(self.bin as u32).to_le_bytes())?;
            w.write_all(&BIN_CHUNK.to_le_bytes())?;
            for block in &self.blocks {
                block(w)?;
            }
        }
        Ok(())
    }

    /// The file in memory.
    pub fn to_vec(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.len());
        self.write_to(&mut out).expect("writing to memory does not fail");
        out
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use crate::{ARRAY_BUFFER, Gltf};

    #[test]
    fn chunks_are_aligned_and_the_header_gives_the_length() {
        let mut b = Gltf::new();
        let view = b.view(6, ARRAY_BUFFER, |w| w.write_all(&[1, 2, 3, 4, 5, 6]));
        b.view(4, ARRAY_BUFFER, |w| w.write_all(&[7, 8, 9, 10]));
        b.node(json!({ "name": "a" }));
        let glb = b.finish("test", json!([{ "nodes": [0] }])).unwrap();
        let bytes = glb.to_vec();
        assert_eq!(bytes.len(), glb.len());
        assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize, bytes.len());
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        assert_eq!(json_len % 4, 0);
        let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        assert_eq!(doc["bufferViews"][1]["byteOffset"], 8, "the second view starts aligned");
        assert_eq!(doc["buffers"][0]["byteLength"], 12);
        let bin = &bytes[20 + json_len + 8..];
        assert_eq!(bin, [1, 2, 3, 4, 5, 6, 0, 0, 7, 8, 9, 10]);
        assert_eq!(view, 0);
    }
}
