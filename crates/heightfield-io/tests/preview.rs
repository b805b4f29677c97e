//! Shaded-relief previews: lighting direction, orientation, no-data, downsampling.

mod common;

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};
use relief_heightfield_io::{NO_DATA_RGB, RgbImage, ShadeOptions, shaded_relief};

/// A cone 100 m high and 1 km in radius on a 10 m grid, centred in a 201² field.
fn cone() -> Heightfield {
    let grid = GridSpec::new(201, 201, DVec2::ZERO, DVec2::splat(10.0)).unwrap();
    Heightfield::from_fn(grid, |p| (100.0 - 0.1 * (p - DVec2::splat(1000.0)).length()).max(0.0) as f32).unwrap()
}

fn luminance(img: &RgbImage, x: usize, y: usize) -> u32 {
    img.pixel(x, y).iter().map(|&c| u32::from(c)).sum()
}

#[test]
fn default_light_from_the_north_west_brightens_north_west_slopes() {
    let img = shaded_relief(&cone(), &ShadeOptions::default().with_hypsometric(false));
    assert_eq!((img.width, img.height, img.pixels.len()), (201, 201, 3 * 201 * 201));
    // Image row 0 is north: (50, 50) is north-west of the peak at (100, 100), (150, 150) south-east.
    let (nw, se, ne) = (luminance(&img, 50, 50), luminance(&img, 150, 150), luminance(&img, 150, 50));
    assert!(nw > ne && ne > se, "nw {nw}, ne {ne}, se {se}");
    // Slope facing the light: cos(45° − atan 0.1) · 255; flat ground: sin 45° · 255.
    let facing = (45f64.to_radians() - 0.1f64.atan()).cos() * 255.0;
    assert!((f64::from(img.pixel(50, 50)[0]) - facing).abs() <= 1.0, "{:?} vs {facing}", img.pixel(50, 50));
    assert_eq!(img.pixel(0, 0)[0], (45f64.to_radians().sin() * 255.0).round() as u8);
    // Gray without the tint.
    assert!(img.pixels.chunks_exact(3).all(|c| c[0] == c[1] && c[1] == c[2]));
}

#[test]
fn light_from_the_south_east_reverses_the_shading() {
    let img = shaded_relief(&cone(), &ShadeOptions::default().with_azimuth_deg(135.0).with_hypsometric(false));
    assert!(luminance(&img, 150, 150) > luminance(&img, 50, 50));
}

#[test]
fn rows_are_north_up_and_no_data_has_its_own_colour() {
    let mut hf = cone();
    // Blank the northern edge (j = ny − 1) and one sample in the south-west.
    for i in 0..hf.nx() {
        hf.set(i, 200, f32::NAN).unwrap();
    }
    hf.set(3, 5, f32::NAN).unwrap();
    let img = shaded_relief(&hf, &ShadeOptions::default());
    assert!((0..201).all(|x| img.pixel(x, 0) == NO_DATA_RGB), "top row is north");
    assert_eq!(img.pixel(3, 200 - 5), NO_DATA_RGB);
    assert_ne!(img.pixel(3, 200), NO_DATA_RGB, "bottom row is south");
    // The tint runs from green lowlands to a white peak.
    let (low, peak) = (img.pixel(5, 100), img.pixel(100, 100));
    assert!(low[1] > low[0] && low[1] > low[2], "{low:?}");
    assert!(peak.iter().all(|&c| c > 150), "{peak:?}");
}

#[test]
fn z_factor_exaggerates_contrast() {
    let flat = ShadeOptions::default().with_hypsometric(false);
    let (a, b) = (shaded_relief(&cone(), &flat), shaded_relief(&cone(), &flat.with_z_factor(5.0)));
    let contrast = |img: &RgbImage| luminance(img, 50, 50).abs_diff(luminance(img, 150, 150));
    assert!(contrast(&b) > contrast(&a));
}

#[test]
fn geographic_grids_shade_with_ground_distances() {
    // The same cone on a 1″ grid (~31 m north-south, ~25 m east-west at 36°N) vs metres:
    // gradients come out in metres per metre, so the shading is gentle, not vertical cliffs.
    let g = GridSpec::geographic(201, 201, DVec2::new(-85.0, 36.0), DVec2::splat(1.0 / 3600.0)).unwrap();
    let hf = Heightfield::from_fn_indexed(g, |i, j| {
        let d = ((i as f64 - 100.0).powi(2) + (j as f64 - 100.0).powi(2)).sqrt();
        (100.0 - d).max(0.0) as f32
    })
    .unwrap();
    let img = shaded_relief(&hf, &ShadeOptions::default().with_hypsometric(false));
    // 1 m per ~25–31 m: a slope of ~2°, so shading stays within a few percent of flat ground.
    let flat = f64::from(img.pixel(0, 0)[0]);
    for (x, y) in [(50, 50), (150, 150)] {
        let v = f64::from(img.pixel(x, y)[0]);
        assert!((v - flat).abs() < 0.1 * flat, "({x}, {y}): {v} vs flat {flat}");
        assert!((v - flat).abs() > 0.0);
    }
}

#[test]
fn max_size_decimates_large_fields() {
    let img = shaded_relief(&cone(), &ShadeOptions::default().with_max_size(50));
    // Stride ⌈201 / 50⌉ = 5 → ⌈201 / 5⌉ = 41 pixels.
    assert_eq!((img.width, img.height), (41, 41));
    assert_eq!(img.pixels.len(), 3 * 41 * 41);
}

#[cfg(feature = "png")]
#[test]
fn preview_png_is_written_atomically_and_is_not_a_heightmap() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cone-preview.png");
    relief_heightfield_io::write_preview_png(&path, &cone(), &ShadeOptions::default()).unwrap();
    assert_eq!(common::dir_entries(dir.path()), vec!["cone-preview.png".to_owned()]);
    // An RGB PNG is refused as a heightmap.
    let err = relief_heightfield_io::read(&path).unwrap_err();
    assert!(matches!(err.kind(), relief_heightfield_io::IoErrorKind::Unsupported(_)), "{err}");
}

#[test]
fn cells_below_sea_level_are_water_and_no_data_is_grey() {
    use relief_heightfield::{GridSpec, Heightfield};
    use relief_heightfield_io::{NO_DATA_RGB, ShadeOptions, shaded_relief};
    // West half under water (−50 m), east half land (+50 m), one no-data sample.
    let grid = GridSpec::new(8, 4, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap();
    let mut hf = Heightfield::from_fn_indexed(grid, |i, _| if i < 4 { -50.0 } else { 50.0 }).unwrap();
    hf.set(7, 3, f32::NAN).unwrap();
    let img = shaded_relief(&hf, &ShadeOptions::default());
    let px = |x: usize, y: usize| &img.pixels[3 * (y * img.width + x)..3 * (y * img.width + x) + 3];
    let (west, east) = (px(1, 2), px(6, 2));
    assert!(west[2] > west[0] && west[2] > west[1], "water should be blue: {west:?}");
    assert!(east[1] >= east[2], "land should not be blue: {east:?}");
    assert_eq!(px(7, 0), &NO_DATA_RGB[..], "no-data (north-east corner, drawn north-up)");
    let no_sea = shaded_relief(&hf, &ShadeOptions::default().with_sea_level(None));
    let w = &no_sea.pixels[3 * (2 * img.width + 1)..3 * (2 * img.width + 1) + 3];
    assert!(w[2] <= w[1], "without a sea level the lowlands are tinted as land: {w:?}");
}

#[cfg(feature = "png")]
#[test]
fn gray_images_read_any_png_colour_type_as_luma() {
    use relief_heightfield_io::{ReadOptions, read_gray_image};
    let dir = tempfile::tempdir().unwrap();
    // A 3 × 2 RGBA image, north row first: red, green, transparent / white, black, blue.
    let rgba: [u8; 24] = [255, 0, 0, 255, 0, 255, 0, 255, 9, 9, 9, 0, 255, 255, 255, 255, 0, 0, 0, 255, 0, 0, 255, 255];
    let path = dir.path().join("mask.png");
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, 3, 2);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().unwrap();
        w.write_image_data(&rgba).unwrap();
    }
    std::fs::write(&path, &bytes).unwrap();
    // RGB is rejected as a heightmap…
    assert!(relief_heightfield_io::read(&path).is_err());
    // …but reads as luma for masks, south row first.
    let img = read_gray_image(&path, &ReadOptions::default()).unwrap();
    assert_eq!((img.nx(), img.ny()), (3, 2));
    let close = |a: Option<f32>, b: f32| a.is_some_and(|a| (a - b).abs() < 1e-6);
    assert!(close(img.get(0, 1), 0.299), "red");
    assert!(close(img.get(1, 1), 0.587), "green");
    assert!(img.is_no_data(2, 1), "transparent");
    assert!(close(img.get(0, 0), 1.0) && close(img.get(1, 0), 0.0) && close(img.get(2, 0), 0.114));
    // 16-bit gray + alpha keeps its precision.
    let path16 = dir.path().join("ga16.png");
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, 1, 1);
        enc.set_color(png::ColorType::GrayscaleAlpha);
        enc.set_depth(png::BitDepth::Sixteen);
        let mut w = enc.write_header().unwrap();
        w.write_image_data(&[0x80, 0x00, 0xff, 0xff]).unwrap();
    }
    std::fs::write(&path16, &bytes).unwrap();
    let g = read_gray_image(&path16, &ReadOptions::default()).unwrap();
    assert!(close(g.get(0, 0), 32768.0 / 65535.0));
}

#[cfg(feature = "png")]
#[test]
fn rgb_images_write_atomically_and_reject_wrong_sizes() {
    use relief_heightfield_io::{RgbImage, write_rgb_png};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("overlay.png");
    let image = RgbImage { width: 2, height: 1, pixels: vec![1, 2, 3, 4, 5, 6] };
    write_rgb_png(&path, &image).unwrap();
    assert!(std::fs::read(&path).unwrap().starts_with(b"\x89PNG"));
    let bad = RgbImage { width: 2, height: 2, pixels: vec![0; 5] };
    assert!(write_rgb_png(dir.path().join("bad.png"), &bad).is_err());
    assert!(!dir.path().join("bad.png").exists());
}
