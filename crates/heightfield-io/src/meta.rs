//! The JSON metadata of the normalised formats (PNG text chunk, raw sidecar) and the quantisation
//! that maps elevations to integer codes and back.

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, Units};
use serde::{Deserialize, Serialize};

use crate::IoErrorKind;

/// Version written into every metadata record; readers reject newer ones.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// What a PNG `relief` text chunk or a raw `<file>.json` sidecar records.
///
/// `min`/`max` are the real elevations that codes `lo` and `hi` stand for (f64 so that the f32
/// values survive JSON exactly); `no_data_code` is present (always 0) when code 0 marks no-data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Metadata {
    pub format_version: u32,
    /// "png8", "png16", "r16" or "r32".
    pub encoding: String,
    pub nx: u64,
    pub ny: u64,
    pub origin: [f64; 2],
    pub cell_size: [f64; 2],
    pub units: Units,
    /// `None` when every sample is no-data.
    pub min: Option<f64>,
    pub max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_data_code: Option<u32>,
    /// The coordinate reference system, when the field has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crs: Option<Crs>,
}

impl Metadata {
    /// The record for `hf` stored as `encoding`; `quantised` says whether code 0 is reserved.
    pub(crate) fn describe(hf: &Heightfield, encoding: &str, quantised: bool) -> Self {
        Self::describe_in(hf, encoding, quantised, None)
    }

    /// [`Metadata::describe`] with the quantised range `range` instead of the field's min and max.
    pub(crate) fn describe_in(hf: &Heightfield, encoding: &str, quantised: bool, range: Option<(f32, f32)>) -> Self {
        let g = hf.grid();
        let mm = range.or_else(|| hf.min_max());
        Self {
            format_version: FORMAT_VERSION,
            encoding: encoding.to_owned(),
            nx: g.nx() as u64,
            ny: g.ny() as u64,
            origin: g.origin().to_array(),
            cell_size: g.cell_size().to_array(),
            units: g.units(),
            min: mm.map(|m| f64::from(m.0)),
            max: mm.map(|m| f64::from(m.1)),
            no_data_code: (quantised && hf.has_no_data()).then_some(0),
            crs: hf.crs().cloned(),
        }
    }

    pub(crate) fn to_json(&self) -> String {
        // Serialising plain numbers and strings cannot fail.
        serde_json::to_string(self).unwrap_or_default()
    }

    pub(crate) fn from_json(text: &str) -> Result<Self, IoErrorKind> {
        let m: Metadata = serde_json::from_str(text).map_err(|e| IoErrorKind::InvalidMetadata(e.to_string()))?;
        if m.format_version > FORMAT_VERSION {
            return Err(IoErrorKind::Unsupported(format!(
                "metadata format_version {} is newer than {FORMAT_VERSION}",
                m.format_version
            )));
        }
        Ok(m)
    }

    /// The grid the record describes, checked against the dimensions the data itself has.
    pub(crate) fn grid(&self, nx: usize, ny: usize) -> Result<GridSpec, IoErrorKind> {
        if self.nx != nx as u64 || self.ny != ny as u64 {
            return Err(IoErrorKind::HeaderMismatch(format!(
                "metadata says {}x{} samples, the image holds {nx}x{ny}",
                self.nx, self.ny
            )));
        }
        let bad = |e: relief_heightfield::HeightfieldError| IoErrorKind::InvalidMetadata(e.to_string());
        GridSpec::new(nx, ny, DVec2::from(self.origin), DVec2::from(self.cell_size))
            .and_then(|g| g.with_units(self.units))
            .map_err(bad)
    }

    /// The mapping from codes back to elevations for a format with `max_code`.
    pub(crate) fn quantiser(&self, max_code: u32) -> Result<Quantiser, IoErrorKind> {
        let lo = match self.no_data_code {
            None => 0,
            Some(0) => 1,
            Some(c) => return Err(IoErrorKind::InvalidMetadata(format!("no_data_code must be 0, got {c}"))),
        };
        match (self.min, self.max) {
            (Some(min), Some(max)) => {
                let (a, b) = (min as f32, max as f32);
                if !(a.is_finite() && b.is_finite() && a <= b && f64::from(a) == min && f64::from(b) == max) {
                    return Err(IoErrorKind::InvalidMetadata(format!(
                        "min {min} and max {max} must be finite f32 values with min <= max"
                    )));
                }
                Ok(Quantiser { min: a, max: b, lo, hi: max_code, no_data: self.no_data_code.is_some() })
            }
            (None, None) if self.no_data_code.is_some() => {
                // Every sample is no-data: any code other than 0 is an error, caught in `decode`.
                Ok(Quantiser { min: 0.0, max: 0.0, lo: 1, hi: 0, no_data: true })
            }
            _ => {
                Err(IoErrorKind::InvalidMetadata("min and max are required unless every sample is no-data".to_owned()))
            }
        }
    }
}

/// Linear map between elevations in `[min, max]` and codes in `[lo, hi]`; code 0 is no-data when
/// `no_data` is set (then `lo = 1`).
///
/// Encoding rounds to the nearest code, so the error is at most half a step
/// `(max − min) / (hi − lo)`; codes `lo` and `hi` decode to exactly `min` and `max`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Quantiser {
    min: f32,
    max: f32,
    lo: u32,
    hi: u32,
    no_data: bool,
}

impl Quantiser {
    /// The quantiser for `hf` with codes up to `max_code`.
    pub(crate) fn for_field(hf: &Heightfield, max_code: u32) -> Self {
        let no_data = hf.has_no_data();
        let (min, max) = hf.min_max().unwrap_or((0.0, 0.0));
        Self { min, max, lo: u32::from(no_data), hi: max_code, no_data }
    }

    /// The quantiser for `hf` over the fixed elevations `range` (its min and max by default),
    /// with codes up to `max_code`.
    ///
    /// # Errors
    /// [`IoErrorKind::OutOfRange`] naming the first sample outside `range`;
    /// [`IoErrorKind::Unsupported`] for a range that is not finite with min < max.
    pub(crate) fn for_field_in(
        hf: &Heightfield,
        max_code: u32,
        range: Option<(f32, f32)>,
    ) -> Result<Self, IoErrorKind> {
        let Some((min, max)) = range else { return Ok(Self::for_field(hf, max_code)) };
        if !(min.is_finite() && max.is_finite() && min < max) {
            return Err(IoErrorKind::Unsupported(format!("the range [{min}, {max}] must be finite with min < max")));
        }
        if let Some(k) = hf.samples().iter().position(|&v| v < min || v > max) {
            let (i, j) = hf.grid().coords(k);
            let value = hf.samples()[k];
            return Err(IoErrorKind::OutOfRange { i, j, value, min: f64::from(min), max: f64::from(max) });
        }
        let no_data = hf.has_no_data();
        Ok(Self { min, max, lo: u32::from(no_data), hi: max_code, no_data })
    }

    /// The code of elevation `v` (NaN → 0 when no-data is reserved).
    #[inline]
    pub(crate) fn encode(&self, v: f32) -> u32 {
        if v.is_nan() {
            return 0;
        }
        let range = f64::from(self.max) - f64::from(self.min);
        if range <= 0.0 {
            return self.lo;
        }
        let t = ((f64::from(v) - f64::from(self.min)) / range).clamp(0.0, 1.0);
        self.lo + (t * f64::from(self.hi - self.lo)).round() as u32
    }

    /// The elevation of `code`.
    #[inline]
    pub(crate) fn decode(&self, code: u32) -> Result<f32, IoErrorKind> {
        if self.no_data && code == 0 {
            return Ok(f32::NAN);
        }
        if code < self.lo || code > self.hi {
            return Err(IoErrorKind::HeaderMismatch(format!(
                "code {code} lies outside the range {}..={} the metadata allows",
                self.lo, self.hi
            )));
        }
        Ok(if code == self.lo {
            self.min
        } else if code == self.hi {
            self.max
        } else {
            let t = f64::from(code - self.lo) / f64::from(self.hi - self.lo);
            (f64::from(self.min) + t * (f64::from(self.max) - f64::from(self.min))) as f32
        })
    }
}

/// Grid of a file that carries no geometry: origin 0, cell size 1, metres.
pub(crate) fn plain_grid(nx: usize, ny: usize) -> Result<GridSpec, IoErrorKind> {
    Ok(GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE)?)
}

/// Converts north-up rows (file order) to our south-first storage in place.
pub(crate) fn flip_rows<T>(samples: &mut [T], nx: usize) {
    if nx == 0 {
        return;
    }
    let ny = samples.len() / nx;
    for j in 0..ny / 2 {
        let (top, bottom) = samples.split_at_mut((ny - 1 - j) * nx);
        top[j * nx..(j + 1) * nx].swap_with_slice(&mut bottom[..nx]);
    }
}

/// The samples of `hf` in file order (north row first), mapped through `f`.
#[cfg_attr(
    not(any(feature = "exr", feature = "geotiff")),
    expect(dead_code, reason = "used by the exr and tiff codecs only")
)]
pub(crate) fn north_up<T>(hf: &Heightfield, mut f: impl FnMut(usize, usize, f32) -> T) -> Vec<T> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut out = Vec::with_capacity(nx * ny);
    for j in (0..ny).rev() {
        out.extend(hf.row(j).iter().enumerate().map(|(i, &v)| f(i, j, v)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiser_maps_the_ends_exactly_and_reserves_zero_for_no_data() {
        let grid = GridSpec::new(4, 1, DVec2::ZERO, DVec2::ONE).unwrap();
        let hf = Heightfield::from_samples(grid, vec![-3.5, 0.1, 7.25, f32::NAN]).unwrap();
        let q = Quantiser::for_field(&hf, 255);
        assert_eq!((q.encode(-3.5), q.encode(7.25), q.encode(f32::NAN)), (1, 255, 0));
        assert_eq!((q.decode(1).unwrap(), q.decode(255).unwrap()), (-3.5, 7.25));
        assert!(q.decode(0).unwrap().is_nan());
        let mid = q.decode(q.encode(0.1)).unwrap();
        assert!((mid - 0.1).abs() <= 10.75 / 254.0 / 2.0 + 1e-6, "{mid}");
        // Without no-data, code 0 is the minimum.
        let full = Heightfield::from_samples(grid, vec![-3.5, 0.1, 7.25, 2.0]).unwrap();
        let q = Quantiser::for_field(&full, 65535);
        assert_eq!((q.encode(-3.5), q.encode(7.25)), (0, 65535));
        assert_eq!(q.decode(0).unwrap(), -3.5);
    }

    #[test]
    fn metadata_rejects_min_above_max_and_foreign_no_data_codes() {
        let grid = GridSpec::new(2, 1, DVec2::ZERO, DVec2::ONE).unwrap();
        let hf = Heightfield::from_samples(grid, vec![1.0, 2.0]).unwrap();
        let mut m = Metadata::describe(&hf, "png16", true);
        assert!(m.quantiser(65535).is_ok());
        m.min = Some(3.0);
        assert!(matches!(m.quantiser(65535), Err(IoErrorKind::InvalidMetadata(_))));
        m.min = Some(1.0);
        m.no_data_code = Some(7);
        assert!(matches!(m.quantiser(65535), Err(IoErrorKind::InvalidMetadata(_))));
        m.no_data_code = None;
        m.min = Some(0.1); // not an f32
        assert!(matches!(m.quantiser(65535), Err(IoErrorKind::InvalidMetadata(_))));
        let back = Metadata::from_json(&Metadata::describe(&hf, "r16", true).to_json()).unwrap();
        assert_eq!(back, Metadata::describe(&hf, "r16", true));
    }

    #[test]
    fn flip_rows_reverses_row_order() {
        for ny in 1..5 {
            let mut v: Vec<usize> = (0..3 * ny).collect();
            flip_rows(&mut v, 3);
            let expected: Vec<usize> = (0..ny).rev().flat_map(|j| 3 * j..3 * j + 3).collect();
            assert_eq!(v, expected, "ny = {ny}");
        }
    }
}
