//! The conduit probability as one 3D volume, `probability.vti`: a VTK XML ImageData file that
//! ParaView (and anything built on VTK) opens as it is.
//!
//! The image's points are the grid's cell corners (`WholeExtent 0 nx 0 ny 0 nz`, `Origin` the
//! grid's min corner, `Spacing` the cell), so each grid cell is one VTK cell. Cell data: the
//! float `probability` (fraction of realizations with a conduit in the cell, the active
//! scalars) and the integer `count` (how many); field data `realizations`. The arrays follow
//! the XML in one raw appended block, little-endian, each behind its 64-bit byte count, x
//! fastest, then y, then z — VTK's own cell order.

use std::io::Write;

use super::grid::Grid;

/// Writes the volume of `counts` (one per cell) over `realizations` into `out`.
pub fn write_vti(
    out: &mut dyn Write,
    grid: &Grid,
    counts: &[u32],
    realizations: usize,
) -> std::io::Result<()> {
    let n = realizations.max(1) as f64;
    let probability: Vec<u8> =
        counts.iter().flat_map(|&c| ((f64::from(c) / n) as f32).to_le_bytes()).collect();
    let count: Vec<u8> = counts.iter().flat_map(|c| c.to_le_bytes()).collect();
    let [nx, ny, nz] = grid.dims;
    let extent = format!("0 {nx} 0 {ny} 0 {nz}");
    let [x, y, z] = grid.min;
    let c = grid.cell;
    let second = 8 + probability.len();
    write!(
        out,
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
         \x20 <ImageData WholeExtent=\"{extent}\" Origin=\"{x} {y} {z}\" Spacing=\"{c} {c} {c}\">\n\
         \x20   <FieldData>\n\
         \x20     <DataArray type=\"UInt64\" Name=\"realizations\" NumberOfTuples=\"1\" format=\"ascii\">{realizations}</DataArray>\n\
         \x20   </FieldData>\n\
         \x20   <Piece Extent=\"{extent}\">\n\
         \x20     <PointData/>\n\
         \x20     <CellData Scalars=\"probability\">\n\
         \x20       <DataArray type=\"Float32\" Name=\"probability\" format=\"appended\" offset=\"0\"/>\n\
         \x20       <DataArray type=\"UInt32\" Name=\"count\" format=\"appended\" offset=\"{second}\"/>\n\
         \x20     </CellData>\n\
         \x20   </Piece>\n\
         \x20 </ImageData>\n\
         \x20 <AppendedData encoding=\"raw\">\n_"
    )?;
    for block in [&probability, &count] {
        out.write_all(&(block.len() as u64).to_le_bytes())?;
        out.write_all(block)?;
    }
    out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_places_the_grid_and_the_blocks_hold_every_cell() {
        let grid = Grid { min: [1.5, -2.0, 100.0], cell: 2.5, dims: [3, 2, 2] };
        let counts: Vec<u32> = (0..12).collect();
        let mut bytes = Vec::new();
        write_vti(&mut bytes, &grid, &counts, 4).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("WholeExtent=\"0 3 0 2 0 2\" Origin=\"1.5 -2 100\" Spacing=\"2.5 2.5 2.5\""));
        assert!(text.contains("offset=\"56\""), "8 + 12 × 4 bytes before the counts");
        let start = bytes.windows(2).position(|w| w == b"\n_").unwrap() + 2;
        let block = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
        assert_eq!(block(start), 48);
        let p =
            |i: usize| f32::from_le_bytes(bytes[start + 8 + 4 * i..start + 12 + 4 * i].try_into().unwrap());
        assert_eq!((p(0), p(6), p(11)), (0.0, 1.5, 2.75));
        assert_eq!(block(start + 56), 48);
        assert!(text.ends_with("</AppendedData>\n</VTKFile>\n"));
    }
}
