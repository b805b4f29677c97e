//! Images of any kind the `image` crate decodes (JPEG, BMP, WebP, colour PNG and TIFF) read as
//! one gray value per pixel: heightmaps insist on gray (equal channels) unless a [`Channel`] is
//! named; masks and probability maps take the luma of colour pixels.
//!
//! Grayscale PNG and single-band TIFF keep their own readers (16-bit codes, metadata, geo tags);
//! this path is for what those refuse.

use std::io::Cursor;

use image::ImageReader;
use relief_heightfield::{GridSpec, Heightfield};

use crate::meta::{flip_rows, plain_grid};
use crate::{IoErrorKind, Limits};

/// Which value of a colour pixel a gray reading takes ([`crate::ReadOptions::channel`]). In JSON:
/// `"red"`, `"green"`, `"blue"`, `"alpha"` or `"luma"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[non_exhaustive]
pub enum Channel {
    /// The red channel.
    Red,
    /// The green channel.
    Green,
    /// The blue channel.
    Blue,
    /// The alpha channel (opacity; fully transparent pixels are then not no-data).
    Alpha,
    /// ITU-R BT.601 luma `0.299 R + 0.587 G + 0.114 B`.
    Luma,
}

impl std::str::FromStr for Channel {
    type Err = String;

    /// `red`, `green`, `blue`, `alpha`, `luma` (or `r`, `g`, `b`, `a`, `l`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "r" | "red" => Ok(Channel::Red),
            "g" | "green" => Ok(Channel::Green),
            "b" | "blue" => Ok(Channel::Blue),
            "a" | "alpha" => Ok(Channel::Alpha),
            "l" | "luma" | "gray" | "grey" => Ok(Channel::Luma),
            _ => Err(format!("unknown channel {s:?}: use red, green, blue, alpha or luma")),
        }
    }
}

/// How colour pixels become one value.
#[derive(Clone, Copy)]
pub(crate) enum Gray {
    /// A heightmap: every opaque pixel's R, G and B must be equal, unless a channel is named.
    Strict(Option<Channel>),
    /// A mask or probability map: the named channel, else luma.
    Lenient(Option<Channel>),
}

/// An image decoded to RGBA in [0, 1], north row first.
pub(crate) struct Pixels {
    width: usize,
    height: usize,
    rgba: Vec<[f32; 4]>,
}

/// Decodes any image the `image` crate knows (format from the bytes), within `limits`.
pub(crate) fn decode(bytes: &[u8], limits: Limits) -> Result<Pixels, IoErrorKind> {
    let reader = || ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| decode_error(&e.into()));
    let (w, h) = reader()?.into_dimensions().map_err(|e| decode_error(&e))?;
    limits.check(u64::from(w), u64::from(h))?;
    let mut image_limits = image::Limits::default();
    // The decoder's buffer (up to 16 bytes a pixel for float RGBA) plus our RGBA copy.
    image_limits.max_alloc = Some(limits.byte_budget(32, 16 << 20) as u64);
    let mut reader = reader()?;
    reader.limits(image_limits);
    let image = reader.decode().map_err(|e| decode_error(&e))?;
    let rgba = image.to_rgba32f().pixels().map(|p| p.0).collect();
    Ok(Pixels { width: w as usize, height: h as usize, rgba })
}

fn decode_error(e: &image::ImageError) -> IoErrorKind {
    match e {
        image::ImageError::Limits(_) => {
            IoErrorKind::Decode(format!("{e} (raise Limits::max_cells if the image is meant to be this large)"))
        }
        image::ImageError::Unsupported(u) => IoErrorKind::Unsupported(u.to_string()),
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            IoErrorKind::Truncated { expected_bytes: None, found_bytes: 0 }
        }
        other => IoErrorKind::Decode(other.to_string()),
    }
}

impl Pixels {
    /// One value per pixel in [0, 1] on a plain grid (origin 0, cell 1, south row first); fully
    /// transparent pixels are no-data unless the alpha channel is the value.
    pub(crate) fn to_heightfield(&self, gray: Gray) -> Result<Heightfield, IoErrorKind> {
        let channel = match gray {
            Gray::Strict(c) | Gray::Lenient(c) => c,
        };
        let mut values = Vec::with_capacity(self.rgba.len());
        for (k, &[r, g, b, a]) in self.rgba.iter().enumerate() {
            let value = match (channel, gray) {
                (Some(Channel::Red), _) => r,
                (Some(Channel::Green), _) => g,
                (Some(Channel::Blue), _) => b,
                (Some(Channel::Alpha), _) => a,
                (Some(Channel::Luma), _) | (None, Gray::Lenient(_)) => luma(r, g, b),
                (None, Gray::Strict(_)) if (r == g && g == b) || a == 0.0 => r,
                (None, Gray::Strict(_)) => {
                    let (x, y) = (k % self.width, k / self.width);
                    let code = |v: f32| (v * 255.0).round() as u8;
                    return Err(IoErrorKind::Unsupported(format!(
                        "colour image: pixel ({x}, {y}) from the top left is RGB ({}, {}, {}); a heightmap must be \
                         gray (equal channels). Name the channel that holds the heights (--channel red|green|blue|luma)",
                        code(r),
                        code(g),
                        code(b)
                    )));
                }
            };
            values.push(if a == 0.0 && channel != Some(Channel::Alpha) { f32::NAN } else { value });
        }
        flip_rows(&mut values, self.width);
        Heightfield::from_samples(plain_grid(self.width, self.height)?, values).map_err(IoErrorKind::InvalidData)
    }
    /// The RGBA pixels south row first, on a plain grid.
    pub(crate) fn into_south_up(self) -> Result<(GridSpec, Vec<[f32; 4]>), IoErrorKind> {
        let grid = plain_grid(self.width, self.height)?;
        let mut rgba = self.rgba;
        flip_rows(&mut rgba, self.width);
        Ok((grid, rgba))
    }
}

/// ITU-R BT.601 luma.
fn luma(r: f32, g: f32, b: f32) -> f32 {
    0.299 * r + 0.587 * g + 0.114 * b
}
