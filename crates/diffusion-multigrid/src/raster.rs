//! Rasterization of feature curves into constraint maps (§4.1): strict elevation, gradient norm
//! and direction, noise amplitude and roughness, and what kind of equation each sample obeys.
//! Crossing slope bands are filled afterwards by Laplace solves (`DiffusionProblem::laplace`) on crops
//! around them.

use std::ops::ControlFlow;
use std::sync::Mutex;

use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::GridSpec;
use relief_heightfield::rounding::{ceil, floor};

use crate::DiffusionError;
use crate::curve::{FeatureCurve, Station};
use crate::maps::{CellKind, ConstraintMaps};
use crate::parameters::NOISE_TOLERANCE;
use crate::solver::{DiffusionProblem, SolveOptions};

/// Most samples one feature curve may take when rasterized (a station every half cell): 2^23, a
/// curve thousands of grid widths long. Longer curves are refused with
/// [`DiffusionError::CurveTooLong`] before any is allocated.
pub const MAX_STATIONS: usize = 1 << 23;

/// Accumulators while painting one band of rows `j0..j1` (row-major from row `j0`).
struct Canvas {
    grid: GridSpec,
    j0: usize,
    j1: usize,
    /// Per sample, the sum of the elevations painted and their count.
    elev: Vec<f64>,
    elev_count: Vec<u32>,
    /// Per sample, the sums of the noise amplitudes and roughnesses painted (always together) and
    /// their count.
    amp: Vec<f64>,
    rough: Vec<f64>,
    noise_count: Vec<u32>,
    grad: Vec<(f32, [f32; 2])>,
    writer: Vec<u32>,
    hole: Vec<bool>,
}

const NONE: u32 = u32::MAX;

impl ConstraintMaps {
    /// Rasterizes `curves` on `grid`. Curves are validated first.
    ///
    /// Elevation bands are quads of half-width r (at least ¾ of a cell so the centre line is always
    /// caught) painted with h; slope bands run from r to r + a on the left and r to r + b on the
    /// right, the prescribed slope fading linearly to 0 at their far end. Overlapping strict values
    /// average; overlapping slope bands of different curve sides leave a [`CellKind::Hole`].
    ///
    /// # Errors
    /// The validation errors of [`FeatureCurve::validate`]; [`DiffusionError::GridTooSmall`];
    /// [`DiffusionError::CurveTooLong`] before sampling a curve of more than [`MAX_STATIONS`]
    /// half-cell steps.
    pub fn rasterize(curves: &[FeatureCurve], grid: &GridSpec) -> Result<Self, DiffusionError> {
        Self::rasterize_observed(curves, grid, &mut |_, _| ControlFlow::Continue(()))
    }

    /// [`Self::rasterize`], calling `observe(done, total)` after each batch of hole windows is
    /// filled (`total` windows in all; once with `(0, 0)` when there is no hole);
    /// [`ControlFlow::Break`] stops there.
    ///
    /// # Errors
    /// Those of [`Self::rasterize`]; [`DiffusionError::Cancelled`] when `observe` breaks.
    pub fn rasterize_observed(
        curves: &[FeatureCurve],
        grid: &GridSpec,
        observe: &mut dyn FnMut(usize, usize) -> ControlFlow<()>,
    ) -> Result<Self, DiffusionError> {
        if grid.nx() < 2 || grid.ny() < 2 {
            return Err(DiffusionError::GridTooSmall { nx: grid.nx(), ny: grid.ny() });
        }
        let step = 0.5 * grid.cell_size().x.min(grid.cell_size().y);
        for (k, c) in curves.iter().enumerate() {
            c.validate(k)?;
            let stations = c.samples_at(step);
            if stations.is_nan() || stations > MAX_STATIONS as f64 {
                return Err(DiffusionError::CurveTooLong { curve: k, stations, max: MAX_STATIONS });
            }
        }
        let stations: Vec<(Vec<Station>, bool)> =
            curves.par_iter().map(|c| (c.stations(step), c.has_elevation())).collect();
        // Each band paints every segment's samples in its rows, in curve order: the same
        // accumulation per sample as one canvas over the whole grid, for any number of bands.
        let rows = grid.ny().div_ceil(BANDS).max(MIN_BAND_ROWS);
        let n = grid.len();
        let mut maps = ConstraintMaps {
            grid: *grid,
            kind: vec![CellKind::Free; n],
            elevation: vec![0.0; n],
            gradient: vec![0.0; n],
            normal: vec![[0.0; 2]; n],
            amplitude: vec![0.0; n],
            roughness: vec![0.0; n],
        };
        let pieces = pieces_by_band(grid, &stations, rows);
        let canvases = CanvasPool::new(grid, rows);
        maps.bands(rows).into_par_iter().zip(pieces).enumerate().for_each(|(b, (mut band, pieces))| {
            canvases.with(|canvas| {
                let j0 = b * rows;
                canvas.paint(j0, (j0 + rows).min(grid.ny()), &stations, &pieces);
                canvas.finish(&mut band);
            });
        });
        fill_holes(&mut maps, observe)?;
        Ok(maps)
    }

    /// The maps cut into bands of `rows` rows, top to bottom.
    fn bands(&mut self, rows: usize) -> Vec<Band<'_>> {
        let len = rows * self.grid.nx();
        let mut kind = self.kind.chunks_mut(len);
        let mut elevation = self.elevation.chunks_mut(len);
        let mut gradient = self.gradient.chunks_mut(len);
        let mut normal = self.normal.chunks_mut(len);
        let mut amplitude = self.amplitude.chunks_mut(len);
        let mut roughness = self.roughness.chunks_mut(len);
        std::iter::from_fn(|| {
            Some(Band {
                kind: kind.next()?,
                elevation: elevation.next()?,
                gradient: gradient.next()?,
                normal: normal.next()?,
                amplitude: amplitude.next()?,
                roughness: roughness.next()?,
            })
        })
        .collect()
    }
}

/// The rows of [`ConstraintMaps`] one [`Canvas`] band fills.
struct Band<'a> {
    kind: &'a mut [CellKind],
    elevation: &'a mut [f32],
    gradient: &'a mut [f32],
    normal: &'a mut [[f32; 2]],
    amplitude: &'a mut [f32],
    roughness: &'a mut [f32],
}

/// One segment of a curve to paint: curve `id`, from station `from` to station `to` (the same
/// station twice for a curve of one station).
#[derive(Debug, Clone, Copy)]
struct Piece {
    id: u32,
    from: u32,
    to: u32,
}

/// For each band of `rows` rows, the segments whose paint may reach it, in curve and station
/// order (so each band paints its samples in the same order as one canvas over the whole grid
/// would). Everything a segment paints lies within its stations' largest elevation radius plus
/// slope extent of its two station points.
fn pieces_by_band(grid: &GridSpec, stations: &[(Vec<Station>, bool)], rows: usize) -> Vec<Vec<Piece>> {
    let bands = grid.ny().div_ceil(rows);
    let mut out = vec![Vec::new(); bands];
    let min_r = min_radius(grid);
    let reach = |s: &Station| band_radius(s, min_r) + s.slope.map_or(0.0, |g| g.a.max(g.b).max(0.0));
    for (id, (stations, _)) in stations.iter().enumerate() {
        let pairs = (1..stations.len()).map(|k| (k - 1, k)).chain((stations.len() == 1).then_some((0, 0)));
        for (from, to) in pairs {
            let (a, b) = (&stations[from], &stations[to]);
            let r = reach(a).max(reach(b));
            let (lo, hi) = (a.p.y.min(b.p.y) - r, a.p.y.max(b.p.y) + r);
            let (j_lo, j_hi) = (grid.grid_coords(DVec2::new(0.0, lo)).y, grid.grid_coords(DVec2::new(0.0, hi)).y);
            if !(j_lo.is_finite() && j_hi.is_finite()) || j_hi < -1.0 || j_lo > grid.ny() as f64 {
                continue;
            }
            let first = (floor(j_lo) - 1.0).max(0.0) as usize / rows;
            let last = ((ceil(j_hi) + 1.0).min(grid.ny() as f64 - 1.0).max(0.0) as usize / rows).min(bands - 1);
            let piece = Piece { id: id as u32, from: from as u32, to: to as u32 };
            for band in &mut out[first..=last] {
                band.push(piece);
            }
        }
    }
    out
}

/// The least half-width of a curve's elevation and noise bands on `grid`: ¾ of a cell, so the
/// centre line is always caught.
fn min_radius(grid: &GridSpec) -> f64 {
    0.75 * grid.cell_size().max_element()
}

/// The half-width of the elevation and noise bands at station `s`: its elevation radius r, at
/// least `min_r`. The slope bands start there.
fn band_radius(s: &Station, min_r: f64) -> f64 {
    s.elevation.map_or(0.0, |e| e.r).max(min_r)
}

/// One [`Canvas`] per worker thread, made on its first band and cleared for each next one.
/// `for_each_init` made one per job rayon split the bands into (16–20 for 32 bands on two
/// threads), and each fresh canvas costs a page fault per 4 KiB of its 49 bytes a sample: the
/// volcanic island's first rasterization at 2048² in a fresh process took 100 k page faults, with
/// the pool and this layout 71 k (the CLI's allocator settings already reuse freed canvases).
struct CanvasPool {
    grid: GridSpec,
    rows: usize,
    slots: Vec<Mutex<Option<Canvas>>>,
}

impl CanvasPool {
    /// An empty pool for bands of up to `rows` rows of `grid`, one slot per thread of the pool.
    fn new(grid: &GridSpec, rows: usize) -> Self {
        let slots = (0..rayon::current_num_threads().max(1)).map(|_| Mutex::new(None)).collect();
        Self { grid: *grid, rows, slots }
    }

    /// Runs `f` on the calling thread's canvas; on a fresh one when that is busy (a thread that
    /// took another band while waiting inside `f`) or outside the pool.
    fn with(&self, f: impl FnOnce(&mut Canvas)) {
        let slot = rayon::current_thread_index().and_then(|t| self.slots.get(t));
        match slot.map(Mutex::try_lock) {
            Some(Ok(mut canvas)) => f(canvas.get_or_insert_with(|| Canvas::new(&self.grid, self.rows))),
            _ => f(&mut Canvas::new(&self.grid, self.rows)),
        }
    }
}

/// Bands of rows the painting is split into (at most), so that a few run on each core.
const BANDS: usize = 32;

/// Fewest rows in a band: thinner ones would repeat every segment's set-up for little work.
const MIN_BAND_ROWS: usize = 16;

impl Canvas {
    /// An empty canvas for bands of up to `rows` rows of `grid`.
    fn new(grid: &GridSpec, rows: usize) -> Self {
        let n = rows * grid.nx();
        Canvas {
            grid: *grid,
            j0: 0,
            j1: 0,
            elev: vec![0.0; n],
            elev_count: vec![0; n],
            amp: vec![0.0; n],
            rough: vec![0.0; n],
            noise_count: vec![0; n],
            grad: vec![(0.0, [0.0, 0.0]); n],
            writer: vec![NONE; n],
            hole: vec![false; n],
        }
    }

    /// Clears the canvas and paints `pieces` of the curves' stations (each with whether its curve
    /// is anchored by an elevation) on rows `j0..j1` of the grid, at most the rows it was made for.
    fn paint(&mut self, j0: usize, j1: usize, stations: &[(Vec<Station>, bool)], pieces: &[Piece]) {
        let n = (j1 - j0) * self.grid.nx();
        (self.j0, self.j1) = (j0, j1);
        self.elev[..n].fill(0.0);
        self.elev_count[..n].fill(0);
        self.amp[..n].fill(0.0);
        self.rough[..n].fill(0.0);
        self.noise_count[..n].fill(0);
        self.grad[..n].fill((0.0, [0.0, 0.0]));
        self.writer[..n].fill(NONE);
        self.hole[..n].fill(false);
        let min_r = min_radius(&self.grid);
        for p in pieces {
            let (curve, anchored) = &stations[p.id as usize];
            self.segment(p.id, *anchored, curve[p.from as usize], curve[p.to as usize], min_r);
        }
    }

    /// Paints one segment of a curve: the elevation band, the two slope bands, the noise.
    fn segment(&mut self, id: u32, anchored: bool, s0: Station, s1: Station, min_r: f64) {
        let (r0, r1) = (band_radius(&s0, min_r), band_radius(&s1, min_r));
        for side in [1.0, -1.0] {
            let (o0, o1) = (s0.left * side, s1.left * side);
            let band = [s0.p, s1.p, s1.p + o1 * r1, s0.p + o0 * r0];
            // The elevation and the noise share the band: one pass paints both.
            let (elevation, noise) = (s0.elevation.zip(s1.elevation), s0.noise.zip(s1.noise));
            if elevation.is_some() || noise.is_some() {
                self.quad(band, |w| Paint::Band {
                    elevation: elevation.map(|(e0, e1)| w[0] * e0.h + w[1] * e1.h + w[2] * e1.h + w[3] * e0.h),
                    noise: noise.map(|(n0, n1)| {
                        let a = (w[0] + w[3]) * n0.amplitude + (w[1] + w[2]) * n1.amplitude;
                        let rr = (w[0] + w[3]) * n0.roughness + (w[1] + w[2]) * n1.roughness;
                        (a, rr)
                    }),
                });
            }
            if let (Some(g0), Some(g1)) = (s0.slope, s1.slope) {
                let (ext0, ext1, ang0, ang1) =
                    if side > 0.0 { (g0.a, g1.a, g0.theta, g1.theta) } else { (g0.b, g1.b, g0.phi, g1.phi) };
                if ext0 <= 0.0 && ext1 <= 0.0 {
                    continue;
                }
                let outer = [s0.p + o0 * r0, s1.p + o1 * r1, s1.p + o1 * (r1 + ext1), s0.p + o0 * (r0 + ext0)];
                let (t0, t1) = (ang0.to_radians().tan(), ang1.to_radians().tan());
                let writer = 2 * id + u32::from(side < 0.0);
                let cell = self.grid.cell_size();
                self.quad(outer, |w| {
                    // Slope (descending away from the curve) fading to 0 at the far edge.
                    let s = w[0] * t0 + w[1] * t1;
                    let out = ((w[0] + w[3]) * o0 + (w[1] + w[2]) * o1).normalize_or_zero();
                    // Anchored curves propagate their elevation outwards (n outward, F falls by
                    // s per unit length); free-standing ones inwards (the paper's inversion).
                    let n = if anchored { out } else { -out };
                    let sign = if anchored { -1.0 } else { 1.0 };
                    // The upwind neighbours sit one step along x and y, weighted n²: one grid
                    // step covers |nx|³·dx + |ny|³·dy of distance along n.
                    let reach = n.x.abs().powi(3) * cell.x + n.y.abs().powi(3) * cell.y;
                    Paint::Gradient(writer, (sign * s * reach) as f32, [n.x as f32, n.y as f32])
                });
            }
        }
    }

    /// Paints the samples inside quad `q` (corners in order), with bilinear-like weights of the
    /// four corners from its two triangles' barycentric coordinates.
    fn quad(&mut self, q: [DVec2; 4], paint: impl Fn([f64; 4]) -> Paint) {
        self.quad_scanned(q, paint, None);
    }

    /// [`Self::quad`], each triangle scanned by rows (`Some(false)`), by columns (`Some(true)`) or
    /// (`None`) by whichever crosses it fewer times: the slices of a slope band between two
    /// stations, half a cell apart, are long and thin, and a row scan across one running along the
    /// rows finds no sample on most rows. On `volcanic-island-48` at 2048² rows alone scanned 5.65 M
    /// lines for 2.1 M samples, the choice 4.07 M (`mountain`: 15.0 M and 12.7 M lines for
    /// 4.9 M samples); the time saved is within this VM's noise, a few per cent of the painting.
    /// Either scan paints the samples inside with the same weights; they can differ only on a
    /// sample within 10⁻⁹ of a cell of an edge (the golden scenes' bits did not change).
    fn quad_scanned(&mut self, q: [DVec2; 4], paint: impl Fn([f64; 4]) -> Paint, by_columns: Option<bool>) {
        let (nx, j_end) = (self.grid.nx() as f64, self.j1 as f64);
        for t in [[0, 1, 2], [0, 2, 3]] {
            let (a, b, c) = (q[t[0]], q[t[1]], q[t[2]]);
            let area = (b - a).perp_dot(c - a);
            if area.abs() < 1e-12 {
                continue;
            }
            let g = [self.grid.grid_coords(a), self.grid.grid_coords(b), self.grid.grid_coords(c)];
            let (lo, hi) = (g[0].min(g[1]).min(g[2]), g[0].max(g[1]).max(g[2]));
            let (j0, j1) = (ceil(lo.y).max(self.j0 as f64), floor(hi.y).min(j_end - 1.0));
            if j1 < j0 {
                continue;
            }
            let mut sample = |i: usize, j: usize| {
                let p = self.grid.position(i, j);
                let l0 = ((b - p).perp_dot(c - p) / area).clamp(0.0, 1.0);
                let l1 = ((c - p).perp_dot(a - p) / area).clamp(0.0, 1.0);
                let l2 = (1.0 - l0 - l1).max(0.0);
                // A sample on the shared diagonal is painted twice with the same values.
                let k = (j - self.j0) * self.grid.nx() + i;
                let mut w = [0.0; 4];
                w[t[0]] += l0;
                w[t[1]] += l1;
                w[t[2]] += l2;
                self.apply(k, paint(w));
            };
            // Columns cross the whole triangle, rows only the band's: fewer columns than rows here.
            if by_columns.unwrap_or(hi.x - lo.x < j1 - j0) {
                let (i0, i1) = (ceil(lo.x).max(0.0), floor(hi.x).min(nx - 1.0));
                if i1 < i0 {
                    continue;
                }
                let across = g.map(|p| DVec2::new(p.y, p.x));
                for i in i0 as usize..=i1 as usize {
                    let (ylo, yhi) = span(across, i as f64);
                    let (ja, jb) = (ceil(ylo - 1e-9).max(j0), floor(yhi + 1e-9).min(j1));
                    if jb < ja {
                        continue;
                    }
                    for j in ja as usize..=jb as usize {
                        sample(i, j);
                    }
                }
            } else {
                // Scanlines: per sample row, the span of i the triangle covers (area-proportional
                // work, unlike a bounding box around a long slanted band).
                for j in j0 as usize..=j1 as usize {
                    let (xlo, xhi) = span(g, j as f64);
                    let (i0, i1) = (ceil(xlo - 1e-9).max(0.0), floor(xhi + 1e-9).min(nx - 1.0));
                    if i1 < i0 {
                        continue;
                    }
                    for i in i0 as usize..=i1 as usize {
                        sample(i, j);
                    }
                }
            }
        }
    }

    fn apply(&mut self, k: usize, paint: Paint) {
        match paint {
            Paint::Band { elevation, noise } => {
                if let Some(h) = elevation {
                    self.elev[k] += h;
                    self.elev_count[k] += 1;
                }
                if let Some((a, r)) = noise {
                    self.amp[k] += a;
                    self.rough[k] += r;
                    self.noise_count[k] += 1;
                }
            }
            Paint::Gradient(writer, g, n) => {
                if self.writer[k] == NONE || self.writer[k] == writer {
                    self.writer[k] = writer;
                    self.grad[k] = (g, n);
                } else {
                    self.hole[k] = true;
                }
            }
        }
    }

    /// Writes the band's rows of the maps: the means of what was painted, and each sample's kind.
    fn finish(&self, band: &mut Band<'_>) {
        // Most samples take one value or none: no division for them (s / 1 is s, bit for bit).
        let mean = |s: f64, c: u32| match c {
            0 => f32::NAN,
            1 => s as f32,
            _ => (s / f64::from(c)) as f32,
        };
        for k in 0..band.kind.len() {
            let elevation = mean(self.elev[k], self.elev_count[k]);
            band.elevation[k] = elevation;
            band.kind[k] = if !elevation.is_nan() {
                CellKind::Elevation
            } else if self.hole[k] {
                CellKind::Hole
            } else if self.writer[k] != NONE {
                CellKind::Gradient
            } else {
                CellKind::Free
            };
            (band.gradient[k], band.normal[k]) = self.grad[k];
            band.amplitude[k] = mean(self.amp[k], self.noise_count[k]);
            band.roughness[k] = mean(self.rough[k], self.noise_count[k]);
        }
    }
}

/// The range of x that triangle `g` (grid coordinates) covers on the line at `y`: from the
/// edges that cross it (an edge along the line gives both its ends); empty (`lo > hi`) when none
/// does.
fn span(g: [DVec2; 3], y: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (p, q) in [(g[0], g[1]), (g[1], g[2]), (g[2], g[0])] {
        if (p.y <= y && y <= q.y) || (q.y <= y && y <= p.y) {
            let along = (q.y - p.y).abs() < 1e-12;
            let x = if along { p.x.min(q.x) } else { p.x + (y - p.y) / (q.y - p.y) * (q.x - p.x) };
            let x2 = if along { p.x.max(q.x) } else { x };
            lo = lo.min(x);
            hi = hi.max(x2);
        }
    }
    (lo, hi)
}

/// What one sample of a quad receives.
#[derive(Clone, Copy)]
enum Paint {
    /// The elevation band's elevation and noise (amplitude, roughness), where the curve has them.
    Band { elevation: Option<f64>, noise: Option<(f64, f64)> },
    /// A slope band: its writer (curve and side), gradient step and normal.
    Gradient(u32, f32, [f32; 2]),
}

/// Fills the gradient and normal of hole samples by Laplace diffusion (the paper's rule for
/// crossing slope bands). Where the diffused normals of antagonistic bands cancel, the filled
/// normal is short; renormalised to unit length it would point anywhere, and a descent chain
/// that loops digs a pit (a five-ridge summit sank to −1 200 m that way). So the normal keeps the
/// diffused direction but not more than unit length, and the slope is scaled by its squared
/// length: a coherent fill keeps the full constraint, a cancelled one fades to plain Laplace. Each
/// 4-connected group of holes is solved on its bounding box grown by a margin (windows that share
/// samples are solved as one, [`merge_overlapping`]), with the slope samples there as fixed values
/// and everything else free, by the same multigrid solver as the elevation.
///
/// The solves read only slope samples, which no fill changes, so they run in parallel (a few
/// windows at a time, to bound the memory their solutions take); the fills are then written in
/// the order of the groups, the same for any thread count.
fn fill_holes(
    maps: &mut ConstraintMaps,
    observe: &mut dyn FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(), DiffusionError> {
    let (nx, ny) = (maps.grid.nx(), maps.grid.ny());
    let mut seen = vec![false; nx * ny];
    let mut stack = Vec::new();
    let mut windows = Vec::new();
    for start in 0..nx * ny {
        if seen[start] || maps.kind[start] != CellKind::Hole {
            continue;
        }
        let group = hole_group_bounds(maps, start, &mut seen, &mut stack);
        windows.extend(Window::around(group, nx, ny));
    }
    let windows = merge_overlapping(windows);
    if windows.is_empty() && observe(0, 0).is_break() {
        return Err(DiffusionError::Cancelled);
    }
    for (b, batch) in windows.chunks(WINDOWS_AT_ONCE).enumerate() {
        let fills: Vec<Fill> = batch.par_iter().map(|window| Fill::solve(maps, window)).collect();
        for (window, fill) in batch.iter().zip(&fills) {
            fill.write(maps, window);
        }
        if observe(b * WINDOWS_AT_ONCE + batch.len(), windows.len()).is_break() {
            return Err(DiffusionError::Cancelled);
        }
    }
    Ok(())
}

/// Hole windows solved at once by [`fill_holes`].
const WINDOWS_AT_ONCE: usize = 8;

/// Windows that share samples, solved apart, diffuse those samples once each: on a mountain range
/// the windows of neighbouring hole groups covered 2.7 times the samples of their union. So each
/// set of windows linked by shared samples becomes one window, their bounding box, when that box
/// has no more samples than they have in all; a set whose box would be larger stays as it was
/// (the same windows, in the same order). A merged window diffuses over a larger part of the grid,
/// closer to the paper's diffusion of the whole map.
///
/// The sets are found row by row: each row's spans of windows, sorted, join the sets of the spans
/// they overlap; the work is one span per window row, bounded by the windows' own solves. The
/// result is in the order of each set's first window, the same for any thread count.
fn merge_overlapping(windows: Vec<Window>) -> Vec<Window> {
    let Some(nx) = windows.first().map(|w| w.nx) else {
        return windows;
    };
    let mut parent: Vec<usize> = (0..windows.len()).collect();
    let rows = windows.iter().map(|w| w.j0 + w.h).max().unwrap_or(0);
    let mut spans: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); rows];
    for (k, w) in windows.iter().enumerate() {
        for row in &mut spans[w.j0..w.j0 + w.h] {
            row.push((w.i0, w.i0 + w.w, k));
        }
    }
    for row in &mut spans {
        row.sort_unstable();
        let mut run: Option<(usize, usize)> = None;
        for &(i0, i1, k) in row.iter() {
            match run {
                Some((end, first)) if i0 < end => {
                    union(&mut parent, first, k);
                    run = Some((end.max(i1), first));
                }
                _ => run = Some((i1, k)),
            }
        }
    }
    let mut sets: Vec<([usize; 4], usize, Vec<usize>)> = Vec::new();
    let mut slot = vec![usize::MAX; windows.len()];
    for (k, w) in windows.iter().enumerate() {
        let root = find(&mut parent, k);
        if slot[root] == usize::MAX {
            slot[root] = sets.len();
            sets.push(([w.i0, w.j0, w.i0 + w.w, w.j0 + w.h], 0, Vec::new()));
        }
        let (b, area, members) = &mut sets[slot[root]];
        *b = [b[0].min(w.i0), b[1].min(w.j0), b[2].max(w.i0 + w.w), b[3].max(w.j0 + w.h)];
        *area += w.w * w.h;
        members.push(k);
    }
    let mut merged = Vec::with_capacity(sets.len());
    for ([i0, j0, i1, j1], area, members) in sets {
        if members.len() > 1 && (i1 - i0) * (j1 - j0) <= area {
            merged.push(Window { i0, j0, w: i1 - i0, h: j1 - j0, nx });
        } else {
            merged.extend(members.iter().map(|&k| windows[k]));
        }
    }
    merged
}

/// The root of `k`'s set, halving the path on the way.
fn find(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

/// Joins the sets of `a` and `b` under the smaller root (so a set's root is its first window).
fn union(parent: &mut [usize], a: usize, b: usize) {
    let (a, b) = (find(parent, a), find(parent, b));
    parent[a.max(b)] = a.min(b);
}

/// Marks the 4-connected group of holes containing `start` as `seen` (depth-first, on `stack`)
/// and returns its bounding box `[i0, j0, i1, j1]`, bounds included.
fn hole_group_bounds(maps: &ConstraintMaps, start: usize, seen: &mut [bool], stack: &mut Vec<usize>) -> [usize; 4] {
    let (nx, ny) = (maps.grid.nx(), maps.grid.ny());
    let (mut i0, mut j0, mut i1, mut j1) = (nx, ny, 0, 0);
    seen[start] = true;
    stack.push(start);
    while let Some(k) = stack.pop() {
        let (i, j) = (k % nx, k / nx);
        (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
            let (a, b) = (i as i64 + di, j as i64 + dj);
            if a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64 {
                let w = b as usize * nx + a as usize;
                if !seen[w] && maps.kind[w] == CellKind::Hole {
                    seen[w] = true;
                    stack.push(w);
                }
            }
        }
    }
    [i0, j0, i1, j1]
}

/// The crop of the grid one group of holes is filled on.
#[derive(Clone, Copy)]
struct Window {
    /// Column of the crop's first sample in the full grid.
    i0: usize,
    /// Row of the crop's first sample in the full grid.
    j0: usize,
    /// Samples along x.
    w: usize,
    /// Samples along y.
    h: usize,
    /// Samples along x of the full grid.
    nx: usize,
}

impl Window {
    /// The group's bounding box `[i0, j0, i1, j1]` grown by a margin of 2 plus a quarter of its
    /// larger side, clamped to the `nx × ny` grid; `None` when narrower than 2 samples (nothing
    /// to diffuse on).
    fn around([i0, j0, i1, j1]: [usize; 4], nx: usize, ny: usize) -> Option<Self> {
        let margin = 2 + (i1 - i0).max(j1 - j0) / 4;
        let (i0, j0) = (i0.saturating_sub(margin), j0.saturating_sub(margin));
        let (i1, j1) = ((i1 + margin).min(nx - 1), (j1 + margin).min(ny - 1));
        let (w, h) = (i1 - i0 + 1, j1 - j0 + 1);
        (w >= 2 && h >= 2).then_some(Self { i0, j0, w, h, nx })
    }

    /// Index in the full grid of crop sample `c` (row-major in the crop).
    fn full_index(&self, c: usize) -> usize {
        (self.j0 + c / self.w) * self.nx + self.i0 + c % self.w
    }
}

/// The gradient step and both normal components diffused over one window; `None` where a solve
/// failed (no slope sample in the window).
struct Fill {
    gradient: Option<Vec<f32>>,
    x: Option<Vec<f32>>,
    y: Option<Vec<f32>>,
}

impl Fill {
    /// The three solves of `window`, side by side, each to a relative residual of
    /// [`NOISE_TOLERANCE`].
    fn solve(maps: &ConstraintMaps, window: &Window) -> Self {
        let values = |field: &(dyn Fn(usize) -> f32 + Sync)| -> Vec<f32> {
            let mut out = vec![0.0; window.w * window.h];
            out.par_chunks_mut(window.w).enumerate().for_each(|(r, row)| {
                let k0 = window.full_index(r * window.w);
                for (o, k) in row.iter_mut().zip(k0..) {
                    *o = if maps.kind[k] == CellKind::Gradient { field(k) } else { f32::NAN };
                }
            });
            out
        };
        // The three fields are fixed on the same slope samples: one hierarchy serves them all.
        let Some(problem) = DiffusionProblem::laplace(window.w, window.h, &values(&|k| maps.gradient[k])) else {
            return Self { gradient: None, x: None, y: None };
        };
        let options = SolveOptions { tolerance: NOISE_TOLERANCE, ..SolveOptions::default() };
        let solve = |p: &DiffusionProblem| p.solve(&options).ok().map(|(x, _)| x);
        let like =
            |field: &(dyn Fn(usize) -> f32 + Sync)| problem.laplace_like(&values(field)).as_ref().and_then(solve);
        let (gradient, (x, y)) = rayon::join(
            || solve(&problem),
            || rayon::join(|| like(&|k| maps.normal[k][0]), || like(&|k| maps.normal[k][1])),
        );
        Self { gradient, x, y }
    }

    /// Writes the fill into the window's holes: the normal capped at unit length, the step scaled
    /// by the cap's square; zeros for a failed solve.
    fn write(&self, maps: &mut ConstraintMaps, window: &Window) {
        let (g, x, y) = (&self.gradient, &self.x, &self.y);
        let (nx, w) = (window.nx, window.w);
        let rows = window.j0 * nx..(window.j0 + window.h) * nx;
        let kind = maps.kind[rows.clone()].par_chunks(nx);
        let gradient = maps.gradient[rows.clone()].par_chunks_mut(nx);
        let normal = maps.normal[rows].par_chunks_mut(nx);
        kind.zip(gradient).zip(normal).enumerate().for_each(|(r, ((kind, gradient), normal))| {
            let span = window.i0..window.i0 + w;
            let cells = kind[span.clone()].iter().zip(&mut gradient[span.clone()]).zip(&mut normal[span]);
            for (c, ((kind, gradient), normal)) in (r * w..).zip(cells) {
                if *kind != CellKind::Hole {
                    continue;
                }
                let (a, b) = (x.as_ref().map_or(0.0, |x| x[c]), y.as_ref().map_or(0.0, |y| y[c]));
                let len = a.hypot(b);
                let keep = len.min(1.0);
                *normal = if len > 1e-6 { [a / len * keep, b / len * keep] } else { [0.0, 0.0] };
                *gradient = g.as_ref().map_or(0.0, |g| g[c]) * (keep * keep);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A worker thread gets its own canvas back, as the last band left it; a thread outside the
    /// pool, or one whose canvas is in use, a fresh one.
    #[test]
    fn each_worker_paints_on_its_own_canvas() {
        let grid = GridSpec::new(8, 8, DVec2::ZERO, DVec2::ONE).unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let canvases = pool.install(|| CanvasPool::new(&grid, 4));
        assert_eq!(canvases.slots.len(), 2);
        pool.install(|| {
            canvases.with(|canvas| canvas.j0 = 7);
            canvases.with(|canvas| {
                assert_eq!(canvas.j0, 7, "the same canvas");
                canvases.with(|inner| assert_eq!(inner.j0, 0, "a fresh one while it is in use"));
            });
        });
        canvases.with(|canvas| assert_eq!(canvas.j0, 0, "outside the pool"));
    }

    /// Scanning a triangle by columns paints the same samples with the same weights as by rows:
    /// thin slivers (a slope band's slice between two stations) and wide quads in every
    /// direction, partly off the grid and across the band's first and last rows, on a grid of
    /// unequal cell sides.
    #[test]
    fn column_scans_paint_what_row_scans_paint() {
        let grid = GridSpec::new(61, 47, DVec2::new(-5.0, 3.0), DVec2::new(1.7, 2.3)).unwrap();
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let quads: Vec<[DVec2; 4]> = (0..400)
            .map(|q| {
                let centre = DVec2::new(-20.0 + 140.0 * next(), -10.0 + 130.0 * next());
                let along = DVec2::from_angle(std::f64::consts::TAU * next());
                let (long, wide) = if q % 2 == 0 {
                    (2.0 + 60.0 * next(), 0.2 + next())
                } else {
                    (1.0 + 9.0 * next(), 1.0 + 9.0 * next())
                };
                let (l, w) = (along * long * 0.5, along.perp() * wide * 0.5);
                let mut jitter = |p: DVec2| p + DVec2::new(next() - 0.5, next() - 0.5) * 0.3;
                [jitter(centre - l - w), jitter(centre - l + w), jitter(centre + l + w), jitter(centre + l - w)]
            })
            .collect();
        let paint = |by_columns: Option<bool>| {
            let mut canvas = Canvas::new(&grid, 35);
            (canvas.j0, canvas.j1) = (5, 40);
            for (q, quad) in quads.iter().enumerate() {
                if q % 3 == 0 {
                    let paint = |w: [f64; 4]| Paint::Gradient(q as u32 % 4, w[0] as f32, [w[1] as f32, w[2] as f32]);
                    canvas.quad_scanned(*quad, paint, by_columns);
                } else {
                    let paint = |w: [f64; 4]| Paint::Band {
                        elevation: Some(w[0] + 2.0 * w[1] + 3.0 * w[2] + 4.0 * w[3]),
                        noise: Some((w[0] - w[3], w[1] * w[2])),
                    };
                    canvas.quad_scanned(*quad, paint, by_columns);
                }
            }
            let sums = |v: &[f64], c: &[u32]| v.iter().zip(c).map(|(s, c)| (s.to_bits(), *c)).collect::<Vec<_>>();
            let grad =
                canvas.grad.iter().map(|(g, n)| [g.to_bits(), n[0].to_bits(), n[1].to_bits()]).collect::<Vec<_>>();
            (
                sums(&canvas.elev, &canvas.elev_count),
                sums(&canvas.amp, &canvas.noise_count),
                sums(&canvas.rough, &canvas.noise_count),
                grad,
                canvas.writer.clone(),
                canvas.hole.clone(),
            )
        };
        let rows = paint(Some(false));
        let painted = rows.0.iter().filter(|(_, c)| *c > 0).count();
        assert!(painted > 500, "{painted} samples painted");
        assert!(rows.5.iter().any(|&h| h), "some slope quads overlap");
        assert!(rows == paint(Some(true)), "by columns");
        assert!(rows == paint(None), "each triangle along its longer side");
    }

    fn window(i0: usize, j0: usize, w: usize, h: usize) -> Window {
        Window { i0, j0, w, h, nx: 64 }
    }

    fn boxes(windows: &[Window]) -> Vec<[usize; 4]> {
        windows.iter().map(|w| [w.i0, w.j0, w.w, w.h]).collect()
    }

    #[test]
    fn windows_sharing_samples_merge_when_their_box_is_no_larger() {
        let merged = merge_overlapping(vec![
            // A chain: the first shares samples with the second, the second with the third, the
            // first not with the third; their box (26 × 5) is smaller than they are (150).
            window(2, 20, 10, 5),
            // Apart from everything.
            window(40, 40, 10, 10),
            window(10, 20, 10, 5),
            // One sample shared at a corner: the box (19 × 19) would be larger than both (200).
            window(30, 0, 10, 10),
            window(39, 9, 10, 10),
            window(18, 20, 10, 5),
            // Side by side without a shared sample: apart.
            window(0, 50, 5, 5),
            window(5, 50, 5, 5),
        ]);
        assert_eq!(
            boxes(&merged),
            [[2, 20, 26, 5], [40, 40, 10, 10], [30, 0, 10, 10], [39, 9, 10, 10], [0, 50, 5, 5], [5, 50, 5, 5]]
        );
        // Windows on the first rows only.
        assert_eq!(boxes(&merge_overlapping(vec![window(0, 0, 4, 3), window(2, 0, 4, 3)])), [[0, 0, 6, 3]]);
        assert!(merge_overlapping(Vec::new()).is_empty());
    }

    /// Maps of an `nx × ny` grid of unit cells with nothing painted.
    fn unpainted(nx: usize, ny: usize) -> ConstraintMaps {
        ConstraintMaps {
            grid: GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap(),
            kind: vec![CellKind::Free; nx * ny],
            elevation: vec![f32::NAN; nx * ny],
            gradient: vec![0.0; nx * ny],
            normal: vec![[0.0; 2]; nx * ny],
            amplitude: vec![f32::NAN; nx * ny],
            roughness: vec![f32::NAN; nx * ny],
        }
    }

    /// 24 × 16 samples: slope columns 6–8 (step 1, normal east) and 15–17 (step 3, normal north),
    /// and two groups of holes between them whose windows share columns 11 and 12.
    fn two_hole_groups() -> ConstraintMaps {
        let (nx, ny) = (24, 16);
        let mut maps = unpainted(nx, ny);
        for j in 0..ny {
            for (i0, step, normal) in [(6, 1.0, [1.0, 0.0]), (15, 3.0, [0.0, 1.0])] {
                for i in i0..i0 + 3 {
                    let k = j * nx + i;
                    (maps.kind[k], maps.gradient[k], maps.normal[k]) = (CellKind::Gradient, step, normal);
                }
            }
        }
        for j in 6..10 {
            for i in [9, 10, 13, 14] {
                maps.kind[j * nx + i] = CellKind::Hole;
            }
        }
        maps
    }

    /// 96 × 64 samples: diagonal slope bands one sample wide whose steps and normals change along
    /// them, and a block of holes: a window where the solver's tolerance decides the fill (its
    /// full multigrid start lands between 10⁻³ and 10⁻² of the initial residual).
    fn wide_holes() -> ConstraintMaps {
        let (nx, ny) = (96, 64);
        let mut maps = unpainted(nx, ny);
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                if (i + 2 * j) % 23 == 0 || (3 * i + j) % 29 == 0 {
                    let t = (i as f32 * 0.37 + j as f32 * 0.11).sin();
                    (maps.kind[k], maps.gradient[k], maps.normal[k]) =
                        (CellKind::Gradient, 1.0 + t, [t, 1.0 - t.abs()]);
                } else if (20..44).contains(&j) && (30..66).contains(&i) {
                    maps.kind[k] = CellKind::Hole;
                }
            }
        }
        maps
    }

    /// Each field of a fill is its Laplace solve to [`NOISE_TOLERANCE`], bit for bit; a tighter
    /// or a looser tolerance gives other values on this window.
    #[test]
    fn fills_are_solved_to_the_noise_tolerance() {
        let maps = wide_holes();
        let window = Window { i0: 0, j0: 0, w: 96, h: 64, nx: 96 };
        let fill = Fill::solve(&maps, &window);
        let fixed = |k: usize, v: f32| if maps.kind[k] == CellKind::Gradient { v } else { f32::NAN };
        let fields: [Vec<f32>; 3] = [
            (0..maps.kind.len()).map(|k| fixed(k, maps.gradient[k])).collect(),
            (0..maps.kind.len()).map(|k| fixed(k, maps.normal[k][0])).collect(),
            (0..maps.kind.len()).map(|k| fixed(k, maps.normal[k][1])).collect(),
        ];
        let solved = |values: &[f32], tolerance: f64| {
            let options = SolveOptions { tolerance, ..SolveOptions::default() };
            DiffusionProblem::laplace(96, 64, values).unwrap().solve(&options).unwrap().0
        };
        for (field, values) in [&fill.gradient, &fill.x, &fill.y].into_iter().zip(&fields) {
            let field = field.as_ref().unwrap();
            assert!(field == &solved(values, 1e-3), "the fill is the solve to 1e-3");
            assert!(field != &solved(values, 1e-4) && field != &solved(values, 1e-2), "the tolerance decides");
        }
    }

    #[test]
    fn overlapping_hole_windows_are_filled_by_one_diffusion() {
        let mut maps = two_hole_groups();
        let before = maps.clone();
        fill_holes(&mut maps, &mut |_, _| ControlFlow::Continue(())).unwrap();
        // The groups' windows (columns 7–12 and 11–16, rows 4–11) are one window: what one
        // diffusion over both gives.
        let (nx, ny) = (24, 16);
        let apart = [[9, 6, 10, 9], [13, 6, 14, 9]].map(|group| Window::around(group, nx, ny).unwrap());
        assert_eq!(boxes(&apart), [[7, 4, 6, 8], [11, 4, 6, 8]]);
        let both = Window { i0: 7, j0: 4, w: 10, h: 8, nx };
        let mut expected = before.clone();
        Fill::solve(&before, &both).write(&mut expected, &both);
        assert_eq!((&maps.gradient, &maps.normal), (&expected.gradient, &expected.normal));
        // Each window on its own sees one slope band only, and its holes take that band's step and
        // normal; one diffusion over both bands blends them.
        let mut separate = before.clone();
        for window in &apart {
            Fill::solve(&before, window).write(&mut separate, window);
        }
        let (k, l) = (7 * nx + 10, 7 * nx + 13);
        let took = |m: &ConstraintMaps, k: usize, step: f32, [x, y]: [f32; 2]| {
            let [a, b] = m.normal[k];
            (m.gradient[k] - step).abs() < 1e-5 && (a - x).abs() < 1e-5 && (b - y).abs() < 1e-5
        };
        assert!(took(&separate, k, 1.0, [1.0, 0.0]) && took(&separate, l, 3.0, [0.0, 1.0]));
        for k in [k, l] {
            let [x, y] = maps.normal[k];
            assert!(x > 0.1 && y > 0.1, "between east and north: {:?}", maps.normal[k]);
        }
        assert!(maps.gradient[l] < 2.0, "the steps blend: {}", maps.gradient[l]);
    }
}
