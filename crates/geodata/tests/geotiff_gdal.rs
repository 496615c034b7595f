//! The GeoTIFF reader checked by GDAL itself (Debian's gdal-bin, installed by `cargo xtask
//! test`): a raster written by our test writer is converted by `gdal_translate` to tiles,
//! Deflate and LZW with predictors, integer and float types, BigTIFF and pixel-is-point; for
//! each, the georeferencing, CRS and no-data value must equal `gdalinfo -json`'s, and the value
//! at every pixel centre must equal `gdallocationinfo -geoloc`'s there.

use std::path::{Path, PathBuf};

use karst_testkit::scratch;

use karst_testkit::gdal::gdal;

use karst_geodata::crs::Epsg;
use karst_geodata::geotiff::testing::{Encoding, write};
use karst_geodata::geotiff::{GeoRaster, GeoTiffError};
use tiff::encoder::Compression;

/// 37 × 23 pixels of 5 m in Lambert-93, a smooth surface with one no-data pixel.
fn source(scratch: &Path) -> PathBuf {
    let (w, h) = (37, 23);
    let values: Vec<f32> = (0..h)
        .flat_map(|r| {
            (0..w).map(move |c| {
                if (c, r) == (30, 20) {
                    -9999.0
                } else {
                    (800.0 + 3.0 * c as f64 - 2.0 * r as f64 + 10.0 * ((c * r) as f64 * 0.05).sin()) as f32
                }
            })
        })
        .collect();
    let path = scratch.join("source.tif");
    let encoding = Encoding {
        corner: [651_200.0, 6_862_400.0],
        scale: Some([5.0, 5.0]),
        nodata: Some("-9999".into()),
        compression: Compression::Lzw,
        rows_per_strip: 3,
        ..Encoding::default()
    };
    write(&path, w, h, &values, &encoding).unwrap();
    path
}

struct Info {
    size: [usize; 2],
    transform: [f64; 6],
    epsg: Option<u32>,
    nodata: Option<f64>,
}

fn gdalinfo(path: &Path) -> Info {
    let json: serde_json::Value =
        serde_json::from_str(&gdal("gdalinfo", &["-json", path.to_str().unwrap()], None)).unwrap();
    let size =
        json["size"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect::<Vec<_>>();
    let transform: Vec<f64> =
        json["geoTransform"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let epsg = json["stac"]["proj:epsg"].as_u64().map(|c| c as u32);
    let nodata = json["bands"][0]["noDataValue"].as_f64();
    Info { size: [size[0], size[1]], transform: transform.try_into().unwrap(), epsg, nodata }
}

/// Checks `path` against GDAL: georeferencing and every pixel centre's value.
fn agrees_with_gdal(path: &Path) {
    let raster = GeoRaster::read(path, None, None).unwrap_or_else(|e| panic!("{e}"));
    let info = gdalinfo(path);
    let [x0, dx, rx, y0, ry, dy] = info.transform;
    assert_eq!((rx, ry), (0.0, 0.0));
    assert_eq!([raster.nx, raster.ny], info.size, "{}", path.display());
    assert_eq!(raster.cell, dx);
    // The south-west pixel's centre: column 0, last row.
    let south_west = [x0 + 0.5 * dx, y0 + (info.size[1] as f64 - 0.5) * dy];
    assert!(
        (raster.origin[0] - south_west[0]).abs() < 1e-6 && (raster.origin[1] - south_west[1]).abs() < 1e-6,
        "{}: origin {:?} vs gdal {south_west:?}",
        path.display(),
        raster.origin
    );
    assert_eq!(raster.crs.map(|c| c.0), info.epsg);
    assert_eq!(info.epsg, Some(2154));
    let mut coordinates = String::new();
    for j in 0..raster.ny {
        for i in 0..raster.nx {
            let [x, y] = raster.position(i, j);
            coordinates.push_str(&format!("{x} {y}\n"));
        }
    }
    let values =
        gdal("gdallocationinfo", &["-valonly", "-geoloc", path.to_str().unwrap()], Some(&coordinates));
    for (k, line) in values.lines().enumerate() {
        let expected: f64 = line.trim().parse().unwrap();
        let ours = raster.values[k];
        if info.nodata == Some(expected) {
            assert!(ours.is_nan(), "{}: sample {k} is no data in GDAL, {ours} here", path.display());
        } else {
            assert!(
                (ours - expected).abs() <= 1e-6 * expected.abs().max(1.0),
                "{}: sample {k}: {ours} vs {expected}",
                path.display()
            );
        }
    }
    assert_eq!(values.lines().count(), raster.nx * raster.ny);
}

/// The reader refuses the whole raster (it has a no-data pixel), so the comparison reads
/// through a no-data override that no pixel has.
#[test]
fn every_layout_gdal_writes_reads_like_gdal() {
    let scratch = scratch("layouts");
    let source = source(&scratch);
    let variants: [(&str, &[&str]); 8] = [
        (
            "tiled-deflate.tif",
            &["-co", "TILED=YES", "-co", "BLOCKXSIZE=16", "-co", "BLOCKYSIZE=16", "-co", "COMPRESS=DEFLATE"],
        ),
        ("lzw-float-predictor.tif", &["-co", "COMPRESS=LZW", "-co", "PREDICTOR=3"]),
        ("deflate-int16-predictor.tif", &["-ot", "Int16", "-co", "COMPRESS=DEFLATE", "-co", "PREDICTOR=2"]),
        ("uint16.tif", &["-ot", "UInt16"]),
        ("float64-tiled-lzw.tif", &["-ot", "Float64", "-co", "TILED=YES", "-co", "COMPRESS=LZW"]),
        ("int32-bigtiff.tif", &["-ot", "Int32", "-co", "BIGTIFF=YES", "-co", "COMPRESS=DEFLATE"]),
        ("byte.tif", &["-ot", "Byte", "-scale", "700", "950", "0", "250", "-a_nodata", "255"]),
        ("point.tif", &["-mo", "AREA_OR_POINT=Point"]),
    ];
    agrees_with_gdal_except_holes(&scratch, &source);
    for (name, options) in variants {
        let path = scratch.join(name);
        let mut args = options.to_vec();
        args.extend(["-q", source.to_str().unwrap(), path.to_str().unwrap()]);
        gdal("gdal_translate", &args, None);
        agrees_with_gdal_except_holes(&scratch, &path);
    }
    let point = GeoRaster::read(
        &scratch.join("point.tif"),
        Some([[651_210.0, 651_300.0], [6_862_320.0, 6_862_380.0]]),
        None,
    )
    .unwrap();
    assert!(point.pixel_is_point, "GDAL writes AREA_OR_POINT=Point as RasterPixelIsPoint");
    let _ = std::fs::remove_dir_all(&scratch);
}

/// `agrees_with_gdal` on a copy without the no-data pixel's hole, and the hole itself refused.
fn agrees_with_gdal_except_holes(scratch: &Path, path: &Path) {
    let e = GeoRaster::read(path, None, None).unwrap_err();
    assert!(matches!(e, GeoTiffError::NoData { column: 30, row: 20, .. }), "{}: {e}", path.display());
    let filled = scratch.join(format!("filled-{}", path.file_name().unwrap().to_str().unwrap()));
    // gdal_translate -a_nodata none keeps the pixel's value but no longer calls it no data.
    gdal(
        "gdal_translate",
        &["-q", "-a_nodata", "none", path.to_str().unwrap(), filled.to_str().unwrap()],
        None,
    );
    agrees_with_gdal(&filled);
}

#[test]
fn a_crop_reads_the_same_pixels_as_gdal() {
    let scratch = scratch("crop");
    let source = source(&scratch);
    let domain = [[651_232.0, 651_301.5], [6_862_330.0, 6_862_391.0]];
    let crop = GeoRaster::read(&source, Some(domain), None).unwrap();
    let whole = GeoRaster::read(&source, None, Some(-1e30)).unwrap();
    assert_eq!((crop.nx, crop.ny), (16, 14), "centres 651_227.5 .. 651_302.5 and 6_862_327.5 .. 6_862_392.5");
    for j in 0..crop.ny {
        for i in 0..crop.nx {
            let [x, y] = crop.position(i, j);
            let (wi, wj) = (((x - whole.origin[0]) / 5.0) as usize, ((y - whole.origin[1]) / 5.0) as usize);
            assert_eq!(crop.at(i, j), whole.at(wi, wj));
            assert_eq!(crop.pixel_of(i, j), whole.pixel_of(wi, wj));
        }
    }
    assert_eq!(crop.crs, Some(Epsg(2154)));
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn unsupported_files_are_refused_with_the_reason() {
    let scratch = scratch("unsupported");
    let source = source(&scratch);
    let cases: [(&str, &[&str], &str); 3] = [
        ("packbits.tif", &["-co", "COMPRESS=PACKBITS"], "compression 32773 (PackBits) is not supported"),
        ("rgb.tif", &["-b", "1", "-b", "1", "-b", "1"], "has 3 bands"),
        ("complex.tif", &["-ot", "CFloat32"], "samples of"),
    ];
    for (name, options, expected) in cases {
        let path = scratch.join(name);
        let mut args = options.to_vec();
        args.extend(["-q", source.to_str().unwrap(), path.to_str().unwrap()]);
        gdal("gdal_translate", &args, None);
        let e = GeoRaster::read(&path, None, None).unwrap_err();
        assert!(matches!(e, GeoTiffError::Unsupported { .. }), "{name}: {e}");
        assert!(e.to_string().contains(expected), "{name}: {e}");
    }
    let geographic = scratch.join("wgs84.tif");
    gdal(
        "gdal_translate",
        &[
            "-q",
            "-a_srs",
            "EPSG:4326",
            "-a_ullr",
            "5",
            "45",
            "6",
            "44",
            source.to_str().unwrap(),
            geographic.to_str().unwrap(),
        ],
        None,
    );
    let e = GeoRaster::read(&geographic, None, None).unwrap_err();
    assert!(e.to_string().contains("geographic coordinates (EPSG:4326, degrees)"), "{e}");
    let not_a_tiff = scratch.join("text.tif");
    std::fs::write(&not_a_tiff, "not a tiff").unwrap();
    assert!(matches!(GeoRaster::read(&not_a_tiff, None, None), Err(GeoTiffError::Read { .. })));
    let _ = std::fs::remove_dir_all(&scratch);
}
