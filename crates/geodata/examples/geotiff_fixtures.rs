//! Writes the data of the georeferenced example scene (`fixtures/scenes/geotiff.toml`, in
//! Lambert-93, EPSG:2154) into `fixtures/scenes/data/geotiff/`, the files a hydrogeologist
//! brings from a GIS and a geomodeller:
//!
//! - `dem.tif`: a 10 m DEM, 100 × 80 pixels of float32, LZW, with GDAL_NODATA = −9999 and a
//!   hole in its margin outside the domain (karstgen crops the domain out of it);
//! - `water-table.tif`: a 20 m piezometric map, 42 × 32 pixels of float32, Deflate;
//! - `field.csv`: the sinks (no z: on the ground) and the spring, as surveyed;
//! - `lithology.vti`: a 40 × 40 × 10 m voxel model (VTK ImageData, cell data, appended raw
//!   binary as VTK writes it): limestone over marl, and a granite intrusion.
//!
//! `cargo run --release -p karst-geodata --example geotiff_fixtures`. The scene's domain is
//! x 651000–651800, y 6862000–6862600, z 250–500 m.

use std::path::Path;

use karst_geodata::geotiff::testing::{Encoding, write};
use tiff::encoder::Compression;

/// The plateau: 480 m in the west falling 9 % to the east, rolling hills and a valley running
/// east around y = 6862300 towards the spring.
fn ground(x: f64, y: f64) -> f64 {
    let (u, v) = (x - 651_000.0, y - 6_862_000.0);
    let hills = 4.0 * (u / 90.0).sin() * (v / 130.0).cos();
    let east = (u / 800.0).clamp(0.0, 1.0);
    let valley = 18.0 * (-((v - 300.0) / 120.0).powi(2)).exp() * east * east;
    480.0 - 0.09 * u + hills - valley
}

/// The water table: 362 m at the spring, rising 3 % westwards and a little to the north and
/// south of the valley.
fn water_table(x: f64, y: f64) -> f64 {
    let (u, v) = (x - 651_000.0, y - 6_862_000.0);
    362.0 + 0.03 * (795.0 - u) + 0.01 * (v - 300.0).abs()
}

/// Lithology code at a voxel centre: 3 granite inside a dome, 1 limestone above the marl top
/// (dipping 1° east from 330 m), 2 marl below.
fn lithology(x: f64, y: f64, z: f64) -> i32 {
    let (u, v) = (x - 651_000.0, y - 6_862_000.0);
    let granite =
        ((u - 420.0) / 130.0).powi(2) + ((v - 150.0) / 110.0).powi(2) + ((z - 250.0) / 70.0).powi(2) < 1.0;
    let marl_top = 330.0 - 1f64.to_radians().tan() * u;
    if granite {
        3
    } else if z > marl_top {
        1
    } else {
        2
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/data/geotiff");
    std::fs::create_dir_all(&folder)?;
    // DEM: pixel (c, r) covers [650900 + 10c, +10] × [6862700 − 10(r + 1), −10]; centre values.
    let (w, h) = (100u32, 80u32);
    let dem: Vec<f32> = (0..h)
        .flat_map(|r| (0..w).map(move |c| (c, r)))
        .map(|(c, r)| {
            let (x, y) = (650_905.0 + 10.0 * c as f64, 6_862_695.0 - 10.0 * r as f64);
            let in_margin_hole = (2..5).contains(&c) && (3..6).contains(&r);
            if in_margin_hole { -9999.0 } else { ((ground(x, y) * 100.0).round() / 100.0) as f32 }
        })
        .collect();
    let lambert = Encoding {
        corner: [650_900.0, 6_862_700.0],
        scale: Some([10.0, 10.0]),
        nodata: Some("-9999".into()),
        compression: Compression::Lzw,
        rows_per_strip: 8,
        ..Encoding::default()
    };
    write(&folder.join("dem.tif"), w, h, &dem, &lambert)?;
    let (w, h) = (42u32, 32u32);
    let wt: Vec<f32> = (0..h)
        .flat_map(|r| (0..w).map(move |c| (c, r)))
        .map(|(c, r)| water_table(650_990.0 + 20.0 * c as f64, 6_862_610.0 - 20.0 * r as f64) as f32)
        .collect();
    let piezometry = Encoding {
        corner: [650_980.0, 6_862_620.0],
        scale: Some([20.0, 20.0]),
        nodata: None,
        compression: Compression::Deflate(Default::default()),
        ..lambert
    };
    write(&folder.join("water-table.tif"), w, h, &wt, &piezometry)?;
    std::fs::write(folder.join("field.csv"), FIELD)?;
    std::fs::write(folder.join("lithology.vti"), vti())?;
    Ok(())
}

/// The field campaign: sinks on the plateau (z left empty: on the ground), the spring in the
/// valley on the water table. Extra columns (discharge, comment) are ignored.
const FIELD: &str = "name,x,y,z,kind,recharge,water_table,discharge_l_s,comment
Gouffre des Biches,651234.567,6862345.678,,sink,3,,,doline on the plateau
Perte du Creux,651120.250,6862480.125,,sink,2,,,swallet at the end of a dry valley
Aven de la Combe,651410.000,6862110.500,,sink,1,,,
Doline Ronde,651520.400,6862420.900,,sink,1,,,
Source du Lison,651795.000,6862300.000,362.2,spring,,water-table,450,resurgence in the valley
";

/// 20 × 15 × 25 cells of 40 × 40 × 10 m from (651000, 6862000, 250), Int32 codes, appended
/// raw binary with a UInt32 byte count, as vtkXMLImageDataWriter writes it.
fn vti() -> Vec<u8> {
    let (nx, ny, nz) = (20usize, 15usize, 25usize);
    let mut data = Vec::with_capacity(nx * ny * nz * 4);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let (x, y, z) =
                    (651_020.0 + 40.0 * i as f64, 6_862_020.0 + 40.0 * j as f64, 255.0 + 10.0 * k as f64);
                data.extend(lithology(x, y, z).to_le_bytes());
            }
        }
    }
    let mut file = format!(
        r#"<?xml version="1.0"?>
<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" header_type="UInt32">
  <ImageData WholeExtent="0 {nx} 0 {ny} 0 {nz}" Origin="651000 6862000 250" Spacing="40 40 10" Direction="1 0 0 0 1 0 0 0 1">
    <Piece Extent="0 {nx} 0 {ny} 0 {nz}">
      <PointData>
      </PointData>
      <CellData Scalars="lithology">
        <DataArray type="Int32" Name="lithology" format="appended" RangeMin="1" RangeMax="3" offset="0"/>
      </CellData>
    </Piece>
  </ImageData>
  <AppendedData encoding="raw">
   _"#
    )
    .into_bytes();
    file.extend((data.len() as u32).to_le_bytes());
    file.extend(data);
    file.extend(b"\n  </AppendedData>\n</VTKFile>\n");
    file
}
