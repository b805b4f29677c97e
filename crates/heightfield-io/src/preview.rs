//! Shaded-relief previews: Lambertian hillshade under a sun at (azimuth, altitude), optionally
//! tinted by elevation.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use relief_heightfield::Heightfield;

/// Colour of no-data pixels: a neutral mid gray, apart from every tint.
pub const NO_DATA_RGB: [u8; 3] = [128, 128, 128];

/// How to light and colour a shaded relief.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ShadeOptions {
    /// Direction the light comes from, degrees clockwise from north (default 315: north-west, the
    /// cartographic convention that makes relief read as raised rather than sunken).
    pub azimuth_deg: f64,
    /// Sun height above the horizon in degrees (default 45).
    pub altitude_deg: f64,
    /// Vertical exaggeration applied to the gradients (default 1).
    pub z_factor: f64,
    /// Tint by elevation (green lowlands, ochre hills, white peaks) instead of plain gray (default on).
    pub hypsometric: bool,
    /// Largest image side in pixels; bigger fields are decimated by a whole stride (default `None`:
    /// one pixel per sample).
    pub max_size: Option<usize>,
    /// Elevation of the sea surface (default `Some(0.0)`): with the tint on, lower cells are drawn
    /// as water shaded by depth and the land ramp starts here. `None` tints the whole range as land.
    pub sea_level: Option<f64>,
}

impl Default for ShadeOptions {
    fn default() -> Self {
        Self {
            azimuth_deg: 315.0,
            altitude_deg: 45.0,
            z_factor: 1.0,
            hypsometric: true,
            max_size: None,
            sea_level: Some(0.0),
        }
    }
}

impl ShadeOptions {
    /// The same options with the light from `azimuth_deg` (clockwise from north).
    #[must_use]
    pub fn with_azimuth_deg(mut self, azimuth_deg: f64) -> Self {
        self.azimuth_deg = azimuth_deg;
        self
    }

    /// The same options with the sun `altitude_deg` above the horizon.
    #[must_use]
    pub fn with_altitude_deg(mut self, altitude_deg: f64) -> Self {
        self.altitude_deg = altitude_deg;
        self
    }

    /// The same options with vertical exaggeration `z_factor`.
    #[must_use]
    pub fn with_z_factor(mut self, z_factor: f64) -> Self {
        self.z_factor = z_factor;
        self
    }

    /// The same options with the sea surface at `sea_level` (`None`: no water tint).
    #[must_use]
    pub fn with_sea_level(mut self, sea_level: Option<f64>) -> Self {
        self.sea_level = sea_level;
        self
    }

    /// The same options with the elevation tint on or off.
    #[must_use]
    pub fn with_hypsometric(mut self, hypsometric: bool) -> Self {
        self.hypsometric = hypsometric;
        self
    }

    /// The same options with the image's longer side capped at `max_size` pixels.
    #[must_use]
    pub fn with_max_size(mut self, max_size: usize) -> Self {
        self.max_size = Some(max_size);
        self
    }
}

/// An 8-bit RGB image, rows top (north) to bottom, `pixels.len() == 3 · width · height`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `[r, g, b]` triples, row-major, first row = north.
    pub pixels: Vec<u8>,
}

impl RgbImage {
    /// The colour at column `x`, row `y` (0 = top = north).
    ///
    /// # Panics
    /// If `(x, y)` is outside the image.
    pub fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {}x{}", self.width, self.height);
        let k = 3 * (y * self.width + x);
        [self.pixels[k], self.pixels[k + 1], self.pixels[k + 2]]
    }
}

/// Hypsometric ramp over `t ∈ [0, 1]` (low → high).
/// Water colour for a relative depth `t` in [0, 1] (0 at the surface).
fn water(t: f64) -> [f64; 3] {
    let (shallow, deep) = ([150.0, 200.0, 230.0], [40.0, 80.0, 150.0]);
    let u = t.clamp(0.0, 1.0).sqrt();
    [
        shallow[0] + u * (deep[0] - shallow[0]),
        shallow[1] + u * (deep[1] - shallow[1]),
        shallow[2] + u * (deep[2] - shallow[2]),
    ]
}

/// The hypsometric tint of a shaded relief at fraction `t` of the land's height range (0: lowest,
/// 1: highest; clamped): green lowlands, tan hills, brown heights, white peaks. RGB, 0 … 255.
pub fn hypsometric_tint(t: f64) -> [f64; 3] {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [70.0, 130.0, 80.0]),
        (0.3, [150.0, 180.0, 100.0]),
        (0.6, [205.0, 170.0, 110.0]),
        (0.85, [160.0, 120.0, 90.0]),
        (1.0, [250.0, 250.0, 250.0]),
    ];
    let t = t.clamp(0.0, 1.0);
    let k = STOPS.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(STOPS.len() - 2);
    let ((t0, c0), (t1, c1)) = (STOPS[k], STOPS[k + 1]);
    let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    [c0[0] + u * (c1[0] - c0[0]), c0[1] + u * (c1[1] - c0[1]), c0[2] + u * (c1[2] - c0[2])]
}

/// A north-up shaded relief of `hf`: one pixel per sample (or per `stride` samples when
/// [`ShadeOptions::max_size`] asks for a smaller image).
///
/// Brightness is Lambert's cosine `max(0, n · l)` between the surface normal
/// `n ∝ (−z·∂h/∂x, −z·∂h/∂y, 1)` — gradients from [`Heightfield::gradient`], in metres per metre
/// even on geographic grids — and the unit vector toward the sun
/// `l = (sin A cos a, cos A cos a, sin a)` for azimuth `A` (clockwise from north) and altitude `a`.
/// With the tint on, colour = tint(elevation) · (0.35 + 0.65 · brightness); no-data pixels are
/// [`NO_DATA_RGB`].
pub fn shaded_relief(hf: &Heightfield, options: &ShadeOptions) -> RgbImage {
    let (nx, ny) = (hf.nx(), hf.ny());
    let stride = options.max_size.filter(|&m| m > 0).map_or(1, |m| nx.max(ny).div_ceil(m)).max(1);
    let (width, height) = (nx.div_ceil(stride), ny.div_ceil(stride));
    let (az, alt) = (options.azimuth_deg.to_radians(), options.altitude_deg.to_radians());
    let light = DVec3::new(az.sin() * alt.cos(), az.cos() * alt.cos(), alt.sin());
    let (lo, hi) = hf.min_max().map_or((0.0, 1.0), |(a, b)| (f64::from(a), f64::from(b)));
    // Water only when part of the field lies below the sea surface; land spans the rest.
    let sea = options.sea_level.filter(|&s| s.is_finite() && lo < s);
    let land_lo = sea.map_or(lo, |s| s.min(hi));
    let span = if hi > land_lo { hi - land_lo } else { 1.0 };
    let samples = hf.samples();
    let mut pixels = vec![0u8; 3 * width * height];
    // Rows in parallel: every pixel depends on the field alone, so the image is the same for any
    // thread count.
    pixels.par_chunks_mut(3 * width).enumerate().for_each(|(y, row)| {
        let j = ny - 1 - y * stride;
        let step = hf.grid().cell_size_m(j);
        let interior_row = j > 0 && j + 1 < ny && step.x > 0.0 && step.y > 0.0;
        for (x, px) in row.chunks_exact_mut(3).enumerate() {
            let i = x * stride;
            let k = j * nx + i;
            let h = samples[k];
            if h.is_nan() {
                px.copy_from_slice(&NO_DATA_RGB);
                continue;
            }
            // Central differences straight from the samples inside the grid; the general
            // gradient (one-sided at edges and next to no-data) elsewhere.
            let g = if interior_row && i > 0 && i + 1 < nx {
                let (l, r, d, u) = (samples[k - 1], samples[k + 1], samples[k - nx], samples[k + nx]);
                if (l + r + d + u).is_nan() {
                    hf.gradient(i, j).unwrap_or(DVec2::ZERO)
                } else {
                    DVec2::new(f64::from(r - l) / (2.0 * step.x), f64::from(u - d) / (2.0 * step.y))
                }
            } else {
                hf.gradient(i, j).unwrap_or(DVec2::ZERO)
            };
            let n = DVec3::new(-options.z_factor * g.x, -options.z_factor * g.y, 1.0).normalize();
            let lum = n.dot(light).max(0.0);
            let h = f64::from(h);
            let rgb = if options.hypsometric {
                let c = match sea {
                    Some(s) if h < s => water((s - h) / (s - lo)),
                    _ => hypsometric_tint((h - land_lo) / span),
                };
                let k = 0.35 + 0.65 * lum;
                [c[0] * k, c[1] * k, c[2] * k]
            } else {
                [255.0 * lum; 3]
            };
            for (p, v) in px.iter_mut().zip(rgb) {
                *p = v.round().clamp(0.0, 255.0) as u8;
            }
        }
    });
    RgbImage { width, height, pixels }
}
