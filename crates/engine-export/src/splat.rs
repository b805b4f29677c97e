//! Texturing masks from the terrain's shape: slope, elevation, curvature and water flow, and four
//! splat layers (ground, rock, snow, water) whose weights sum to one, as engines' terrain
//! texturing (Unity's alphamaps, `HTerrain`'s splat map, Unreal's layer weight maps) expects.

use rayon::prelude::*;
use relief_heightfield::Heightfield;
use relief_hydrology::{D8, Outlets};

use crate::EngineError;

/// Where each splat layer and mask fades in. Every range `[a, b]` is a smoothstep: nothing at or
/// below `a`, everything at or above `b`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct SplatOptions {
    /// Slope, degrees, over which rock takes over. Default `[30, 45]`.
    pub rock_slope_deg: [f64; 2],
    /// Elevation as a fraction of the height range (0 lowest, 1 highest) over which snow covers
    /// what is not rock. Default `[0.7, 0.9]`.
    pub snow_height: [f64; 2],
    /// Drainage area as a fraction of the whole terrain's area, on a log scale, over which
    /// water and sediment cover the channels. Default `[1e-3, 3e-2]`: a 513² map's channels
    /// start at about 260 samples' catchment.
    pub flow_area: [f64; 2],
}

impl Default for SplatOptions {
    fn default() -> Self {
        Self { rock_slope_deg: [30.0, 45.0], snow_height: [0.7, 0.9], flow_area: [1e-3, 3e-2] }
    }
}

impl SplatOptions {
    /// Each range finite and increasing.
    ///
    /// # Errors
    /// [`EngineError::InvalidSplat`] naming the field.
    pub fn validate(&self) -> Result<(), EngineError> {
        let fields = [("rock_slope_deg", self.rock_slope_deg), ("snow_height", self.snow_height)];
        for (name, [a, b]) in fields.into_iter().chain([("flow_area", self.flow_area)]) {
            if !(a.is_finite() && b.is_finite() && a < b) || (name == "flow_area" && a <= 0.0) {
                return Err(EngineError::InvalidSplat {
                    field: name,
                    reason: format!("[{a}, {b}] must be finite and increasing (flow_area above 0)"),
                });
            }
        }
        Ok(())
    }
}

/// Per-sample masks in 0 … 1, rows from the south like the heightfield's.
#[derive(Debug, Clone, PartialEq)]
pub struct Masks {
    /// Samples along x.
    pub nx: usize,
    /// Samples along y.
    pub ny: usize,
    /// Steepness: the rock ramp of the slope.
    pub slope: Vec<f32>,
    /// Height: the snow ramp of the elevation.
    pub elevation: Vec<f32>,
    /// Convexity: ½ on planes, toward 1 on ridges and crests, toward 0 in valleys
    /// (½ − ½ tanh(∇²h / s), `s` the median of the non-zero |∇²h|, which cliffs do not sway).
    pub convexity: Vec<f32>,
    /// Channels: the flow ramp of the D8 drainage area of the depression-filled terrain.
    pub flow: Vec<f32>,
}

/// The four masks of `hf`, computed in parallel (the same values for any thread count).
/// No-data samples get zero masks (their layer is ground).
///
/// # Errors
/// [`EngineError::InvalidSplat`] for bad options, [`EngineError::NoData`] without a valid sample.
pub fn masks(hf: &Heightfield, options: &SplatOptions) -> Result<Masks, EngineError> {
    options.validate()?;
    let (lo, hi) = hf.min_max().ok_or(EngineError::NoData)?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let [s0, s1] = options.rock_slope_deg.map(f64::to_radians);
    let slope = per_sample(hf, |i, j| hf.slope(i, j).map_or(0.0, |s| smoothstep(s0, s1, s)));
    let span = f64::from(hi - lo).max(f64::MIN_POSITIVE);
    let [e0, e1] = options.snow_height;
    let elevation = per_sample(hf, |i, j| hf.get(i, j).map_or(0.0, |h| smoothstep(e0, e1, f64::from(h - lo) / span)));
    let laplacian = per_sample(hf, |i, j| laplacian(hf, i, j));
    let scale = median_magnitude(&laplacian);
    let convexity = laplacian
        .iter()
        .zip(hf.samples())
        .map(|(&l, h)| if h.is_nan() { 0.0 } else { (0.5 - 0.5 * (f64::from(l) / scale.max(1e-12)).tanh()) as f32 })
        .collect();
    let flow = flow_mask(hf, options.flow_area)?;
    Ok(Masks { nx, ny, slope, elevation, convexity, flow })
}

impl Masks {
    /// The `w × h` samples from column `i0`, row `j0` (a tile's).
    pub(crate) fn crop(&self, i0: usize, j0: usize, [w, h]: [usize; 2]) -> Self {
        let cut = |v: &[f32]| -> Vec<f32> {
            (j0..j0 + h).flat_map(|j| v[j * self.nx + i0..j * self.nx + i0 + w].iter().copied()).collect()
        };
        Self {
            nx: w,
            ny: h,
            slope: cut(&self.slope),
            elevation: cut(&self.elevation),
            convexity: cut(&self.convexity),
            flow: cut(&self.flow),
        }
    }

    /// The four layers' weights at each sample, summing to 255: ground (R), rock (G), snow (B),
    /// water (A). Rock covers steep ground; snow what is high and not rock; water the channels
    /// that are neither; ground the rest: `rock = s`, `snow = e(1 − s)`,
    /// `water = f(1 − s)(1 − e)`, `ground = (1 − s)(1 − e)(1 − f)`.
    pub fn splat(&self) -> Vec<[u8; 4]> {
        (0..self.slope.len())
            .map(|k| {
                let (s, e, f) = (f64::from(self.slope[k]), f64::from(self.elevation[k]), f64::from(self.flow[k]));
                let w = [s, e * (1.0 - s), f * (1.0 - s) * (1.0 - e)];
                let mut q = w.map(|w| (w * 255.0).round() as u16);
                while q.iter().sum::<u16>() > 255 {
                    let big = (0..3).max_by_key(|&i| q[i]).unwrap_or(0);
                    q[big] -= 1;
                }
                let ground = 255 - q.iter().sum::<u16>();
                [ground, q[0], q[1], q[2]].map(|v| v as u8)
            })
            .collect()
    }

    /// The raw masks packed as RGBA bytes: slope (R), elevation (G), convexity (B), flow (A).
    pub fn packed(&self) -> Vec<[u8; 4]> {
        let byte = |v: f32| (v * 255.0).round().clamp(0.0, 255.0) as u8;
        (0..self.slope.len())
            .map(|k| [byte(self.slope[k]), byte(self.elevation[k]), byte(self.convexity[k]), byte(self.flow[k])])
            .collect()
    }
}

fn per_sample(hf: &Heightfield, f: impl Fn(usize, usize) -> f64 + Sync) -> Vec<f32> {
    let nx = hf.nx();
    (0..hf.grid().len()).into_par_iter().with_min_len(4096).map(|k| f(k % nx, k / nx) as f32).collect()
}

/// The median of the non-zero magnitudes (1 when there is none).
fn median_magnitude(values: &[f32]) -> f64 {
    let mut m: Vec<f32> = values.iter().map(|v| v.abs()).filter(|v| *v > 0.0).collect();
    if m.is_empty() {
        return 1.0;
    }
    let mid = m.len() / 2;
    let (_, median, _) = m.select_nth_unstable_by(mid, f32::total_cmp);
    f64::from(*median)
}

/// ∇²h in metres⁻¹ by the five-point stencil; 0 at the border (a neighbour out of the grid)
/// and next to no-data. Interior rows have a positive width in metres: only a geographic grid's
/// pole row has none, and a pole is always a border row.
fn laplacian(hf: &Heightfield, i: usize, j: usize) -> f64 {
    let (Some(west), Some(south)) = (i.checked_sub(1), j.checked_sub(1)) else { return 0.0 };
    let h = |i: usize, j: usize| hf.get(i, j).map(f64::from);
    let (Some(c), Some(l), Some(r), Some(d), Some(u)) = (h(i, j), h(west, j), h(i + 1, j), h(i, south), h(i, j + 1))
    else {
        return 0.0;
    };
    let step = hf.grid().cell_size_m(j);
    (l + r - 2.0 * c) / (step.x * step.x) + (d + u - 2.0 * c) / (step.y * step.y)
}

/// The flow ramp of log drainage area (as a fraction of the total) on the filled terrain.
fn flow_mask(hf: &Heightfield, [a0, a1]: [f64; 2]) -> Result<Vec<f32>, EngineError> {
    let filled = relief_hydrology::fill(hf, Outlets::new())?;
    let d8 = D8::new(&filled)?;
    let area = d8.drainage_area();
    let total: f64 = (0..hf.ny())
        .map(|j| {
            let c = hf.grid().cell_size_m(j);
            (c.x * c.y).abs() * hf.row(j).iter().filter(|v| !v.is_nan()).count() as f64
        })
        .sum();
    let (l0, l1) = (a0.log10(), a1.log10());
    Ok(area
        .iter()
        .zip(hf.samples())
        .map(
            |(&a, h)| {
                if h.is_nan() || a <= 0.0 || total <= 0.0 {
                    0.0
                } else {
                    smoothstep(l0, l1, (a / total).log10()) as f32
                }
            },
        )
        .collect())
}

/// 0 at or below `a`, 1 at or above `b`, 3t² − 2t³ between.
fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use relief_heightfield::GridSpec;

    #[test]
    fn smoothstep_ends_and_middle() {
        assert_eq!(smoothstep(1.0, 3.0, 0.0), 0.0);
        assert_eq!(smoothstep(1.0, 3.0, 1.0), 0.0);
        assert_eq!(smoothstep(1.0, 3.0, 2.0), 0.5);
        assert!((smoothstep(1.0, 3.0, 1.5) - 0.156_25).abs() < 1e-12);
        assert_eq!(smoothstep(1.0, 3.0, 9.0), 1.0);
    }

    #[test]
    fn the_scale_is_the_median_of_the_non_zero_magnitudes() {
        assert_eq!(median_magnitude(&[0.0, -3.0, 1.0, 0.0, 2.0, 100.0, -0.5]), 2.0);
        assert_eq!(median_magnitude(&[0.0; 4]), 1.0);
    }

    #[test]
    fn laplacian_of_a_paraboloid() {
        // h = x² + 2y² on a 0.5 × 3 m grid: ∇²h = 2 + 4 = 6 everywhere inside.
        let grid = GridSpec::new(9, 9, DVec2::ZERO, DVec2::new(0.5, 3.0)).unwrap();
        let hf = Heightfield::from_fn(grid, |p| (p.x * p.x + 2.0 * p.y * p.y) as f32).unwrap();
        assert!((laplacian(&hf, 4, 4) - 6.0).abs() < 1e-3, "{}", laplacian(&hf, 4, 4));
        for (i, j) in [(0, 4), (8, 4), (4, 0), (4, 8), (9, 4)] {
            assert_eq!(laplacian(&hf, i, j), 0.0, "({i}, {j}) is on the border");
        }
    }

    #[test]
    fn weights_sum_to_255_and_follow_the_layers() {
        let m = Masks {
            nx: 4,
            ny: 1,
            slope: vec![1.0, 0.0, 0.0, 0.5],
            elevation: vec![1.0, 1.0, 0.0, 0.5],
            convexity: vec![0.5; 4],
            flow: vec![1.0, 1.0, 1.0, 0.5],
        };
        let w = m.splat();
        assert_eq!(w[0], [0, 255, 0, 0], "steep: rock whatever else");
        assert_eq!(w[1], [0, 0, 255, 0], "high and gentle: snow over the channel");
        assert_eq!(w[2], [0, 0, 0, 255], "low channel: water");
        // s = e = f = ½: rock ½, snow ¼, water ⅛, ground ⅛.
        assert_eq!(w[3], [31, 128, 64, 32]);
        // Snow and water ½ each both round up to 128: one code comes off the larger (the last).
        let tie = Masks { slope: vec![0.0], elevation: vec![0.5], flow: vec![1.0], convexity: vec![0.5], nx: 1, ny: 1 };
        assert_eq!(tie.splat()[0], [0, 0, 128, 127]);
        assert!(w.iter().all(|p| p.iter().map(|&v| u16::from(v)).sum::<u16>() == 255));
    }

    #[test]
    fn bad_ranges_are_named() {
        let bad = SplatOptions { rock_slope_deg: [45.0, 30.0], ..SplatOptions::default() };
        assert!(bad.validate().unwrap_err().to_string().contains("rock_slope_deg"));
        let bad = SplatOptions { snow_height: [0.8, 0.8], ..SplatOptions::default() };
        assert!(bad.validate().unwrap_err().to_string().contains("snow_height"), "an empty ramp");
        let bad = SplatOptions { flow_area: [0.0, 0.1], ..SplatOptions::default() };
        assert!(bad.validate().unwrap_err().to_string().contains("flow_area"));
        assert!(SplatOptions::default().validate().is_ok());
    }
}
