//! Round trips through every format: property tests on random grids (with no-data, random origins,
//! cell sizes and units) and the real Jacksboro DEM.

mod common;

use common::{assert_close, fixture, quantisation_step};
use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::{GridSpec, Heightfield, Units};
use relief_heightfield_io::{
    Format, IoErrorKind, ReadNote, ReadOptions, WriteOptions, read, read_bytes, read_with, read_with_notes, write,
    write_bytes, write_with,
};

/// Metric or geographic grids of 1–12 samples per side, anywhere, with unequal cell sizes.
fn grid() -> impl Strategy<Value = GridSpec> {
    (1usize..12, 1usize..12, -1e6f64..1e6, -60.0f64..60.0, 1e-4f64..1e3, 1e-4f64..1e3, any::<bool>()).prop_map(
        |(nx, ny, ox, oy, cx, cy, degrees)| {
            if degrees {
                let origin = DVec2::new(ox.rem_euclid(360.0) - 180.0, oy);
                GridSpec::geographic(nx, ny, origin, DVec2::new(cx, cy) * 1e-3).unwrap()
            } else {
                GridSpec::new(nx, ny, DVec2::new(ox, oy), DVec2::new(cx, cy)).unwrap()
            }
        },
    )
}

/// Any finite f32 (both signs, subnormals, ±0) or no-data: for the bit-exact formats.
fn exact_value() -> BoxedStrategy<f32> {
    use proptest::num::f32 as f;
    prop_oneof![
        6 => -1e4f32..1e4,
        3 => f::POSITIVE | f::NEGATIVE | f::NORMAL | f::SUBNORMAL | f::ZERO,
        1 => Just(f32::NAN),
    ]
    .boxed()
}

/// Elevations in ±10 km or no-data: for the quantised formats.
fn elevation() -> BoxedStrategy<f32> {
    prop_oneof![9 => -1e4f32..1e4, 1 => Just(f32::NAN)].boxed()
}

fn field(values: BoxedStrategy<f32>) -> impl Strategy<Value = Heightfield> {
    grid().prop_flat_map(move |g| (Just(g), proptest::collection::vec(values.clone(), g.len()))).prop_map(|(g, s)| {
        // A field whose samples are all no-data but one keeps min/max meaningful; all-no-data
        // fields are covered by a separate test.
        Heightfield::from_samples(g, s).unwrap()
    })
}

fn through_file(hf: &Heightfield, file: &str, format: Option<Format>) -> Heightfield {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(file);
    let options = format.map_or_else(WriteOptions::default, |f| WriteOptions::default().with_format(f));
    write_with(&path, hf, &options).unwrap();
    read(&path).unwrap()
}

/// The bit-exact formats whose codec is compiled in, with a file name for each.
fn exact_formats() -> Vec<&'static str> {
    let mut v = vec!["f.r32", "f.asc"];
    if cfg!(feature = "exr") {
        v.push("f.exr");
    }
    if cfg!(feature = "geotiff") {
        v.push("f.tif");
    }
    v
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn exact_formats_round_trip_bit_for_bit(hf in field(exact_value())) {
        for file in exact_formats() {
            let back = through_file(&hf, file, None);
            prop_assert_eq!(&back, &hf, "{}", file);
        }
    }

    #[test]
    fn r16_restores_metres_within_one_step(hf in field(elevation())) {
        let back = through_file(&hf, "f.r16", None);
        assert_close(&back, &hf, quantisation_step(&hf, 16));
    }

    #[test]
    #[cfg(feature = "png")]
    fn png16_restores_metres_within_one_step(hf in field(elevation())) {
        let back = through_file(&hf, "f.png", None);
        assert_close(&back, &hf, quantisation_step(&hf, 16));
    }

    #[test]
    #[cfg(feature = "png")]
    fn png8_restores_metres_within_one_step(hf in field(elevation())) {
        let back = through_file(&hf, "f.png", Some(Format::Png8));
        assert_close(&back, &hf, quantisation_step(&hf, 8));
    }

    #[test]
    fn in_memory_exact_formats_round_trip(hf in field(exact_value())) {
        // In memory there are no sidecars: compare on a metric grid, and give r32 its dimensions.
        let metric = GridSpec::new(hf.nx(), hf.ny(), hf.grid().origin(), hf.grid().cell_size()).unwrap();
        let hf = Heightfield::from_samples(metric, hf.into_samples()).unwrap();
        let mut formats = vec![Format::Asc];
        if cfg!(feature = "exr") { formats.push(Format::Exr); }
        if cfg!(feature = "geotiff") { formats.push(Format::GeoTiff); }
        for f in formats {
            let bytes = write_bytes(&hf, f).unwrap();
            prop_assert_eq!(&read_bytes(&bytes, f, "mem", &ReadOptions::default()).unwrap(), &hf, "{}", f);
        }
        let raw = write_bytes(&hf, Format::R32).unwrap();
        let back = read_bytes(&raw, Format::R32, "mem.r32", &ReadOptions::default().with_raw_dims(hf.nx(), hf.ny())).unwrap();
        prop_assert_eq!(back.samples().len(), hf.samples().len());
        prop_assert!(back.samples().iter().zip(hf.samples()).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}

/// A 1201² tile of whole metres in ±30 km with voids, its south-west corner at `(lon, lat)`.
fn hgt_tile(seed: u64, lon: f64, lat: f64) -> Heightfield {
    let grid = GridSpec::geographic(1201, 1201, DVec2::new(lon, lat), DVec2::splat(1.0 / 1200.0)).unwrap();
    let mut state = seed | 1;
    let samples = (0..grid.len())
        .map(|_| {
            // xorshift64: deterministic, no dependency.
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if state.is_multiple_of(97) { f32::NAN } else { ((state % 60_000) as i32 - 30_000) as f32 }
        })
        .collect();
    Heightfield::from_samples(grid, samples).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3, ..ProptestConfig::default() })]

    #[test]
    fn hgt_round_trips_whole_metres_voids_and_tile_origin(seed in any::<u64>(), lat in -60i32..60, lon in -180i32..180) {
        let hf = hgt_tile(seed, f64::from(lon), f64::from(lat));
        let name = format!(
            "{}{:02}{}{:03}.hgt",
            if lat < 0 { 'S' } else { 'N' }, lat.abs(),
            if lon < 0 { 'W' } else { 'E' }, lon.abs()
        );
        let back = through_file(&hf, &name, None);
        prop_assert_eq!(back.grid().units(), Units::Degrees);
        prop_assert_eq!(back, hf);
    }
}

#[test]
fn constant_and_all_no_data_fields_round_trip() {
    let grid = GridSpec::new(3, 2, DVec2::new(5.0, 6.0), DVec2::splat(2.0)).unwrap();
    let flat = Heightfield::filled(grid, 123.25).unwrap();
    let mut holed = flat.clone();
    holed.set(1, 1, f32::NAN).unwrap();
    let empty = Heightfield::filled(grid, f32::NAN).unwrap();
    let mut files = vec!["c.r16", "c.r32", "c.asc"];
    if cfg!(feature = "png") {
        files.push("c.png");
    }
    if cfg!(feature = "exr") {
        files.push("c.exr");
    }
    if cfg!(feature = "geotiff") {
        files.push("c.tif");
    }
    for hf in [&flat, &holed, &empty] {
        for file in &files {
            // Codes lo and hi decode to exactly min and max, so even quantised formats are exact here.
            assert_eq!(&through_file(hf, file, None), hf, "{file}");
        }
        if cfg!(feature = "png") {
            assert_eq!(&through_file(hf, "c8.png", Some(Format::Png8)), hf);
        }
    }
}

#[test]
fn quantised_formats_restore_min_and_max_exactly() {
    let hf = common::small_field(9, 7);
    let (lo, hi) = hf.min_max().unwrap();
    let mut files = vec![("q.r16", None)];
    if cfg!(feature = "png") {
        files.push(("q.png", None));
        files.push(("q8.png", Some(Format::Png8)));
    }
    for (file, format) in files {
        let back = through_file(&hf, file, format);
        assert_eq!(back.min_max(), Some((lo, hi)), "{file}");
        assert!(back.is_no_data(4, 3), "{file}");
    }
}

// --- The real DEM ---------------------------------------------------------------------------------

fn jacksboro() -> Heightfield {
    read(fixture("jacksboro.asc")).unwrap()
}

#[test]
fn jacksboro_reads_with_its_published_shape_range_and_origin() {
    let hf = jacksboro();
    assert_eq!((hf.nx(), hf.ny()), (403, 344));
    assert_eq!(hf.min_max(), Some((236.0, 1076.0)));
    assert!(!hf.has_no_data());
    let g = hf.grid();
    // xllcorner/yllcorner are cell corners: the first sample sits half a cell in.
    let cell = 0.000_833_333_3;
    assert_eq!(g.cell_size(), DVec2::splat(cell));
    assert_eq!(g.origin(), DVec2::new(-84.413_75 + 0.5 * cell, 36.446_25 + 0.5 * cell));
    // The sibling jacksboro.prj says WGS84 geographic.
    assert_eq!(g.units(), Units::Degrees);
    // The file's first value (483) is the north-west sample; its last (row 344 in the file) is south.
    assert_eq!(hf.value(0, 343), 483.0);
    assert_eq!(hf.value(1, 343), 487.0);
    // Degrees → true ground slopes: 3″ cells are ~75 m east-west at 36.5° N, ~92 m north-south.
    let m = g.cell_size_m(0);
    assert!((m.x - 74.6).abs() < 0.5 && (m.y - 92.5).abs() < 0.5, "{m}");
}

#[test]
fn jacksboro_units_follow_the_prj_unless_overridden() {
    let dir = tempfile::tempdir().unwrap();
    let bare = dir.path().join("bare.asc");
    std::fs::copy(fixture("jacksboro.asc"), &bare).unwrap();
    let (guessed, notes) = read_with_notes(&bare, &ReadOptions::default()).unwrap();
    assert_eq!(guessed.grid().units(), Units::Degrees, "no .prj, sub-arc-minute cells inside ±180/±90: degrees");
    assert_eq!(notes, [ReadNote::GuessedDegrees { cell_size: 0.000_833_333_3 }], "and the guess is said");
    let (_, notes) = read_with_notes(fixture("jacksboro.asc"), &ReadOptions::default()).unwrap();
    assert!(notes.is_empty(), "a .prj leaves nothing to guess");
    let forced = read_with(fixture("jacksboro.asc"), &ReadOptions::default().with_units(Units::Metres)).unwrap();
    assert_eq!(forced.grid().units(), Units::Metres);
}

#[test]
fn jacksboro_round_trips_through_every_format() {
    let hf = jacksboro();
    let mut exact = vec!["j.r32", "j.asc"];
    if cfg!(feature = "exr") {
        exact.push("j.exr");
    }
    if cfg!(feature = "geotiff") {
        exact.push("j.tif");
    }
    for file in exact {
        assert_eq!(through_file(&hf, file, None), hf, "{file}");
    }
    let mut quantised = vec![("j.r16", None, 16)];
    if cfg!(feature = "png") {
        quantised.push(("j.png", None, 16));
        quantised.push(("j8.png", Some(Format::Png8), 8));
    }
    for (file, format, bits) in quantised {
        let back = through_file(&hf, file, format);
        assert_close(&back, &hf, quantisation_step(&hf, bits));
        if bits == 16 {
            // Half a 16-bit step over 840 m is 6 mm: rounding restores the whole metres exactly.
            assert!(back.samples().iter().zip(hf.samples()).all(|(a, b)| a.round() == *b), "{file}");
        }
    }
}

#[test]
fn compressed_float_formats_round_trip_and_shrink_whole_metre_dems() {
    let hf = jacksboro();
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    if cfg!(feature = "exr") {
        files.push("z.exr");
    }
    if cfg!(feature = "geotiff") {
        files.push("z.tif");
    }
    for file in files {
        let (plain, zipped) = (dir.path().join(file), dir.path().join(format!("zip-{file}")));
        write_with(&plain, &hf, &WriteOptions::default().with_compress(false)).unwrap();
        write_with(&zipped, &hf, &WriteOptions::default().with_compress(true)).unwrap();
        assert_eq!(read(&zipped).unwrap(), hf, "{file}");
        let size = |p: &std::path::Path| std::fs::metadata(p).unwrap().len();
        assert!(size(&zipped) * 2 < size(&plain), "{file}: {} vs {}", size(&zipped), size(&plain));
    }
}

#[test]
fn jacksboro_pasted_into_its_srtm_tile_round_trips_through_hgt() {
    let hf = jacksboro();
    // The DEM is SRTM 3″ data: its samples sit on the nodes of tile N36W085 (1/1200° apart).
    let (i0, j0) = (704, 536);
    let tile_grid = GridSpec::geographic(1201, 1201, DVec2::new(-85.0, 36.0), DVec2::splat(1.0 / 1200.0)).unwrap();
    assert!((tile_grid.position(i0, j0) - hf.grid().origin()).abs().max_element() < 1e-6);
    let tile = Heightfield::from_fn_indexed(tile_grid, |i, j| {
        let (di, dj) = (i.wrapping_sub(i0), j.wrapping_sub(j0));
        if di < hf.nx() && dj < hf.ny() { hf.value(di, dj) } else { f32::NAN }
    })
    .unwrap();
    assert_eq!(hf.nx() * hf.ny(), tile.samples().iter().filter(|v| !v.is_nan()).count());
    let back = through_file(&tile, "N36W085.hgt", None);
    assert_eq!(back, tile);
    assert_eq!(back.value(i0, j0 + 343), 483.0);

    // The DEM itself is not a tile size.
    let dir = tempfile::tempdir().unwrap();
    let err = write(dir.path().join("N36W085.hgt"), &hf).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Unsupported(m) if m.contains("403x344")), "{err}");
}

/// Same field ⇒ same bytes, every time and in every format: outputs are reproducible (an EXR
/// header with several custom attributes would not be: `exr` keeps them in a `HashMap`).
#[test]
fn encoding_is_byte_for_byte_reproducible() {
    let grid = GridSpec::new(700, 530, DVec2::new(-3.0, 2.0), DVec2::splat(10.0)).unwrap();
    let hf =
        Heightfield::from_fn(grid, |p| (p.x * 0.01).sin() as f32 * 300.0 + (p.y * 0.013).cos() as f32 * 200.0).unwrap();
    let formats: Vec<Format> = [Format::Asc, Format::R16, Format::R32]
        .into_iter()
        .chain(cfg!(feature = "exr").then_some(Format::Exr))
        .chain(cfg!(feature = "png").then_some(Format::Png16))
        .chain(cfg!(feature = "geotiff").then_some(Format::GeoTiff))
        .collect();
    for f in formats {
        let first = write_bytes(&hf, f).unwrap();
        for _ in 0..3 {
            assert!(write_bytes(&hf, f).unwrap() == first, "{f} bytes vary between runs");
        }
    }
}

/// A fixed vertical range: the quantised formats map it, not the field's min and max, onto their
/// codes, record it, and read back metres; a sample outside it is an error, never clamped.
#[test]
fn quantised_formats_take_a_fixed_vertical_range() {
    let dir = tempfile::tempdir().unwrap();
    let grid = GridSpec::new(6, 4, DVec2::ZERO, DVec2::splat(10.0)).unwrap();
    let hf = Heightfield::from_fn(grid, |p| 100.0 + 8.0 * (p.x + p.y) as f32).unwrap();
    let range = WriteOptions::default().with_range(0.0, 1000.0);
    for (file, format, codes) in
        [("t.png", None, 65535.0), ("t8.png", Some(Format::Png8), 255.0), ("t.r16", None, 65535.0)]
    {
        let path = dir.path().join(file);
        let options = format.map_or(range, |f| range.with_format(f));
        write_with(&path, &hf, &options).unwrap();
        let back = read(&path).unwrap();
        let step = 1000.0 / codes;
        for (a, b) in hf.samples().iter().zip(back.samples()) {
            assert!(f64::from((a - b).abs()) <= 0.5 * step + 1e-3, "{file}: {a} vs {b}");
        }
        // Code k holds 1000·k/codes metres: 100 m is code round(100·codes/1000), not 0.
        let coded = (100.0 * codes / 1000.0_f64).round() * 1000.0 / codes;
        assert!((f64::from(back.min_max().unwrap().0) - coded).abs() < 1e-3, "{file}");
    }
    // A range that is exactly the field's own min and max holds every sample.
    let (lo, hi) = hf.min_max().unwrap();
    write_with(dir.path().join("exact.r16"), &hf, &WriteOptions::default().with_range(lo, hi)).unwrap();
    // Outside the range: an error naming the sample, and no file.
    let tight = WriteOptions::default().with_range(0.0, 150.0);
    let out = dir.path().join("tight.png");
    let e = write_with(&out, &hf, &tight).unwrap_err();
    assert!(matches!(e.kind(), IoErrorKind::OutOfRange { .. }), "{e}");
    assert!(!out.exists());
    let e = write_with(dir.path().join("bad.r16"), &hf, &WriteOptions::default().with_range(5.0, 5.0)).unwrap_err();
    assert!(e.to_string().contains("min < max"), "{e}");
    // The float formats keep their floats whatever the range.
    write_with(dir.path().join("t.exr"), &hf, &range).unwrap();
    assert_eq!(read(dir.path().join("t.exr")).unwrap().samples(), hf.samples());
}

#[cfg(all(feature = "png", feature = "exr"))]
#[test]
fn a_quantised_file_tells_how_its_codes_map_to_elevations() {
    use relief_heightfield_io::quantisation;
    let dir = tempfile::tempdir().unwrap();
    let grid = GridSpec::new(5, 3, DVec2::ZERO, DVec2::ONE).unwrap();
    let mut hf = Heightfield::from_fn(grid, |p| 10.0 * p.x as f32).unwrap();
    let range = WriteOptions::default().with_range(-50.0, 200.0);
    write_with(dir.path().join("a.png"), &hf, &range).unwrap();
    let q = quantisation(dir.path().join("a.png")).unwrap().unwrap();
    assert_eq!((q.bits, q.lowest_code, q.highest_code, q.no_data_code), (16, 0, 65535, None));
    assert_eq!((q.min, q.max, q.from_metadata), (-50.0, 200.0, true));
    assert!((q.step() - 250.0 / 65535.0).abs() < 1e-12);
    // With no-data, code 0 is reserved and the codes start at 1.
    hf.samples_mut()[3] = f32::NAN;
    write_with(dir.path().join("b.r16"), &hf, &WriteOptions::default()).unwrap();
    let q = quantisation(dir.path().join("b.r16")).unwrap().unwrap();
    assert_eq!((q.lowest_code, q.no_data_code, q.min, q.max), (1, Some(0), 0.0, 40.0));
    assert!((q.step() - 40.0 / 65534.0).abs() < 1e-12);
    // Which code holds what, checked against the bytes: sample (4, 2) is the maximum (top row,
    // written first, last column) and the no-data sample (3, 0) sits in the last row written.
    let bytes = std::fs::read(dir.path().join("b.r16")).unwrap();
    let code = |i: usize, j: usize| {
        let k = 2 * ((2 - j) * 5 + i);
        u16::from_le_bytes([bytes[k], bytes[k + 1]])
    };
    assert_eq!((code(4, 2), code(3, 0), code(0, 0)), (65535, 0, 1));
    // A plain image from a paint program reads as code / max_code; float formats have no codes.
    std::fs::remove_file(dir.path().join("b.r16.json")).unwrap();
    let q = quantisation(dir.path().join("b.r16")).unwrap().unwrap();
    assert_eq!((q.min, q.max, q.lowest_code, q.highest_code, q.from_metadata), (0.0, 1.0, 0, 65535, false));
    let plain8 = dir.path().join("plain8.png");
    let img = [0u8, 9, 255, 4];
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 2, 2);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header().unwrap().write_image_data(&img).unwrap();
    std::fs::write(&plain8, &bytes).unwrap();
    let q = quantisation(&plain8).unwrap().unwrap();
    assert_eq!((q.bits, q.highest_code, q.from_metadata, q.no_data_code), (8, 255, false, None));
    write(dir.path().join("c.exr"), &hf).unwrap();
    assert_eq!(quantisation(dir.path().join("c.exr")).unwrap(), None);
}
