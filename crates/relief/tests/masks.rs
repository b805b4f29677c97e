//! Label images as paint programs save them, through scenes: 16-bit gray with an anti-aliased
//! alpha edge, colour regions with a `levels` table of heights and a crater, the contours paper
//! authors' own masks.

use std::path::Path;

use glam::DVec2;
use image::{ImageBuffer, LumaA, Rgba};
use relief::pipeline::generate;
use relief::scene::{Generator, Scene};
use serde_json::json;

const N: u32 = 256;

/// Distance of pixel `(x, y)` (top row first) from the image centre, in pixels.
fn radius(x: u32, y: u32) -> f64 {
    DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5).distance(DVec2::splat(f64::from(N) / 2.0))
}

#[allow(clippy::needless_pass_by_value, reason = "called with json! literals")]
fn scene(label_image: serde_json::Value) -> Scene {
    let value = json!({
        "version": 1,
        "seed": 4,
        "generator": { "contours": { "label_image": label_image, "particles": 3000 } },
        "reconstruction": { "resolution": [128, 128] }
    });
    Scene::from_json(&value.to_string()).unwrap()
}

fn extent() -> serde_json::Value {
    json!({ "min": [0, 0], "max": [2550, 2550] })
}

/// A 16-bit gray+alpha island whose coast fades out in alpha over two pixels and whose range is
/// one 16-bit step of 8-bit gray away from a speck colour; a single speck pixel and a small clump.
fn write_gray_alpha(path: &Path) {
    let img = ImageBuffer::from_fn(N, N, |x, y| {
        let r = radius(x, y);
        let alpha = ((100.0 - r) / 2.0 + 0.5).clamp(0.0, 1.0);
        let gray: u16 = if r < 40.0 { 0xC000 } else { 0x6000 };
        let gray = if (x, y) == (60, 128) { 0x1234 } else { gray };
        let gray = if (150..154).contains(&x) && (120..123).contains(&y) { 0x9000 } else { gray };
        LumaA([gray, (alpha * 65535.0).round() as u16])
    });
    img.save(path).unwrap();
}

#[test]
fn a_sixteen_bit_gray_alpha_mask_with_specks_generates() {
    let dir = tempfile::tempdir().unwrap();
    write_gray_alpha(&dir.path().join("mask.png"));
    let mut scene = scene(json!({ "path": "mask.png", "extent": extent() }));
    if let Generator::Contours(c) = &mut scene.generator {
        c.histogram = Some(serde_json::from_value(json!({ "uniform": { "min": 0, "max": 900 } })).unwrap());
    }
    let terrain = generate(&scene, dir.path(), &mut ()).unwrap();
    let mask = terrain.summary.label_image.as_ref().unwrap();
    assert_eq!(mask.levels, ["transparent", "#606060", "#bfbfbf"], "transparency outside, two grays");
    assert_eq!(mask.merged_count, 1, "{mask:?}");
    assert_eq!((mask.merged[0].pixels, mask.merged[0].color.as_str()), (12, "#8f8f8f"), "0x9000 of 65535");
    assert!(mask.snapped_pixels >= 1);
    assert!(
        terrain.summary.warnings.iter().any(|w| w.contains("merged into the level around it")),
        "{:?}",
        terrain.summary.warnings
    );
    assert_eq!(terrain.summary.graph.as_ref().unwrap().levels, 2);
}

#[test]
fn a_colour_table_gives_heights_and_a_crater() {
    let dir = tempfile::tempdir().unwrap();
    // Sea blue, a sand-coloured island, a red range with a black crater, anti-aliased edges.
    let (sea, sand, red, crater) = ([20u8, 60, 200], [230u8, 210, 150], [200u8, 30, 30], [10u8, 10, 10]);
    let blend = |a: [u8; 3], b: [u8; 3], t: f64| {
        let mix = |k: usize| (f64::from(a[k]) * (1.0 - t) + f64::from(b[k]) * t).round() as u8;
        Rgba([mix(0), mix(1), mix(2), 255])
    };
    let img = ImageBuffer::from_fn(N, N, |x, y| {
        let r = radius(x, y);
        let edge = |rim: f64| (rim + 0.5 - r).clamp(0.0, 1.0);
        match r {
            r if r < 20.0 => blend(red, crater, edge(16.0)),
            r if r < 60.0 => blend(sand, red, edge(50.0)),
            _ => blend(sea, sand, edge(100.0)),
        }
    });
    img.save(dir.path().join("colours.png")).unwrap();
    let levels = json!([
        { "value": "#143cc8" },
        { "value": "#e6d296", "height": 0 },
        { "value": "#c81e1e", "height": 400 },
        { "value": "#0a0a0a", "depression": true }
    ]);
    let terrain =
        generate(&scene(json!({ "path": "colours.png", "extent": extent(), "levels": levels })), dir.path(), &mut ())
            .unwrap();
    let mask = terrain.summary.label_image.as_ref().unwrap();
    assert_eq!(mask.levels, ["#143cc8", "#e6d296", "#c81e1e"]);
    assert!(mask.snapped_pixels > 100, "{}", mask.snapped_pixels);
    let hf = &terrain.heightfield;
    let at = |d: f64| f64::from(hf.sample_bilinear_clamped(DVec2::new(1275.0 + d, 1275.0)).unwrap());
    let (centre, range, coast, sea_pt) = (at(0.0), at(300.0), at(700.0), at(1200.0));
    assert!(range > 400.0, "the range lies above its 400 m contour: {range}");
    assert!(coast > 0.0 && coast < 400.0, "{coast}");
    assert!(sea_pt < 0.0, "{sea_pt}");
    assert!(centre < 400.0, "the crater floor sinks below its rim's 400 m contour: {centre}");
    // The histogram comes from the heights: no histogram given, none needed.
    let ks = terrain.summary.histogram_match.as_ref().unwrap().nodes;
    assert!(ks < 0.01, "{ks}");

    // A colour the table lacks is refused at the table, naming it.
    let short =
        json!([{ "value": "#143cc8" }, { "value": "#e6d296", "height": 0 }, { "value": "#c81e1e", "height": 400 }]);
    let err =
        generate(&scene(json!({ "path": "colours.png", "extent": extent(), "levels": short })), dir.path(), &mut ())
            .unwrap_err();
    let message = err.to_string();
    assert!(message.starts_with("generator.contours.label_image.levels") && message.contains("#0a0a0a"), "{message}");
    // So is a value that is not a colour.
    let bad = json!([{ "value": "#12345" }, { "value": 0.5 }]);
    let err =
        generate(&scene(json!({ "path": "colours.png", "extent": extent(), "levels": bad })), dir.path(), &mut ())
            .unwrap_err();
    assert!(err.to_string().starts_with("generator.contours.label_image.levels[0].value"), "{err}");
}

/// The contours paper authors' own label masks (`fixtures/scenes/inputs/`, from their repository):
/// palette PNGs, RGB and RGBA, 1024² to 2048². Each must give its nested levels at the default
/// 50 000 particles — and a sketch of strokes must be refused as having no region.
#[test]
fn the_authors_masks_give_their_levels() {
    use relief::eden_growth::{Graph, GraphOptions, LabelMap, MaskOptions, Sampling};
    let inputs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/inputs");
    let cases = [
        ("teaser-1.png", 2),
        ("teaser-2-a.png", 3),
        ("teaser-2-b.png", 2),
        ("mask_double.png", 2),
        ("mask_triple.png", 3),
        ("mask_boundaries.png", 3),
        ("multi_mask_2.png", 3),
        ("editing-1.png", 1),
        ("editing-2.png", 2),
        ("mask_lambda.png", 2),
    ];
    for (name, levels) in cases {
        let image = relief::io::read_color_image(inputs.join(name), &relief::io::ReadOptions::default()).unwrap();
        let options = MaskOptions { levels: None, sampling: Sampling::Particles(50_000) };
        let labels = LabelMap::from_mask(image.grid, &image.pixels, &options).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(labels.max_level(), levels, "{name}: {:?}", labels.cleaning());
        Graph::from_labels(&labels, &GraphOptions::particles(50_000).with_seed(1))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    let image =
        relief::io::read_color_image(inputs.join("user_input_10.png"), &relief::io::ReadOptions::default()).unwrap();
    let options = MaskOptions { levels: None, sampling: Sampling::Particles(50_000) };
    let err = LabelMap::from_mask(image.grid, &image.pixels, &options).unwrap_err();
    assert!(err.to_string().contains("thin lines"), "{err}");
}
