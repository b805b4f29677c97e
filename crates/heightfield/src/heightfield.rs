use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::{Crs, Extent, GridSpec, HeightfieldError};

/// A grid of f32 elevations over a [`GridSpec`], with optional no-data cells.
///
/// No-data cells hold NaN (always the canonical `f32::NAN`); every other sample is finite. The mask
/// is therefore implicit: [`Heightfield::is_no_data`], [`Heightfield::no_data_mask`]. Equality is
/// bitwise on samples, so a field equals itself even when it holds no-data.
///
/// A field may carry the coordinate reference system it was read in ([`Heightfield::crs`]); fields
/// derived from it ([`Heightfield::map`], [`Heightfield::resample`], …) keep it. Equality compares
/// the grid and samples only: compare `crs()` where the label matters.
///
/// Elevations are in metres (or whatever unit the caller uses consistently); gradients are in
/// elevation units per metre of ground distance, also on geographic grids.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(try_from = "HeightfieldRepr", into = "HeightfieldRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Heightfield {
    grid: GridSpec,
    samples: Vec<f32>,
    crs: Option<Crs>,
}

impl PartialEq for Heightfield {
    fn eq(&self, other: &Self) -> bool {
        self.grid == other.grid
            && self.samples.len() == other.samples.len()
            && self.samples.iter().zip(&other.samples).all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// Summary statistics of the valid (non-no-data) samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Statistics {
    /// Number of valid samples.
    pub count: usize,
    /// Number of no-data samples.
    pub no_data: usize,
    /// Lowest valid elevation.
    pub min: f32,
    /// Highest valid elevation.
    pub max: f32,
    /// Mean of valid elevations (accumulated in f64).
    pub mean: f64,
    /// Population standard deviation of valid elevations.
    pub std_dev: f64,
}

/// The JSON form of a [`Heightfield`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "Heightfield"))]
struct HeightfieldRepr {
    /// The grid.
    grid: GridSpec,
    /// No-data samples are written as 0 and listed in `no_data`, because JSON has no NaN.
    samples: Vec<f32>,
    /// Runs `[start, length]` of no-data samples, in flat-index order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    no_data: Vec<[usize; 2]>,
    /// The coordinate reference system of the grid's coordinates, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    crs: Option<Crs>,
}

impl TryFrom<HeightfieldRepr> for Heightfield {
    type Error = HeightfieldError;
    fn try_from(r: HeightfieldRepr) -> Result<Self, Self::Error> {
        let mut samples = r.samples;
        let total = samples.len();
        for [start, len] in r.no_data {
            let run = start.checked_add(len).and_then(|end| samples.get_mut(start..end));
            let Some(run) = run else {
                return Err(HeightfieldError::NoDataRunOutOfRange { start, len, total });
            };
            run.fill(f32::NAN);
        }
        Ok(Heightfield::from_samples(r.grid, samples)?.with_crs(r.crs))
    }
}

impl From<Heightfield> for HeightfieldRepr {
    fn from(h: Heightfield) -> Self {
        let mut no_data = Vec::new();
        let mut samples = h.samples;
        let mut k = 0;
        while k < samples.len() {
            if samples[k].is_nan() {
                let start = k;
                while k < samples.len() && samples[k].is_nan() {
                    samples[k] = 0.0;
                    k += 1;
                }
                no_data.push([start, k - start]);
            } else {
                k += 1;
            }
        }
        Self { grid: h.grid, samples, no_data, crs: h.crs }
    }
}

/// Validates that every sample is finite or NaN, canonicalising NaN payloads.
fn check_samples(grid: &GridSpec, samples: &mut [f32]) -> Result<(), HeightfieldError> {
    for (k, v) in samples.iter_mut().enumerate() {
        if v.is_nan() {
            *v = f32::NAN;
        } else if v.is_infinite() {
            let (i, j) = grid.coords(k);
            return Err(HeightfieldError::NonFiniteSample { i, j, value: *v });
        }
    }
    Ok(())
}

impl Heightfield {
    /// A field with every sample equal to `value` (NaN makes every cell no-data).
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] when `value` is infinite.
    pub fn filled(grid: GridSpec, value: f32) -> Result<Self, HeightfieldError> {
        Self::from_samples(grid, vec![value; grid.len()])
    }

    /// A field of zeros.
    pub fn zeros(grid: GridSpec) -> Self {
        Self { grid, samples: vec![0.0; grid.len()], crs: None }
    }

    /// Wraps row-major samples (row 0 = south). NaN marks no-data.
    ///
    /// # Errors
    /// [`HeightfieldError::SampleCountMismatch`] or [`HeightfieldError::NonFiniteSample`] (±∞).
    pub fn from_samples(grid: GridSpec, mut samples: Vec<f32>) -> Result<Self, HeightfieldError> {
        if samples.len() != grid.len() {
            return Err(HeightfieldError::SampleCountMismatch {
                nx: grid.nx(),
                ny: grid.ny(),
                expected: grid.len(),
                found: samples.len(),
            });
        }
        check_samples(&grid, &mut samples)?;
        Ok(Self { grid, samples, crs: None })
    }

    /// Evaluates `f` at every sample's world position.
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] when `f` returns ±∞ (NaN means no-data).
    pub fn from_fn(grid: GridSpec, f: impl Fn(DVec2) -> f32) -> Result<Self, HeightfieldError> {
        Self::from_fn_indexed(grid, |i, j| f(grid.position(i, j)))
    }

    /// Evaluates `f(i, j)` for every sample.
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] when `f` returns ±∞ (NaN means no-data).
    pub fn from_fn_indexed(grid: GridSpec, f: impl Fn(usize, usize) -> f32) -> Result<Self, HeightfieldError> {
        let mut samples = Vec::with_capacity(grid.len());
        for j in 0..grid.ny() {
            samples.extend((0..grid.nx()).map(|i| f(i, j)));
        }
        Self::from_samples(grid, samples)
    }

    /// The coordinate reference system the field was read in, when known.
    pub fn crs(&self) -> Option<&Crs> {
        self.crs.as_ref()
    }

    /// The same field labelled with another coordinate reference system (`None`: unknown). Nothing
    /// is reprojected.
    #[must_use]
    pub fn with_crs(mut self, crs: Option<Crs>) -> Self {
        self.crs = crs;
        self
    }

    /// The grid geometry.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// Samples along x.
    pub fn nx(&self) -> usize {
        self.grid.nx()
    }

    /// Samples along y.
    pub fn ny(&self) -> usize {
        self.grid.ny()
    }

    /// World rectangle spanned by the samples.
    pub fn extent(&self) -> Extent {
        self.grid.extent()
    }

    /// All samples, row-major, row 0 = south; no-data cells are NaN.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }

    /// Mutable samples for in-place algorithms. Keep every value finite, or NaN for no-data:
    /// [`Heightfield::validate`] re-checks that contract.
    pub fn samples_mut(&mut self) -> &mut [f32] {
        &mut self.samples
    }

    /// Consumes the field, returning its samples.
    pub fn into_samples(self) -> Vec<f32> {
        self.samples
    }

    /// Row `j` (south to north), west to east.
    pub fn row(&self, j: usize) -> &[f32] {
        let nx = self.nx();
        &self.samples[j * nx..(j + 1) * nx]
    }

    /// Re-checks the sample contract after raw mutation through [`Heightfield::samples_mut`].
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] naming the first infinite sample.
    pub fn validate(&mut self) -> Result<(), HeightfieldError> {
        check_samples(&self.grid, &mut self.samples)
    }

    /// Elevation at sample `(i, j)`, or `None` if out of range or no-data.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Option<f32> {
        if i >= self.nx() || j >= self.ny() {
            return None;
        }
        let v = self.samples[self.grid.index(i, j)];
        (!v.is_nan()).then_some(v)
    }

    /// Raw sample `(i, j)` (NaN for no-data).
    ///
    /// # Panics
    /// If `(i, j)` is outside the grid.
    #[inline]
    pub fn value(&self, i: usize, j: usize) -> f32 {
        assert!(i < self.nx() && j < self.ny(), "sample ({i}, {j}) outside {}x{}", self.nx(), self.ny());
        self.samples[self.grid.index(i, j)]
    }

    /// Sets sample `(i, j)`; NaN marks it no-data.
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] for ±∞.
    ///
    /// # Panics
    /// If `(i, j)` is outside the grid.
    pub fn set(&mut self, i: usize, j: usize, value: f32) -> Result<(), HeightfieldError> {
        assert!(i < self.nx() && j < self.ny(), "sample ({i}, {j}) outside {}x{}", self.nx(), self.ny());
        if value.is_infinite() {
            return Err(HeightfieldError::NonFiniteSample { i, j, value });
        }
        let k = self.grid.index(i, j);
        self.samples[k] = if value.is_nan() { f32::NAN } else { value };
        Ok(())
    }

    /// Whether sample `(i, j)` is no-data.
    pub fn is_no_data(&self, i: usize, j: usize) -> bool {
        self.samples[self.grid.index(i, j)].is_nan()
    }

    /// Number of no-data samples.
    pub fn no_data_count(&self) -> usize {
        self.samples.iter().filter(|v| v.is_nan()).count()
    }

    /// Whether any sample is no-data.
    pub fn has_no_data(&self) -> bool {
        self.samples.iter().any(|v| v.is_nan())
    }

    /// The no-data mask, `true` where a sample has no data, row-major.
    pub fn no_data_mask(&self) -> Vec<bool> {
        self.samples.iter().map(|v| v.is_nan()).collect()
    }

    /// Replaces every no-data sample by `value`.
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] if `value` is not finite.
    pub fn fill_no_data(&mut self, value: f32) -> Result<(), HeightfieldError> {
        if !value.is_finite() {
            return Err(HeightfieldError::NonFiniteSample { i: 0, j: 0, value });
        }
        self.samples.iter_mut().filter(|v| v.is_nan()).for_each(|v| *v = value);
        Ok(())
    }

    /// Bilinear interpolation at world point `p`.
    ///
    /// `None` outside the extent or when a corner with non-zero weight is no-data (so sampling exactly
    /// on a valid node next to a hole still succeeds).
    pub fn sample_bilinear(&self, p: DVec2) -> Option<f32> {
        // Points a rounding error outside (extent corners recomputed from the origin) still count.
        const TOL: f64 = 1e-9;
        let g = self.grid.grid_coords(p);
        let (mx, my) = ((self.nx() - 1) as f64, (self.ny() - 1) as f64);
        if !(g.x >= -TOL && g.y >= -TOL && g.x <= mx + TOL && g.y <= my + TOL) {
            return None;
        }
        self.bilinear_at_grid(g.clamp(DVec2::ZERO, DVec2::new(mx, my)))
    }

    /// Bilinear interpolation at `p` clamped into the extent (edge values extend outward).
    pub fn sample_bilinear_clamped(&self, p: DVec2) -> Option<f32> {
        let g = self.grid.grid_coords(p);
        if g.is_nan() {
            return None;
        }
        let max = DVec2::new((self.nx() - 1) as f64, (self.ny() - 1) as f64);
        self.bilinear_at_grid(g.clamp(DVec2::ZERO, max))
    }

    /// Bilinear interpolation at continuous grid coordinates already clamped into range.
    fn bilinear_at_grid(&self, g: DVec2) -> Option<f32> {
        let (nx, ny) = (self.nx(), self.ny());
        let split = |x: f64, n: usize| -> (usize, f64) {
            if n == 1 {
                return (0, 0.0);
            }
            let i = (x.floor() as usize).min(n - 2);
            (i, x - i as f64)
        };
        let (i0, tx) = split(g.x, nx);
        let (j0, ty) = split(g.y, ny);
        let corners = [
            (i0, j0, (1.0 - tx) * (1.0 - ty)),
            (i0 + 1, j0, tx * (1.0 - ty)),
            (i0, j0 + 1, (1.0 - tx) * ty),
            (i0 + 1, j0 + 1, tx * ty),
        ];
        let mut acc = 0.0f64;
        for (i, j, w) in corners {
            if w == 0.0 {
                continue;
            }
            let v = self.samples[j * nx + i];
            if v.is_nan() {
                return None;
            }
            acc += w * f64::from(v);
        }
        Some(acc as f32)
    }

    /// Elevation gradient `(∂h/∂x, ∂h/∂y)` at sample `(i, j)` in elevation units per metre.
    ///
    /// Central differences, one-sided at the grid edge or next to no-data; a component with no valid
    /// neighbour on either side is 0. `None` if `(i, j)` is no-data or out of range.
    pub fn gradient(&self, i: usize, j: usize) -> Option<DVec2> {
        let h = f64::from(self.get(i, j)?);
        let step = self.grid.cell_size_m(j);
        let fetch = |i: Option<usize>, j: Option<usize>| match (i, j) {
            (Some(i), Some(j)) => self.get(i, j).map(f64::from),
            _ => None,
        };
        let diff = |lo: Option<f64>, hi: Option<f64>, d: f64| -> f64 {
            if d <= 0.0 {
                return 0.0; // pole rows of a geographic grid have zero width
            }
            match (lo, hi) {
                (Some(l), Some(r)) => (r - l) / (2.0 * d),
                (None, Some(r)) => (r - h) / d,
                (Some(l), None) => (h - l) / d,
                (None, None) => 0.0,
            }
        };
        let gx = diff(fetch(i.checked_sub(1), Some(j)), fetch(Some(i + 1), Some(j)), step.x);
        let gy = diff(fetch(Some(i), j.checked_sub(1)), fetch(Some(i), Some(j + 1)), step.y);
        Some(DVec2::new(gx, gy))
    }

    /// Slope angle at sample `(i, j)` in radians, `atan(‖∇h‖)`.
    pub fn slope(&self, i: usize, j: usize) -> Option<f64> {
        self.gradient(i, j).map(|g| g.length().atan())
    }

    /// Unit surface normal at sample `(i, j)`: `normalize(−∂h/∂x, −∂h/∂y, 1)`.
    pub fn normal(&self, i: usize, j: usize) -> Option<DVec3> {
        self.gradient(i, j).map(|g| DVec3::new(-g.x, -g.y, 1.0).normalize())
    }

    /// Slope angle of every sample in radians (no-data stays no-data).
    #[must_use]
    pub fn slope_map(&self) -> Heightfield {
        let samples = (0..self.grid.len())
            .map(|k| {
                let (i, j) = self.grid.coords(k);
                self.slope(i, j).map_or(f32::NAN, |s| s as f32)
            })
            .collect();
        Self { grid: self.grid, samples, crs: self.crs.clone() }
    }

    /// The same extent resampled to `nx × ny` samples by bilinear interpolation.
    ///
    /// Samples whose interpolation touches no-data become no-data. Bilinear filtering is exact when
    /// refining; when coarsening by more than 2× it aliases — pre-smooth first if that matters.
    ///
    /// # Errors
    /// As [`GridSpec::resized`].
    pub fn resample(&self, nx: usize, ny: usize) -> Result<Heightfield, HeightfieldError> {
        Ok(self.resample_to(&self.grid.resized(nx, ny)?))
    }

    /// Bilinear resampling onto an arbitrary grid; samples outside this field's extent are no-data.
    #[must_use]
    pub fn resample_to(&self, grid: &GridSpec) -> Heightfield {
        let mut samples = Vec::with_capacity(grid.len());
        for j in 0..grid.ny() {
            samples.extend((0..grid.nx()).map(|i| self.sample_bilinear(grid.position(i, j)).unwrap_or(f32::NAN)));
        }
        Self { grid: *grid, samples, crs: self.crs.clone() }
    }

    /// Lowest and highest valid elevation, `None` if every sample is no-data.
    pub fn min_max(&self) -> Option<(f32, f32)> {
        self.samples.iter().filter(|v| !v.is_nan()).fold(None, |acc, &v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
    }

    /// Count, min, max, mean and standard deviation of the valid samples; `None` if there are none.
    pub fn statistics(&self) -> Option<Statistics> {
        let (min, max) = self.min_max()?;
        let (mut count, mut sum) = (0usize, 0.0f64);
        for &v in self.samples.iter().filter(|v| !v.is_nan()) {
            count += 1;
            sum += f64::from(v);
        }
        let mean = sum / count as f64;
        // Two-pass variance: exact enough for f32 data and immune to the cancellation of sum-of-squares.
        let var = self.samples.iter().filter(|v| !v.is_nan()).map(|&v| (f64::from(v) - mean).powi(2)).sum::<f64>()
            / count as f64;
        Some(Statistics { count, no_data: self.samples.len() - count, min, max, mean, std_dev: var.sqrt() })
    }

    /// Applies `f` to every valid sample; no-data stays no-data.
    ///
    /// # Errors
    /// [`HeightfieldError::NonFiniteSample`] when `f` returns ±∞.
    pub fn map(&self, f: impl Fn(f32) -> f32) -> Result<Heightfield, HeightfieldError> {
        let samples = self.samples.iter().map(|&v| if v.is_nan() { v } else { f(v) }).collect();
        Ok(Self::from_samples(self.grid, samples)?.with_crs(self.crs.clone()))
    }

    /// Combines two fields on the same grid sample by sample; a sample that is no-data in either
    /// input is no-data in the output.
    ///
    /// # Errors
    /// [`HeightfieldError::GridMismatch`] when the grids differ, [`HeightfieldError::NonFiniteSample`]
    /// when `f` returns ±∞.
    pub fn zip_with(&self, other: &Heightfield, f: impl Fn(f32, f32) -> f32) -> Result<Heightfield, HeightfieldError> {
        if self.grid != other.grid {
            return Err(HeightfieldError::GridMismatch {
                left_nx: self.nx(),
                left_ny: self.ny(),
                right_nx: other.nx(),
                right_ny: other.ny(),
            });
        }
        let samples = self
            .samples
            .iter()
            .zip(&other.samples)
            .map(|(&a, &b)| if a.is_nan() || b.is_nan() { f32::NAN } else { f(a, b) })
            .collect();
        Ok(Self::from_samples(self.grid, samples)?.with_crs(self.crs.clone()))
    }
}
