//! Mutation fuzzing in miniature: valid files with random bytes overwritten and random truncation
//! must decode to `Ok` or a typed `Err`, never panic, and never exceed the limits.

mod common;

use proptest::prelude::*;
use relief_heightfield_io::{Format, Limits, ReadOptions, read_bytes, write_bytes};

const MAX_CELLS: u64 = 1 << 16;

fn seed_file(format: Format) -> Option<Vec<u8>> {
    write_bytes(&common::small_field(13, 9), format).ok()
}

/// Every format whose codec is compiled in, with its valid seed file; GDAL-written `GeoTIFF`s too
/// (LZMA strips and tiles, ZSTD, big-endian, user CRS keys), so the decoders of their own
/// paths are mutated as well.
fn seeds() -> Vec<(Format, Vec<u8>)> {
    let mut seeds: Vec<(Format, Vec<u8>)> =
        [Format::Png8, Format::Png16, Format::Exr, Format::R16, Format::R32, Format::Asc, Format::GeoTiff]
            .into_iter()
            .filter_map(|f| seed_file(f).map(|b| (f, b)))
            .collect();
    if cfg!(feature = "geotiff") {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gdal");
        for name in ["lzma-i16-tiled.tif", "lzma-f64-be.tif", "lzma-f32.tif", "zstd-f32.tif", "tn-ftus.tif"] {
            seeds.push((Format::GeoTiff, std::fs::read(dir.join(name)).unwrap()));
        }
    }
    if cfg!(feature = "images") {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/images");
        for (name, format) in [
            ("gray.jpg", Format::Image),
            ("gray.bmp", Format::Image),
            ("gray.webp", Format::Image),
            ("rgb-equal.png", Format::Png16),
            ("palette-gray.png", Format::Png16),
            ("three-band.tif", Format::GeoTiff),
        ] {
            seeds.push((format, std::fs::read(dir.join(name)).unwrap()));
        }
    }
    seeds
}

fn mutate(mut bytes: Vec<u8>, edits: &[(usize, u8)], keep: usize) -> Vec<u8> {
    for &(at, v) in edits {
        if !bytes.is_empty() {
            let k = at % bytes.len();
            bytes[k] = v;
        }
    }
    bytes.truncate(keep.max(1).min(bytes.len()));
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn mutated_files_never_panic(edits in proptest::collection::vec((any::<usize>(), any::<u8>()), 0..6),
                                 keep in any::<usize>()) {
        let options = ReadOptions::default()
            .with_limits(Limits::default().with_max_cells(MAX_CELLS))
            .with_raw_dims(13, 9);
        for (format, seed) in seeds() {
            let keep = if keep % 3 == 0 { keep % (seed.len() + 1) } else { seed.len() };
            let bytes = mutate(seed, &edits, keep);
            if let Ok(hf) = read_bytes(&bytes, format, "fuzz", &options) {
                prop_assert!((hf.nx() * hf.ny()) as u64 <= MAX_CELLS, "{}", format);
            }
        }
    }

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let options = ReadOptions::default().with_limits(Limits::default().with_max_cells(MAX_CELLS));
        for format in Format::ALL {
            let _ = read_bytes(&bytes, format, "N10E010.hgt", &options);
        }
    }
}

#[test]
fn random_ascii_grids_with_header_prefixes_never_panic() {
    // Headers kept intact, bodies replaced by near-misses of numbers.
    let bodies =
        ["1 2 3", "1e", "-", "+.", "1e99999", "nan nan", "0x10", "1,5", "\u{00e9}", "--1", "1 2 3 4 5 6 7 8 9 10"];
    for body in bodies {
        for header in [
            "ncols 3\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n",
            "ncols 1\nnrows 3\nxllcenter 0\nyllcenter 0\ndx 1\ndy 2\n",
        ] {
            let text = format!("{header}{body}\n");
            let _ = read_bytes(text.as_bytes(), Format::Asc, "fuzz.asc", &ReadOptions::default());
        }
    }
    assert!(
        read_bytes(
            b"ncols 3\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\nnan 1 2\n",
            Format::Asc,
            "n.asc",
            &ReadOptions::default()
        )
        .unwrap()
        .is_no_data(0, 0)
    );
}
