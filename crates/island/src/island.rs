//! The island model: a coastline, hills and filters, and the three grids of §5.1 (heights, hills,
//! filters) whose sum is the terrain.

use glam::DVec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use relief_heightfield::{GridSpec, Heightfield, distance_transform_seeded};
use relief_poisson_sampling::{ring_contains, signed_area};
use serde::{Deserialize, Serialize};

use crate::IslandError;
use crate::geometry::{Coast, EditKind, nearest_on_boundary, simple_polygon};
use crate::hill::{Hill, Shape};

/// The most samples an island grid may hold: 2²⁵ (a 5792² grid). An island keeps about 25 bytes
/// per sample, so this caps it near 850 MB.
pub const MAX_CELLS: usize = 1 << 25;

/// The largest height a setting or a hill may give, world units (10 000 km). The grids hold f32
/// samples: far larger heights, and the sums of many, would overflow them.
pub const MAX_HEIGHT: f64 = 1.0e7;

/// The largest side of an island's domain, world units (a million km): the perturbations' heights
/// scale with the island's size, and must stay within f32's range.
pub const MAX_EXTENT: f64 = 1.0e9;

/// Below this many samples a pass runs on the calling thread: waking the pool costs more.
const PARALLEL_MIN: usize = 1 << 14;

/// The most perturbations one island may carry.
pub const MAX_FILTERS: usize = 1 << 20;

/// How an island is shaped.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[serde(default, deny_unknown_fields)]
pub struct IslandSettings {
    /// Height of a freshly drawn island at the point farthest from its coast, world units
    /// (the island is a cone over its coastline; default 100).
    pub height: f64,
    /// How close to the coast a stroke must start or end to count as touching it, and how close a
    /// drawn coastline's ends must be to count as closed, world units (default: 2 % of the
    /// domain's shorter side).
    pub snap: Option<f64>,
    /// Land never goes below this height, so only the coastline is at sea level, except in the
    /// hollows of negative hills (lakes and craters may go under it, §3.3; default 0.1).
    pub land_floor: f64,
    /// Perturbation radii as fractions of the island's equivalent radius `√(area / π)`
    /// (default [0.03, 0.1]).
    pub filter_radius: [f64; 2],
    /// Perturbation heights as fractions of their radius, up or down at random (default
    /// [0.02, 0.08]: wider than tall, as §3.4 wants).
    pub filter_height: [f64; 2],
    /// The new heights `H_n` a coastline edit blends in (default [`NewHeights::Cone`]).
    pub new_heights: NewHeights,
}

/// The layers of an island's heights ([`Island::layers`]).
#[derive(Debug, Clone, PartialEq)]
pub struct IslandLayers {
    /// The heights the coastline gives (the cone and the blends of its edits), 0 at sea.
    pub base: Heightfield,
    /// The sum of the hills (negative in hollows).
    pub hills: Heightfield,
    /// The sum of the perturbations.
    pub filters: Heightfield,
}

/// The new heights `H_n` of §3.2, which `H = H_o·(1 − W) + H_n·W` blends in after a coastline
/// edit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum NewHeights {
    /// A cone over the whole coastline: `height ×` the distance to the nearest coast, new or
    /// unchanged, over its largest value on land. Zero at every shore, so the unchanged coast
    /// stays at sea level. The default, because it looks better: see [`NewHeights::Paper`].
    #[default]
    Cone,
    /// The paper's rule: `H_n = height × D_n`, proportional to the scaled distance to the new
    /// pieces of coast. On an unchanged shore far from the edit `D_o = 0` and `D_n ≈ 1`, so
    /// `W = ½ + ½·tanh(−1) ≈ 0.12` and `H ≈ 0.12 × height`: the old coastline rises into a low
    /// cliff (13.5 % of the height on average along a circle's shore opposite a straight cut;
    /// the cone leaves 1 % there, what the land floor and the blend keep).
    Paper,
}

impl Default for IslandSettings {
    fn default() -> Self {
        Self {
            height: 100.0,
            snap: None,
            land_floor: 0.1,
            filter_radius: [0.03, 0.1],
            filter_height: [0.02, 0.08],
            new_heights: NewHeights::Cone,
        }
    }
}

impl IslandSettings {
    fn check(&self) -> Result<(), IslandError> {
        let bad = |name, value, reason| Err(IslandError::InvalidParameter { name, value, reason });
        if !(self.height.is_finite() && self.height > 0.0 && self.height <= MAX_HEIGHT) {
            return bad("height", self.height, "must be positive and at most 1e7 (MAX_HEIGHT)");
        }
        if let Some(s) = self.snap
            && !(s.is_finite() && s > 0.0)
        {
            return bad("snap", s, "must be positive");
        }
        if !(self.land_floor.is_finite() && self.land_floor > 0.0 && self.land_floor <= MAX_HEIGHT) {
            return bad("land_floor", self.land_floor, "must be positive and at most 1e7 (MAX_HEIGHT)");
        }
        for (name, [lo, hi]) in [("filter_radius", self.filter_radius), ("filter_height", self.filter_height)] {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
                return bad(name, lo, "needs 0 < min ≤ max");
            }
            if hi > 10.0 {
                return bad(name, hi, "a fraction: at most 10");
            }
        }
        Ok(())
    }
}

/// One step of an island's editing history, as scenes store it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Operation {
    /// Replace the coastline by a closed polygon (first and last points within the snap distance);
    /// heights restart as a cone over it.
    Coastline {
        /// The points `[x, y]`.
        points: Vec<[f64; 2]>,
    },
    /// A stroke across or around the coast: cuts and supplements at each crossing (§3.1).
    Stroke {
        /// The points `[x, y]`, in drawing order.
        points: Vec<[f64; 2]>,
    },
    /// Add a hill (or, with a negative height, a hollow).
    AddHill(Hill),
    /// Move hill `hill` (its index in order of addition) to `center`.
    MoveHill {
        /// Index of the hill.
        hill: usize,
        /// New centre `[x, y]`.
        center: [f64; 2],
    },
    /// Change hill `hill`'s radii, and optionally its height and rotation.
    ResizeHill {
        /// Index of the hill.
        hill: usize,
        /// New semi-axes `[a, b]`.
        radii: [f64; 2],
        /// New height (default: unchanged).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        height: Option<f64>,
        /// New rotation, degrees (default: unchanged).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotation: Option<f64>,
    },
    /// Remove hill `hill` (later hills move down one index).
    RemoveHill {
        /// Index of the hill.
        hill: usize,
    },
    /// Apply the perturbation filter once: about `coverage` × (island area / mean perturbation
    /// area) new perturbations, seeded.
    AddFilters {
        /// How many perturbations, in island areas covered (default 1).
        #[serde(default = "one")]
        coverage: f64,
    },
    /// Remove the `count` most recent perturbations.
    RemoveFilters {
        /// How many.
        count: usize,
    },
}

fn one() -> f64 {
    1.0
}

/// Which grid a primitive edit touches.
#[derive(Clone, Copy)]
enum Layer {
    Hills,
    Filters,
}

/// An island being sketched: its coastline, hills and perturbations, with the heights grid the
/// coastline edits have shaped and the final terrain kept up to date after every edit.
#[derive(Debug, Clone)]
pub struct Island {
    grid: GridSpec,
    settings: IslandSettings,
    seed: u64,
    coast: Coast,
    land: Vec<bool>,
    heights: Vec<f32>,
    hills: Vec<Hill>,
    hills_grid: Vec<f64>,
    filters: Vec<Hill>,
    filters_grid: Vec<f64>,
    batches: u64,
    terrain: Vec<f32>,
}

impl Island {
    /// The start state of §4: a circular coastline (radius 0.4 of the domain's shorter side,
    /// centred) over a conical island of `settings.height`.
    ///
    /// # Errors
    /// [`IslandError::Grid`] for grids narrower than 3 samples, above [`MAX_CELLS`] or wider than
    /// [`MAX_EXTENT`];
    /// [`IslandError::InvalidParameter`] for bad settings.
    pub fn new(grid: GridSpec, settings: IslandSettings, seed: u64) -> Result<Self, IslandError> {
        let (nx, ny) = (grid.nx(), grid.ny());
        if nx < 3 || ny < 3 {
            return Err(IslandError::Grid { nx, ny, reason: "needs at least 3 samples along each axis" });
        }
        if nx.saturating_mul(ny) > MAX_CELLS {
            return Err(IslandError::Grid { nx, ny, reason: "more samples than the island limit (2^25)" });
        }
        settings.check()?;
        let extent = grid.extent();
        if extent.size().max_element() > MAX_EXTENT {
            return Err(IslandError::Grid { nx, ny, reason: "a domain wider than 1e9 world units (MAX_EXTENT)" });
        }
        let (center, r) = (extent.center(), 0.4 * extent.size().min_element());
        let circle: Vec<DVec2> = (0..128)
            .map(|k| {
                let a = std::f64::consts::TAU * f64::from(k) / 128.0;
                center + r * DVec2::new(a.cos(), a.sin())
            })
            .collect();
        let n = grid.len();
        let mut island = Self {
            grid,
            settings,
            seed,
            coast: Coast::new(simple_polygon(&circle)?),
            land: vec![false; n],
            heights: vec![0.0; n],
            hills: Vec::new(),
            hills_grid: vec![0.0; n],
            filters: Vec::new(),
            filters_grid: vec![0.0; n],
            batches: 0,
            terrain: vec![0.0; n],
        };
        island.update_heights();
        Ok(island)
    }

    /// The grid.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// The settings.
    pub fn settings(&self) -> &IslandSettings {
        &self.settings
    }

    /// The coastline, counter-clockwise, not repeating its first point.
    pub fn coastline(&self) -> &[DVec2] {
        &self.coast.points
    }

    /// The hills, in order of addition.
    pub fn hills(&self) -> &[Hill] {
        &self.hills
    }

    /// The perturbations of the filters, in order of addition.
    pub fn filters(&self) -> &[Hill] {
        &self.filters
    }

    /// The grids the final one adds up (the paper's Fig. 13): the coastline's heights (0 at
    /// sea), the hills' sum and the perturbations' sum, each over the whole grid. On land the
    /// terrain is their sum, held at the land floor but in hollows; at sea it is 0.
    ///
    /// # Panics
    /// Never in practice: every layer is finite (parameters are checked on entry) and the grid is
    /// the island's own.
    pub fn layers(&self) -> IslandLayers {
        let grid = |v: Vec<f32>| Heightfield::from_samples(self.grid, v).expect("finite layers on the island's grid");
        let narrow = |v: &[f64]| v.iter().map(|&x| x as f32).collect();
        IslandLayers {
            base: grid(self.heights.clone()),
            hills: grid(narrow(&self.hills_grid)),
            filters: grid(narrow(&self.filters_grid)),
        }
    }

    /// Per sample: inside the coastline.
    pub fn land(&self) -> &[bool] {
        &self.land
    }

    /// The heights grid (the coastline's shape, before hills and filters).
    pub fn heights(&self) -> &[f32] {
        &self.heights
    }

    /// The final grid: heights + hills + filters on land (at least `land_floor`, except in the
    /// hollows of negative hills), exactly 0 at sea.
    pub fn terrain(&self) -> &[f32] {
        &self.terrain
    }

    /// The final grid as a heightfield.
    ///
    /// # Panics
    /// Never in practice: every sample is finite (parameters are checked on entry) and the grid
    /// is the island's own.
    pub fn heightfield(&self) -> Heightfield {
        Heightfield::from_samples(self.grid, self.terrain.clone()).expect("finite samples on the island's own grid")
    }

    /// Area inside the coastline, world units².
    pub fn area(&self) -> f64 {
        signed_area(&self.coast.points)
    }

    /// The snap distance in force.
    pub fn snap(&self) -> f64 {
        self.settings.snap.unwrap_or(0.02 * self.grid.extent().size().min_element())
    }

    /// Replaces the coastline by the closed polygon `points` and rebuilds the heights as a cone
    /// over it.
    ///
    /// # Errors
    /// [`IslandError::OpenCoastline`], [`IslandError::DegenerateCoastline`],
    /// [`IslandError::SelfIntersecting`], [`IslandError::NotFinite`], [`IslandError::NoLand`].
    pub fn set_coastline(&mut self, points: &[DVec2]) -> Result<(), IslandError> {
        if points.len() >= 2 {
            let gap = points[0].distance(points[points.len() - 1]);
            if gap > self.snap() {
                return Err(IslandError::OpenCoastline { gap, snap: self.snap() });
            }
        }
        let coast = Coast::new(simple_polygon(points)?);
        self.commit(coast)
    }

    /// Applies a stroke (§3.1): split at its contacts with the coast, each piece through the land
    /// cuts off the part left of the stroke, each piece outside adds the area it encloses
    /// (clockwise) or keeps only that area (counter-clockwise). Heights then follow §3.2.
    ///
    /// # Errors
    /// [`IslandError::ShortStroke`], [`IslandError::StrokeMissesCoast`],
    /// [`IslandError::SelfIntersecting`] (the stroke crosses itself or the result does),
    /// [`IslandError::NoLand`], [`IslandError::NotFinite`].
    pub fn stroke(&mut self, points: &[DVec2]) -> Result<Vec<EditKind>, IslandError> {
        let mut coast = self.coast.clone();
        coast.fresh.iter_mut().for_each(|f| *f = false);
        let pieces = coast.pieces(points, self.snap())?;
        let mut kinds = Vec::with_capacity(pieces.len());
        for piece in &pieces {
            kinds.extend(coast.apply(piece)?);
        }
        if kinds.is_empty() {
            return Err(IslandError::StrokeMissesCoast { snap: self.snap() });
        }
        self.commit(coast)?;
        Ok(kinds)
    }

    fn commit(&mut self, coast: Coast) -> Result<(), IslandError> {
        let previous = std::mem::replace(&mut self.coast, coast);
        if !self.update_heights() {
            self.coast = previous;
            self.update_heights();
            return Err(IslandError::NoLand);
        }
        Ok(())
    }

    /// §3.2: `H = H_o·(1 − W) + H_n·W` with `W = ½ + ½·tanh(D_o² − D_n)`, where `D_o` and `D_n`
    /// are the distances to the unchanged and to the new pieces of the coastline, each scaled to
    /// [0, 1] over the land. `H_n` follows [`IslandSettings::new_heights`]: by default the height
    /// a fresh island with this coastline would have (`height ×` distance to the coast / its
    /// largest value, a cone), or the paper's `height × D_n`. Next to a cut W ≥ ½, so the new
    /// coast keeps up to half the old height: cuts leave cliffs, as in the paper's figures. Sea samples get 0. Returns false when no sample is on land (and changes
    /// nothing then).
    fn update_heights(&mut self) -> bool {
        let land = self.mask();
        if !land.contains(&true) {
            return false;
        }
        // Seeds and land all lie in the coast's bounds: the distance fields need only that window.
        let window = self.coast_window();
        let (d_new, d_old) = if (window.1 - window.0 + 1) * (window.3 - window.2 + 1) < PARALLEL_MIN {
            (self.distance_to(true, window, &land), self.distance_to(false, window, &land))
        } else {
            rayon::join(|| self.distance_to(true, window, &land), || self.distance_to(false, window, &land))
        };
        let (i0, j0, w) = (window.0, window.2, window.1 - window.0 + 1);
        // Maxima over land of the new, old and nearest coast distance (order-free, so parallel).
        let (m_new, m_old, m_coast) = d_new
            .par_iter()
            .with_min_len(PARALLEL_MIN)
            .zip(&d_old)
            .map(|(&a, &b)| {
                let f = |v: f32| if v.is_finite() { f64::from(v) } else { 0.0 };
                (f(a), f(b), f(a.min(b)))
            })
            .reduce(|| (0.0, 0.0, 0.0), |x, y| (x.0.max(y.0), x.1.max(y.1), x.2.max(y.2)));
        let cell = self.grid.cell_size().min_element();
        let scale = self.settings.height / m_coast.max(cell);
        let (to_new, to_old) = (1.0 / m_new.max(cell), 1.0 / m_old.max(cell));
        let nx = self.grid.nx();
        self.heights.par_chunks_mut(nx).with_min_len(PARALLEL_MIN / nx + 1).enumerate().for_each(|(j, row)| {
            for (i, h) in row.iter_mut().enumerate() {
                if !land[j * nx + i] {
                    *h = 0.0;
                    continue;
                }
                // Land lies inside the window.
                let k = (j - j0) * w + (i - i0);
                let (dn, dold) = (f64::from(d_new[k]), f64::from(d_old[k]));
                let hn = match self.settings.new_heights {
                    NewHeights::Cone => scale * dn.min(dold),
                    // With no new piece W is 0 and H_n unused.
                    NewHeights::Paper if dn.is_finite() => self.settings.height * dn * to_new,
                    NewHeights::Paper => 0.0,
                };
                let wt = if dold.is_finite() {
                    let (dn, dold) = (dn * to_new, dold * to_old);
                    // ½ + ½·tanh(x) = 1 / (1 + e^(−2x)): one exponential instead of a tanh.
                    1.0 / (1.0 + f64::from((2.0 * (dn - dold * dold) as f32).exp()))
                } else {
                    1.0
                };
                // A sample that was at sea had no old height.
                let ho = f64::from(*h);
                *h = (ho * (1.0 - wt) + hn * wt) as f32;
            }
        });
        self.land = land;
        self.refresh_terrain((0, self.grid.nx() - 1, 0, self.grid.ny() - 1));
        true
    }

    /// Sample box `(i0, i1, j0, j1)` holding the coast's bounds grown by three cells, clipped to
    /// the grid: every land sample and every distance seed lies in it.
    fn coast_window(&self) -> (usize, usize, usize, usize) {
        let (lo, hi) = self.coast.bounds();
        let (a, b) = (self.grid.grid_coords(lo), self.grid.grid_coords(hi));
        let clip = |v: f64, n: usize| v.clamp(0.0, (n - 1) as f64) as usize;
        let (nx, ny) = (self.grid.nx(), self.grid.ny());
        (
            clip(a.x.floor() - 3.0, nx),
            clip(b.x.ceil() + 3.0, nx),
            clip(a.y.floor() - 3.0, ny),
            clip(b.y.ceil() + 3.0, ny),
        )
    }

    /// Samples inside the coastline (scanline fill at the sample positions).
    fn mask(&self) -> Vec<bool> {
        let (nx, p) = (self.grid.nx(), &self.coast.points);
        let n = p.len();
        let mut mask = vec![false; self.grid.len()];
        mask.par_chunks_mut(nx).with_min_len(PARALLEL_MIN / nx + 1).enumerate().for_each(|(j, row)| {
            let y = self.grid.position(0, j).y;
            let mut xs: Vec<f64> = Vec::new();
            for i in 0..n {
                let (a, b) = (p[i], p[(i + 1) % n]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let g0 = self.grid.grid_coords(DVec2::new(pair[0], y)).x;
                let g1 = self.grid.grid_coords(DVec2::new(pair[1], y)).x;
                // Samples strictly inside: i > g0 and i < g1.
                let lo = (g0.floor() + 1.0).max(0.0) as usize;
                let hi = g1.ceil() - 1.0;
                if hi < 0.0 {
                    continue;
                }
                for v in row.iter_mut().take((hi as usize).min(nx - 1) + 1).skip(lo) {
                    *v = true;
                }
            }
        });
        mask
    }

    /// Distance from every land sample of `window` to the coast edges whose fresh flag is
    /// `fresh` (infinite when there is none, and at sea samples, which need none), row-major over
    /// the window.
    ///
    /// A labelled Euclidean distance transform on the window's even samples (half resolution,
    /// a quarter of the work) finds which edge is nearest there: samples within two coarse cells
    /// of an edge seed it with that edge and their exact squared distance. Two label sweeps then
    /// fix the bands where seed offsets made the transform pick the farther of two nearly equally
    /// far edges. Every land sample measures its exact distance to the edges labelling the four
    /// coarse samples around it and keeps the least: the distance to the coast, or where two
    /// edges are almost equally near at most a fraction of a cell more (a test bounds it against
    /// brute force on a star and a jagged coast: within half a cell).
    fn distance_to(&self, fresh: bool, window: (usize, usize, usize, usize), land: &[bool]) -> Vec<f32> {
        let coarse = Coarse::new(self.grid, window);
        // f32: a relative 6e-8 is far below the cell (and halves the memory these fields move).
        let mut out = vec![f32::INFINITY; coarse.w * coarse.h];
        let Some((mut sq, mut label)) = self.seed_labels(fresh, &coarse) else { return out };
        distance_transform_seeded(coarse.cw, coarse.ch, 2.0 * self.grid.cell_size(), &mut sq, Some(&mut label));
        let edges = EdgeDistance::new(&self.coast.points);
        // A seed off its edge by t counts as t nearer to far samples, and t differs between
        // edges, so where two edges are nearly equally far the transform may pick the wrong one
        // over a band (wide when their directions from the sample nearly agree). Two raster
        // sweeps hand each coarse sample its neighbours' edges when they are nearer: a correct
        // edge at a band's border spreads across it (as a chamfer transform spreads distances).
        sweep_labels(&mut label, coarse.cw, coarse.ch, |e, ci, cj| edges.squared(e, coarse.position(ci, cj)));
        measure_land(&coarse, &label, &edges, land, &mut out);
        out
    }

    /// The seeds of [`Self::distance_to`]'s transform on the coarse grid: every coarse sample
    /// within two coarse cells of a point sampled along an edge flagged `fresh` gets that edge's
    /// exact squared distance and its index as label (the nearest such edge wins). `None` when no
    /// edge has the flag.
    fn seed_labels(&self, fresh: bool, coarse: &Coarse) -> Option<(Vec<f64>, Vec<u32>)> {
        let (cw, ch) = (coarse.cw, coarse.ch);
        let mut sq = vec![f64::INFINITY; cw * ch];
        let mut label = vec![u32::MAX; cw * ch];
        let (p, n) = (&self.coast.points, self.coast.points.len());
        let step = 0.5 * (2.0 * self.grid.cell_size()).min_element();
        let origin = DVec2::new(coarse.i0 as f64, coarse.j0 as f64);
        let mut any = false;
        for e in (0..n).filter(|&e| self.coast.fresh[e] == fresh) {
            any = true;
            let (a, b) = (p[e], p[(e + 1) % n]);
            // Half a coarse cell apart, but no more points than a few window perimeters: an edge
            // far longer than the window gets sparser seeds instead of unbounded work.
            let steps = ((a.distance(b) / step).ceil() as usize + 1).min(4 * (cw + ch) + 64);
            for s in 0..=steps {
                let g = (self.grid.grid_coords(a + (b - a) * (s as f64 / steps as f64)) - origin) / 2.0;
                // Points off the window seed its nearest border samples (with their exact,
                // larger, offsets): coast beyond the grid still reaches the samples on it.
                let gi = (g.x.floor() - 1.0).clamp(0.0, cw.saturating_sub(4) as f64) as usize;
                let gj = (g.y.floor() - 1.0).clamp(0.0, ch.saturating_sub(4) as f64) as usize;
                for cj in gj..(gj + 4).min(ch) {
                    for ci in gi..(gi + 4).min(cw) {
                        let c = coarse.position(ci, cj);
                        let d2 = crate::geometry::project(a, b, c).0.distance_squared(c);
                        let k = cj * cw + ci;
                        if d2 < sq[k] {
                            sq[k] = d2;
                            label[k] = e as u32;
                        }
                    }
                }
            }
        }
        any.then_some((sq, label))
    }

    /// Sample box `[i0, i1] × [j0, j1]` covering world bounds, or `None` off the grid.
    fn cell_box(&self, lo: DVec2, hi: DVec2) -> Option<(usize, usize, usize, usize)> {
        let (a, b) = (self.grid.grid_coords(lo), self.grid.grid_coords(hi));
        let (nx, ny) = (self.grid.nx() as f64, self.grid.ny() as f64);
        let (i0, j0) = (a.x.min(b.x).floor().max(0.0), a.y.min(b.y).floor().max(0.0));
        let (i1, j1) = (a.x.max(b.x).ceil().min(nx - 1.0), a.y.max(b.y).ceil().min(ny - 1.0));
        (i0 <= i1 && j0 <= j1).then_some((i0 as usize, i1 as usize, j0 as usize, j1 as usize))
    }

    /// Recomputes a layer's grid over the box covering `bounds`, summing its primitives in order,
    /// then the final grid there. A full rebuild is the same call over the whole grid.
    fn refresh(&mut self, layer: Layer, bounds: (DVec2, DVec2)) {
        let Some(window) = self.cell_box(bounds.0, bounds.1) else { return };
        let (i0, i1, j0, j1) = window;
        let (prims, grid) = match layer {
            Layer::Hills => (&self.hills, &mut self.hills_grid),
            Layer::Filters => (&self.filters, &mut self.filters_grid),
        };
        let (lo, hi) = (self.grid.position(i0, j0), self.grid.position(i1, j1));
        let near: Vec<Shape> = prims
            .iter()
            .map(Shape::new)
            .filter(|s| s.lo.x <= hi.x && s.hi.x >= lo.x && s.lo.y <= hi.y && s.hi.y >= lo.y)
            .collect();
        let spec = self.grid;
        for_rows(grid, spec.nx(), window, |j, row| {
            row[i0..=i1].fill(0.0);
            for s in &near {
                add_span(s, &spec, j, row, (i0, i1));
            }
        });
        self.refresh_terrain(window);
    }

    /// Adds the primitives of a layer from index `from` on top of its grid, each in order (the
    /// ordered sum continues, so the result equals a rebuild bit for bit), then refreshes the
    /// final grid under them. Rows go in parallel; each row adds the primitives in order.
    fn append(&mut self, layer: Layer, from: usize) {
        let prims = match layer {
            Layer::Hills => &self.hills[from..],
            Layer::Filters => &self.filters[from..],
        };
        let shapes: Vec<Shape> = prims.iter().map(Shape::new).collect();
        let Some(window) = shapes
            .iter()
            .filter_map(|s| self.cell_box(s.lo, s.hi))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1), a.2.min(b.2), a.3.max(b.3)))
        else {
            return;
        };
        let grid = match layer {
            Layer::Hills => &mut self.hills_grid,
            Layer::Filters => &mut self.filters_grid,
        };
        let spec = self.grid;
        for_rows(grid, spec.nx(), window, |j, row| {
            for s in &shapes {
                add_span(s, &spec, j, row, (window.0, window.1));
            }
        });
        self.refresh_terrain(window);
    }

    /// The final grid over a sample box `(i0, i1, j0, j1)`.
    fn refresh_terrain(&mut self, (i0, i1, j0, j1): (usize, usize, usize, usize)) {
        let nx = self.grid.nx();
        let floor = self.settings.land_floor;
        let (land, heights, hills, filters) = (&self.land, &self.heights, &self.hills_grid, &self.filters_grid);
        for_rows(&mut self.terrain, nx, (i0, i1, j0, j1), |j, row| {
            let cols = j * nx + i0..=j * nx + i1;
            let sources =
                land[cols.clone()].iter().zip(&heights[cols.clone()]).zip(&hills[cols.clone()]).zip(&filters[cols]);
            for (v, (((&on_land, &h), &a), &b)) in row[i0..=i1].iter_mut().zip(sources) {
                *v = terrain_sample(on_land, h, a, b, floor);
            }
        });
    }

    /// Recomputes the hills, filters and final grids from scratch: what every incremental update
    /// must equal (tests compare the two).
    pub fn rebuild(&mut self) {
        let e = self.grid.extent();
        self.refresh(Layer::Hills, (e.min, e.max));
        self.refresh(Layer::Filters, (e.min, e.max));
    }

    /// Verifies the island's invariants, naming the first one broken; the tests call it after
    /// every edit.
    ///
    /// Checked, cheapest first:
    /// - sizes: the land mask and the heights, hills, filters and terrain grids hold one value per
    ///   grid sample, the coastline one fresh flag per edge, the filters at most [`MAX_FILTERS`];
    /// - the coastline is a simple counter-clockwise polygon: validating it again returns it
    ///   unchanged (finite, at least three distinct points, positive area, no two non-adjacent
    ///   edges meeting); O(n log n) in its n points, plus the edge pairs whose x-ranges overlap;
    /// - every hill and perturbation is valid ([`Hill::validate`]);
    /// - the land mask is the coastline's scanline fill: O(rows × coast edges);
    /// - sea samples are exactly +0 in the heights and the terrain; land samples are finite and at
    ///   least `land_floor` (rounded to f32, as the terrain stores it) unless the hills sum below
    ///   zero there (a hollow: lakes and craters may go under the floor); the hills and filters grids
    ///   are finite and the terrain is their sum with the heights: O(samples).
    ///
    /// Not checked here, because it costs a full rebuild: that incremental edits equal
    /// [`Island::rebuild`] bit for bit (every span's row walk starts at its first sample however
    /// an edit's window clips it); the tests compare the two after seeded edit sessions.
    ///
    /// # Errors
    /// [`IslandError::Invariant`] describing the first violation found and the sample, edge or
    /// primitive at fault.
    pub fn check_invariants(&self) -> Result<(), IslandError> {
        let fail = |m: String| Err(IslandError::Invariant(m));
        let n = self.grid.len();
        let sizes = [
            ("land mask", self.land.len()),
            ("heights grid", self.heights.len()),
            ("hills grid", self.hills_grid.len()),
            ("filters grid", self.filters_grid.len()),
            ("terrain", self.terrain.len()),
        ];
        if let Some((name, len)) = sizes.into_iter().find(|&(_, len)| len != n) {
            return fail(format!("the {name} holds {len} samples, the grid {n}"));
        }
        let (edges, flags) = (self.coast.points.len(), self.coast.fresh.len());
        if flags != edges {
            return fail(format!("the coastline has {edges} edges but {flags} fresh flags"));
        }
        if self.filters.len() > MAX_FILTERS {
            return fail(format!("{} perturbations, over the limit of {MAX_FILTERS}", self.filters.len()));
        }
        match simple_polygon(&self.coast.points) {
            Ok(valid) if valid == self.coast.points => {}
            Ok(_) => return fail("the coastline is clockwise or repeats a point".into()),
            Err(e) => return fail(format!("the coastline is not a simple polygon: {e}")),
        }
        for (kind, prims) in [("hill", &self.hills), ("perturbation", &self.filters)] {
            for (k, prim) in prims.iter().enumerate() {
                prim.validate().map_err(|e| IslandError::Invariant(format!("{kind} {k}: {e}")))?;
            }
        }
        if let Some(k) = self.mask().iter().zip(&self.land).position(|(a, b)| a != b) {
            let (i, j) = self.grid.coords(k);
            return fail(format!(
                "sample ({i}, {j}) is {} but the coastline puts it on the other side",
                side(self.land[k])
            ));
        }
        self.check_samples()
    }

    /// Sea samples exactly +0, land samples finite and at least the land floor (unless a hollow
    /// digs there), layers finite, and the terrain the sum of the layers the grids hold.
    fn check_samples(&self) -> Result<(), IslandError> {
        let land_floor = self.settings.land_floor;
        let floor = land_floor as f32;
        for k in 0..self.grid.len() {
            let (h, z, a, b) = (self.heights[k], self.terrain[k], self.hills_grid[k], self.filters_grid[k]);
            let sample_ok = if self.land[k] {
                h.is_finite() && z.is_finite() && (z >= floor || a < 0.0)
            } else {
                h.to_bits() == 0 && z.to_bits() == 0
            };
            let sum_ok = z.to_bits() == terrain_sample(self.land[k], h, a, b, land_floor).to_bits();
            if !(sample_ok && sum_ok && a.is_finite() && b.is_finite()) {
                let (i, j) = self.grid.coords(k);
                return Err(IslandError::Invariant(format!(
                    "{} sample ({i}, {j}) has height {h}, hills {a}, filters {b}, terrain {z} (land floor {floor})",
                    side(self.land[k])
                )));
            }
        }
        Ok(())
    }

    fn hill_index(&self, index: usize) -> Result<usize, IslandError> {
        if index < self.hills.len() {
            Ok(index)
        } else {
            Err(IslandError::NoSuchHill { index, count: self.hills.len() })
        }
    }

    /// Adds a hill; returns its index. Only the samples under it are recomputed.
    ///
    /// # Errors
    /// [`IslandError::InvalidHill`], [`IslandError::NotFinite`].
    pub fn add_hill(&mut self, hill: Hill) -> Result<usize, IslandError> {
        hill.validate()?;
        self.hills.push(hill);
        self.append(Layer::Hills, self.hills.len() - 1);
        Ok(self.hills.len() - 1)
    }

    /// Replaces hill `index`; the samples under the old and the new one are recomputed.
    ///
    /// # Errors
    /// [`IslandError::NoSuchHill`], [`IslandError::InvalidHill`], [`IslandError::NotFinite`].
    pub fn set_hill(&mut self, index: usize, hill: Hill) -> Result<(), IslandError> {
        let index = self.hill_index(index)?;
        hill.validate()?;
        let old = std::mem::replace(&mut self.hills[index], hill);
        let (a, b) = (old.bounds(), hill.bounds());
        let union = (a.0.min(b.0), a.1.max(b.1));
        let area = |(lo, hi): (DVec2, DVec2)| (hi - lo).element_product();
        if area(union) <= area(a) + area(b) {
            // Overlapping (a small move or a resize): one pass over both.
            self.refresh(Layer::Hills, union);
        } else {
            self.refresh(Layer::Hills, a);
            self.refresh(Layer::Hills, b);
        }
        Ok(())
    }

    /// Moves hill `index` to `center`.
    ///
    /// # Errors
    /// As [`Self::set_hill`].
    pub fn move_hill(&mut self, index: usize, center: DVec2) -> Result<(), IslandError> {
        let mut hill = self.hills[self.hill_index(index)?];
        hill.center = center.to_array();
        self.set_hill(index, hill)
    }

    /// Removes hill `index` (later hills move down one index).
    ///
    /// # Errors
    /// [`IslandError::NoSuchHill`].
    pub fn remove_hill(&mut self, index: usize) -> Result<Hill, IslandError> {
        let index = self.hill_index(index)?;
        let old = self.hills.remove(index);
        self.refresh(Layer::Hills, old.bounds());
        Ok(old)
    }

    /// Applies the filter once (§3.4): `coverage` × (land area / mean perturbation area)
    /// perturbations at random land positions, each an elliptic paraboloid wider than tall, up or
    /// down at random. Batches draw from the island's seed and their own stream, so replaying
    /// the same edits gives the same perturbations. Returns how many were added.
    ///
    /// # Errors
    /// [`IslandError::InvalidParameter`] for a coverage that is negative, not finite, or would
    /// exceed [`MAX_FILTERS`].
    pub fn add_filters(&mut self, coverage: f64) -> Result<usize, IslandError> {
        if !(coverage.is_finite() && coverage >= 0.0) {
            return Err(IslandError::InvalidParameter {
                name: "coverage",
                value: coverage,
                reason: "must be finite and ≥ 0",
            });
        }
        let area = self.area();
        let r_eq = (area / std::f64::consts::PI).sqrt();
        let [r0, r1] = self.settings.filter_radius.map(|f| f * r_eq);
        let mean_area = std::f64::consts::PI * (0.5 * (r0 + r1)).powi(2);
        let count = (coverage * area / mean_area).round();
        if count > (MAX_FILTERS - self.filters.len()) as f64 {
            return Err(IslandError::InvalidParameter {
                name: "coverage",
                value: coverage,
                reason: "asks for more perturbations than the limit (2^20 per island)",
            });
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(self.batches);
        self.batches += 1;
        let (lo, hi) = self.coast.bounds();
        let [h0, h1] = self.settings.filter_height;
        let mut added = 0;
        for _ in 0..count as usize {
            // Rejection sampling in the coast's bounds (the land fills a good share of them).
            let mut center = None;
            for _ in 0..64 {
                let p = DVec2::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y));
                if ring_contains(&self.coast.points, p) {
                    center = Some(p);
                    break;
                }
            }
            let Some(center) = center else { continue };
            let r = rng.random_range(r0..=r1);
            let aspect = rng.random_range(0.5..=1.0);
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let height = sign * r * rng.random_range(h0..=h1);
            let rotation = rng.random_range(0.0..180.0);
            self.filters.push(Hill { center: center.to_array(), radii: [r, r * aspect], rotation, height });
            added += 1;
        }
        // One pass for the whole batch (the same sums, in the same order, as one at a time).
        self.append(Layer::Filters, self.filters.len() - added);
        Ok(added)
    }

    /// Removes the `count` most recent perturbations (all if fewer); returns how many went.
    pub fn remove_filters(&mut self, count: usize) -> usize {
        let keep = self.filters.len().saturating_sub(count);
        let removed: Vec<Hill> = self.filters.drain(keep..).collect();
        // One pass over the bounds of all of them.
        if let Some(bounds) = removed.iter().map(Hill::bounds).reduce(|a, b| (a.0.min(b.0), a.1.max(b.1))) {
            self.refresh(Layer::Filters, bounds);
        }
        removed.len()
    }

    /// Applies one operation.
    ///
    /// # Errors
    /// Those of the method the operation calls.
    pub fn apply(&mut self, op: &Operation) -> Result<(), IslandError> {
        let points = |p: &[[f64; 2]]| p.iter().map(|&q| DVec2::from(q)).collect::<Vec<_>>();
        match op {
            Operation::Coastline { points: p } => self.set_coastline(&points(p)),
            Operation::Stroke { points: p } => self.stroke(&points(p)).map(|_| ()),
            Operation::AddHill(h) => self.add_hill(*h).map(|_| ()),
            Operation::MoveHill { hill, center } => self.move_hill(*hill, DVec2::from(*center)),
            Operation::ResizeHill { hill, radii, height, rotation } => {
                let mut h = self.hills[self.hill_index(*hill)?];
                h.radii = *radii;
                h.height = height.unwrap_or(h.height);
                h.rotation = rotation.unwrap_or(h.rotation);
                self.set_hill(*hill, h)
            }
            Operation::RemoveHill { hill } => self.remove_hill(*hill).map(|_| ()),
            Operation::AddFilters { coverage } => self.add_filters(*coverage).map(|_| ()),
            Operation::RemoveFilters { count } => {
                self.remove_filters(*count);
                Ok(())
            }
        }
    }

    /// Replays `ops` in order.
    ///
    /// # Errors
    /// [`IslandError::Operation`] with the index of the first operation that fails; the island
    /// keeps the operations before it.
    pub fn replay(&mut self, ops: &[Operation]) -> Result<(), IslandError> {
        for (index, op) in ops.iter().enumerate() {
            self.apply(op).map_err(|e| IslandError::Operation { index, source: Box::new(e) })?;
        }
        Ok(())
    }

    /// Distance from `p` to the coastline.
    pub fn distance_to_coast(&self, p: DVec2) -> f64 {
        nearest_on_boundary(&self.coast.points, p).0
    }
}

/// A sample window `(i0, i1, j0, j1)` and its even samples: the half-resolution grid the coast
/// distances are labelled on. Coarse sample `(ci, cj)` sits on fine sample `(i0 + 2ci, j0 + 2cj)`.
#[derive(Clone, Copy)]
struct Coarse {
    grid: GridSpec,
    i0: usize,
    i1: usize,
    j0: usize,
    /// Fine samples across and along the window.
    w: usize,
    h: usize,
    /// Coarse samples across and along the window.
    cw: usize,
    ch: usize,
}

impl Coarse {
    fn new(grid: GridSpec, (i0, i1, j0, j1): (usize, usize, usize, usize)) -> Self {
        let (w, h) = (i1 - i0 + 1, j1 - j0 + 1);
        Self { grid, i0, i1, j0, w, h, cw: w / 2 + 1, ch: h / 2 + 1 }
    }

    /// Position of coarse sample `(ci, cj)`.
    #[inline]
    fn position(&self, ci: usize, cj: usize) -> DVec2 {
        self.grid.position(self.i0 + 2 * ci, self.j0 + 2 * cj)
    }
}

/// Squared distances to a ring's edges, with each edge's direction and inverse squared length
/// prepared once (the measures run a few million times on a large grid).
struct EdgeDistance {
    /// Per edge: start, direction, 1 / squared length (0 for a zero-length edge).
    segs: Vec<(DVec2, DVec2, f64)>,
}

impl EdgeDistance {
    fn new(p: &[DVec2]) -> Self {
        let n = p.len();
        let segs = (0..n)
            .map(|e| {
                let (a, b) = (p[e], p[(e + 1) % n]);
                let d = b - a;
                let len2 = d.length_squared();
                (a, d, if len2 > 0.0 { 1.0 / len2 } else { 0.0 })
            })
            .collect();
        Self { segs }
    }

    /// Squared distance from `q` to edge `e`.
    #[inline]
    fn squared(&self, e: u32, q: DVec2) -> f64 {
        let (a, d, inv) = self.segs[e as usize];
        let t = ((q - a).dot(d) * inv).clamp(0.0, 1.0);
        (a + d * t).distance_squared(q)
    }
}

/// The last stage of [`Island::distance_to`]: every land sample of the window measures its exact
/// distance to the edges labelling the four coarse samples around it and keeps the least (rows
/// in parallel). Sea samples keep their value in `out`.
fn measure_land(coarse: &Coarse, label: &[u32], edges: &EdgeDistance, land: &[bool], out: &mut [f32]) {
    let Coarse { grid, i0, i1, j0, w, cw, ch, .. } = *coarse;
    let nx = grid.nx();
    out.par_chunks_mut(w).with_min_len(PARALLEL_MIN / w + 1).enumerate().for_each(|(r, row)| {
        let j = j0 + r;
        let on_land = &land[j * nx + i0..=j * nx + i1];
        let (c0, c1) = (r / 2 * cw, (r / 2 + 1).min(ch - 1) * cw);
        for (c, (v, &is_land)) in row.iter_mut().zip(on_land).enumerate() {
            if !is_land {
                continue;
            }
            let (a, b) = (c / 2, (c / 2 + 1).min(cw - 1));
            let q = grid.position(i0 + c, j);
            let first = label[c0 + a];
            let mut best = edges.squared(first, q);
            for e in [label[c0 + b], label[c1 + a], label[c1 + b]] {
                if e != first {
                    best = best.min(edges.squared(e, q));
                }
            }
            *v = best.sqrt() as f32;
        }
    });
}

/// The final grid's value at a sample: heights + hills + filters on land, at least `land_floor`,
/// exactly +0 at sea. Where the hills sum below zero (a hollow the user placed: a valley, lake or
/// crater, §3.3) the floor holds the ground under the hollow and the hollow is dug below it, so a
/// lake can go under sea level and hold water; nothing else takes land below the floor.
#[inline]
fn terrain_sample(on_land: bool, height: f32, hills: f64, filters: f64, land_floor: f64) -> f32 {
    let ground = f64::from(height) + filters;
    let z = if hills >= 0.0 { (ground + hills).max(land_floor) } else { ground.max(land_floor) + hills };
    if on_land { z as f32 } else { 0.0 }
}

/// "land" or "sea", for messages.
fn side(land: bool) -> &'static str {
    if land { "land" } else { "sea" }
}

/// Two raster sweeps over a `cw × ch` label grid, forward then backward, that hand each sample
/// a neighbour's label whenever `dist2(label, ci, cj)` is smaller with it: a right label spreads
/// across a band of wrong ones, as a chamfer transform spreads distances. Distances are measured
/// only where neighbouring labels differ (a few samples in a hundred).
fn sweep_labels(label: &mut [u32], cw: usize, ch: usize, dist2: impl Fn(u32, usize, usize) -> f64) {
    // NaN: not measured yet.
    let mut best = vec![f64::NAN; cw * ch];
    let mut relax = |k: usize, m: usize, ci: usize, cj: usize| {
        if label[m] != label[k] {
            if best[k].is_nan() {
                best[k] = dist2(label[k], ci, cj);
            }
            let d = dist2(label[m], ci, cj);
            if d < best[k] {
                (best[k], label[k]) = (d, label[m]);
            }
        }
    };
    for cj in 0..ch {
        for ci in 0..cw {
            let k = cj * cw + ci;
            if ci > 0 {
                relax(k, k - 1, ci, cj);
            }
            if cj > 0 {
                relax(k, k - cw, ci, cj);
                if ci > 0 {
                    relax(k, k - cw - 1, ci, cj);
                }
                if ci + 1 < cw {
                    relax(k, k - cw + 1, ci, cj);
                }
            }
        }
    }
    for cj in (0..ch).rev() {
        for ci in (0..cw).rev() {
            let k = cj * cw + ci;
            if ci + 1 < cw {
                relax(k, k + 1, ci, cj);
            }
            if cj + 1 < ch {
                relax(k, k + cw, ci, cj);
                if ci + 1 < cw {
                    relax(k, k + cw + 1, ci, cj);
                }
                if ci > 0 {
                    relax(k, k + cw - 1, ci, cj);
                }
            }
        }
    }
}

/// Calls `f(j, row)` for the rows `j0..=j1` of a row-major grid (whole rows; `f` touches only
/// the box's columns), in parallel when the box `(i0, i1, j0, j1)` is large enough to pay for it.
/// Each row is computed on its own, so the result is the same either way.
fn for_rows<T: Send>(
    grid: &mut [T],
    nx: usize,
    (i0, i1, j0, j1): (usize, usize, usize, usize),
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    let rows = j1 - j0 + 1;
    if (i1 - i0 + 1) * rows < PARALLEL_MIN {
        grid.chunks_mut(nx).enumerate().skip(j0).take(rows).for_each(|(j, row)| f(j, row));
    } else {
        grid.par_chunks_mut(nx).enumerate().skip(j0).take(rows).for_each(|(j, row)| f(j, row));
    }
}

/// Adds a primitive's heights along grid row `j` (a whole row), over its span there widened by a
/// sample each side and clipped to columns `i0..=i1`. Beyond the span the paraboloid is 0.
#[inline]
fn add_span(s: &Shape, spec: &GridSpec, j: usize, row: &mut [f64], (i0, i1): (usize, usize)) {
    let y = spec.position(0, j).y;
    let Some((x0, x1)) = s.span(y) else { return };
    let g0 = spec.grid_coords(DVec2::new(x0, y)).x.floor() - 1.0;
    let g1 = spec.grid_coords(DVec2::new(x1, y)).x.ceil() + 1.0;
    if g1 < i0 as f64 || g0 > i1 as f64 {
        return;
    }
    // Evaluate from the span's first sample even when the window starts later, so an edit's
    // window sums exactly what a rebuild of the whole row sums.
    let start = g0.max(0.0) as usize;
    let (lo, hi) = (g0.max(i0 as f64) as usize, g1.min(i1 as f64) as usize);
    s.add_row(spec.position(start, j).x, spec.cell_size().x, y, lo - start, &mut row[lo..=hi]);
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use relief_heightfield::{Extent, GridSpec};

    use super::*;

    /// A stroke that starts just inside the coast (within the snap distance) and crosses out a
    /// little further on: the stub from its start to the crossing never leaves the coast's snap
    /// band, so it is no piece; the bump is. Drawn clockwise it adds the bump; counter-clockwise
    /// the island becomes the bump (§3.1). The stub used to be a piece of its own: the stroke
    /// failed as missing the coast, or cut the land away.
    #[test]
    fn a_stroke_starting_just_inside_the_coast_adds_its_bump() {
        let grid = GridSpec::from_extent(96, 96, Extent::new(DVec2::ZERO, DVec2::splat(4000.0))).unwrap();
        let fresh = || Island::new(grid, IslandSettings::default(), 1).unwrap();
        // The start circle: radius 1600 about (2000, 2000); the snap 80. (3300, 1200) lies 74
        // inside it, the crossing 95 further along the stroke.
        let (inside, out, back) = (DVec2::new(3300.0, 1200.0), DVec2::new(3900.0, 2000.0), DVec2::new(3300.0, 2800.0));
        let mut island = fresh();
        let area = island.area();
        let kinds = island.stroke(&[back, out, inside]).unwrap();
        assert!(kinds.contains(&EditKind::Add), "{kinds:?}");
        assert!(island.area() > 1.01 * area, "{} → {}", area, island.area());
        let mut island = fresh();
        let kinds = island.stroke(&[inside, out, back]).unwrap();
        assert!(kinds.contains(&EditKind::Replace), "{kinds:?}");
        assert!(island.area() < 0.2 * area, "the island is the bump: {} → {}", area, island.area());
        // A stroke from there out to sea crosses once: no piece, where its stub once cut a sliver.
        let mut island = fresh();
        assert!(matches!(island.stroke(&[inside, out]), Err(IslandError::StrokeMissesCoast { .. })));
        assert_eq!(island.area(), area);
        // A two-point stroke from just inside the west coast straight across the land cuts the
        // island in two (its one segment leaves the snap band): the northern half goes.
        let mut island = fresh();
        let kinds = island.stroke(&[DVec2::new(450.0, 2000.0), DVec2::new(3900.0, 2000.0)]).unwrap();
        assert_eq!(kinds, [EditKind::Cut]);
        assert!((island.area() / area - 0.5).abs() < 0.05, "{} → {}", area, island.area());
    }

    /// An island cut by a vertical stroke at x = 350, and what the blend of §3.2 saw.
    struct Cut {
        island: Island,
        /// Base heights before the cut.
        before: Vec<f32>,
        /// Per sample, on land, the distances to the new and to the unchanged coast.
        distances: Vec<Option<(f64, f64)>>,
        /// Their largest values over the land.
        largest: (f64, f64),
    }

    fn cut(rule: NewHeights) -> Cut {
        let grid = GridSpec::from_extent(257, 257, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
        let settings = IslandSettings { new_heights: rule, ..IslandSettings::default() };
        let mut island = Island::new(grid, settings, 1).unwrap();
        let before = island.heights.clone();
        island.stroke(&[DVec2::new(350.0, -10.0), DVec2::new(350.0, 1010.0)]).unwrap();
        let land = island.mask();
        let window = island.coast_window();
        let (d_new, d_old) = (island.distance_to(true, window, &land), island.distance_to(false, window, &land));
        // The largest finite distance over the land of the window.
        let on_land = land_in(&land, window, 257);
        let largest = |d: &[f32]| {
            d.iter().zip(&on_land).filter(|(v, l)| **l && v.is_finite()).map(|(v, _)| f64::from(*v)).fold(0.0, f64::max)
        };
        let (m_new, m_old) = (largest(&d_new), largest(&d_old));
        let w = window.1 - window.0 + 1;
        let scaled = (0..257 * 257)
            .map(|k| {
                let (i, j) = (k % 257, k / 257);
                land[k].then(|| {
                    let c = (j - window.2) * w + (i - window.0);
                    (f64::from(d_new[c]), f64::from(d_old[c]))
                })
            })
            .collect();
        Cut { island, before, distances: scaled, largest: (m_new, m_old) }
    }

    /// `land` cut to `window`, row-major in it.
    fn land_in(land: &[bool], (i0, i1, j0, j1): (usize, usize, usize, usize), nx: usize) -> Vec<bool> {
        (j0..=j1).flat_map(|j| (i0..=i1).map(move |i| land[j * nx + i])).collect()
    }

    #[test]
    fn a_coastline_edit_blends_by_the_papers_tanh() {
        for rule in [NewHeights::Cone, NewHeights::Paper] {
            let Cut { island, before, distances, largest: (m_new, m_old) } = cut(rule);
            let height = island.settings.height;
            // The cone's H_n: a fresh island's heights over the whole coast.
            let cone_max = distances.iter().flatten().map(|&(a, b)| a.min(b)).fold(0.0, f64::max);
            let (mut worst, mut linear_off, mut n) = (0.0f64, 0.0f64, 0);
            for (k, d) in distances.iter().enumerate() {
                let Some((to_new, to_old)) = *d else { continue };
                let (dn, dold) = (to_new / m_new, to_old / m_old);
                let hn = match rule {
                    NewHeights::Cone => height * to_new.min(to_old) / cone_max,
                    NewHeights::Paper => height * dn,
                };
                let ho = f64::from(before[k]);
                let w = 0.5 + 0.5 * (dold * dold - dn).tanh();
                let h = ho * (1.0 - w) + hn * w;
                worst = worst.max((f64::from(island.heights[k]) - h).abs());
                let linear = (0.5 + 0.5 * (dold * dold - dn)).clamp(0.0, 1.0);
                linear_off = linear_off.max((ho * (1.0 - linear) + hn * linear - h).abs());
                n += 1;
            }
            assert!(n > 20_000);
            assert!(
                worst < 1e-3 * height,
                "{rule:?}: {worst} m from H = H_o(1 − W) + H_n·W, W = ½ + ½·tanh(D_o² − D_n)"
            );
            assert!(linear_off > 0.05 * height, "{rule:?}: a linear W would be at most {linear_off} m off");
        }
    }

    #[test]
    fn the_papers_new_heights_lift_the_unchanged_shore() {
        // Land within two cells of the unchanged eastern shore, far from the cut.
        let shore = |rule| {
            let Cut { island, distances: scaled, .. } = cut(rule);
            let g = island.grid;
            let heights: Vec<f64> = (0..g.len())
                .filter(|&k| {
                    let p = g.position(k % g.nx(), k / g.nx());
                    scaled[k].is_some() && p.x > 750.0 && (p.distance(DVec2::splat(500.0)) - 400.0).abs() < 8.0
                })
                .map(|k| f64::from(island.heights[k]))
                .collect();
            assert!(heights.len() > 50);
            heights.iter().sum::<f64>() / heights.len() as f64 / island.settings.height
        };
        let (cone, paper) = (shore(NewHeights::Cone), shore(NewHeights::Paper));
        assert!(cone < 0.03, "the cone keeps the shore at sea level: {cone:.3} of the height");
        assert!(paper > 0.08 && paper < 0.18, "H_n ∝ D_n lifts it by about 13 %: {paper:.3} of the height");
    }

    #[test]
    fn filters_follow_section_3_4() {
        let grid = GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
        let mut island = Island::new(grid, IslandSettings::default(), 7).unwrap();
        let area = island.area();
        // The count is proportional to the island's area: coverage × area / the mean
        // perturbation area, whose radii scale with the island's equivalent radius.
        let r_eq = (area / std::f64::consts::PI).sqrt();
        let mean = |[lo, hi]: [f64; 2]| 0.5 * (lo + hi);
        let mean_area = std::f64::consts::PI * (mean(island.settings.filter_radius) * r_eq).powi(2);
        let added = island.add_filters(3.0).unwrap();
        assert_eq!(added as f64, (3.0 * area / mean_area).round(), "count = coverage × area / mean perturbation area");
        let filters = island.filters().to_vec();
        let (up, down) =
            (filters.iter().filter(|f| f.height > 0.0).count(), filters.iter().filter(|f| f.height < 0.0).count());
        assert!(up > added / 3 && down > added / 3, "bumps and dents at random: {up} up, {down} down");
        for f in &filters {
            let [a, b] = f.radii;
            assert!(a >= b && b >= 0.5 * a, "radii {a}, {b}");
            assert!(f.height.abs() < b, "wider than tall: radius {b}, height {}", f.height);
            assert!((0.03 * r_eq..=0.1 * r_eq).contains(&a), "radius {a} outside [0.03, 0.1] × {r_eq}");
            assert!(ring_contains(&island.coast.points, DVec2::from(f.center)), "centre {:?} at sea", f.center);
        }
        // The perturbations add to the coastline's heights: the terrain is their sum on land.
        let g = island.grid;
        let mut checked = 0;
        for k in (0..g.len()).filter(|&k| island.land[k] && island.heights[k] > 5.0) {
            let p = g.position(k % g.nx(), k / g.nx());
            let bumps: f64 = filters.iter().map(|f| f.at(p)).sum();
            let want = f64::from(island.heights[k]) + bumps;
            assert!(
                (f64::from(island.terrain[k]) - want).abs() < 1e-3,
                "sample {k}: {} is not {want}",
                island.terrain[k]
            );
            checked += usize::from(bumps.abs() > 0.1);
        }
        assert!(checked > 1000, "{checked} samples under a perturbation");
        // A second batch differs from the first (a new stream); removing it leaves the first.
        let first = island.terrain().to_vec();
        let more = island.add_filters(1.0).unwrap();
        assert!(more > 0 && island.filters()[added..] != filters[..more], "a new batch draws new perturbations");
        assert_eq!(island.remove_filters(more), more);
        assert_eq!(island.filters(), &filters[..]);
        assert_eq!(island.terrain(), &first[..]);
        assert_eq!(island.remove_filters(usize::MAX), added, "removing more than there are removes all");
        assert!(island.filters().is_empty());
    }

    /// Regression: an edit's window used to start a paraboloid's row walk at the window's edge
    /// instead of the span's first sample, so sums over a clipped span differed from a rebuild's
    /// in their last bits (a volcano's western rim, a batch of filters). Seeded edit sessions,
    /// their f64 grids compared bit for bit with a rebuild's.
    #[test]
    fn windowed_edits_sum_exactly_what_a_rebuild_sums() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move |lo: f64, hi: f64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            lo + (hi - lo) * (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let grid = GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
        for session in 0..100 {
            let mut island = Island::new(grid, IslandSettings::default(), session).unwrap();
            for _ in 0..3 {
                let a = next(20.0, 300.0);
                let center = [next(0.0, 1000.0), next(0.0, 1000.0)];
                let hill = Hill { center, radii: [a, a * next(0.3, 1.0)], rotation: next(0.0, 180.0), height: 50.0 };
                island.add_hill(hill).unwrap();
            }
            island.move_hill(0, DVec2::new(next(0.0, 1000.0), next(0.0, 1000.0))).unwrap();
            island.add_filters(1.0).unwrap();
            let mut full = island.clone();
            full.rebuild();
            let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same(&island.hills_grid, &full.hills_grid), "session {session}: hills {:?}", island.hills);
            assert!(same(&island.filters_grid, &full.filters_grid), "session {session}: filters");
            assert_eq!(island.terrain, full.terrain, "session {session}");
        }
    }

    /// Damage done to an island's state behind its API's back.
    type Corruption<'a> = Box<dyn Fn(&mut Island) + 'a>;

    /// Every kind of damage a bug could leave in an island's state fails `check_invariants`,
    /// with a message naming it.
    #[test]
    fn corrupted_islands_fail_their_invariants() {
        let grid = GridSpec::from_extent(65, 65, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
        let mut good = Island::new(grid, IslandSettings::default(), 1).unwrap();
        good.add_hill(Hill::round(DVec2::splat(500.0), 200.0, 80.0)).unwrap();
        good.add_filters(1.0).unwrap();
        good.check_invariants().unwrap();
        let (sea, land) = (grid.index(0, 0), grid.index(32, 32));
        assert!(!good.land[sea] && good.land[land]);
        let corruptions: [(&str, Corruption); 9] = [
            ("sea sample (0, 0)", Box::new(|i| i.terrain[sea] = 1.0)),
            ("land sample (32, 32)", Box::new(|i| i.terrain[land] = 0.0)),
            ("land sample (32, 32)", Box::new(|i| i.hills_grid[land] += 1.0)),
            ("clockwise", Box::new(|i| i.coast.points.reverse())),
            ("not a simple polygon", Box::new(|i| i.coast.points.swap(3, 40))),
            ("heights grid holds 4224 samples", Box::new(|i| i.heights.truncate(4224))),
            ("sample (32, 32) is sea", Box::new(|i| i.land[land] = false)),
            ("fresh flags", Box::new(|i| i.coast.fresh.truncate(1))),
            ("hill 0", Box::new(|i| i.hills[0].radii = [1.0, 2.0])),
        ];
        for (expected, corrupt) in corruptions {
            let mut bad = good.clone();
            corrupt(&mut bad);
            match bad.check_invariants() {
                Err(IslandError::Invariant(m)) => assert!(m.contains(expected), "{expected:?} not in {m:?}"),
                other => panic!("{expected}: {other:?}"),
            }
        }
    }

    /// The half-resolution labelled distances against the brute-force distance to the nearest
    /// edge of each kind, on a jagged coast after a stroke (both kinds present).
    #[test]
    fn coast_distances_match_brute_force_within_half_a_cell() {
        let grid = GridSpec::from_extent(203, 181, Extent::new(DVec2::ZERO, DVec2::new(1000.0, 900.0))).unwrap();
        // A star (long straight arms meeting at shallow angles) and a jagged 300-gon.
        let outline = |count: u32, radius: &dyn Fn(u32) -> f64| -> Vec<DVec2> {
            (0..=count)
                .map(|k| {
                    let a = std::f64::consts::TAU * f64::from(k) / f64::from(count);
                    DVec2::new(500.0, 450.0) + radius(k % count) * DVec2::new(a.cos(), a.sin())
                })
                .collect()
        };
        let star = outline(40, &|k| if k % 2 == 0 { 420.0 } else { 340.0 + 2.0 * f64::from(k) });
        let jagged = outline(300, &|k| 330.0 + 60.0 * (f64::from(k) * 12.9898).sin().fract().abs());
        for coast in [star, jagged] {
            let mut island = Island::new(grid, IslandSettings::default(), 3).unwrap();
            island.set_coastline(&coast).unwrap();
            island.stroke(&[DVec2::new(330.0, -10.0), DVec2::new(330.0, 910.0)]).unwrap();
            check_distances(&island);
        }
    }

    fn check_distances(island: &Island) {
        let grid = island.grid;
        assert!(island.coast.fresh.contains(&true) && island.coast.fresh.contains(&false));
        let window = island.coast_window();
        let (i0, j0, w) = (window.0, window.2, window.1 - window.0 + 1);
        let cell = grid.cell_size().max_element();
        let p = &island.coast.points;
        for fresh in [true, false] {
            let d = island.distance_to(fresh, window, &island.land);
            let (mut worst, mut checked) = (0.0f64, 0);
            for (k, &is_land) in island.land.iter().enumerate() {
                if !is_land {
                    continue;
                }
                let (i, j) = grid.coords(k);
                let q = grid.position(i, j);
                let exact = (0..p.len())
                    .filter(|&e| island.coast.fresh[e] == fresh)
                    .map(|e| crate::geometry::project(p[e], p[(e + 1) % p.len()], q).0.distance(q))
                    .fold(f64::INFINITY, f64::min);
                let got = f64::from(d[(j - j0) * w + (i - i0)]);
                assert!(got >= exact * (1.0 - 1e-6) - 1e-9, "never below the true distance: {got} < {exact} at {q}");
                if got - exact > 2.5 {
                    eprintln!("{q} got {got} exact {exact}");
                }
                worst = worst.max(got - exact);
                checked += 1;
            }
            assert!(checked > 10_000);
            assert!(worst <= 0.5 * cell, "fresh = {fresh}: off by up to {worst} (cell {cell})");
        }
    }
}
