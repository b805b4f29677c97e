//! Flow routing (D8 and multiple flow direction), drainage area, streams and Strahler order.

use rayon::prelude::*;
use relief_heightfield::Heightfield;
use serde::{Deserialize, Serialize};

use crate::HydrologyError;
use crate::error::check_param;
use crate::grid8::Grid8;

/// Marks a cell without a receiver in [`D8::receivers`] (a sink: outlet, pit, flat or no-data).
pub const NO_RECEIVER: u32 = u32::MAX;

/// Single-flow-direction routing: every cell sends its water to its steepest-descent neighbour
/// (O'Callaghan & Mark 1984), with slopes measured over true ground distances.
///
/// Route a depression-filled DEM ([`crate::fill`]): on a raw DEM pits and flats become sinks.
#[derive(Debug, Clone, PartialEq)]
pub struct D8 {
    nx: usize,
    receivers: Vec<u32>,
    distance: Vec<f32>,
    /// Every cell after its receiver, like Braun & Willett's stack.
    order: Vec<u32>,
    area: Vec<f64>,
}

impl D8 {
    /// Steepest-descent receivers (parallel over rows), the downstream-first order and the
    /// drainage area of every cell.
    ///
    /// # Errors
    /// [`HydrologyError::AllNoData`].
    pub fn new(hf: &Heightfield) -> Result<Self, HydrologyError> {
        let n = hf.grid().len();
        if hf.no_data_count() == n {
            return Err(HydrologyError::AllNoData { cells: n });
        }
        let g = Grid8::new(hf.grid());
        let z = hf.samples();
        let (receivers, distance): (Vec<u32>, Vec<f32>) = (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map(|k| {
                if z[k].is_nan() {
                    return (NO_RECEIVER, 0.0);
                }
                let (mut best, mut best_slope, mut best_d) = (NO_RECEIVER, 0.0f64, 0.0);
                g.each(k, |w, _, d| {
                    // NaN compares false: no-data is never a receiver.
                    if z[w] < z[k] {
                        let s = f64::from(z[k] - z[w]) / d;
                        if s > best_slope {
                            (best, best_slope, best_d) = (w as u32, s, d);
                        }
                    }
                });
                (best, best_d as f32)
            })
            .unzip();
        let mut area = g.cell_areas(z);
        let order = accumulate(&receivers, &mut area);
        Ok(Self { nx: g.nx, receivers, distance, order, area })
    }

    /// Per cell, the flat index of its receiver, or [`NO_RECEIVER`] for a sink.
    pub fn receivers(&self) -> &[u32] {
        &self.receivers
    }

    /// Per cell, the ground distance to its receiver in metres (0 for a sink).
    pub fn distances(&self) -> &[f32] {
        &self.distance
    }

    /// Cells in downstream-first order: every cell comes after its receiver.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Drainage area per cell, m²: its own area plus everything upstream (0 on no-data).
    pub fn drainage_area(&self) -> &[f64] {
        &self.area
    }

    /// Flow accumulation in cells (drainage area counted in cells instead of m²).
    pub fn accumulation(&self) -> Vec<u32> {
        let mut acc: Vec<u32> = self.area.iter().map(|&a| u32::from(a > 0.0)).collect();
        for &k in self.order.iter().rev() {
            let r = self.receivers[k as usize];
            if r != NO_RECEIVER {
                acc[r as usize] += acc[k as usize];
            }
        }
        acc
    }

    /// Sinks: cells with no receiver that hold data (outlets, and pits or flats on an unfilled DEM).
    pub fn sinks(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let nx = self.nx;
        self.receivers
            .iter()
            .zip(&self.area)
            .enumerate()
            .filter(|(_, (r, a))| **r == NO_RECEIVER && **a > 0.0)
            .map(move |(k, _)| (k % nx, k / nx))
    }

    /// Stream cells: drainage area at least `min_area_m2`.
    ///
    /// # Errors
    /// [`HydrologyError::InvalidParameter`] for a negative or non-finite threshold.
    pub fn streams(&self, min_area_m2: f64) -> Result<Vec<bool>, HydrologyError> {
        check_param("min_area_m2", min_area_m2, |a| a >= 0.0, "must be a finite area ≥ 0")?;
        Ok(self.area.iter().map(|&a| a > 0.0 && a >= min_area_m2).collect())
    }

    /// Strahler order of the stream network `streams` (0 off the network): a source is 1, and a
    /// cell takes the largest order among its stream donors, plus one where two or more donors
    /// share that largest order.
    ///
    /// # Errors
    /// [`HydrologyError::LengthMismatch`] if `streams` does not have one flag per cell.
    pub fn strahler(&self, streams: &[bool]) -> Result<Vec<u8>, HydrologyError> {
        strahler(&self.receivers, &self.order, streams)
    }
}

/// Adds every cell's `area` into its receiver's, upstream first, and returns the cells in
/// downstream-first order (each after its receiver). O(N) and cache-friendly: a scan finds the
/// sources (no donors), and from each the walk follows receivers downstream until it meets a cell
/// that still waits for another donor (Kahn's algorithm walked as chains). Deterministic.
fn accumulate(receivers: &[u32], area: &mut [f64]) -> Vec<u32> {
    let n = receivers.len();
    // Donor counts: at most 8 on a grid, but any network may use this, so u32.
    let mut waiting = vec![0u32; n];
    for &r in receivers {
        if r != NO_RECEIVER {
            waiting[r as usize] += 1;
        }
    }
    let mut order = Vec::with_capacity(n);
    for start in 0..n {
        if waiting[start] != 0 {
            continue;
        }
        let mut c = start;
        loop {
            order.push(c as u32);
            // Done: the scan must not start here again.
            waiting[c] = u32::MAX;
            let r = receivers[c];
            if r == NO_RECEIVER {
                break;
            }
            let r = r as usize;
            area[r] += area[c];
            waiting[r] -= 1;
            if waiting[r] != 0 {
                break;
            }
            c = r;
        }
    }
    order.reverse();
    order
}

/// Strahler order over any single-receiver network given in downstream-first `order`
/// (see [`D8::strahler`]).
///
/// # Errors
/// [`HydrologyError::LengthMismatch`] when the arrays disagree in length.
pub fn strahler(receivers: &[u32], order: &[u32], streams: &[bool]) -> Result<Vec<u8>, HydrologyError> {
    let n = receivers.len();
    if streams.len() != n {
        return Err(HydrologyError::LengthMismatch { what: "stream flags", expected: n, found: streams.len() });
    }
    if order.len() != n {
        return Err(HydrologyError::LengthMismatch { what: "cell order", expected: n, found: order.len() });
    }
    // Per cell: the largest donor order so far and how many donors reach it.
    let mut top = vec![(0u8, 0u8); n];
    let mut out = vec![0u8; n];
    for &k in order.iter().rev() {
        let k = k as usize;
        if !streams[k] {
            continue;
        }
        let (m, c) = top[k];
        let s = match (m, c) {
            (0, _) => 1,
            (m, c) if c >= 2 => m.saturating_add(1),
            (m, _) => m,
        };
        out[k] = s;
        let r = receivers[k];
        if r != NO_RECEIVER && streams[r as usize] {
            let t = &mut top[r as usize];
            if s > t.0 {
                *t = (s, 1);
            } else if s == t.0 {
                t.1 = t.1.saturating_add(1);
            }
        }
    }
    Ok(out)
}

/// How multiple-flow-direction routing splits a cell's water among its lower neighbours.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Mfd {
    /// Freeman (1991): fractions ∝ tan(β)^p, `p` = 1.1 in the paper.
    Freeman {
        /// Slope exponent.
        p: f64,
    },
    /// Quinn et al. (1991): fractions ∝ tan(β) · L, with contour length L = ½ cell side on
    /// cardinal and 0.354 cell side on diagonal neighbours.
    Quinn,
}

impl Default for Mfd {
    fn default() -> Self {
        Self::Freeman { p: 1.1 }
    }
}

/// Drainage area (m²) under multiple-flow-direction routing: each cell passes its area to all
/// strictly lower neighbours. Cells are processed from the highest down (a parallel sort, ties by
/// index), so the result is deterministic. Route a filled DEM ([`crate::fill`]) for water to reach
/// the outlets.
///
/// # Errors
/// [`HydrologyError::AllNoData`], or [`HydrologyError::InvalidParameter`] for a Freeman exponent
/// that is not finite and positive.
pub fn mfd_drainage_area(hf: &Heightfield, method: Mfd) -> Result<Vec<f64>, HydrologyError> {
    let n = hf.grid().len();
    if hf.no_data_count() == n {
        return Err(HydrologyError::AllNoData { cells: n });
    }
    let p = match method {
        Mfd::Freeman { p } => {
            check_param("p", p, |p| p > 0.0, "the Freeman exponent must be positive")?;
            p
        }
        Mfd::Quinn => 1.0,
    };
    let g = Grid8::new(hf.grid());
    let z = hf.samples();
    let mut order: Vec<u32> = (0..n as u32).filter(|&k| !z[k as usize].is_nan()).collect();
    order.par_sort_unstable_by(|&a, &b| z[b as usize].total_cmp(&z[a as usize]).then(a.cmp(&b)));
    let mut area = g.cell_areas(z);
    let mut share = [(0usize, 0.0f64); 8];
    for &k in &order {
        let k = k as usize;
        let mut count = 0;
        let mut total = 0.0;
        g.each(k, |w, dir, d| {
            if z[w] < z[k] {
                let tan = f64::from(z[k] - z[w]) / d;
                let weight = match method {
                    Mfd::Freeman { .. } => tan.powf(p),
                    Mfd::Quinn => tan * if dir % 2 == 0 { 0.5 } else { 0.354 },
                };
                share[count] = (w, weight);
                count += 1;
                total += weight;
            }
        });
        if total > 0.0 {
            let a = area[k];
            for &(w, weight) in &share[..count] {
                area[w] += a * weight / total;
            }
        }
    }
    Ok(area)
}
