//! Bad input, format detection and atomic writes: every failure is a typed error naming the file,
//! never a panic, and never a half-written file.

mod common;

use std::path::{Path, PathBuf};

use common::{dir_entries, fixture, small_field};
use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield, HeightfieldError};
use relief_heightfield_io::{
    Format, IoError, IoErrorKind, Limits, ReadOptions, WriteOptions, read, read_bytes, read_with, write, write_bytes,
    write_with,
};

fn tiny_limits(max_cells: u64) -> ReadOptions {
    ReadOptions::default().with_limits(Limits::default().with_max_cells(max_cells))
}

/// Writes `bytes` to `dir/name` and reads it back with `options`, expecting an error.
#[track_caller]
fn read_error(dir: &Path, name: &str, bytes: &[u8], options: &ReadOptions) -> IoError {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    let err = read_with(&path, options).expect_err("reading should fail");
    // Every error names its file.
    assert!(err.to_string().contains(name), "{err}");
    err
}

// --- Files under tests/bad/, each named for its expected error ------------------------------------

#[track_caller]
fn check(file: &str, expected: impl Fn(&IoErrorKind) -> bool) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad").join(file);
    let err = read(&path).expect_err(file);
    assert!(expected(err.kind()), "{file}: unexpected {err}");
    assert_eq!(err.path(), path);
}

#[test]
fn stored_bad_ascii_grids_give_their_documented_errors() {
    check("missing_values.asc", |k| {
        matches!(k, IoErrorKind::MissingValues { expected: 12, found: 10, row: 3, col: 3 })
    });
    check(
        "garbage_token.asc",
        |k| matches!(k, IoErrorKind::InvalidToken { line: 8, row: 2, col: 2, token } if token == "12x"),
    );
    check("trailing_data.asc", |k| matches!(k, IoErrorKind::TrailingData { line: 9, token } if token == "oops"));
    check("no_ncols.asc", |k| matches!(k, IoErrorKind::InvalidMetadata(m) if m.contains("ncols")));
    check("duplicate_key.asc", |k| matches!(k, IoErrorKind::InvalidMetadata(m) if m.contains("twice")));
    check("bad_header_value.asc", |k| matches!(k, IoErrorKind::InvalidMetadata(m) if m.contains("positive integer")));
    check(
        "over_limit.asc",
        |k| matches!(k, IoErrorKind::TooLarge { cells: 10_000_000_000, limit } if *limit == 1 << 30),
    );
    // 900 million cells fit the limit but not the 60-odd bytes that follow: the reader reports
    // the missing values without reserving 3.6 GB first.
    check("lying_header.asc", |k| {
        matches!(k, IoErrorKind::MissingValues { expected: 900_000_000, found: 4, row: 1, col: 5 })
    });
    check("infinite.asc", |k| matches!(k, IoErrorKind::InvalidToken { row: 1, col: 2, .. }));
}

// --- Generated bad input ---------------------------------------------------------------------------

#[test]
fn nonexistent_file_is_an_io_error_naming_it() {
    let err = read("/definitely/not/here/dem.tif").unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Io(e) if e.kind() == std::io::ErrorKind::NotFound), "{err}");
    assert!(err.to_string().starts_with("/definitely/not/here/dem.tif: "), "{err}");
    // The OS's words are in the message, so they are not repeated as a source (an anyhow `{:#}`
    // chain would print them twice).
    assert!(std::error::Error::source(&err).is_none());
    assert_eq!(format!("{:#}", anyhow_like(&err)).matches(": ").count(), 1, "{err}");
}

#[test]
fn unknown_extension_without_magic_is_unknown_format() {
    let dir = tempfile::tempdir().unwrap();
    let err = read_error(dir.path(), "dem.xyz", b"\x01\x02\x03\x04 not a heightfield", &ReadOptions::default());
    assert!(matches!(err.kind(), IoErrorKind::UnknownFormat), "{err}");
    let err = write(dir.path().join("out.xyz"), &small_field(3, 3)).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::UnknownFormat), "{err}");
    assert!(!dir.path().join("out.xyz").exists());
}

#[test]
fn truncated_raw_with_sidecar_names_expected_and_found_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.r16");
    write(&path, &small_field(5, 4)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..33]).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: Some(40), found_bytes: 33 }), "{err}");
    std::fs::write(&path, [bytes.as_slice(), &[0, 0]].concat()).unwrap();
    let err = read(&path).unwrap_err();
    assert!(
        matches!(err.kind(), IoErrorKind::WrongSize { found_bytes: 42, accepted_bytes } if accepted_bytes == &[40])
    );
}

#[test]
fn raw_without_sidecar_needs_dims_or_a_square_size() {
    let dir = tempfile::tempdir().unwrap();
    // 3 samples: not square.
    let err = read_error(dir.path(), "odd.r32", &[0u8; 12], &ReadOptions::default());
    assert!(
        matches!(err.kind(), IoErrorKind::MissingSidecar { sidecar } if sidecar.ends_with("odd.r32.json")),
        "{err}"
    );
    // 4 samples: a 2×2 Unity-style heightmap in [0, 1].
    std::fs::write(dir.path().join("sq.raw"), [0u8, 0, 255, 255, 0, 128, 255, 127]).unwrap();
    let hf = read(dir.path().join("sq.raw")).unwrap();
    assert_eq!((hf.nx(), hf.ny()), (2, 2));
    assert_eq!(hf.value(1, 1), 1.0, "first file sample is the north-west... east: 0xffff");
    assert_eq!(hf.value(0, 1), 0.0);
    // Explicit dims that the length contradicts.
    let err = read_error(dir.path(), "dims.r32", &[0u8; 16], &ReadOptions::default().with_raw_dims(3, 2));
    assert!(matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: Some(24), found_bytes: 16 }), "{err}");
    // Dims over the limit are refused before the length is even looked at.
    let err = read_error(dir.path(), "big.r16", &[0u8; 8], &tiny_limits(100).with_raw_dims(1000, 1000));
    assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 1_000_000, limit: 100 }), "{err}");
    // An empty file.
    let err = read_error(dir.path(), "empty.r16", &[], &ReadOptions::default());
    assert!(matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: None, found_bytes: 0 }), "{err}");
}

#[test]
fn raw_sidecar_problems_name_the_sidecar() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.r16");
    write(&path, &small_field(4, 4)).unwrap();
    let sidecar = dir.path().join("s.r16.json");
    let json = std::fs::read_to_string(&sidecar).unwrap();

    std::fs::write(&sidecar, "{ not json").unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(_)), "{err}");
    assert_eq!(err.path(), sidecar);

    std::fs::write(&sidecar, json.replace("\"r16\"", "\"r32\"")).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::HeaderMismatch(m) if m.contains("r32")), "{err}");
    let err = relief_heightfield_io::quantisation(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::HeaderMismatch(m) if m.contains("r32")), "{err}");
    assert_eq!(err.path(), sidecar);

    std::fs::write(&sidecar, json.replace("\"cell_size\":[2.5,5.0]", "\"cell_size\":[-2.5,5.0]")).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(m) if m.contains("cell size")), "{err}");

    std::fs::write(&sidecar, json.replace("\"format_version\":1", "\"format_version\":7")).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Unsupported(m) if m.contains("format_version")), "{err}");
}

#[test]
fn r32_with_infinite_samples_is_invalid_data() {
    let dir = tempfile::tempdir().unwrap();
    let bytes: Vec<u8> = [1.0f32, f32::INFINITY, 3.0, 4.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let err = read_error(dir.path(), "inf.r32", &bytes, &ReadOptions::default());
    assert!(matches!(err.kind(), IoErrorKind::InvalidData(HeightfieldError::NonFiniteSample { .. })), "{err}");
}

#[test]
fn hgt_of_wrong_size_lists_the_accepted_sizes() {
    let dir = tempfile::tempdir().unwrap();
    for len in [0, 2 * 1201 * 1201 - 2, 2 * 1201 * 1201 + 1, 2 * 1200 * 1200] {
        let err = read_error(dir.path(), "N36W085.hgt", &vec![0u8; len], &ReadOptions::default());
        assert!(
            matches!(err.kind(), IoErrorKind::WrongSize { found_bytes, accepted_bytes }
                if *found_bytes == len as u64 && accepted_bytes == &[2_884_802, 25_934_402]),
            "{err}"
        );
    }
}

#[test]
fn hgt_needs_a_tile_name_or_an_origin() {
    let bytes = vec![0u8; 2 * 1201 * 1201];
    let err = read_bytes(&bytes, Format::Hgt, "tile.hgt", &ReadOptions::default()).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(m) if m.contains("N36W085")), "{err}");
    let hf = read_bytes(&bytes, Format::Hgt, "tile.hgt", &ReadOptions::default().with_origin(DVec2::new(7.0, 45.0)))
        .unwrap();
    assert_eq!(hf.grid().origin(), DVec2::new(7.0, 45.0));
    let hf = read_bytes(&bytes, Format::Hgt, "s12e007.SRTMGL3.hgt", &ReadOptions::default()).unwrap();
    assert_eq!(hf.grid().origin(), DVec2::new(7.0, -12.0));
    // Tile sizes still count against the limit.
    let err = read_bytes(&bytes, Format::Hgt, "N00E000.hgt", &tiny_limits(1000)).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 1_442_401, limit: 1000 }), "{err}");
}

#[test]
fn hgt_writes_refuse_what_the_format_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let grid = GridSpec::geographic(1201, 1201, DVec2::new(-85.0, 36.0), DVec2::splat(1.0 / 1200.0)).unwrap();
    let mut hf = Heightfield::zeros(grid);
    hf.set(3, 1200, 40_000.0).unwrap();
    let path = dir.path().join("N36W085.hgt");
    let err = write(&path, &hf).unwrap_err();
    assert!(
        matches!(err.kind(), IoErrorKind::OutOfRange { i: 3, j: 1200, value, min: -32767.0, max: 32767.0 } if *value == 40_000.0),
        "{err}"
    );
    hf.set(3, 1200, -32_768.0).unwrap();
    assert!(matches!(write(&path, &hf).unwrap_err().kind(), IoErrorKind::OutOfRange { .. }), "−32768 is the void code");
    assert!(!path.exists(), "a refused write leaves no file");
    hf.set(3, 1200, 32_767.4).unwrap();
    write(&path, &hf).unwrap();
    assert_eq!(read(&path).unwrap().value(3, 1200), 32_767.0, "rounded to whole metres");
    // A grid that is not on the tile its name names.
    let err = write(dir.path().join("N37W085.hgt"), &hf).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::HeaderMismatch(_)), "{err}");
    // Not a tile size.
    let err = write_bytes(&small_field(4, 4), Format::Hgt).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Unsupported(_)), "{err}");
    assert_eq!(err.path(), Path::new("<memory>"));
}

#[cfg(feature = "png")]
mod png_input {
    use super::*;

    fn gray_png(w: u32, h: u32, depth: png::BitDepth, color: png::ColorType, text: Option<&str>) -> Vec<u8> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(color);
        enc.set_depth(depth);
        if let Some(t) = text {
            enc.add_text_chunk("relief".to_owned(), t.to_owned()).unwrap();
        }
        let row_bytes = (w as usize * color.samples() * depth as usize).div_ceil(8);
        let data: Vec<u8> = (0..row_bytes * h as usize).map(|k| (k * 37 % 251) as u8).collect();
        let mut writer = enc.write_header().unwrap();
        writer.write_image_data(&data).unwrap();
        writer.finish().unwrap();
        out
    }

    #[test]
    fn truncated_png_is_truncated() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.png");
        write(&path, &small_field(40, 30)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        for cut in [10, 40, bytes.len() / 2, bytes.len() - 12, bytes.len() - 1] {
            let err = read_error(dir.path(), "cut.png", &bytes[..cut], &ReadOptions::default());
            assert!(
                matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: None, found_bytes } if *found_bytes == cut as u64),
                "cut at {cut}: {err}"
            );
        }
    }

    #[test]
    fn colour_png_heightmaps_must_be_gray_and_low_depth_reads_through_image() {
        let dir = tempfile::tempdir().unwrap();
        let rgb = gray_png(4, 4, png::BitDepth::Eight, png::ColorType::Rgb, None);
        let err = read_error(dir.path(), "rgb.png", &rgb, &ReadOptions::default());
        let hint = if cfg!(feature = "images") { "--channel" } else { "Rgb" };
        assert!(matches!(err.kind(), IoErrorKind::Unsupported(m) if m.contains(hint)), "{err}");
        let one_bit = gray_png(8, 2, png::BitDepth::One, png::ColorType::Grayscale, None);
        let read = read_bytes(&one_bit, Format::Png16, "bits.png", &ReadOptions::default());
        if cfg!(feature = "images") {
            let hf = read.unwrap();
            assert!(hf.samples().iter().all(|&v| v == 0.0 || v == 1.0), "1-bit gray: 0 or 1");
        } else {
            assert!(matches!(read.unwrap_err().kind(), IoErrorKind::Unsupported(_)));
        }
    }

    #[test]
    fn plain_gray_png_reads_as_zero_to_one_on_a_unit_grid() {
        let bytes = gray_png(3, 2, png::BitDepth::Eight, png::ColorType::Grayscale, None);
        let hf = read_bytes(&bytes, Format::Png8, "plain.png", &ReadOptions::default()).unwrap();
        assert_eq!(hf.grid(), &GridSpec::new(3, 2, DVec2::ZERO, DVec2::ONE).unwrap());
        // First file byte is 0 (north-west), second 37.
        assert_eq!(hf.value(0, 1), 0.0);
        assert_eq!(hf.value(1, 1), 37.0 / 255.0);
    }

    #[test]
    fn png_metadata_that_lies_about_dimensions_is_a_header_mismatch() {
        let json = r#"{"format_version":1,"encoding":"png16","nx":3,"ny":3,"origin":[0,0],"cell_size":[1,1],
                       "units":"metres","min":0,"max":10}"#;
        let bytes = gray_png(4, 3, png::BitDepth::Sixteen, png::ColorType::Grayscale, Some(json));
        let err = read_bytes(&bytes, Format::Png16, "lie.png", &ReadOptions::default()).unwrap_err();
        assert!(matches!(err.kind(), IoErrorKind::HeaderMismatch(m) if m.contains("3x3")), "{err}");
        let bad = json.replace("\"min\":0", "\"min\":20");
        let bytes = gray_png(3, 3, png::BitDepth::Sixteen, png::ColorType::Grayscale, Some(&bad));
        let err = read_bytes(&bytes, Format::Png16, "minmax.png", &ReadOptions::default()).unwrap_err();
        assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(_)), "{err}");
    }

    #[test]
    fn png_over_the_cell_limit_is_refused_from_its_header() {
        let bytes = gray_png(64, 64, png::BitDepth::Eight, png::ColorType::Grayscale, None);
        let err = read_bytes(&bytes, Format::Png8, "big.png", &tiny_limits(4095)).unwrap_err();
        assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 4096, limit: 4095 }), "{err}");
    }
}

#[cfg(feature = "exr")]
#[test]
fn truncated_and_oversized_exr() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = write_bytes(&small_field(50, 40), Format::Exr).unwrap();
    for cut in [3, 100, bytes.len() / 2, bytes.len() - 1] {
        let err = read_error(dir.path(), "cut.exr", &bytes[..cut], &ReadOptions::default());
        assert!(matches!(err.kind(), IoErrorKind::Truncated { .. }), "cut at {cut}: {err}");
    }
    // Uncompressed: the header alone shows 2000 f32 samples cannot fit.
    let err = read_error(dir.path(), "cut.exr", &bytes[..bytes.len() / 2], &ReadOptions::default());
    assert!(matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: Some(8000), .. }), "{err}");
    // Compressed: the decoder runs out of bytes.
    let zipped = dir.path().join("zip.exr");
    write_with(&zipped, &small_field(50, 40), &WriteOptions::default().with_compress(true)).unwrap();
    let zipped = std::fs::read(zipped).unwrap();
    for cut in [100, zipped.len() / 2, zipped.len() - 1] {
        let err = read_error(dir.path(), "cutzip.exr", &zipped[..cut], &ReadOptions::default());
        assert!(matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: None, .. }), "cut at {cut}: {err}");
    }
    let err = read_error(dir.path(), "big.exr", &bytes, &tiny_limits(1999));
    assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 2000, limit: 1999 }), "{err}");
}

#[cfg(feature = "geotiff")]
mod tiff_input {
    use super::*;

    /// Replaces the LONG value of `ImageWidth` (tag 256) in a little-endian TIFF's directory.
    fn patch_width(bytes: &mut [u8], width: u32) {
        let entry = [0x00, 0x01, 0x04, 0x00, 0x01, 0x00, 0x00, 0x00];
        let at = bytes.windows(8).position(|w| w == entry).expect("ImageWidth entry");
        bytes[at + 8..at + 12].copy_from_slice(&width.to_le_bytes());
    }

    #[test]
    fn truncated_tiff_is_truncated() {
        let dir = tempfile::tempdir().unwrap();
        let plain = dir.path().join("u.tif");
        write_with(&plain, &small_field(30, 20), &WriteOptions::default().with_compress(false)).unwrap();
        let plain = std::fs::read(plain).unwrap();
        let deflated = dir.path().join("z.tif");
        write_with(&deflated, &small_field(30, 20), &WriteOptions::default()).unwrap();
        for bytes in [plain, std::fs::read(deflated).unwrap()] {
            for cut in [5, 100, bytes.len() / 2, bytes.len() - 1] {
                let err = read_error(dir.path(), "cut.tif", &bytes[..cut], &ReadOptions::default());
                assert!(matches!(err.kind(), IoErrorKind::Truncated { .. }), "cut at {cut}: {err}");
            }
        }
    }

    #[test]
    fn tiff_header_that_lies_about_dimensions() {
        let dir = tempfile::tempdir().unwrap();
        let plain = dir.path().join("plain.tif");
        write_with(&plain, &small_field(30, 20), &WriteOptions::default().with_compress(false)).unwrap();
        let mut bytes = std::fs::read(plain).unwrap();
        patch_width(&mut bytes, 30_000);
        // 600 000 f32 samples cannot hide in a 2.5 kB uncompressed file: refused before allocation.
        let err = read_error(dir.path(), "lie.tif", &bytes, &ReadOptions::default());
        assert!(
            matches!(err.kind(), IoErrorKind::Truncated { expected_bytes: Some(2_400_000), found_bytes }
                if *found_bytes == bytes.len() as u64),
            "{err}"
        );
        let err = read_error(dir.path(), "lie.tif", &bytes, &tiny_limits(1000));
        assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 600_000, limit: 1000 }), "{err}");
    }

    #[test]
    fn rgb_tiff_reads_when_gray_and_asks_for_a_band_or_channel_otherwise() {
        let rgb = |pixels: &[u8]| {
            let mut out = std::io::Cursor::new(Vec::new());
            let mut enc = tiff::encoder::TiffEncoder::new(&mut out).unwrap();
            enc.write_image::<tiff::encoder::colortype::RGB8>(2, 2, pixels).unwrap();
            read_bytes(out.get_ref(), Format::GeoTiff, "rgb.tif", &ReadOptions::default())
        };
        let gray = rgb(&[7u8; 12]);
        let colour = rgb(&[1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3]).unwrap_err();
        if cfg!(feature = "images") {
            assert_eq!(gray.unwrap().min_max(), Some((7.0 / 255.0, 7.0 / 255.0)));
            assert!(colour.to_string().contains("--channel"), "{colour}");
        } else {
            assert!(gray.unwrap_err().to_string().contains("--band"));
        }
        assert!(matches!(colour.kind(), IoErrorKind::Unsupported(_)), "{colour}");
    }

    #[test]
    fn foreign_tiffs_convert_integers_nodata_and_pixel_is_area() {
        use tiff::tags::Tag;
        let mut out = std::io::Cursor::new(Vec::new());
        let mut enc = tiff::encoder::TiffEncoder::new(&mut out).unwrap();
        let mut image = enc.new_image::<tiff::encoder::colortype::GrayI16>(3, 2).unwrap();
        // GDAL's usual layout: PixelIsArea (the default, no raster-type key), tiepoint on the
        // north-west corner, geographic.
        image.encoder().write_tag(Tag::ModelPixelScaleTag, &[0.5f64, 0.25, 0.0][..]).unwrap();
        image.encoder().write_tag(Tag::ModelTiepointTag, &[0.0f64, 0.0, 0.0, 10.0, 50.0, 0.0][..]).unwrap();
        image.encoder().write_tag(Tag::GeoKeyDirectoryTag, &[1u16, 1, 0, 1, 1024, 0, 1, 2][..]).unwrap();
        image.encoder().write_tag(Tag::GdalNodata, "-9999").unwrap();
        image.write_data(&[1i16, 2, 3, 4, -9999, 6]).unwrap();
        let hf = read_bytes(out.get_ref(), Format::GeoTiff, "gdal.tif", &ReadOptions::default()).unwrap();
        let g = hf.grid();
        assert_eq!(g.units(), relief_heightfield::Units::Degrees);
        assert_eq!(g.cell_size(), DVec2::new(0.5, 0.25));
        // South-west pixel centre: x = 10 + 0.25, y = 50 − 2·0.25 + 0.125.
        assert_eq!(g.origin(), DVec2::new(10.25, 49.625));
        assert_eq!(hf.value(0, 1), 1.0, "first file row is north");
        assert_eq!(hf.value(2, 0), 6.0);
        assert!(hf.is_no_data(1, 0));
    }

    /// `fixtures/gdal/scale-offset.tif`: Int16 codes 1 2 3 4 / 10 −9999 30 40 / 100 200 300 400
    /// (north row first), written by `gdal_translate -q -ot Int16 -a_scale 0.5 -a_offset 100
    /// -co COMPRESS=DEFLATE` from an ASCII grid with NODATA −9999, 30 m cells from (1000, 2000).
    #[test]
    fn gdal_scale_and_offset_turn_codes_into_elevations() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gdal/scale-offset.tif");
        let hf = relief_heightfield_io::read(&path).unwrap();
        // Elevation = code × 0.5 + 100; the no-data code stays no-data (it is matched before scaling).
        assert_eq!(hf.value(0, 2), 100.5, "north-west code 1");
        assert_eq!(hf.value(3, 2), 102.0);
        assert_eq!(hf.value(2, 1), 115.0, "code 30");
        assert_eq!(hf.value(3, 0), 300.0, "south-east code 400");
        assert!(hf.is_no_data(1, 1));
        assert_eq!(hf.grid().cell_size(), DVec2::splat(30.0));
    }

    /// `fixtures/gdal/world-file.tif` + `.tfw`: a baseline TIFF with no geo tags, placed only by its
    /// world file (`gdal_translate -q -ot Float32 -co PROFILE=BASELINE -co TFW=YES`, 30 m cells,
    /// upper-left pixel centre (1015, 2075)).
    #[test]
    fn a_world_file_places_a_tiff_without_geo_tags() {
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gdal");
        let hf = relief_heightfield_io::read(fixtures.join("world-file.tif")).unwrap();
        assert_eq!(hf.grid().cell_size(), DVec2::splat(30.0));
        assert_eq!(hf.grid().origin(), DVec2::new(1015.0, 2015.0), "the south-west sample, two rows below");
        assert_eq!(hf.value(0, 2), 1.0, "north-west pixel");
        // Without it the grid is in pixels; a `.wld` serves too; a rotated one is refused by name.
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy(fixtures.join("world-file.tif"), dir.path().join("t.tif")).unwrap();
        let bare = relief_heightfield_io::read(dir.path().join("t.tif")).unwrap();
        assert_eq!((bare.grid().origin(), bare.grid().cell_size()), (DVec2::ZERO, DVec2::ONE));
        std::fs::write(dir.path().join("t.wld"), "2\n0\n0\n-2\n10\n20\n").unwrap();
        let placed = relief_heightfield_io::read(dir.path().join("t.tif")).unwrap();
        assert_eq!((placed.grid().origin(), placed.grid().cell_size()), (DVec2::new(10.0, 16.0), DVec2::splat(2.0)));
        std::fs::write(dir.path().join("t.tfw"), "2\n0.1\n0\n-2\n10\n20\n").unwrap();
        let err = relief_heightfield_io::read(dir.path().join("t.tif")).unwrap_err();
        assert!(err.to_string().contains("t.tfw") && err.to_string().contains("rotated"), "{err}");
        // A tagged GeoTIFF keeps its own placement whatever lies beside it, as in GDAL.
        std::fs::copy(fixtures.join("scale-offset.tif"), dir.path().join("g.tif")).unwrap();
        std::fs::write(dir.path().join("g.tfw"), "2\n0\n0\n-2\n10\n20\n").unwrap();
        let tagged = relief_heightfield_io::read(dir.path().join("g.tif")).unwrap();
        assert_eq!(tagged.grid().cell_size(), DVec2::splat(30.0));
    }

    #[test]
    fn unreadable_gdal_scale_is_an_error_naming_it() {
        use tiff::tags::Tag;
        let mut out = std::io::Cursor::new(Vec::new());
        let mut enc = tiff::encoder::TiffEncoder::new(&mut out).unwrap();
        let mut image = enc.new_image::<tiff::encoder::colortype::GrayI16>(2, 1).unwrap();
        let xml = r#"<GDALMetadata><Item name="SCALE" sample="0" role="scale">lots</Item></GDALMetadata>"#;
        image.encoder().write_tag(Tag::Unknown(42112), xml).unwrap();
        image.write_data(&[1i16, 2]).unwrap();
        let err = read_bytes(out.get_ref(), Format::GeoTiff, "s.tif", &ReadOptions::default()).unwrap_err();
        assert!(err.to_string().contains("scale \"lots\" is not a finite number"), "{err}");
    }
}

// --- Format detection -------------------------------------------------------------------------------

#[test]
fn detection_prefers_magic_bytes_then_extension() {
    let p = Path::new;
    assert_eq!(Format::detect(p("a.tif"), b"\x89PNG\r\n\x1a\n...."), Some(Format::Png16));
    assert_eq!(Format::detect(p("a.png"), b"II*\0\x08\0\0\0"), Some(Format::GeoTiff));
    assert_eq!(Format::detect(p("a.png"), b"MM\0*"), Some(Format::GeoTiff));
    assert_eq!(Format::detect(p("a.r16"), &[0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0]), Some(Format::Exr));
    assert_eq!(Format::detect(p("a.txt"), b"NCOLS 4\nNROWS 3\n"), Some(Format::Asc));
    assert_eq!(Format::detect(p("a.dat"), b"\xef\xbb\xbf  xllcorner 0\n"), Some(Format::Asc));
    assert_eq!(Format::detect(p("a.asc"), b"1 2 3"), Some(Format::Asc), "extension when the text has no header key");
    assert_eq!(Format::detect(p("a.RAW"), &[1, 2, 3, 4]), Some(Format::R16));
    assert_eq!(Format::detect(p("a.r32"), &[1, 2, 3, 4]), Some(Format::R32));
    assert_eq!(Format::detect(p("N36W085.HGT"), &[1, 2, 3, 4]), Some(Format::Hgt));
    assert_eq!(Format::detect(p("a.TIFF"), &[]), Some(Format::GeoTiff));
    assert_eq!(Format::detect(p("a.exr"), &[]), Some(Format::Exr));
    assert_eq!(Format::detect(p("a.xyz"), b"hello"), None);
    assert_eq!(Format::detect(p("noext"), &[]), None);
    assert_eq!(Format::from_extension(p("x.png")), Some(Format::Png16));
    for f in Format::ALL {
        let name = format!("x.{}", f.extension());
        let expected = if f == Format::Png8 { Format::Png16 } else { f };
        assert_eq!(Format::from_extension(p(&name)), Some(expected), "{f}");
    }
}

#[test]
fn a_file_with_the_wrong_extension_is_read_by_its_magic() {
    let dir = tempfile::tempdir().unwrap();
    let hf = small_field(6, 5);
    let formats = [(Format::Asc, true), (Format::Png16, cfg!(feature = "png")), (Format::Exr, cfg!(feature = "exr"))];
    for (format, enabled) in formats.into_iter().chain([(Format::GeoTiff, cfg!(feature = "geotiff"))]) {
        if !enabled {
            continue;
        }
        let path = dir.path().join(format!("misnamed-{}.r16", format.extension()));
        write_with(&path, &hf, &WriteOptions::default().with_format(format)).unwrap();
        let back = read(&path).unwrap();
        assert_eq!((back.nx(), back.ny()), (6, 5), "{format}");
        assert!(back.is_no_data(3, 2), "{format}");
    }
}

#[test]
fn disabled_codecs_say_which_feature_to_enable() {
    let hf = small_field(2, 2);
    for (format, on, feature) in [
        (Format::Png16, cfg!(feature = "png"), "png"),
        (Format::Exr, cfg!(feature = "exr"), "exr"),
        (Format::GeoTiff, cfg!(feature = "geotiff"), "geotiff"),
    ] {
        let written = write_bytes(&hf, format);
        if on {
            assert!(written.is_ok(), "{format}");
        } else {
            let err = written.unwrap_err();
            assert!(matches!(err.kind(), IoErrorKind::FormatDisabled { feature: f, .. } if *f == feature), "{err}");
            let err = read_bytes(&[0; 8], format, "x", &ReadOptions::default()).unwrap_err();
            assert!(matches!(err.kind(), IoErrorKind::FormatDisabled { .. }), "{err}");
        }
    }
}

// --- Atomic writes ----------------------------------------------------------------------------------

fn all_files() -> Vec<&'static str> {
    let mut v = vec!["a.r16", "a.r32", "a.asc"];
    if cfg!(feature = "png") {
        v.push("a.png");
    }
    if cfg!(feature = "exr") {
        v.push("a.exr");
    }
    if cfg!(feature = "geotiff") {
        v.push("a.tif");
    }
    v
}

#[test]
fn writing_into_a_missing_directory_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    for file in all_files() {
        let path = dir.path().join("missing").join(file);
        let err = write(&path, &small_field(3, 3)).unwrap_err();
        assert!(matches!(err.kind(), IoErrorKind::Io(e) if e.kind() == std::io::ErrorKind::NotFound), "{err}");
        assert!(err.to_string().contains(file), "{err}");
    }
    assert!(dir_entries(dir.path()).is_empty(), "{:?}", dir_entries(dir.path()));
}

#[test]
fn successful_writes_leave_only_the_files_and_their_sidecars() {
    let dir = tempfile::tempdir().unwrap();
    let hf = small_field(5, 4);
    for file in all_files() {
        write(dir.path().join(file), &hf).unwrap();
        // Overwriting replaces the file in place.
        write(dir.path().join(file), &hf).unwrap();
    }
    let mut expected: Vec<String> = all_files().iter().map(|s| (*s).to_owned()).collect();
    expected.extend(["a.prj".to_owned(), "a.r16.json".to_owned(), "a.r32.json".to_owned()]);
    expected.sort();
    assert_eq!(dir_entries(dir.path()), expected);
}

/// Written files get the permissions of any new file (0666 less the umask), not the private 0600
/// of the temporary file they start as: other users can read a DEM someone shares.
#[cfg(unix)]
#[test]
fn written_files_are_not_private_to_their_owner() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = tempfile::tempdir().unwrap();
    // What this process's umask makes of a plainly created file.
    std::fs::write(dir.path().join("plain"), b"x").unwrap();
    let plain = std::fs::metadata(dir.path().join("plain")).unwrap().permissions().mode() & 0o777;
    for file in all_files() {
        write(dir.path().join(file), &small_field(4, 4)).unwrap();
        let mode = std::fs::metadata(dir.path().join(file)).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, plain, "{file}: {mode:o} != {plain:o}");
    }
}

#[test]
fn a_failed_rename_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    // The target is a non-empty directory: the final rename must fail.
    let target = dir.path().join("blocked.asc");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep"), b"x").unwrap();
    let err = write(&target, &small_field(3, 3)).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Io(_)), "{err}");
    assert_eq!(dir_entries(dir.path()), vec!["blocked.asc".to_owned()]);
}

#[test]
fn fixture_is_where_the_tests_expect_it() {
    assert!(fixture("jacksboro.asc").is_file());
    assert!(fixture("jacksboro.prj").is_file());
}

#[test]
fn png_header_announcing_more_than_deflate_could_hold_is_refused_before_allocating() {
    // A valid 16-bit gray PNG of 4x4, then its IHDR rewritten to claim 30000x30000 (with a fixed CRC).
    let grid = relief_heightfield::GridSpec::new(4, 4, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap();
    let hf = relief_heightfield::Heightfield::from_fn_indexed(grid, |i, j| (i + j) as f32).unwrap();
    let mut bytes = relief_heightfield_io::write_bytes(&hf, relief_heightfield_io::Format::Png16).unwrap();
    bytes[16..20].copy_from_slice(&30_000u32.to_be_bytes());
    bytes[20..24].copy_from_slice(&30_000u32.to_be_bytes());
    let crc = crc_ihdr(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    let err = relief_heightfield_io::read_bytes(
        &bytes,
        relief_heightfield_io::Format::Png16,
        "liar.png",
        &relief_heightfield_io::ReadOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(err.kind(), relief_heightfield_io::IoErrorKind::HeaderMismatch(_)), "{err}");
}

/// CRC-32 (PNG polynomial) of a chunk's type and data.
fn crc_ihdr(data: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { 0xedb8_8320 ^ (crc >> 1) } else { crc >> 1 };
        }
    }
    !crc
}

/// The error and its sources joined by ": ", as `anyhow`'s `{:#}` prints them.
fn anyhow_like(err: &(dyn std::error::Error + 'static)) -> String {
    let mut out = err.to_string();
    let mut cause = err.source();
    while let Some(c) = cause {
        out.push_str(": ");
        out.push_str(&c.to_string());
        cause = c.source();
    }
    out
}

#[test]
fn only_regular_files_within_the_byte_budget_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // A directory, and on Unix a device that never ends: refused before a byte is read.
    let mut not_files = vec![dir.path().to_path_buf()];
    if cfg!(unix) {
        not_files.push(PathBuf::from("/dev/zero"));
    }
    for path in &not_files {
        for result in [read(path), relief_heightfield_io::read_gray_image(path, &ReadOptions::default())] {
            let err = result.expect_err("not a file");
            assert!(matches!(err.kind(), IoErrorKind::NotAFile), "{}: {err}", path.display());
        }
    }
    // 32 bytes per cell plus 1 MiB: a 4 MiB file cannot hold a grid of at most 1000 cells.
    let path = dir.path().join("padded.r32");
    std::fs::write(&path, vec![0u8; 4 << 20]).unwrap();
    let err = read_with(&path, &tiny_limits(1000)).unwrap_err();
    match err.kind() {
        IoErrorKind::FileTooLarge { bytes, limit, max_cells: 1000 } => {
            assert_eq!((*bytes, *limit), (4 << 20, 32_000 + (1 << 20)));
        }
        other => panic!("{other:?}"),
    }
    // Under the default limits the same file is read (a square r32 of 1024²).
    let hf = read_with(&path, &ReadOptions::default()).unwrap();
    assert_eq!((hf.nx(), hf.ny()), (1024, 1024));
}

#[cfg(feature = "exr")]
#[test]
fn exr_channels_all_count_against_the_cell_limit() {
    // Every channel is decoded before the height channel is picked, so a 20×10 RGBA file is 800
    // samples, not 200.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgba.exr");
    exr::prelude::write_rgba_file(&path, 20, 10, |x, y| (x as f32, y as f32, 0.0f32, 1.0f32)).unwrap();
    let err = read_with(&path, &tiny_limits(799)).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::TooLarge { cells: 800, limit: 799 }), "{err}");
    let hf = read_with(&path, &tiny_limits(800)).unwrap();
    assert_eq!((hf.nx(), hf.ny()), (20, 10));
}

#[test]
fn a_sidecar_without_min_and_max_must_mark_no_data() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("n.r16");
    let grid = GridSpec::new(2, 2, DVec2::ZERO, DVec2::ONE).unwrap();
    write(&path, &Heightfield::from_samples(grid, vec![f32::NAN; 4]).unwrap()).unwrap();
    // Every sample no-data: no min or max, code 0 everywhere; reads back as all no-data.
    assert!(read(&path).unwrap().samples().iter().all(|v| v.is_nan()));
    // Any other code in such a file is an error, not an elevation made up.
    std::fs::write(&path, [0u8, 0, 7, 0, 0, 0, 0, 0]).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::HeaderMismatch(m) if m.contains("code 7")), "{err}");
    // Without min and max, a sidecar that does not reserve code 0 says nothing of elevations.
    let sidecar = dir.path().join("n.r16.json");
    let json = std::fs::read_to_string(&sidecar).unwrap();
    assert!(json.contains("\"no_data_code\":0"), "{json}");
    std::fs::write(&sidecar, json.replace(",\"no_data_code\":0", "")).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(m) if m.contains("min and max")), "{err}");
}

/// The cells a file announces come from its header alone: every format gives the grid's count,
/// and a PNG cut after its header (no pixel data at all, unreadable as a whole) still gives it.
#[test]
#[cfg(all(feature = "png", feature = "exr", feature = "geotiff", feature = "images"))]
fn announced_cells_read_the_header_only() {
    use relief_heightfield_io::announced_cells;
    let grid = GridSpec::new(37, 23, DVec2::new(500.0, 200.0), DVec2::splat(30.0)).unwrap();
    let hf = Heightfield::from_fn_indexed(grid, |i, j| (i + 2 * j) as f32).unwrap();
    let options = ReadOptions::default();
    for format in [Format::Png16, Format::Png8, Format::Exr, Format::GeoTiff, Format::Asc, Format::R16, Format::R32] {
        let bytes = write_bytes(&hf, format).unwrap();
        assert_eq!(announced_cells(&bytes, format, "f", &options).unwrap(), 37 * 23, "{format:?}");
    }
    // Signature and IHDR: 33 bytes.
    let png = write_bytes(&hf, Format::Png16).unwrap();
    assert!(read_bytes(&png[..33], Format::Png16, "cut.png", &options).is_err());
    assert_eq!(announced_cells(&png[..33], Format::Png16, "cut.png", &options).unwrap(), 851);
    // A colour image's header, read by the image crate.
    let mut colour = Vec::new();
    image::RgbImage::new(40, 30).write_to(&mut std::io::Cursor::new(&mut colour), image::ImageFormat::Png).unwrap();
    assert_eq!(announced_cells(&colour, Format::Png8, "c.png", &options).unwrap(), 1200);
    // An ASCII grid's header with no values; a header that cannot be read is an error naming it.
    let header = b"ncols 4000\nnrows 3000\nxllcorner 0\nyllcorner 0\ncellsize 30\n";
    assert_eq!(announced_cells(header, Format::Asc, "h.asc", &options).unwrap(), 12_000_000);
    let err = announced_cells(b"not a grid", Format::Asc, "bad.asc", &options).unwrap_err();
    assert!(err.to_string().contains("bad.asc"), "{err}");
    // Raw files: their length over the sample size.
    assert_eq!(announced_cells(&[0u8; 11], Format::R16, "r.r16", &options).unwrap(), 5);
}
