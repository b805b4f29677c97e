//! The refined ridge and river networks of §6.2: nodes with heights, segments with linear
//! heights between them, their refinement below λ, and what the terrain asks of them (distance
//! and height at the nearest point, crests burnt into a grid, nearest-segment labels).

use glam::DVec2;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use relief_heightfield::{Extent, GridSpec, Heightfield, distance_transform_seeded};
use relief_tin::poisson_sampling::{PoissonDisc, Rect};

use crate::OrometryError;

/// A network of refined nodes and segments with linear heights.
#[derive(Default)]
pub(crate) struct Network {
    pub(crate) points: Vec<DVec2>,
    pub(crate) heights: Vec<f64>,
    pub(crate) segments: Vec<[u32; 2]>,
    /// Valley width per segment (rivers only).
    pub(crate) widths: Vec<f64>,
    /// Per segment, the height of the saddle its leg (peak → saddle) ends at (ridges only).
    pub(crate) saddles: Vec<f64>,
}

impl Network {
    pub(crate) fn push(&mut self, p: DVec2, h: f64) -> u32 {
        self.points.push(p);
        self.heights.push(h);
        self.points.len() as u32 - 1
    }

    /// Distance from `p` to segment `s`, and the height of its closest point.
    pub(crate) fn project(&self, s: u32, p: DVec2) -> (f64, f64) {
        let [a, b] = self.segments[s as usize];
        let (pa, pb) = (self.points[a as usize], self.points[b as usize]);
        let ab = pb - pa;
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 { ((p - pa).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let h = self.heights[a as usize] + t * (self.heights[b as usize] - self.heights[a as usize]);
        (p.distance(pa + ab * t), h)
    }

    /// Raises the samples along every ridge segment to the segment's height there, capped at
    /// [`BURN_ABOVE_SADDLE_M`] above the saddle its leg ends at: rasterizing the TIN samples
    /// ridges off their lines, on their flanks, and a crest path on the grid would dip below
    /// the saddle next to it (a lower effective col, a higher prominence). Higher up a leg the
    /// dip does not matter, and raising the whole crest would bring higher ground nearer to the
    /// peaks beside it (shorter isolations). Each segment is walked in steps of half a cell; the
    /// nearest sample takes the larger of its value and the capped segment's.
    pub(crate) fn burn(&self, hf: &mut Heightfield) {
        let grid = *hf.grid();
        let samples = hf.samples_mut();
        for (s, &saddle) in self.saddles.iter().enumerate() {
            let [a, b] = self.segments[s];
            let (ha, hb) = (self.heights[a as usize], self.heights[b as usize]);
            self.walk(s, &grid, |at, _, t| {
                let v = &mut samples[at];
                *v = v.max((ha + (hb - ha) * t).min(saddle + BURN_ABOVE_SADDLE_M) as f32);
            });
        }
    }

    /// Walks segment `s` in steps of at most half a cell of `grid`, calling `f(sample, point, t)`
    /// with the nearest sample of each point `t` of the way along.
    fn walk(&self, s: usize, grid: &GridSpec, mut f: impl FnMut(usize, DVec2, f64)) {
        let [a, b] = self.segments[s];
        let (pa, pb) = (self.points[a as usize], self.points[b as usize]);
        let k = (pa.distance(pb) / (grid.cell_size().min_element() * 0.5)).ceil().max(1.0) as usize;
        for t in 0..=k {
            let t = t as f64 / k as f64;
            let q = pa.lerp(pb, t);
            if let Some((i, j)) = grid.nearest_sample(q) {
                f(grid.index(i, j), q, t);
            }
        }
    }

    /// Nearest-segment labels on `grid`: each sample holds the segment closest to it.
    pub(crate) fn nearest_segments(&self, grid: &GridSpec) -> Option<Vec<u32>> {
        if self.segments.is_empty() {
            return None;
        }
        let (nx, ny) = (grid.nx(), grid.ny());
        let mut sq = vec![f64::INFINITY; nx * ny];
        let mut label = vec![0u32; nx * ny];
        for s in 0..self.segments.len() {
            self.walk(s, grid, |at, q, _| {
                let d = grid.position(at % nx, at / nx).distance_squared(q);
                if d < sq[at] {
                    sq[at] = d;
                    label[at] = s as u32;
                }
            });
        }
        distance_transform_seeded(nx, ny, grid.cell_size(), &mut sq, Some(&mut label));
        Some(label)
    }
}

/// How far above its saddle a leg's crest is burnt into the grid, metres (see `Network::burn`).
const BURN_ABOVE_SADDLE_M: f64 = 10.0;

/// §6.2's refinement of one leg `a → b` of `net`: split into segments shorter than λ, heights
/// linear along it, inner nodes jittered sideways by up to `jitter·λ` (`lambda` = λ) tapered to zero at both
/// ends by `sin(πt)`. Returns how many segments were added (none for a leg of zero length).
pub(crate) fn jittered_leg(net: &mut Network, a: u32, b: u32, lambda: f64, jitter: f64, rng: &mut ChaCha8Rng) -> usize {
    let (pa, pb) = (net.points[a as usize], net.points[b as usize]);
    if pa == pb {
        return 0;
    }
    let (ha, hb) = (net.heights[a as usize], net.heights[b as usize]);
    let k = (pa.distance(pb) / lambda).ceil().max(1.0) as usize;
    let side = (pb - pa).perp().normalize_or_zero();
    let mut prev = a;
    for i in 1..k {
        let t = i as f64 / k as f64;
        let wobble = rng.random_range(-1.0..1.0) * jitter * lambda * (std::f64::consts::PI * t).sin();
        let v = net.push(pa.lerp(pb, t) + side * wobble, ha + (hb - ha) * t);
        net.segments.push([prev, v]);
        prev = v;
    }
    net.segments.push([prev, b]);
    k
}

/// Points along the border of `extent` at most `step` apart, corners included, each once.
pub(crate) fn border_points(extent: Extent, step: f64) -> Vec<DVec2> {
    let size = extent.size();
    let count = |n: f64| (n / step).ceil().max(1.0) as usize;
    let (bx, by) = (count(size.x), count(size.y));
    let mut points = Vec::with_capacity(2 * (bx + by));
    for i in 0..=bx {
        let x = extent.min.x + size.x * i as f64 / bx as f64;
        points.push(DVec2::new(x, extent.min.y));
        points.push(DVec2::new(x, extent.max.y));
    }
    for j in 1..by {
        let y = extent.min.y + size.y * j as f64 / by as f64;
        points.push(DVec2::new(extent.min.x, y));
        points.push(DVec2::new(extent.max.x, y));
    }
    points
}

/// Drops exact duplicate points (keeping the first) and remaps constraints.
pub(crate) fn dedup(
    points: Vec<DVec2>,
    values: Vec<f64>,
    constraints: Vec<[u32; 2]>,
) -> (Vec<DVec2>, Vec<f64>, Vec<[u32; 2]>) {
    let mut seen = std::collections::HashMap::with_capacity(points.len());
    let mut remap = Vec::with_capacity(points.len());
    let (mut p2, mut v2) = (Vec::with_capacity(points.len()), Vec::with_capacity(points.len()));
    for (p, v) in points.into_iter().zip(values) {
        let key = (p.x.to_bits(), p.y.to_bits());
        let idx = *seen.entry(key).or_insert_with(|| {
            p2.push(p);
            v2.push(v);
            p2.len() as u32 - 1
        });
        remap.push(idx);
    }
    let c2 =
        constraints.into_iter().map(|[a, b]| [remap[a as usize], remap[b as usize]]).filter(|[a, b]| a != b).collect();
    (p2, v2, c2)
}

/// Poisson-disc samples over `extent`, `radius` apart (the meshing distance λ or a multiple of it,
/// named `lambda_m` in the error of a bad one), from `seed`.
pub(crate) fn poisson_samples(extent: Extent, radius: f64, seed: u64) -> Result<Vec<DVec2>, OrometryError> {
    PoissonDisc::new(radius)
        .map_err(|_| OrometryError::InvalidOption {
            name: "lambda_m",
            value: radius,
            reason: "must be finite and > 0",
        })?
        .with_seed(seed)
        .with_max_points(50_000_000)
        .sample(&Rect::new(extent.min, extent.max))
        .map_err(|e| OrometryError::InvalidTree(format!("sampling the domain failed: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crests_are_burnt_in_up_to_a_little_above_their_saddle() {
        // A leg from a peak at (0, 1), 100 m, down to its saddle at (10, 1), 50 m: 5 m per cell.
        let grid = GridSpec::new(11, 3, DVec2::ZERO, DVec2::ONE).unwrap();
        let mut hf = Heightfield::from_samples(grid, vec![0.0; 33]).unwrap();
        hf.samples_mut()[0] = 200.0; // higher already: kept
        let mut leg = Network::default();
        let (a, b) = (leg.push(DVec2::new(0.0, 1.0), 100.0), leg.push(DVec2::new(10.0, 1.0), 50.0));
        leg.segments.push([a, b]);
        leg.saddles.push(50.0);
        leg.burn(&mut hf);
        let cap = 50.0 + BURN_ABOVE_SADDLE_M;
        for x in 0..11 {
            let v = f64::from(hf.value(x, 1));
            let line = (100.0 - 5.0 * x as f64).min(cap);
            // The nearest sample of points up to half a cell away: within 2.5 m above the line.
            assert!(v >= line && v <= line + 2.5, "x = {x}: {v} for a crest of {line}");
            assert!(v <= cap);
        }
        assert_eq!(f64::from(hf.value(10, 1)), 52.5, "the saddle's sample: half a cell up the leg");
        assert!((0..11).all(|x| hf.value(x, 2) == 0.0));
        assert_eq!(hf.samples()[0], 200.0);
        assert!((1..11).all(|x| hf.value(x, 0) == 0.0));
    }
}
