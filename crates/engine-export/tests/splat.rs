//! Splat maps read back as an engine's terrain texturing reads them: one image per heightmap at
//! its size, weights that sum to 255, rock on the steep walls, water down the valley, ground on
//! gentle slopes, and tiles that meet without a seam.

use glam::DVec2;
use relief_engine_export::{Engine, ExportOptions, SplatOptions, export, masks};
use relief_heightfield::{GridSpec, Heightfield};

/// A valley 2 km long draining south along x = 500 m: a gentle western wall (11°), a steep
/// eastern one (56°), and a snowy plateau in the north-west corner.
fn valley() -> Heightfield {
    let grid = GridSpec::new(201, 201, DVec2::ZERO, DVec2::splat(5.0)).unwrap();
    Heightfield::from_fn(grid, |p| {
        let wall = if p.x < 500.0 { 0.2 * (500.0 - p.x) } else { 1.5 * (p.x - 500.0) };
        let plateau = if p.x < 150.0 && p.y > 850.0 { 700.0 } else { 0.0 };
        (200.0 + 0.05 * p.y + wall + plateau) as f32
    })
    .unwrap()
}

fn rgba(path: &std::path::Path) -> image::RgbaImage {
    image::open(path).unwrap().into_rgba8()
}

#[test]
fn layers_land_where_the_terrain_says() {
    let dem = valley();
    let m = masks(&dem, &SplatOptions::default()).unwrap();
    let w = m.splat();
    let at = |x: f64, y: f64| w[(y / 5.0) as usize * 201 + (x / 5.0) as usize];
    assert_eq!(at(800.0, 500.0), [0, 255, 0, 0], "the 56° wall is rock");
    // The gentle wall is ground; D8's parallel sheet flow down it stays far below a channel.
    let gentle = at(250.0, 500.0);
    assert!(gentle[0] > 240 && gentle[1] == 0 && gentle[2] == 0, "the 11° wall is ground: {gentle:?}");
    assert!(at(50.0, 950.0)[2] > 200, "the plateau is snow: {:?}", at(50.0, 950.0));
    // Down the valley the channel gathers water: the axis near the outlet is water.
    assert!(at(500.0, 40.0)[3] > 200, "{:?}", at(500.0, 40.0));
    assert_eq!(at(30.0, 500.0)[3], 0, "no water near the western divide");
    // Convexity: the valley floor is concave, the plateau's rim convex, the cliff's foot concave,
    // a planar wall neither.
    let k = |x: f64, y: f64| m.convexity[(y / 5.0) as usize * 201 + (x / 5.0) as usize];
    assert!(k(500.0, 500.0) < 0.2, "valley floor {}", k(500.0, 500.0));
    assert!(k(145.0, 950.0) > 0.95 && k(150.0, 950.0) < 0.05, "rim {} foot {}", k(145.0, 950.0), k(150.0, 950.0));
    assert_eq!(k(300.0, 500.0), 0.5);
    assert!(w.iter().all(|p| p.iter().map(|&v| u16::from(v)).sum::<u16>() == 255));
}

#[test]
fn splat_maps_sit_beside_each_tile_and_meet_without_seams() {
    let dem = valley();
    let dir = tempfile::tempdir().unwrap();
    let options = ExportOptions { tile: Some(129), splat: Some(SplatOptions::default()), ..ExportOptions::default() };
    let out = export(&dem, Engine::Godot, &options, dir.path()).unwrap();
    assert_eq!(out.settings.tiles, [2, 2]);
    assert_eq!(out.splat_files.len(), 4);
    let images: Vec<image::RgbaImage> = out.splat_files.iter().map(|f| rgba(&f[0])).collect();
    assert!(images.iter().all(|i| i.dimensions() == (129, 129)), "the heightmap's size");
    // Tile (0, 0) is the north-west, (1, 0) north-east: the first's east column is the second's west.
    for y in 0..129 {
        assert_eq!(images[0].get_pixel(128, y), images[1].get_pixel(0, y), "row {y}");
        // Tile (0, 1) is south of (0, 0): its top row is the other's bottom row.
        assert_eq!(images[0].get_pixel(y, 128), images[2].get_pixel(y, 0), "column {y}");
    }
    let masks = rgba(&out.splat_files[0][1]);
    assert!(masks.pixels().any(|p| p[2] > 200) && masks.pixels().any(|p| p[2] < 50), "convexity spans the range");
    let sidecar: serde_json::Value = serde_json::from_slice(&std::fs::read(&out.sidecar).unwrap()).unwrap();
    assert_eq!(sidecar["splat_layers"], serde_json::json!(["ground", "rock", "snow", "water"]));
    // The tile suffix stays last, where tiled imports look for it.
    assert_eq!(sidecar["tiles"][0]["splat"], serde_json::json!(["heightmap_splat_0_0.png", "heightmap_masks_0_0.png"]));
}

#[test]
fn unreal_gets_one_grayscale_weight_map_per_layer() {
    let dem = valley();
    let dir = tempfile::tempdir().unwrap();
    let options = ExportOptions { splat: Some(SplatOptions::default()), ..ExportOptions::default() };
    let out = export(&dem, Engine::Unreal, &options, dir.path()).unwrap();
    let names: Vec<String> =
        out.splat_files[0].iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(
        names,
        [
            "heightmap_ground.png",
            "heightmap_rock.png",
            "heightmap_snow.png",
            "heightmap_water.png",
            "heightmap_masks.png"
        ]
    );
    // Tiled, each layer's maps carry World Partition's suffix at the end.
    let tiled = ExportOptions { tile: Some(127), ..options.clone() };
    let names = relief_engine_export::prepare(&dem, Engine::Unreal, &tiled).unwrap().splat_names("heightmap", 1);
    assert_eq!(names[1], "heightmap_rock_x1_y0.png");
    assert_eq!(names[4], "heightmap_masks_x1_y0.png");
    let layers: Vec<image::GrayImage> =
        out.splat_files[0][..4].iter().map(|f| image::open(f).unwrap().into_luma8()).collect();
    assert!(layers.iter().all(|l| l.dimensions() == (253, 253)));
    for (x, y) in [(0, 0), (126, 126), (252, 7), (200, 100)] {
        let sum: u32 = layers.iter().map(|l| u32::from(l.get_pixel(x, y)[0])).sum();
        assert_eq!(sum, 255);
    }
    // North row first: the plateau (north-west) is snow in the image's top-left corner.
    assert!(layers[2].get_pixel(5, 5)[0] > 200);
    assert_eq!(layers[2].get_pixel(5, 247)[0], 0);
}

#[test]
fn bad_splat_options_are_refused() {
    let bad = ExportOptions {
        splat: Some(SplatOptions { snow_height: [0.9, f64::NAN], ..SplatOptions::default() }),
        ..ExportOptions::default()
    };
    let e = relief_engine_export::prepare(&valley(), Engine::Unity, &bad).unwrap_err();
    assert!(e.to_string().contains("snow_height"), "{e}");
}
