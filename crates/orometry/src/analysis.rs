//! Peaks, key saddles and prominence by flooding from the top (§4.1): cells are visited from the
//! highest down, joined into components with a union–find; a cell that joins components is a
//! saddle, and every component but the one with the highest peak ends there, giving its peak its
//! key saddle and prominence. O(N log N) for the sort, near-linear after.
//!
//! Conventions (those of summit lists, Kirmse & de Ferranti 2017):
//! - cells compare by elevation, ties by row-major index (the earlier cell is higher), a strict
//!   order that resolves plateaus and flats deterministically; a plateau peak sits at its first
//!   cell in row-major order;
//! - peaks of zero prominence (the corners of flats that touch higher ground) are not peaks,
//!   except the highest of a land mass, which is always listed as the root of its divide tree
//!   (with prominence 0 on a map without relief);
//! - the highest peak of each connected land mass has no key saddle: its prominence is its
//!   height above the lowest outlet of that land mass, the lowest cell where water leaves the map
//!   (the border, a no-data cell or the sea), or the sea level when it touches the sea;
//! - a peak whose component reached the map's border before its key saddle is flagged
//!   `edge_effect`: higher ground beyond the map could join it through a higher saddle, so its
//!   prominence is an upper bound;
//! - no-data samples and samples at or below the sea level are not land.

use rayon::prelude::*;
use relief_heightfield::Heightfield;
use serde::{Deserialize, Serialize};

use crate::OrometryError;
use crate::isolation::{Isolation, isolation};

/// The most samples the analysis indexes (`u32` cell indices).
pub const MAX_CELLS: usize = u32::MAX as usize;

/// How to analyse.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnalysisOptions {
    /// Samples at or below this are sea (default: none). Dominance measures heights above it
    /// (or above 0 without a sea).
    pub sea_level: Option<f32>,
    /// Keep only peaks at least this prominent (default 0: every peak of positive prominence).
    pub min_prominence: f64,
}

impl AnalysisOptions {
    fn validate(&self) -> Result<(), OrometryError> {
        if let Some(s) = self.sea_level
            && !s.is_finite()
        {
            return Err(OrometryError::InvalidOption {
                name: "sea_level",
                value: f64::from(s),
                reason: "must be finite",
            });
        }
        if !(self.min_prominence >= 0.0 && self.min_prominence.is_finite()) {
            return Err(OrometryError::InvalidOption {
                name: "min_prominence",
                value: self.min_prominence,
                reason: "must be finite and ≥ 0",
            });
        }
        Ok(())
    }
}

/// A summit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// Grid cell `[i, j]`.
    pub cell: [usize; 2],
    /// World position `[x, y]`.
    pub position: [f64; 2],
    /// Elevation `h`.
    pub elevation: f64,
    /// Prominence `π` (§4.1).
    pub prominence: f64,
    /// Index of its key saddle in [`Orometry::saddles`]; `None` for the highest peak of a land mass.
    pub key_saddle: Option<usize>,
    /// The peak across the key saddle: the highest peak of the higher side when they joined.
    pub parent: Option<usize>,
    /// Dominance `δ = π / h` (heights above the sea level, or 0), in `[0, 1]`.
    pub dominance: f64,
    /// `π / max π` over the analysed peaks.
    pub relative_prominence: f64,
    /// `h / max h` over the analysed peaks (heights above the sea level, or 0).
    pub relative_elevation: f64,
    /// Relevance `ρ = √(π̃·h̃)`.
    pub relevance: f64,
    /// Distance and direction to the nearest strictly higher sample; `None` for the highest.
    pub isolation: Option<Isolation>,
    /// The peak's component reached the map's border before its key saddle (see the module docs).
    pub edge_effect: bool,
}

/// A key saddle: the lowest point on the highest path from a peak to higher ground.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Saddle {
    /// Grid cell `[i, j]`.
    pub cell: [usize; 2],
    /// World position `[x, y]`.
    pub position: [f64; 2],
    /// Elevation.
    pub elevation: f64,
    /// The peak it is the key saddle of, and the peak across it (indices into [`Orometry::peaks`]).
    pub peaks: [usize; 2],
}

/// The orometry of a DEM: its peaks and key saddles, which together form the divide tree.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Orometry {
    /// Peaks, highest first (ties by cell order).
    pub peaks: Vec<Peak>,
    /// Key saddles; peak `k`'s is `saddles[peaks[k].key_saddle]`.
    pub saddles: Vec<Saddle>,
}

/// Union–find with path halving; the root of a component holds its top peak and outlet.
struct Components {
    parent: Vec<u32>,
}

impl Components {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let up = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = up;
            x = up;
        }
        x
    }
}

/// A raw peak from the flood: its cell and, once known, key saddle cell and partner.
struct RawPeak {
    cell: u32,
    saddle: Option<u32>,
    parent: Option<u32>,
    edge: bool,
}

/// Key of a cell in the strict order: higher elevation first, then lower index.
fn order_key(h: f32, k: usize) -> u64 {
    // Map f32 to an unsigned key that sorts ascending with the value, then flip for descending.
    let bits = h.to_bits();
    let asc = if bits >> 31 == 1 { !bits } else { bits | 0x8000_0000 };
    (u64::from(!asc) << 32) | k as u64
}

/// Analyses `dem`: peaks, key saddles, prominence, dominance, relevance, isolation.
///
/// # Errors
/// [`OrometryError::NoLand`] when no sample is valid land, [`OrometryError::TooLarge`] beyond
/// [`MAX_CELLS`], [`OrometryError::InvalidOption`] for a non-finite sea level or a negative or
/// non-finite prominence threshold.
pub fn analyze(dem: &Heightfield, options: &AnalysisOptions) -> Result<Orometry, OrometryError> {
    let grid = dem.grid();
    let (nx, ny) = (grid.nx(), grid.ny());
    let n = grid.len();
    if n > MAX_CELLS {
        return Err(OrometryError::TooLarge { cells: n, limit: MAX_CELLS });
    }
    options.validate()?;
    let z = dem.samples();
    let sea = options.sea_level;
    let land = |k: usize| !z[k].is_nan() && sea.is_none_or(|s| z[k] > s);
    let mut order: Vec<u64> = (0..n).into_par_iter().filter(|&k| land(k)).map(|k| order_key(z[k], k)).collect();
    if order.is_empty() {
        return Err(OrometryError::NoLand { cells: n });
    }
    order.par_sort_unstable();

    // Flood from the top.
    let mut comps = Components { parent: vec![u32::MAX; n] };
    let mut top = vec![u32::MAX; n]; // per root: index into `raw`
    let mut edge = vec![false; n]; // per root: reached an outlet
    let mut outlet = vec![f32::INFINITY; n]; // per root: lowest outlet seen
    let mut sea_touch = vec![false; n];
    let mut raw: Vec<RawPeak> = Vec::new();
    let mut roots: Vec<u32> = Vec::with_capacity(8);
    for &key in &order {
        let k = (key & 0xffff_ffff) as usize;
        let (i, j) = (k % nx, k / nx);
        roots.clear();
        let mut is_outlet = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
        let mut near_sea = false;
        for (di, dj) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (a, b) = (i as i64 + di, j as i64 + dj);
            if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                continue;
            }
            let w = b as usize * nx + a as usize;
            if !land(w) {
                is_outlet = true;
                near_sea |= !z[w].is_nan();
                continue;
            }
            if comps.parent[w] != u32::MAX {
                let r = comps.find(w as u32);
                if !roots.contains(&r) {
                    roots.push(r);
                }
            }
        }
        let root = if roots.is_empty() {
            comps.parent[k] = k as u32;
            top[k] = raw.len() as u32;
            raw.push(RawPeak { cell: k as u32, saddle: None, parent: None, edge: false });
            k as u32
        } else {
            // The component whose top peak is highest (found first, so the lowest `raw` index)
            // absorbs the rest.
            let mut best = roots[0];
            for &r in &roots[1..] {
                if top[r as usize] < top[best as usize] {
                    best = r;
                }
            }
            for &r in &roots {
                if r != best {
                    let p = &mut raw[top[r as usize] as usize];
                    p.saddle = Some(k as u32);
                    p.parent = Some(top[best as usize]);
                    p.edge = edge[r as usize];
                    comps.parent[r as usize] = best;
                    edge[best as usize] |= edge[r as usize];
                    sea_touch[best as usize] |= sea_touch[r as usize];
                    outlet[best as usize] = outlet[best as usize].min(outlet[r as usize]);
                }
            }
            comps.parent[k] = best;
            best
        };
        if is_outlet {
            edge[root as usize] = true;
            outlet[root as usize] = outlet[root as usize].min(z[k]);
        }
        sea_touch[root as usize] |= near_sea;
    }
    let mut prominence: Vec<f64> = Vec::with_capacity(raw.len());
    for p in &raw {
        let h = f64::from(z[p.cell as usize]);
        let base = if let Some(s) = p.saddle {
            f64::from(z[s as usize])
        } else {
            let r = comps.find(p.cell) as usize;
            match (sea_touch[r], sea) {
                (true, Some(s)) => f64::from(s).min(f64::from(outlet[r])),
                _ => f64::from(outlet[r]),
            }
        };
        prominence.push(h - base);
    }
    Ok(assemble(dem, options, &raw, &prominence))
}

/// For peaks listed parents first, with `parents[k]` before `k`: each kept peak's new index,
/// each peak's nearest kept ancestor (its parent, or the parent's, … when those are dropped),
/// and the number kept.
fn relink(parents: impl Iterator<Item = Option<usize>>, keep: &[bool]) -> (Vec<usize>, Vec<Option<usize>>, usize) {
    let mut index = vec![usize::MAX; keep.len()];
    let mut linked: Vec<Option<usize>> = vec![None; keep.len()];
    let mut kept = 0;
    for (k, parent) in parents.enumerate() {
        linked[k] = parent.and_then(|q| if keep[q] { Some(q) } else { linked[q] });
        if keep[k] {
            index[k] = kept;
            kept += 1;
        }
    }
    (index, linked, kept)
}

/// Drops the peaks of zero prominence or below the threshold (land-mass tops stay, so the tree
/// keeps its roots), re-links their children to the nearest kept ancestor, and fills in the
/// derived measures.
fn assemble(dem: &Heightfield, options: &AnalysisOptions, raw: &[RawPeak], prominence: &[f64]) -> Orometry {
    let grid = dem.grid();
    let z = dem.samples();
    let nx = grid.nx();
    // Parents always come before their children (they were found first).
    let keep: Vec<bool> = raw
        .iter()
        .zip(prominence)
        .map(|(p, &pi)| p.saddle.is_none() || (pi > 0.0 && pi >= options.min_prominence))
        .collect();
    let (index, linked, kept) = relink(raw.iter().map(|p| p.parent.map(|q| q as usize)), &keep);
    let cell_of = |c: u32| {
        let (i, j) = (c as usize % nx, c as usize / nx);
        ([i, j], grid.position(i, j).to_array())
    };
    let base = f64::from(options.sea_level.unwrap_or(0.0));
    let mut peaks = Vec::with_capacity(kept);
    let mut saddles = Vec::new();
    for (k, p) in raw.iter().enumerate().filter(|(k, _)| keep[*k]) {
        let (cell, position) = cell_of(p.cell);
        let key_saddle = match (p.saddle, linked[k]) {
            (Some(s), Some(q)) => {
                let (cell, position) = cell_of(s);
                saddles.push(Saddle {
                    cell,
                    position,
                    elevation: f64::from(z[s as usize]),
                    peaks: [index[k], index[q]],
                });
                Some(saddles.len() - 1)
            }
            _ => None,
        };
        let elevation = f64::from(z[p.cell as usize]);
        let above = elevation - base;
        peaks.push(Peak {
            cell,
            position,
            elevation,
            prominence: prominence[k],
            key_saddle,
            parent: linked[k].map(|q| index[q]),
            dominance: if above > 0.0 { (prominence[k] / above).clamp(0.0, 1.0) } else { 0.0 },
            relative_prominence: 0.0,
            relative_elevation: 0.0,
            relevance: 0.0,
            isolation: None,
            edge_effect: p.edge,
        });
    }
    let max_p = peaks.iter().map(|p| p.prominence).fold(0.0, f64::max);
    let max_h = peaks.iter().map(|p| p.elevation - base).fold(0.0, f64::max);
    let isolations: Vec<Option<Isolation>> = {
        let pyramid = crate::isolation::Pyramid::new(dem);
        peaks.par_iter().map(|p| isolation(&pyramid, dem, p.cell, p.elevation as f32)).collect()
    };
    for (p, iso) in peaks.iter_mut().zip(isolations) {
        p.relative_prominence = if max_p > 0.0 { p.prominence / max_p } else { 0.0 };
        p.relative_elevation = if max_h > 0.0 { ((p.elevation - base) / max_h).max(0.0) } else { 0.0 };
        p.relevance = (p.relative_prominence * p.relative_elevation).sqrt();
        p.isolation = iso;
    }
    Orometry { peaks, saddles }
}

impl Orometry {
    /// The divide tree pruned to the peaks at least `min_prominence` prominent (§4.1, Fig. 6):
    /// dropped peaks take their key saddles with them; their children re-link to the nearest
    /// kept ancestor. Land-mass tops always stay.
    #[must_use]
    pub fn pruned(&self, min_prominence: f64) -> Orometry {
        let keep: Vec<bool> =
            self.peaks.iter().map(|p| p.key_saddle.is_none() || p.prominence >= min_prominence).collect();
        let (index, linked, kept) = relink(self.peaks.iter().map(|p| p.parent), &keep);
        let mut peaks = Vec::with_capacity(kept);
        let mut saddles = Vec::new();
        for (k, p) in self.peaks.iter().enumerate().filter(|(k, _)| keep[*k]) {
            let mut p = p.clone();
            p.parent = linked[k].map(|q| index[q]);
            p.key_saddle = match (p.key_saddle, p.parent) {
                (Some(s), Some(q)) => {
                    let mut s = self.saddles[s].clone();
                    s.peaks = [peaks.len(), q];
                    saddles.push(s);
                    Some(saddles.len() - 1)
                }
                _ => None,
            };
            peaks.push(p);
        }
        Orometry { peaks, saddles }
    }
}
