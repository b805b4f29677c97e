//! Each engine's files read back as the engine reads them: sizes, bit depth, row order, the
//! import dialog's numbers, and tiles whose shared edges are identical.

use std::path::Path;

use glam::DVec2;
use relief_engine_export::{Dialog, Engine, EngineError, ExportOptions, export, prepare};
use relief_heightfield::{GridSpec, Heightfield};

/// 3 km × 2 km sampled every 10 m from (500, 800): rising east and north, 100 m to about 450 m.
fn dem() -> Heightfield {
    let grid = GridSpec::new(301, 201, DVec2::new(500.0, 800.0), DVec2::splat(10.0)).unwrap();
    Heightfield::from_fn(grid, |p| (100.0 + (p.x - 500.0) / 10.0 + (p.y - 800.0) / 40.0) as f32).unwrap()
}

fn options() -> ExportOptions {
    ExportOptions::default()
}

/// Unity's RAW as Unity reads it: rows from the south, little-endian codes over the terrain's
/// height, lifted by its position Y.
fn unity_heights(path: &Path, n: usize, size_y: f64, position_y: f64) -> Vec<Vec<f64>> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(bytes.len(), n * n * 2, "16 bits per sample, {n} × {n}");
    bytes
        .chunks(2 * n)
        .map(|row| {
            row.chunks(2).map(|c| position_y + f64::from(u16::from_le_bytes([c[0], c[1]])) / 65535.0 * size_y).collect()
        })
        .collect()
}

#[test]
fn unity_reads_its_raw_from_the_south_at_true_size() {
    let dem = dem();
    let dir = tempfile::tempdir().unwrap();
    let out = export(&dem, Engine::Unity, &options(), dir.path()).unwrap();
    let s = &out.settings;
    assert_eq!(s.samples, [257, 257], "2⁸ + 1 is the legal size nearest 301");
    let Dialog::Unity { terrain_size, position_y, depth, flip_vertically, .. } = s.dialog else { panic!() };
    assert_eq!((depth, flip_vertically), (16, false));
    assert_eq!(terrain_size, [3000.0, 350.0, 2000.0], "width, height range, length in metres");
    assert_eq!(position_y, 100.0);
    let rows = unity_heights(&out.files[0], 257, terrain_size[1], position_y);
    // The first row is the south edge (100 m in the west), the last the north (150 m there).
    let quantum = 350.0 / 65535.0;
    assert!((rows[0][0] - 100.0).abs() <= quantum && (rows[256][0] - 150.0).abs() <= quantum);
    assert!((rows[0][256] - 400.0).abs() <= quantum && (rows[256][256] - 450.0).abs() <= quantum);
    // Everywhere the heights the sample's ground position has, within a code.
    for (j, row) in rows.iter().enumerate().step_by(17) {
        for (i, h) in row.iter().enumerate().step_by(13) {
            let p = DVec2::new(500.0 + 3000.0 * i as f64 / 256.0, 800.0 + 2000.0 * j as f64 / 256.0);
            let want = f64::from(dem.sample_bilinear_clamped(p).unwrap());
            assert!((h - want).abs() <= quantum + 1e-3, "({i}, {j}): {h} vs {want}");
        }
    }
    assert!(s.summary().contains("Width 257, Height 257") && s.summary().contains("Terrain Size X 3000 Y 350 Z 2000"));
}

#[test]
fn unreal_places_its_codes_with_the_scale_it_is_told() {
    let dem = dem();
    let dir = tempfile::tempdir().unwrap();
    let out = export(&dem, Engine::Unreal, &options(), dir.path()).unwrap();
    assert_eq!(out.settings.samples, [253, 253], "Unreal's recommended size nearest 301");
    let Dialog::Unreal { scale, location_z } = out.settings.dialog else { panic!() };
    assert!((scale[0] - 300_000.0 / 252.0).abs() < 1e-9 && (scale[1] - 200_000.0 / 252.0).abs() < 1e-9);
    let png = relief_heightfield_io::read(&out.files[0]).unwrap();
    assert_eq!((png.nx(), png.ny()), (253, 253));
    // Unreal: height (cm) = location Z + (code − 32768) · scale Z / 128.
    let codes = relief_heightfield_io::quantisation(&out.files[0]).unwrap().expect("a 16-bit PNG");
    assert_eq!((codes.bits, codes.lowest_code, codes.highest_code), (16, 0, 65535));
    let quantum = 350.0 / 65535.0;
    for j in (0..253).step_by(11) {
        for i in (0..253).step_by(7) {
            let h = f64::from(png.value(i, j));
            let code = ((h - 100.0) / 350.0 * 65535.0).round();
            let unreal_m = (location_z + (code - 32768.0) * scale[2] / 128.0) / 100.0;
            let want = f64::from(dem.sample_bilinear_clamped(png.grid().position(i, j)).unwrap());
            assert!((unreal_m - want).abs() <= quantum + 1e-3, "({i}, {j}): {unreal_m} vs {want}");
        }
    }
}

#[test]
fn godot_gets_metres_and_blender_its_own_size() {
    let dem = dem();
    let dir = tempfile::tempdir().unwrap();
    let godot = export(&dem, Engine::Godot, &options(), &dir.path().join("godot")).unwrap();
    let exr = relief_heightfield_io::read(&godot.files[0]).unwrap();
    assert_eq!((exr.nx(), exr.ny()), (257, 257));
    let Dialog::Godot { scale } = godot.settings.dialog else { panic!() };
    assert_eq!(scale, [3000.0 / 256.0, 1.0, 2000.0 / 256.0]);
    // Heights in metres, no scale: the south-west and north-east corners.
    assert_eq!((exr.value(0, 0), exr.value(256, 256)), (100.0, 450.0));

    let blender = export(&dem, Engine::Blender, &options(), &dir.path().join("blender")).unwrap();
    assert_eq!(blender.settings.samples, [301, 201], "any size: the heightfield's own");
    let Dialog::Blender { subdivisions, dimensions, strength, midlevel, location_z } = blender.settings.dialog else {
        panic!()
    };
    assert_eq!((subdivisions, dimensions), ([300, 200], [3000.0, 2000.0]));
    assert_eq!((strength, midlevel, location_z), (350.0, 0.0, 100.0));
    let png = relief_heightfield_io::read(&blender.files[0]).unwrap();
    let quantum = 350.0 / 65535.0;
    for (a, b) in png.samples().iter().zip(dem.samples()) {
        assert!((f64::from(*a) - f64::from(*b)).abs() <= quantum);
    }
    // A size for Blender scales the larger side to it, the other in proportion.
    let small = prepare(&dem, Engine::Blender, &ExportOptions { size: Some(151), ..options() }).unwrap();
    assert_eq!(small.settings.samples, [151, 101]);
}

#[test]
fn tiles_share_their_edges_bit_for_bit() {
    let dem = dem();
    let dir = tempfile::tempdir().unwrap();
    // Unreal World Partition: 127-sample tiles, as many as keep the 10 m spacing (3 × 2: 7.9 m).
    let tiled = ExportOptions { tile: Some(127), ..options() };
    let out = export(&dem, Engine::Unreal, &tiled, dir.path()).unwrap();
    assert_eq!(out.settings.tiles, [3, 2]);
    let names: Vec<String> = out.files.iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect();
    let expected = ["_x0_y0", "_x1_y0", "_x2_y0", "_x0_y1", "_x1_y1", "_x2_y1"].map(|s| format!("heightmap{s}.png"));
    assert_eq!(names, expected);
    let t: Vec<Heightfield> = out.files.iter().map(|f| relief_heightfield_io::read(f).unwrap()).collect();
    for k in 0..127 {
        // West–east neighbours share a column, north–south neighbours a row (y1 is south of y0).
        assert_eq!(t[0].value(126, k).to_bits(), t[1].value(0, k).to_bits());
        assert_eq!(t[4].value(126, k).to_bits(), t[5].value(0, k).to_bits());
        assert_eq!(t[3].value(k, 126).to_bits(), t[0].value(k, 0).to_bits());
        assert_eq!(t[5].value(k, 126).to_bits(), t[2].value(k, 0).to_bits());
    }
    // One height scale for every tile: the north-east tile's top corner is the world's highest.
    assert_eq!(t[2].value(126, 126), 450.0);
    let Dialog::Unreal { scale, .. } = out.settings.dialog else { panic!() };
    assert!((scale[0] - 100.0 * 3000.0 / 378.0).abs() < 1e-9 && (scale[1] - 100.0 * 2000.0 / 252.0).abs() < 1e-9);

    // Unity terrain groups: RAW tiles named X_Z from the south-west, sharing edges too.
    let dir = tempfile::tempdir().unwrap();
    let out = export(&dem, Engine::Unity, &ExportOptions { tile: Some(129), ..options() }, dir.path()).unwrap();
    let names: Vec<String> = out.files.iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect();
    let expected = ["_0_1", "_1_1", "_2_1", "_0_0", "_1_0", "_2_0"].map(|s| format!("heightmap{s}.raw"));
    assert_eq!(names, expected);
    let Dialog::Unity { terrain_size, position_y, .. } = out.settings.dialog else { panic!() };
    assert_eq!(terrain_size, [1000.0, 350.0, 1000.0], "each tile's size");
    let raw: Vec<Vec<Vec<f64>>> =
        out.files.iter().map(|f| unity_heights(f, 129, terrain_size[1], position_y)).collect();
    for (west, east) in raw[3].iter().zip(&raw[4]) {
        assert_eq!(west[128], east[0], "south-west and its east neighbour share a column");
    }
    assert_eq!(raw[3][128], raw[0][0], "south-west's north row is north-west's south row");
    let sidecar: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out.sidecar).unwrap()).unwrap();
    assert_eq!(sidecar["tiles"][1]["offset_m"], serde_json::json!([1000.0, 1000.0]));
    assert!(sidecar["summary"].as_str().unwrap().contains("3 × 2 tiles"));
}

/// The error of a request that must fail (without printing a whole accepted export).
fn refused(result: Result<relief_engine_export::Prepared, EngineError>) -> EngineError {
    match result {
        Err(e) => e,
        Ok(p) => panic!("accepted: {}", p.settings.summary()),
    }
}

#[test]
fn bad_requests_get_errors_that_say_why() {
    let dem = dem();
    let e = refused(prepare(&dem, Engine::Unity, &ExportOptions { size: Some(1024), ..options() }));
    assert!(matches!(e, EngineError::IllegalSize { size: 1024, .. }), "{e}");
    let e = refused(prepare(&dem, Engine::Unreal, &ExportOptions { tile: Some(128), ..options() }));
    assert!(e.to_string().contains("127, 253"), "{e}");
    let e = refused(prepare(&dem, Engine::Unity, &ExportOptions { size: Some(65), tile: Some(129), ..options() }));
    assert!(e.to_string().contains("tile size"), "{e}");
    // Too many tiles along an axis.
    let long = Heightfield::zeros(GridSpec::new(2400, 2, DVec2::ZERO, DVec2::ONE).unwrap());
    let e = refused(prepare(&long, Engine::Unity, &ExportOptions { tile: Some(33), ..options() }));
    assert!(matches!(e, EngineError::TooLarge { .. }), "{e}");
    let empty = Heightfield::filled(GridSpec::new(4, 4, DVec2::ZERO, DVec2::ONE).unwrap(), f32::NAN).unwrap();
    assert!(matches!(prepare(&empty, Engine::Godot, &options()), Err(EngineError::NoData)));
}

#[test]
fn no_data_becomes_the_lowest_ground_and_flat_ground_exports() {
    let mut dem = dem();
    dem.samples_mut()[..301].fill(f32::NAN);
    let p = prepare(&dem, Engine::Godot, &options()).unwrap();
    assert_eq!(p.filled_no_data, 301);
    assert!(p.tiles[0].heights.samples().iter().all(|v| v.is_finite()));
    assert_eq!(p.settings.min_m, 100.25, "the lowest valid sample, on the second row");
    let flat = Heightfield::filled(GridSpec::new(40, 40, DVec2::ZERO, DVec2::splat(5.0)).unwrap(), 7.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = export(&flat, Engine::Unreal, &options(), dir.path()).unwrap();
    assert_eq!(out.settings.height_range_m, 1.0);
    assert!(relief_heightfield_io::read(&out.files[0]).unwrap().samples().iter().all(|&v| v == 7.0));
}

#[test]
fn geographic_grids_are_measured_in_metres() {
    // One degree square on the equator: about 111.3 km east–west, 110.6 km north–south.
    let grid = GridSpec::geographic(121, 121, DVec2::new(10.0, -0.5), DVec2::splat(1.0 / 120.0)).unwrap();
    let dem = Heightfield::from_fn(grid, |p| (p.x * 10.0) as f32).unwrap();
    let p = prepare(&dem, Engine::Unity, &options()).unwrap();
    let [x, y] = p.settings.world_size_m;
    assert!((x - 111_320.0).abs() < 200.0 && (y - 110_574.0).abs() < 200.0, "{x} × {y}");
}
