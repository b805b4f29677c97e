//! Marching squares over a raster DEM, drawing the lines `gdal_contour` draws.
//!
//! The squares are the cells between four sample centres, plus a ring of half-empty squares
//! around the raster. A square with no-data corners (outside the raster, or NaN samples) is split
//! into quarters, one per corner holding data, whose other corners take the means of the data
//! around them: the value at an edge's midpoint is the mean of its ends that hold data, the value
//! at the centre the mean of the corners that do. So lines run on to the raster's outer edge and
//! to half-way to a no-data sample, as GDAL's do. Saddles are split the way GDAL splits them
//! (whatever the levels): the north-west and south-east corners stay joined, the south-west and
//! north-east ones are cut off, which keeps lines of different levels from crossing.
//!
//! A value within [`TIE`] of a level is moved [`TIE`] above it, as GDAL moves it, so a sample at a
//! level counts as above it and no line passes through a sample. Lines are linked by the identity
//! of the edges they cross (not by comparing coordinates), row by row as the squares are visited,
//! so nothing but the lines themselves is kept; bands of rows are traced in parallel and joined in
//! order.

use std::collections::{HashMap, VecDeque};

use foldhash::fast::FixedState;
use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::Heightfield;

use crate::levels::check_levels;
use crate::{Contour, ContourSet, ContoursError};

/// How close to a level a value must be to count as on it (and be moved above it).
const TIE: f64 = 1e-6;

/// A value moved off `level` when it is within [`TIE`] of it.
fn fudge(value: f64, level: f64) -> f64 {
    if (level - value).abs() < TIE { value + TIE } else { value }
}

/// A corner of a square or quarter: its position and value (NaN: no data).
#[derive(Clone, Copy)]
struct Corner {
    p: DVec2,
    v: f64,
}

impl Corner {
    /// The midpoint of an edge: the mean of its ends' values, or the one end's that holds data.
    fn mid(a: Corner, b: Corner) -> Corner {
        let v = match (a.v.is_nan(), b.v.is_nan()) {
            (true, _) => b.v,
            (_, true) => a.v,
            _ => 0.5 * (a.v + b.v),
        };
        Corner { p: 0.5 * (a.p + b.p), v }
    }
}

/// Where `level` crosses the segment from `a` to `b` (their fudged values on either side of it).
fn interpolate(a: Corner, b: Corner, level: f64) -> DVec2 {
    let fa = fudge(a.v, level);
    let t = (level - fa) / (fudge(b.v, level) - fa);
    a.p * (1.0 - t) + b.p * t
}

/// An edge of a square or quarter: the key its crossings are linked by and the segment they lie on.
#[derive(Clone, Copy)]
struct Edge {
    /// Unique among all edges; [`NEVER`] for an edge whose ends cannot differ (one end or both
    /// without data, so the quarter's side along it is flat).
    id: u64,
    a: Corner,
    b: Corner,
    /// A raster edge between two samples: interpolated on the half that holds the crossing, as a
    /// quarter beside it would, so both squares beside the edge find the same point.
    split: bool,
}

/// The id of edges that no line crosses.
const NEVER: u64 = u64::MAX;

impl Edge {
    fn crossing(&self, level: f64) -> DVec2 {
        if !self.split {
            return interpolate(self.a, self.b, level);
        }
        let m = Corner::mid(self.a, self.b);
        let (fa, fm) = (fudge(self.a.v, level), fudge(m.v, level));
        if (fa < level && level < fm) || (fa > level && level > fm) {
            interpolate(self.a, m, level)
        } else {
            interpolate(m, self.b, level)
        }
    }
}

/// A polyline being linked: its points and the keys of its two open ends.
struct Line {
    level: u32,
    points: VecDeque<DVec2>,
    start: u64,
    end: u64,
    closed: bool,
}

/// The lines so far and their open ends, keyed by `edge id × levels + level`.
struct Linker {
    lines: Vec<Option<Line>>,
    open: HashMap<u64, u32, FixedState>,
    levels: u64,
}

impl Linker {
    fn new(levels: usize) -> Self {
        Linker { lines: Vec::new(), open: HashMap::with_hasher(FixedState::with_seed(0)), levels: levels as u64 }
    }

    /// Adds the segment of level `level` from its crossing of `from` to its crossing of `to`.
    fn add(&mut self, level: u32, height: f64, from: &Edge, to: &Edge) {
        debug_assert!(from.id != NEVER && to.id != NEVER, "a line crosses a flat edge");
        let ka = from.id * self.levels + u64::from(level);
        let kb = to.id * self.levels + u64::from(level);
        // The line ending where this segment starts, and the one starting where it ends.
        let before = self.open.remove(&ka);
        let after = self.open.remove(&kb);
        match (before, after) {
            (None, None) => {
                let id = self.lines.len() as u32;
                let points = VecDeque::from([from.crossing(height), to.crossing(height)]);
                self.lines.push(Some(Line { level, points, start: ka, end: kb, closed: false }));
                self.open.insert(ka, id);
                self.open.insert(kb, id);
            }
            (Some(p), None) => {
                let line = self.line(p);
                line.points.push_back(to.crossing(height));
                line.end = kb;
                self.open.insert(kb, p);
            }
            (None, Some(q)) => {
                let line = self.line(q);
                line.points.push_front(from.crossing(height));
                line.start = ka;
                self.open.insert(ka, q);
            }
            (Some(p), Some(q)) if p == q => {
                let line = self.line(p);
                line.closed = true;
                line.points.shrink_to_fit();
            }
            (Some(p), Some(q)) => self.join(p, q),
        }
    }

    /// Adds a line traced elsewhere (another band of rows): its points run from the crossing
    /// keyed `ka` to the one keyed `kb`, which may continue lines already here.
    fn attach(&mut self, level: u32, ka: u64, kb: u64, mut points: VecDeque<DVec2>) {
        let before = self.open.remove(&ka);
        let after = self.open.remove(&kb);
        // Points already here at either end are not repeated.
        if before.is_some() {
            points.pop_front();
        }
        if after.is_some() {
            points.pop_back();
        }
        match (before, after) {
            (None, None) => {
                let id = self.lines.len() as u32;
                self.lines.push(Some(Line { level, points, start: ka, end: kb, closed: false }));
                self.open.insert(ka, id);
                self.open.insert(kb, id);
            }
            (Some(p), None) => {
                let line = self.line(p);
                line.points.append(&mut points);
                line.end = kb;
                self.open.insert(kb, p);
            }
            (None, Some(q)) => {
                let line = self.line(q);
                while let Some(point) = points.pop_back() {
                    line.points.push_front(point);
                }
                line.start = ka;
                self.open.insert(ka, q);
            }
            (Some(p), Some(q)) => {
                self.line(p).points.append(&mut points);
                if p == q {
                    self.line(p).closed = true;
                } else {
                    self.join(p, q);
                }
            }
        }
    }

    /// Takes over the lines of `band`, traced over the rows after this one's.
    fn absorb(&mut self, band: Linker) {
        for line in band.lines.into_iter().flatten() {
            if line.closed {
                self.lines.push(Some(line));
            } else {
                self.attach(line.level, line.start, line.end, line.points);
            }
        }
    }

    fn line(&mut self, id: u32) -> &mut Line {
        self.lines[id as usize].as_mut().expect("an open end belongs to a live line")
    }

    /// Joins line `p` and the line `q` that continues it; the shorter one moves into the longer.
    fn join(&mut self, p: u32, q: u32) {
        let mut tail = self.lines[q as usize].take().expect("live line");
        let mut head = self.lines[p as usize].take().expect("live line");
        let (keep, line) = if head.points.len() >= tail.points.len() {
            head.points.append(&mut tail.points);
            head.end = tail.end;
            (p, head)
        } else {
            while let Some(point) = head.points.pop_back() {
                tail.points.push_front(point);
            }
            tail.start = head.start;
            (q, tail)
        };
        self.open.insert(line.start, keep);
        self.open.insert(line.end, keep);
        self.lines[keep as usize] = Some(line);
    }

    fn finish(self, levels: &[f64]) -> Vec<Contour> {
        self.lines
            .into_iter()
            .flatten()
            .map(|line| {
                let mut points = Vec::from(line.points);
                points.dedup();
                if line.closed && points.len() > 1 && points.first() == points.last() {
                    points.pop();
                }
                points.shrink_to_fit();
                Contour { level: line.level, height: levels[line.level as usize], points, closed: line.closed }
            })
            .collect()
    }
}

/// The raster seen as squares between sample centres, with the ring of squares around it.
struct Squares<'a> {
    dem: &'a Heightfield,
    levels: &'a [f64],
    linker: Linker,
}

impl Squares<'_> {
    fn nx(&self) -> i64 {
        self.dem.nx() as i64
    }
    fn ny(&self) -> i64 {
        self.dem.ny() as i64
    }

    /// Sample `(i, j)`, or a no-data corner at its place outside the raster.
    fn corner(&self, i: i64, j: i64) -> Corner {
        let grid = self.dem.grid();
        let p = grid.origin() + DVec2::new(i as f64, j as f64) * grid.cell_size();
        let inside = (0..self.nx()).contains(&i) && (0..self.ny()).contains(&j);
        let v = if inside { f64::from(self.dem.samples()[(j * self.nx() + i) as usize]) } else { f64::NAN };
        Corner { p, v }
    }

    /// The raster edge from `a` at `(i, j)` to `b`, east (`north == false`) or north of it.
    fn lattice(&self, i: i64, j: i64, north: bool, a: Corner, b: Corner) -> Edge {
        let (nx, ny) = (self.nx(), self.ny());
        let id = if a.v.is_nan() || b.v.is_nan() {
            NEVER
        } else if north {
            ((nx - 1) * ny + j * nx + i) as u64
        } else {
            (j * (nx - 1) + i) as u64
        };
        Edge { id, a, b, split: true }
    }

    /// The half-line inside square `(i, j)` from its edge midpoint `mid` to its centre; `side`
    /// 0..4 is south, east, north, west.
    fn half(&self, i: i64, j: i64, side: u64, mid: Corner, centre: Corner) -> Edge {
        let (nx, ny) = (self.nx(), self.ny());
        let lattice = (nx - 1) * ny + nx * (ny - 1);
        let square = (j + 1) * (nx + 1) + (i + 1);
        Edge { id: (lattice + square * 4) as u64 + side, a: mid, b: centre, split: false }
    }

    /// The squares of rows `rows`, each row from the west.
    fn trace(mut self, rows: std::ops::Range<i64>) -> Linker {
        for j in rows {
            for i in -1..self.nx() {
                self.square(i, j);
            }
        }
        self.linker
    }

    /// Square `(i, j)`: between samples `(i, j)` and `(i + 1, j + 1)`.
    fn square(&mut self, i: i64, j: i64) {
        let c = [self.corner(i, j), self.corner(i + 1, j), self.corner(i + 1, j + 1), self.corner(i, j + 1)];
        let [sw, se, ne, nw] = c;
        let edges = [
            self.lattice(i, j, false, sw, se),
            self.lattice(i + 1, j, true, se, ne),
            self.lattice(i, j + 1, false, nw, ne),
            self.lattice(i, j, true, sw, nw),
        ];
        let missing = c.iter().filter(|k| k.v.is_nan()).count();
        if missing == 0 {
            self.cases(c.map(|k| k.v), &edges);
            return;
        }
        if missing == 4 {
            return;
        }
        let [s, e, n, w] = edges;
        let centre = {
            let valid = c.iter().filter(|k| !k.v.is_nan());
            Corner { p: 0.5 * (sw.p + ne.p), v: valid.clone().map(|k| k.v).sum::<f64>() / valid.count() as f64 }
        };
        let (ms, me) = (Corner::mid(sw, se), Corner::mid(se, ne));
        let (mn, mw) = (Corner::mid(ne, nw), Corner::mid(nw, sw));
        let hs = self.half(i, j, 0, ms, centre);
        let he = self.half(i, j, 1, me, centre);
        let hn = self.half(i, j, 2, mn, centre);
        let hw = self.half(i, j, 3, mw, centre);
        // Each quarter's corners and edges in the square's order: south-west, south-east,
        // north-east, north-west; south, east, north, west.
        if !sw.v.is_nan() {
            self.cases([sw.v, ms.v, centre.v, mw.v], &[s, hs, hw, w]);
        }
        if !se.v.is_nan() {
            self.cases([ms.v, se.v, me.v, centre.v], &[s, e, he, hs]);
        }
        if !ne.v.is_nan() {
            self.cases([centre.v, me.v, ne.v, mn.v], &[he, e, n, hn]);
        }
        if !nw.v.is_nan() {
            self.cases([mw.v, centre.v, mn.v, nw.v], &[hw, hn, n, w]);
        }
    }

    /// The segments of a square (or quarter) with corner values `v` (south-west, south-east,
    /// north-east, north-west) and edges `e` (south, east, north, west: edge k joins corners k
    /// and k + 1), each oriented with higher ground on its left.
    fn cases(&mut self, v: [f64; 4], e: &[Edge; 4]) {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let first = self.levels.partition_point(|&l| l <= lo - TIE);
        for k in first..self.levels.len() {
            let level = self.levels[k];
            if level >= hi + TIE {
                break;
            }
            let high = v.map(|x| level < fudge(x, level));
            // Edge k rises (low to high, going counter-clockwise) or falls.
            let rising = |k: usize| !high[k] && high[(k + 1) % 4];
            let falling = |k: usize| high[k] && !high[(k + 1) % 4];
            let changes = (0..4).filter(|&k| high[k] != high[(k + 1) % 4]).count();
            let segment = |this: &mut Self, a: usize, b: usize| {
                // Higher ground on the left: from the falling edge to the rising one.
                let (from, to) = if falling(a) { (a, b) } else { (b, a) };
                this.linker.add(k as u32, level, &e[from], &e[to]);
            };
            match changes {
                2 => {
                    let from = (0..4).find(|&k| falling(k)).unwrap_or(0);
                    let to = (0..4).find(|&k| rising(k)).unwrap_or(0);
                    segment(self, from, to);
                }
                4 => {
                    // A saddle: cut off the south-west corner (edges west and south) and the
                    // north-east one (east and north), as GDAL does.
                    segment(self, 3, 0);
                    segment(self, 1, 2);
                }
                _ => {}
            }
        }
    }
}

/// Contours of a raster DEM at `levels` (sorted ascending), the lines `gdal_contour` draws:
/// marching squares between sample centres, saddles split as GDAL splits them, lines carried to
/// the raster's outer edge (half a cell beyond the outermost samples) and to half-way towards
/// no-data (NaN) samples, where they end open.
///
/// Closed contours run counter-clockwise around higher ground.
///
/// # Errors
/// [`ContoursError::InvalidLevels`].
pub fn extract_dem(dem: &Heightfield, levels: &[f64]) -> Result<ContourSet, ContoursError> {
    check_levels(levels)?;
    let contours = trace(dem, levels);
    ContourSet::new(levels.to_vec(), contours)
}

/// Square rows per band: bands are traced in parallel, a batch at a time, and joined in order,
/// so the lines do not depend on the thread count.
const BAND_ROWS: i64 = 16;

/// Bands per batch and thread: enough to keep the threads busy, few enough that the bands'
/// lines waiting to be joined stay small beside the lines themselves. (The batch size changes
/// nothing but the memory: bands are always joined in order.)
const BANDS_PER_THREAD: usize = 2;

/// Every square, in bands of rows from the south.
fn trace(dem: &Heightfield, levels: &[f64]) -> Vec<Contour> {
    let ny = dem.ny() as i64;
    let starts: Vec<i64> = (-1..ny).step_by(BAND_ROWS as usize).collect();
    let mut linker = Linker::new(levels.len());
    for batch in starts.chunks(BANDS_PER_THREAD * rayon::current_num_threads()) {
        let bands: Vec<Linker> = batch
            .par_iter()
            .map(|&j| Squares { dem, levels, linker: Linker::new(levels.len()) }.trace(j..(j + BAND_ROWS).min(ny)))
            .collect();
        for band in bands {
            linker.absorb(band);
        }
    }
    linker.finish(levels)
}
