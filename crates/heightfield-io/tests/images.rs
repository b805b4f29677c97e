//! Images as users make them (fixtures/images): JPEG, BMP, WebP, palette and RGB PNGs, RGB and
//! multi-band TIFFs read as heightmaps (gray or a named channel), masks (luma) and bands.
#![cfg(feature = "images")]

mod common;

use relief_heightfield_io::{
    Channel, Format, IoErrorKind, ReadOptions, WriteOptions, read, read_gray_image, read_with, write_bytes, write_with,
};

fn image(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/images").join(name)
}

/// The 8-bit codes of the DEM window the gray fixtures hold, north row first, as read from the
/// lossless GDAL-written BMP's source: `round((h − 236) · 255 / 840)`.
fn window_codes() -> Vec<f32> {
    let dem = read(common::fixture("jacksboro.asc")).unwrap();
    let mut v = Vec::new();
    for j in (dem.ny() - 140..dem.ny() - 100).rev() {
        v.extend(dem.row(j)[100..160].iter().map(|h| ((h - 236.0) * 255.0 / 840.0).round()));
    }
    v
}

fn codes(hf: &relief_heightfield::Heightfield) -> Vec<f32> {
    let mut v = Vec::new();
    for j in (0..hf.ny()).rev() {
        v.extend(hf.row(j).iter().map(|x| (x * 255.0).round()));
    }
    v
}

#[test]
fn lossless_images_give_the_codes_gdal_wrote() {
    let expected = window_codes();
    for file in ["gray.bmp", "gray.webp", "rgb-equal.png", "rgb-equal.tif"] {
        let hf = read(image(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!((hf.nx(), hf.ny()), (60, 40), "{file}");
        assert_eq!(codes(&hf), expected, "{file}");
    }
    // JPEG is lossy even at quality 100: within a few codes.
    let jpeg = codes(&read(image("gray.jpg")).unwrap());
    let worst = jpeg.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
    assert!(worst <= 3.0, "JPEG differs by {worst} codes");
}

#[test]
fn detection_is_by_content_and_images_are_read_only() {
    let bytes = std::fs::read(image("gray.bmp")).unwrap();
    assert_eq!(Format::detect(std::path::Path::new("x.r16"), &bytes), Some(Format::Image));
    // Two bytes "BM" alone do not make a BMP: a raw heightmap may start with them.
    assert_eq!(Format::detect(std::path::Path::new("x.r16"), b"BM\x00\x00\x00\x00"), Some(Format::R16));
    let mut bmp_start = b"BM".to_vec();
    bmp_start.extend_from_slice(&[0; 12]);
    for (info, image) in [(40u32, true), (124, true), (41, false)] {
        let mut b = bmp_start.clone();
        b.extend_from_slice(&info.to_le_bytes());
        let found = Format::detect(std::path::Path::new("x.r16"), &b);
        assert_eq!(found == Some(Format::Image), image, "BMP info header of {info} bytes");
    }
    let riff = |kind: &[u8]| [b"RIFF\0\0\0\0".as_slice(), kind].concat();
    assert_eq!(Format::detect(std::path::Path::new("x.r16"), &riff(b"WEBP")), Some(Format::Image));
    assert_eq!(
        Format::detect(std::path::Path::new("x.r16"), &riff(b"WAVE")),
        Some(Format::R16),
        "a RIFF that is not WebP"
    );
    assert_eq!(Format::detect(std::path::Path::new("x.r16"), &[0xff, 0xd8, 0xff, 0xe0]), Some(Format::Image));
    let hf = common::small_field(4, 3);
    assert!(matches!(write_bytes(&hf, Format::Image).unwrap_err().kind(), IoErrorKind::Unsupported(_)));
    let dir = tempfile::tempdir().unwrap();
    let err = write_with(dir.path().join("x.jpg"), &hf, &WriteOptions::default()).unwrap_err();
    assert!(matches!(err.kind(), IoErrorKind::Unsupported(_)), "{err}");
}

#[test]
fn colour_heightmaps_need_equal_channels_or_a_named_channel() {
    let err = read(image("rgb-colour.png")).unwrap_err();
    let message = err.to_string();
    assert!(message.contains("(0, 0)") && message.contains("--channel"), "{message}");
    let red = read_with(image("rgb-colour.png"), &ReadOptions::default().with_channel(Channel::Red)).unwrap();
    // Red is 10·x + y, north row first.
    assert_eq!(red.value(3, 2), 30.0 / 255.0);
    assert_eq!(red.value(1, 0), 12.0 / 255.0);
    let blue = read_with(image("rgb-colour.png"), &ReadOptions::default().with_channel(Channel::Blue)).unwrap();
    assert_eq!(blue.min_max(), Some((200.0 / 255.0, 200.0 / 255.0)));
    let scaled =
        read_with(image("rgb-colour.png"), &ReadOptions::default().with_channel(Channel::Red).with_z_range(0.0, 255.0))
            .unwrap();
    assert!((scaled.value(3, 2) - 30.0).abs() < 1e-4, "--z-range applies to colour images too");
    let palette = read(image("palette-gray.png")).unwrap();
    assert_eq!((palette.value(0, 2), palette.value(1, 2), palette.value(2, 2)), (0.0, 128.0 / 255.0, 1.0));
}

#[test]
fn masks_read_colour_as_luma() {
    let mask = read_gray_image(image("rgb-colour.png"), &ReadOptions::default()).unwrap();
    let (r, g, b) = (30.0 / 255.0, 7.0 / 255.0, 200.0 / 255.0);
    assert!((mask.value(3, 2) - (0.299 * r + 0.587 * g + 0.114 * b)).abs() < 1e-6);
    for file in ["gray.jpg", "gray.bmp", "gray.webp", "rgb-equal.tif"] {
        let m = read_gray_image(image(file), &ReadOptions::default()).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!((m.nx(), m.ny()), (60, 40), "{file}");
    }
}

#[test]
fn multi_band_tiffs_take_a_band() {
    let err = read(image("three-band.tif")).unwrap_err();
    assert!(err.to_string().contains("--band"), "{err}");
    let dem = read(common::fixture("jacksboro.asc")).unwrap();
    for band in 1..=3 {
        let hf = read_with(image("three-band.tif"), &ReadOptions::default().with_band(band)).unwrap();
        assert_eq!(hf.value(0, 39), dem.value(100, dem.ny() - 101), "band {band}");
        assert_eq!(hf.crs().and_then(relief_heightfield::Crs::epsg), Some(4326));
    }
    for band in [0, 4] {
        let err = read_with(image("three-band.tif"), &ReadOptions::default().with_band(band)).unwrap_err();
        assert!(matches!(err.kind(), IoErrorKind::InvalidMetadata(_)), "band {band}: {err}");
    }
}

/// A 3 × 2 RGBA PNG: gray but for pixel (2, 0) = RGB (90, 90, 91) (red equals green, not blue)
/// and (2, 1) = RGB (10, 20, 30), with pixel (1, 0) coloured but fully transparent.
fn rgba_png() -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, 3, 2);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().unwrap();
    #[rustfmt::skip]
    let pixels = [
        50, 50, 50, 255,   5, 6, 7, 0,      90, 90, 91, 255,
        0, 0, 0, 255,      255, 255, 255, 255, 10, 20, 30, 255,
    ];
    writer.write_image_data(&pixels).unwrap();
    drop(writer);
    out
}

#[test]
fn the_first_colour_pixel_is_named_and_channels_pick_values() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgba.png");
    std::fs::write(&path, rgba_png()).unwrap();
    let err = read(&path).unwrap_err().to_string();
    assert!(err.contains("pixel (2, 0)") && err.contains("RGB (90, 90, 91)"), "{err}");
    let with = |c: Channel| read_with(&path, &ReadOptions::default().with_channel(c)).unwrap();
    // Row j = 0 is the south (second) image row.
    let luma = with(Channel::Luma);
    let expected = (0.299 * 10.0 + 0.587 * 20.0 + 0.114 * 30.0) / 255.0;
    assert!((luma.value(2, 0) - expected).abs() < 1e-6, "{}", luma.value(2, 0));
    assert!(luma.is_no_data(1, 1), "a transparent pixel is no-data");
    assert_eq!(with(Channel::Green).value(2, 0), 20.0 / 255.0);
    let alpha = with(Channel::Alpha);
    assert_eq!((alpha.value(1, 1), alpha.value(0, 1)), (0.0, 1.0), "alpha as the value keeps transparent pixels");
    let mask = read_gray_image(&path, &ReadOptions::default().with_channel(Channel::Red)).unwrap();
    assert_eq!(mask.value(2, 0), 10.0 / 255.0);
    for (name, channel) in [
        ("red", Channel::Red),
        ("G", Channel::Green),
        ("b", Channel::Blue),
        ("alpha", Channel::Alpha),
        ("luma", Channel::Luma),
    ] {
        assert_eq!(name.parse::<Channel>(), Ok(channel), "{name}");
    }
    assert!("cyan".parse::<Channel>().is_err());
}
