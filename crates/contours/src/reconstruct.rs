use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::{DistanceScratch, GridSpec, Heightfield, distance_transform_seeded_with, fill_depressions};
use relief_tin::poisson_sampling::{Rect, segment_distance_sq};

use crate::{ContourSet, ContoursError};

/// Marks a sample outside every closed contour.
const NONE: u32 = u32::MAX;

/// What the interpolated reconstruction does inside a contour with no contour nested in it (a
/// summit, or the floor of a pit), where Hormann's two-contour formula has no second contour.
#[derive(Clone, Copy, Default)]
pub enum Summit<'a> {
    /// A dome rising half a level step above the contour (sinking, for a pit), flat at its centre.
    #[default]
    Dome,
    /// The contour's own height.
    Flat,
    /// A surface, e.g. the TIN the contours came from, clamped to within one level step of the
    /// contour on its higher (pit: lower) side.
    Surface(&'a (dyn Fn(DVec2) -> f64 + Sync)),
}

/// Options of [`reconstruct_interpolated`].
#[derive(Debug, Clone, Copy)]
pub struct Interpolation<'a> {
    /// Inside contours with nothing nested in them.
    pub summit: Summit<'a>,
    /// Make the raster drain (default on): sharp valleys narrower than a cell, which the contours
    /// resolve but a grid cannot, otherwise leave one-cell pits where every neighbour is higher.
    /// They are filled by Priority-Flood+ε to their spill height (typically by a fraction of a
    /// metre); the sea and every region inside a pit contour are outlets, so intended depressions
    /// stay.
    pub drain: bool,
}

impl Default for Interpolation<'_> {
    fn default() -> Self {
        Self { summit: Summit::Dome, drain: true }
    }
}

impl std::fmt::Debug for Summit<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Summit::Dome => "Dome",
            Summit::Flat => "Flat",
            Summit::Surface(_) => "Surface(..)",
        })
    }
}

/// For every sample of `grid`, the innermost closed contour containing it (`NONE` if none):
/// one sweep per row over the contours' crossings with it, parallel over rows.
fn region_labels(set: &ContourSet, grid: &GridSpec) -> Vec<u32> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let (oy, dy) = (grid.origin().y, grid.cell_size().y);
    let row_y = |j: usize| grid.position(0, j).y;
    // Crossings of each row with the contours: (row, x, contour), with the half-open rule.
    let mut crossings: Vec<(u32, f64, u32)> = set
        .contours()
        .par_iter()
        .enumerate()
        .filter(|(_, c)| c.closed)
        .flat_map_iter(|(k, c)| {
            c.segments().flat_map(move |[a, b]| {
                let (lo, hi) = (a.y.min(b.y), a.y.max(b.y));
                let j0 = (((lo - oy) / dy).floor() - 1.0).max(0.0) as usize;
                let j1 = (((hi - oy) / dy).ceil() + 1.0).clamp(0.0, (ny - 1) as f64) as usize;
                (j0..=j1.min(ny - 1)).filter_map(move |j| {
                    let y = row_y(j);
                    ((a.y > y) != (b.y > y)).then(|| (j as u32, a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y), k as u32))
                })
            })
        })
        .collect();
    crossings.par_sort_unstable_by(|p, q| p.0.cmp(&q.0).then(p.1.total_cmp(&q.1)).then(p.2.cmp(&q.2)));
    let mut starts = vec![0usize; ny + 1];
    for c in &crossings {
        starts[c.0 as usize + 1] += 1;
    }
    for j in 0..ny {
        starts[j + 1] += starts[j];
    }
    let mut labels = vec![NONE; nx * ny];
    labels.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        let xs = &crossings[starts[j]..starts[j + 1]];
        let mut stack: Vec<u32> = Vec::new();
        let mut ptr = 0;
        for (i, label) in row.iter_mut().enumerate() {
            let x = grid.position(i, j).x;
            while ptr < xs.len() && xs[ptr].1 < x {
                let c = xs[ptr].2;
                // Contours never cross, so entering and leaving follow a stack; stay robust anyway.
                match stack.iter().rposition(|&s| s == c) {
                    Some(pos) => {
                        stack.remove(pos);
                    }
                    None => stack.push(c),
                }
                ptr += 1;
            }
            *label = stack.last().copied().unwrap_or(NONE);
        }
    });
    labels
}

/// The stair value of the region just inside contour `k`: the highest level not above the ground
/// there — the contour's own height around higher ground, the level below around a pit (one level
/// step below the lowest level for a pit under every level).
fn stair_value(set: &ContourSet, k: usize) -> f64 {
    let c = &set.contours()[k];
    let levels = set.levels();
    if c.is_counter_clockwise() {
        c.height
    } else if c.level > 0 {
        levels[c.level as usize - 1]
    } else {
        levels[0] - if levels.len() > 1 { levels[1] - levels[0] } else { 1.0 }
    }
}

fn to_heightfield(grid: &GridSpec, values: Vec<f64>) -> Result<Heightfield, ContoursError> {
    Heightfield::from_samples(*grid, values.into_iter().map(|v| v as f32).collect())
        .map_err(|e| ContoursError::Invariant(format!("reconstruction produced an invalid sample: {e}")))
}

fn check_base(base: f64) -> Result<(), ContoursError> {
    if base.is_finite() { Ok(()) } else { Err(ContoursError::NonFinite { what: "base height", value: base }) }
}

/// Stair-step reconstruction (§3.2): each sample takes the height of the innermost contour
/// containing it — the highest level not above the ground there, so a level lower inside a pit
/// contour; samples outside every closed contour take `base`. Discontinuous, but exact and fast: one sweep per row.
///
/// # Errors
/// [`ContoursError::NonFinite`] for a non-finite `base`.
pub fn reconstruct_stairs(set: &ContourSet, grid: &GridSpec, base: f64) -> Result<Heightfield, ContoursError> {
    check_base(base)?;
    let labels = region_labels(set, grid);
    let value: Vec<f64> = (0..set.len()).map(|k| stair_value(set, k)).collect();
    to_heightfield(grid, labels.iter().map(|&l| if l == NONE { base } else { value[l as usize] }).collect())
}

/// Interpolated reconstruction (Hormann et al. 2003, as in §3.2): between the innermost contour
/// Γₖ containing a sample and the nearest contour Γₖ₊₁ nested directly inside it,
/// `h = (d₍ₖ₊₁₎·hₖ + dₖ·h₍ₖ₊₁₎) / (dₖ + d₍ₖ₊₁₎)`; continuous across every contour. Inside contours with
/// nothing nested (summits, pit floors) `summit` decides; outside every contour, `base`.
///
/// Distances are Euclidean distances to the contour polylines themselves: samples near a curve are
/// seeded with their exact squared distance, then a labelled Felzenszwalb–Huttenlocher transform
/// propagates them (error well under a cell). One transform per contour that has contours nested in
/// it, over its bounding box and seeded with those children only, serves two regions exactly: its
/// own (distance to the nearest child) and each child's (distance to that child, which is nearer
/// than any sibling from inside it). With [`Interpolation::drain`] the result is then made to drain.
///
/// # Errors
/// [`ContoursError::NonFinite`] for a non-finite `base`.
pub fn reconstruct_interpolated(
    set: &ContourSet,
    grid: &GridSpec,
    base: f64,
    options: &Interpolation<'_>,
) -> Result<Heightfield, ContoursError> {
    check_base(base)?;
    let labels = region_labels(set, grid);
    let regions = Regions::new(set.len(), &labels);
    let distances = Distances::new(set, grid, &regions);
    let mut values: Vec<f64> = labels.iter().map(|&l| if l == NONE { base } else { f64::NAN }).collect();
    let blended: Vec<Vec<(u32, f64)>> = (0..set.len())
        .into_par_iter()
        .filter(|&k| set.contours()[k].closed)
        .map(|k| region_values(set, grid, k, regions.of(k), &distances.own, &distances.child, options.summit))
        .collect();
    for (g, v) in blended.into_iter().flatten() {
        values[g as usize] = v;
    }
    // A sample labelled by an open contour cannot occur; anything left is outside every region.
    for v in values.iter_mut().filter(|v| v.is_nan()) {
        *v = base;
    }
    let mut dem = to_heightfield(grid, values)?;
    if options.drain {
        drain(&mut dem, set, &labels);
    }
    Ok(dem)
}

/// Fills the raster's one-cell pits by Priority-Flood+ε, with the sea (outside every contour) and
/// every region inside a pit contour as outlets, so intended depressions stay (see
/// [`outlet_mask`] for the slivers that do not count).
fn drain(dem: &mut Heightfield, set: &ContourSet, labels: &[u32]) {
    let outlet = outlet_mask(dem.grid(), set, labels);
    let nx = dem.nx();
    fill_depressions(dem, |i, j| outlet[j * nx + i]);
}

/// Fewest samples an enclosed patch of sea or of a pit's inside needs to stay an outlet.
const MIN_OUTLET_SAMPLES: usize = 4;

/// The samples that drain the raster: outside every contour (the sea) or inside a pit contour,
/// in 8-connected patches that reach the grid's border or hold at least
/// [`MIN_OUTLET_SAMPLES`] samples. A smaller enclosed patch is a sliver of sea or pit that a
/// contour narrower than a cell leaves in the land (an inlet's tip, a pit's spur): it is filled
/// like any other one-cell pit.
fn outlet_mask(grid: &GridSpec, set: &ContourSet, labels: &[u32]) -> Vec<bool> {
    let pit: Vec<bool> = set.contours().iter().map(|c| c.closed && !c.is_counter_clockwise()).collect();
    let candidate: Vec<bool> = labels.iter().map(|&l| l == NONE || pit[l as usize]).collect();
    let (nx, ny) = (grid.nx(), grid.ny());
    let mut outlet = vec![false; labels.len()];
    let mut seen = vec![false; labels.len()];
    let mut patch = Vec::new();
    for start in 0..labels.len() {
        if !candidate[start] || seen[start] {
            continue;
        }
        // One 8-connected patch of candidates, by a depth-first walk.
        patch.clear();
        seen[start] = true;
        let mut stack = vec![start];
        let mut border = false;
        while let Some(k) = stack.pop() {
            patch.push(k);
            let (i, j) = (k % nx, k / nx);
            border |= i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            for (a, b) in neighbours(i, j, nx, ny) {
                let w = b * nx + a;
                if candidate[w] && !seen[w] {
                    seen[w] = true;
                    stack.push(w);
                }
            }
        }
        if border || patch.len() >= MIN_OUTLET_SAMPLES {
            for &k in &patch {
                outlet[k] = true;
            }
        }
    }
    outlet
}

/// The 8-neighbours of sample `(i, j)` inside an `nx × ny` grid.
fn neighbours(i: usize, j: usize, nx: usize, ny: usize) -> impl Iterator<Item = (usize, usize)> {
    let (i0, i1, j0, j1) = (i.saturating_sub(1), (i + 1).min(nx - 1), j.saturating_sub(1), (j + 1).min(ny - 1));
    (j0..=j1).flat_map(move |b| (i0..=i1).map(move |a| (a, b))).filter(move |&(a, b)| (a, b) != (i, j))
}

/// The samples of each region, grouped by contour (CSR).
struct Regions {
    starts: Vec<usize>,
    samples: Vec<u32>,
}

impl Regions {
    /// Groups the samples by their label among `n` contours (`NONE` belongs to no region).
    fn new(n: usize, labels: &[u32]) -> Self {
        let mut starts = vec![0usize; n + 1];
        for &l in labels.iter().filter(|&&l| l != NONE) {
            starts[l as usize + 1] += 1;
        }
        for k in 0..n {
            starts[k + 1] += starts[k];
        }
        let mut fill = starts.clone();
        let mut samples = vec![0u32; starts[n]];
        for (g, &l) in labels.iter().enumerate().filter(|(_, l)| **l != NONE) {
            samples[fill[l as usize]] = g as u32;
            fill[l as usize] += 1;
        }
        Self { starts, samples }
    }

    /// The samples of contour `k`'s region.
    fn of(&self, k: usize) -> &[u32] {
        &self.samples[self.starts[k]..self.starts[k + 1]]
    }
}

/// Per sample, the two distances of Hormann's formula: to the contour of the sample's own region,
/// and to the nearest contour nested in it (with that contour; `NONE` when the children share one
/// height). Infinite where they do not apply.
struct Distances {
    own: Vec<f64>,
    child: Vec<(f64, u32)>,
}

impl Distances {
    /// One transform per parent (and one for the roots), seeded with its children only: it gives
    /// the children's regions their distance to their own contour and the parent's region its
    /// distance to the nearest child, exactly. Parents run in parallel, each thread reusing its
    /// transform buffers.
    fn new(set: &ContourSet, grid: &GridSpec, regions: &Regions) -> Self {
        let parents: Vec<Option<usize>> = std::iter::once(None)
            .chain((0..set.len()).filter(|&k| set.children(k).next().is_some()).map(Some))
            .collect();
        let parts: Vec<ParentDistances> = parents
            .par_iter()
            .map_init(Buffers::default, |buffers, &parent| parent_distances(set, grid, regions, parent, buffers))
            .collect();
        let mut own = vec![f64::INFINITY; grid.len()];
        let mut child = vec![(f64::INFINITY, NONE); grid.len()];
        for ParentDistances { own: to_own, nearest } in parts {
            for (g, d) in to_own {
                own[g as usize] = d;
            }
            for (g, d, c) in nearest {
                child[g as usize] = (d, c);
            }
        }
        Self { own, child }
    }
}

/// The transform of one parent contour (`None`: the closed roots), seeded with its children, read
/// out over the children's regions and the parent's own.
fn parent_distances(
    set: &ContourSet,
    grid: &GridSpec,
    regions: &Regions,
    parent: Option<usize>,
    buffers: &mut Buffers,
) -> ParentDistances {
    let children: Vec<usize> = match parent {
        Some(p) => set.children(p).collect(),
        None => set.roots().filter(|&k| set.contours()[k].closed).collect(),
    };
    let bounds = match parent {
        Some(p) => set.contours()[p].bounds(),
        None => children.iter().map(|&k| set.contours()[k].bounds()).fold(Rect::bounding(&[]), |a, b| a.union(&b)),
    };
    let Some(win) = Window::around(grid, bounds.min, bounds.max) else { return ParentDistances::default() };
    // The nearest child's identity matters only when the children differ in height.
    let first = children.first().map(|&c| set.contours()[c].height);
    let labelled = parent.is_some() && children.iter().any(|&c| Some(set.contours()[c].height) != first);
    let (sq, label) = transform(set, grid, win, &children, labelled, buffers);
    let nearest_default = children.first().map_or(NONE, |&c| c as u32);
    let own: Vec<(u32, f64)> = children
        .iter()
        .flat_map(|&c| regions.of(c).iter().map(|&g| (g, sq[win.local(grid, g as usize)].sqrt())))
        .collect();
    let nearest: Vec<(u32, f64, u32)> = parent.map_or_else(Vec::new, |p| {
        regions
            .of(p)
            .iter()
            .map(|&g| {
                let w = win.local(grid, g as usize);
                (g, sq[w].sqrt(), label.get(w).copied().unwrap_or(nearest_default))
            })
            .collect()
    });
    ParentDistances { own, nearest }
}

/// A rectangle of samples `[i0, i0 + w) × [j0, j0 + h)`.
#[derive(Clone, Copy)]
struct Window {
    i0: usize,
    j0: usize,
    w: usize,
    h: usize,
}

impl Window {
    fn around(grid: &GridSpec, lo: DVec2, hi: DVec2) -> Option<Self> {
        let a = grid.grid_coords(lo);
        let b = grid.grid_coords(hi);
        let i0 = (a.x.floor() - 2.0).max(0.0) as usize;
        let j0 = (a.y.floor() - 2.0).max(0.0) as usize;
        let i1 = ((b.x.ceil() + 3.0).max(0.0) as usize).min(grid.nx());
        let j1 = ((b.y.ceil() + 3.0).max(0.0) as usize).min(grid.ny());
        (i1 > i0 && j1 > j0).then_some(Self { i0, j0, w: i1 - i0, h: j1 - j0 })
    }

    /// Index in the window of grid sample `g` (which must lie inside it).
    fn local(&self, grid: &GridSpec, g: usize) -> usize {
        let (i, j) = grid.coords(g);
        (j - self.j0) * self.w + (i - self.i0)
    }
}

/// Squared distances over a window to the given contours, with nearest-contour labels when
/// `labelled` (otherwise the labels are `NONE`), in buffers reused across calls.
fn transform<'s>(
    set: &ContourSet,
    grid: &GridSpec,
    win: Window,
    sources: &[usize],
    labelled: bool,
    buffers: &'s mut Buffers,
) -> (&'s [f64], &'s [u32]) {
    let Buffers { sq, label, scratch } = buffers;
    sq.clear();
    sq.resize(win.w * win.h, f64::INFINITY);
    label.clear();
    label.resize(if labelled { win.w * win.h } else { 0 }, NONE);
    for &s in sources {
        seed_contour(set, grid, win, s, sq, label);
    }
    distance_transform_seeded_with(
        scratch,
        win.w,
        win.h,
        grid.cell_size(),
        sq,
        labelled.then_some(label.as_mut_slice()),
    );
    (sq, label)
}

/// What one parent's transform yields: `(sample, distance to its own contour)` for the children's
/// regions and `(sample, distance to the nearest child, that child)` for the parent's region.
#[derive(Default)]
struct ParentDistances {
    own: Vec<(u32, f64)>,
    nearest: Vec<(u32, f64, u32)>,
}

/// Per-thread buffers of [`transform`].
#[derive(Default)]
struct Buffers {
    sq: Vec<f64>,
    label: Vec<u32>,
    scratch: DistanceScratch,
}

/// Seeds the samples of `win` near the segments of contour `k` with their exact squared distance
/// to it (keeping the smaller value and its label where seeds overlap).
fn seed_contour(set: &ContourSet, grid: &GridSpec, win: Window, k: usize, sq: &mut [f64], label: &mut [u32]) {
    let cell = grid.cell_size();
    let step = cell.x.min(cell.y);
    for [a, b] in set.contours()[k].segments() {
        let n = (a.distance(b) / step).ceil().max(1.0) as usize;
        for s in 0..=n {
            let g = grid.grid_coords(a + (b - a) * (s as f64 / n as f64)).round();
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (i, j) = (g.x as i64 + di, g.y as i64 + dj);
                    if i < win.i0 as i64
                        || j < win.j0 as i64
                        || i >= (win.i0 + win.w) as i64
                        || j >= (win.j0 + win.h) as i64
                    {
                        continue;
                    }
                    let (i, j) = (i as usize, j as usize);
                    let d2 = segment_distance_sq(grid.position(i, j), a, b);
                    let w = (j - win.j0) * win.w + (i - win.i0);
                    if d2 < sq[w] {
                        sq[w] = d2;
                        if let Some(l) = label.get_mut(w) {
                            *l = k as u32;
                        }
                    }
                }
            }
        }
    }
}

/// Values of region `k`'s samples: Hormann's blend of the distance to its own contour and to the
/// nearest child, or the summit rule when nothing is nested in it.
fn region_values(
    set: &ContourSet,
    grid: &GridSpec,
    k: usize,
    pixels: &[u32],
    d_own: &[f64],
    d_child: &[(f64, u32)],
    summit: Summit<'_>,
) -> Vec<(u32, f64)> {
    let c = &set.contours()[k];
    let h_k = c.height;
    if set.children(k).next().is_some() {
        return pixels
            .iter()
            .map(|&g| {
                let (dk, (dn, child)) = (d_own[g as usize], d_child[g as usize]);
                let h_n = if child == NONE { h_k } else { set.contours()[child as usize].height };
                let v = if dk + dn > 0.0 && dn.is_finite() && dk.is_finite() {
                    (dn * h_k + dk * h_n) / (dk + dn)
                } else {
                    h_k
                };
                (g, v)
            })
            .collect();
    }
    let d_max = pixels.iter().map(|&g| d_own[g as usize]).filter(|d| d.is_finite()).fold(0.0, f64::max);
    let levels = set.levels();
    let l = c.level as usize;
    let step = if l + 1 < levels.len() {
        levels[l + 1] - levels[l]
    } else if l > 0 {
        levels[l] - levels[l - 1]
    } else {
        0.0
    };
    let up = if c.is_counter_clockwise() { 1.0 } else { -1.0 };
    pixels
        .iter()
        .map(|&g| {
            let d = d_own[g as usize];
            let v = match summit {
                Summit::Flat => h_k,
                Summit::Dome => {
                    let t = if d_max > 0.0 && d.is_finite() { d / d_max } else { 0.0 };
                    h_k + up * 0.5 * step * (1.0 - (1.0 - t) * (1.0 - t))
                }
                Summit::Surface(f) => {
                    let (i, j) = grid.coords(g as usize);
                    let s = f(grid.position(i, j));
                    let (lo, hi) = if up > 0.0 { (h_k, h_k + step) } else { (h_k - step, h_k) };
                    if s.is_finite() { s.clamp(lo, hi) } else { h_k }
                }
            };
            (g, v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Contour;

    /// Regression (a shrunk proptest case of `generated_contours_nest_never_cross_and_match_the_histogram`):
    /// a coast contour with an inward spike narrower than a cell left one sample labelled "outside"
    /// inside the land, at the sea's height; as an outlet it stayed a one-cell endorheic pit.
    #[test]
    fn only_sea_and_pit_patches_that_are_real_drain_the_raster() {
        let grid = GridSpec::new(10, 8, DVec2::ZERO, DVec2::ONE).unwrap();
        // Contour 0 is the coast (counter-clockwise), contour 1 a pit (clockwise).
        let ring = |pts: &[[f64; 2]]| pts.iter().map(|&p| DVec2::from(p)).collect::<Vec<_>>();
        let coast = Contour {
            level: 0,
            height: 0.0,
            points: ring(&[[1.0, 1.0], [9.0, 1.0], [9.0, 7.0], [1.0, 7.0]]),
            closed: true,
        };
        let pit = Contour {
            level: 0,
            height: 0.0,
            points: ring(&[[5.0, 2.0], [5.0, 4.0], [7.0, 4.0], [7.0, 2.0]]),
            closed: true,
        };
        let set = ContourSet::new(vec![0.0], vec![coast, pit]).unwrap();
        assert!(!set.contours()[1].is_counter_clockwise(), "contour 1 is a pit");
        let (l, c, p) = (NONE, 0u32, 1u32);
        let at = |i: usize, j: usize| j * 10 + i;
        #[rustfmt::skip]
        let labels = vec![
            l, l, l, l, l, l, l, l, l, l, // the sea along the border: outlets
            l, c, c, c, c, c, c, c, c, l,
            l, c, l, c, c, p, p, c, c, l, // a lone sea sample inside the land: filled
            l, c, c, c, c, p, p, c, c, l, // a pit of four samples: kept
            l, c, c, c, c, c, c, c, c, l,
            l, c, c, p, c, c, c, c, c, l, // a lone pit sample: filled
            l, c, c, c, c, c, c, c, c, l,
            l, l, l, l, l, l, l, l, l, l,
        ];
        let outlet = outlet_mask(&grid, &set, &labels);
        let expected: Vec<bool> = labels
            .iter()
            .enumerate()
            .map(|(k, &label)| match label {
                NONE => k != at(2, 2),
                1 => k != at(3, 5),
                _ => false,
            })
            .collect();
        assert_eq!(outlet, expected);
        // Four or more enclosed sea samples stay sea: a lagoon, not a sliver.
        let mut lagoon = labels.clone();
        for k in [at(3, 2), at(2, 3), at(3, 3)] {
            lagoon[k] = NONE;
        }
        let outlet = outlet_mask(&grid, &set, &lagoon);
        assert!([at(2, 2), at(3, 2), at(2, 3), at(3, 3)].iter().all(|&k| outlet[k]));
        assert_eq!(neighbours(0, 0, 10, 8).count(), 3);
        assert_eq!(neighbours(3, 3, 10, 8).count(), 8);
        assert_eq!(neighbours(9, 2, 10, 8).count(), 5);
    }
}
