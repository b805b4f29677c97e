//! `GeoTIFF` beyond the `tiff` crate's defaults: ZSTD and LZMA files as GDAL writes them (strips and
//! tiles, both byte orders, predictors 2 and 3), and the writer's options (DEFLATE with the
//! floating-point predictor by default, Int16, `PixelIsArea`).
#![cfg(feature = "geotiff")]

mod common;

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};
use relief_heightfield_io::{IoErrorKind, TiffSample, WriteOptions, read, write_with};

fn gdal(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gdal").join(name)
}

/// The 60 × 40 window (columns 100.., rows 100.. from the north) of the Jacksboro ASCII grid that
/// the compressed fixtures hold.
fn window() -> Vec<f32> {
    let dem = read(common::fixture("jacksboro.asc")).unwrap();
    let mut v = Vec::new();
    for j in (dem.ny() - 140..dem.ny() - 100).rev() {
        v.extend_from_slice(&dem.row(j)[100..160]);
    }
    v
}

#[test]
fn zstd_and_lzma_geotiffs_give_the_dem_values() {
    let expected = window();
    let files = [
        "zstd-f32.tif",
        "lzma-f32.tif",
        "lzma-i16-tiled.tif",
        "lzma-u16-be.tif",
        "lzma-f64-be.tif",
        // libtiff's predictors under LZMA (GDAL writes LZMA without them).
        "lzma-i16-p2.tif",
        "lzma-i16-p2-be.tif",
        "lzma-f32-p3-tiled.tif",
    ];
    for file in files {
        let hf = read(gdal(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!((hf.nx(), hf.ny()), (60, 40), "{file}");
        let mut got = Vec::new();
        for j in (0..40).rev() {
            got.extend_from_slice(hf.row(j));
        }
        assert_eq!(got, expected, "{file}");
    }
}

#[test]
fn corrupt_lzma_chunks_are_decode_errors() {
    let mut bytes = std::fs::read(gdal("lzma-f32.tif")).unwrap();
    // The xz magic of every chunk, overwritten.
    let magic = [0xfd, b'7', b'z', b'X', b'Z', 0];
    let at = bytes.windows(6).position(|w| w == magic).unwrap();
    bytes[at + 1] = b'8';
    let path = tempfile::tempdir().unwrap();
    let file = path.path().join("bad.tif");
    std::fs::write(&file, &bytes).unwrap();
    assert!(matches!(read(&file).unwrap_err().kind(), IoErrorKind::Decode(_)));
}

#[test]
fn default_geotiffs_are_deflated_with_the_float_predictor_and_exact() {
    let dem = read(common::fixture("jacksboro.asc")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (packed, plain) = (dir.path().join("p.tif"), dir.path().join("u.tif"));
    write_with(&packed, &dem, &WriteOptions::default()).unwrap();
    write_with(&plain, &dem, &WriteOptions::default().with_compress(false)).unwrap();
    let (a, b) = (std::fs::metadata(&packed).unwrap().len(), std::fs::metadata(&plain).unwrap().len());
    // GDAL's DEFLATE + PREDICTOR=3 of this DEM: 150 447 bytes; plain deflate without the predictor
    // would be about 60 % of the plain size.
    assert!(a < 152_000 && a * 3 < b, "{a} vs {b}");
    assert_eq!(read(&packed).unwrap(), dem);
    let bytes = std::fs::read(&packed).unwrap();
    // Tag 317 (Predictor) = 3, little-endian SHORT.
    assert!(bytes.windows(8).any(|w| w == [0x3d, 0x01, 3, 0, 1, 0, 0, 0]), "Predictor 3 written");
}

#[test]
fn int16_output_rounds_keeps_no_data_and_refuses_what_does_not_fit() {
    let grid = GridSpec::new(4, 3, DVec2::new(10.0, 20.0), DVec2::splat(30.0)).unwrap();
    let mut hf = Heightfield::from_fn_indexed(grid, |i, j| (i * 100 + j) as f32 + 0.4).unwrap();
    hf.set(1, 1, f32::NAN).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("i.tif");
    let i16 = WriteOptions::default().with_tiff_sample(TiffSample::I16);
    write_with(&path, &hf, &i16).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.grid(), hf.grid());
    assert!(back.is_no_data(1, 1));
    assert_eq!(back.value(3, 2), 302.0, "rounded to whole units");
    let tall = hf.map(|v| v + 40_000.0).unwrap();
    assert!(matches!(write_with(&path, &tall, &i16).unwrap_err().kind(), IoErrorKind::OutOfRange { .. }));
    // The range ends: −32767 and 32767 fit, −32768 is the no-data code.
    let edges = |v: f32| Heightfield::filled(grid, v).unwrap();
    write_with(&path, &edges(-32_767.0), &i16).unwrap();
    assert_eq!(read(&path).unwrap().min_max(), Some((-32_767.0, -32_767.0)));
    write_with(&path, &edges(32_767.0), &i16).unwrap();
    assert!(write_with(&path, &edges(-32_768.0), &i16).is_err(), "−32768 would read back as no-data");
}

#[test]
fn pixel_is_area_places_the_samples_where_pixel_is_point_does() {
    let dem = read(gdal("utm17.tif")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.tif");
    write_with(&path, &dem, &WriteOptions::default().with_pixel_is_area(true)).unwrap();
    let back = read(&path).unwrap();
    // Grid and samples, bit for bit (no-data included).
    assert_eq!(back, dem);
    assert_eq!(back.crs(), dem.crs());
}

#[test]
fn lerc_is_a_clear_unsupported_error() {
    let mut bytes = std::fs::read(gdal("zstd-f32.tif")).unwrap();
    // The Compression entry (tag 259, SHORT, count 1) holding ZSTD (50000), made LERC (34887).
    let zstd = [0x03, 0x01, 3, 0, 1, 0, 0, 0, 0x50, 0xc3];
    let at = bytes.windows(10).position(|w| w == zstd).expect("Compression entry");
    bytes[at + 8..at + 10].copy_from_slice(&34887u16.to_le_bytes());
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("lerc.tif");
    std::fs::write(&file, &bytes).unwrap();
    let err = read(&file).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Unsupported(m) if m.contains("LERC")), "{err}");
}
