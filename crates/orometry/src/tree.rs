//! The divide tree as plain vectors (§4.1, §5): peaks, saddles, and for each saddle the two peaks
//! its ridges lead to. It is what analysis exports and what synthesis builds, edits and turns into
//! terrain.
//!
//! Prominence on a tree is the same flood as on a grid, over saddles only: saddles are taken from
//! the highest down (ties by index); a saddle joins two components, and the one whose highest
//! peak is lower ends there, giving that peak its key saddle. O(n log n).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::divide::{Ridge, contract};
use crate::union_find::find;
use crate::{Orometry, OrometryError};

/// A summit of the tree.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct TreePeak {
    /// World position `[x, y]`, metres.
    #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
    pub position: DVec2,
    /// Elevation, metres.
    pub elevation: f64,
}

/// A saddle on the ridge between two peaks: the ridge runs peak → saddle → peak.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TreeSaddle {
    /// World position, metres.
    pub position: DVec2,
    /// Elevation, metres; not above either peak it joins.
    pub elevation: f64,
    /// The two peaks its ridges lead to.
    pub peaks: [u32; 2],
}

/// Peaks joined by saddles. Usually a tree; edits may leave a forest, which every function here
/// accepts (each component has its own top). Deserializing validates it ([`DivideTree::validate`]).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(remote = "Self")]
pub struct DivideTree {
    /// Peaks.
    pub peaks: Vec<TreePeak>,
    /// Saddles, one per ridge pair.
    pub saddles: Vec<TreeSaddle>,
}

impl Serialize for DivideTree {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        DivideTree::serialize(self, s)
    }
}

impl<'de> Deserialize<'de> for DivideTree {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let tree = DivideTree::deserialize(d)?;
        tree.validate().map_err(serde::de::Error::custom)?;
        Ok(tree)
    }
}

/// Prominence and its companions for every peak of a [`DivideTree`].
#[derive(Debug, Clone, PartialEq)]
pub struct TreeOrometry {
    /// `π` per peak: down to the key saddle, or to the base for a component's top.
    pub prominence: Vec<f64>,
    /// Each peak's key saddle, `None` for a component's top.
    pub key_saddle: Vec<Option<u32>>,
}

impl TreeOrometry {
    /// Dominance `π / (h − datum)` per peak (0 for a peak at or below the datum), with `datum`
    /// the level heights are measured from (the sea level, or 0, as in the analysis).
    pub fn dominance(&self, tree: &DivideTree, datum: f64) -> Vec<f64> {
        tree.peaks
            .iter()
            .zip(&self.prominence)
            .map(|(p, &pi)| {
                let h = p.elevation - datum;
                if h > 0.0 { (pi / h).clamp(0.0, 1.0) } else { 0.0 }
            })
            .collect()
    }
}

impl DivideTree {
    /// The divide tree of an analysis: every peak with a key saddle is joined through it to its
    /// parent (the peak across the key saddle).
    pub fn from_orometry(oro: &Orometry) -> Self {
        let peaks =
            oro.peaks.iter().map(|p| TreePeak { position: DVec2::from(p.position), elevation: p.elevation }).collect();
        let saddles = oro
            .saddles
            .iter()
            .map(|s| TreeSaddle {
                position: DVec2::from(s.position),
                elevation: s.elevation,
                peaks: [s.peaks[0] as u32, s.peaks[1] as u32],
            })
            .collect();
        Self { peaks, saddles }
    }

    /// Checks indices and values: finite positions and elevations, saddles joining two distinct
    /// existing peaks and no higher than the lower of them.
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] naming the first offending peak or saddle.
    pub fn validate(&self) -> Result<(), OrometryError> {
        for (k, p) in self.peaks.iter().enumerate() {
            if !(p.position.is_finite() && p.elevation.is_finite()) {
                return Err(OrometryError::InvalidTree(format!("peak {k} has a non-finite position or elevation")));
            }
        }
        for (k, s) in self.saddles.iter().enumerate() {
            let [a, b] = s.peaks;
            if a == b || a as usize >= self.peaks.len() || b as usize >= self.peaks.len() {
                return Err(OrometryError::InvalidTree(format!(
                    "saddle {k} joins peaks {a} and {b}, but there are {} peaks and the two must differ",
                    self.peaks.len()
                )));
            }
            if !(s.position.is_finite() && s.elevation.is_finite()) {
                return Err(OrometryError::InvalidTree(format!("saddle {k} has a non-finite position or elevation")));
            }
            let top = self.peaks[a as usize].elevation.min(self.peaks[b as usize].elevation);
            if s.elevation > top {
                return Err(OrometryError::InvalidTree(format!(
                    "saddle {k} at {} m is above peak {} at {top} m",
                    s.elevation,
                    if self.peaks[a as usize].elevation <= self.peaks[b as usize].elevation { a } else { b }
                )));
            }
        }
        Ok(())
    }

    /// Prominence of every peak, with `base` the elevation a component's top is measured down to.
    /// Saddles that close a cycle (possible after edits) are ignored.
    pub fn orometry(&self, base: f64) -> TreeOrometry {
        let n = self.peaks.len();
        let mut order: Vec<u32> = (0..self.saddles.len() as u32).collect();
        order.sort_by(|&a, &b| {
            self.saddles[b as usize].elevation.total_cmp(&self.saddles[a as usize].elevation).then(a.cmp(&b))
        });
        let mut parent: Vec<u32> = (0..n as u32).collect();
        // Highest peak of each root's component (ties: lower index is higher).
        let mut top: Vec<u32> = (0..n as u32).collect();
        let higher = |a: u32, b: u32, peaks: &[TreePeak]| {
            let (ha, hb) = (peaks[a as usize].elevation, peaks[b as usize].elevation);
            ha > hb || (ha == hb && a < b)
        };
        let mut prominence = vec![0.0; n];
        let mut key_saddle = vec![None; n];
        for s in order {
            let saddle = &self.saddles[s as usize];
            let (ra, rb) = (find(&mut parent, saddle.peaks[0]), find(&mut parent, saddle.peaks[1]));
            if ra == rb {
                continue;
            }
            let (ta, tb) = (top[ra as usize], top[rb as usize]);
            let (win, lose) = if higher(ta, tb, &self.peaks) { (ta, tb) } else { (tb, ta) };
            prominence[lose as usize] = self.peaks[lose as usize].elevation - saddle.elevation;
            key_saddle[lose as usize] = Some(s);
            parent[ra as usize] = rb;
            top[rb as usize] = win;
        }
        for k in 0..n {
            if key_saddle[k].is_none() {
                prominence[k] = self.peaks[k].elevation - base;
            }
        }
        TreeOrometry { prominence, key_saddle }
    }

    /// Keeps only peaks at least `min_prominence` prominent (and each component's top),
    /// reconnecting the survivors the way [`Orometry::pruned`] does: a dropped peak is merged,
    /// from the lowest up, into the neighbour across its highest saddle, which goes; its other
    /// ridges lead on to that neighbour.
    #[must_use]
    pub fn pruned(&self, min_prominence: f64, base: f64) -> Self {
        let oro = self.orometry(base);
        let keep: Vec<bool> =
            oro.prominence.iter().zip(&oro.key_saddle).map(|(&p, ks)| ks.is_none() || p >= min_prominence).collect();
        // Saddles ranked highest first (ties by index), the order the flood takes them in.
        let mut by_height: Vec<usize> = (0..self.saddles.len()).collect();
        by_height.sort_by(|&a, &b| self.saddles[b].elevation.total_cmp(&self.saddles[a].elevation).then(a.cmp(&b)));
        let mut key = vec![0u64; self.saddles.len()];
        for (rank, &s) in by_height.iter().enumerate() {
            key[s] = rank as u64;
        }
        let ridges: Vec<Ridge> =
            self.saddles.iter().zip(&key).map(|(s, &key)| Ridge { near: s.peaks[0], far: s.peaks[1], key }).collect();
        let mut lowest_first: Vec<usize> = (0..self.peaks.len()).filter(|&k| !keep[k]).collect();
        lowest_first.sort_by(|&a, &b| self.peaks[a].elevation.total_cmp(&self.peaks[b].elevation).then(b.cmp(&a)));
        let ends = contract(&ridges, &keep, lowest_first);
        let mut tree = self.clone();
        for (saddle, end) in tree.saddles.iter_mut().zip(&ends) {
            if let Some(end) = end {
                saddle.peaks = *end;
            }
        }
        let alive: Vec<bool> = ends.iter().map(Option::is_some).collect();
        tree.retain(&keep, &alive);
        tree
    }

    /// Drops the peaks and saddles whose flags are false and renumbers the rest; saddles that
    /// lose a peak are dropped too.
    fn retain(&mut self, peaks: &[bool], saddles: &[bool]) {
        let mut remap = vec![u32::MAX; self.peaks.len()];
        let mut next = 0u32;
        for (k, &keep) in peaks.iter().enumerate() {
            if keep {
                remap[k] = next;
                next += 1;
            }
        }
        let mut k = 0;
        self.peaks.retain(|_| {
            k += 1;
            peaks[k - 1]
        });
        let mut s = 0;
        self.saddles.retain_mut(|saddle| {
            s += 1;
            let [a, b] = saddle.peaks.map(|p| remap[p as usize]);
            saddle.peaks = [a, b];
            saddles[s - 1] && a != u32::MAX && b != u32::MAX && a != b
        });
    }

    /// Adds a peak joined to `connect_to` through a new saddle; returns the new peak's index.
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] for an unknown peak, non-finite values or a saddle above
    /// either peak.
    pub fn insert_peak(&mut self, peak: TreePeak, connect_to: u32, saddle: (DVec2, f64)) -> Result<u32, OrometryError> {
        let k = self.peaks.len() as u32;
        self.peaks.push(peak);
        self.saddles.push(TreeSaddle { position: saddle.0, elevation: saddle.1, peaks: [k, connect_to] });
        if let Err(e) = self.validate() {
            self.peaks.pop();
            self.saddles.pop();
            return Err(e);
        }
        Ok(k)
    }

    /// Joins two peaks by a new ridge through a saddle; returns the saddle's index.
    ///
    /// # Errors
    /// As [`DivideTree::insert_peak`].
    pub fn insert_ridge(&mut self, a: u32, b: u32, saddle: (DVec2, f64)) -> Result<u32, OrometryError> {
        self.saddles.push(TreeSaddle { position: saddle.0, elevation: saddle.1, peaks: [a, b] });
        if let Err(e) = self.validate() {
            self.saddles.pop();
            return Err(e);
        }
        Ok(self.saddles.len() as u32 - 1)
    }

    /// Moves a peak (and optionally changes its elevation).
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] for an unknown peak or when the change would leave a saddle
    /// above it.
    pub fn move_peak(&mut self, k: u32, position: DVec2, elevation: Option<f64>) -> Result<(), OrometryError> {
        let Some(old) = self.peaks.get(k as usize).copied() else {
            return Err(OrometryError::InvalidTree(format!("no peak {k}")));
        };
        self.peaks[k as usize] = TreePeak { position, elevation: elevation.unwrap_or(old.elevation) };
        self.validate().inspect_err(|_| self.peaks[k as usize] = old)
    }

    /// Moves a saddle (and optionally changes its elevation).
    ///
    /// # Errors
    /// As [`DivideTree::move_peak`].
    pub fn move_saddle(&mut self, s: u32, position: DVec2, elevation: Option<f64>) -> Result<(), OrometryError> {
        let Some(old) = self.saddles.get(s as usize).copied() else {
            return Err(OrometryError::InvalidTree(format!("no saddle {s}")));
        };
        self.saddles[s as usize] = TreeSaddle { position, elevation: elevation.unwrap_or(old.elevation), ..old };
        self.validate().inspect_err(|_| self.saddles[s as usize] = old)
    }

    /// Deletes a ridge (its saddle): the tree splits in two.
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] for an unknown saddle.
    pub fn delete_ridge(&mut self, s: u32) -> Result<(), OrometryError> {
        if s as usize >= self.saddles.len() {
            return Err(OrometryError::InvalidTree(format!("no saddle {s}")));
        }
        self.saddles.remove(s as usize);
        Ok(())
    }

    /// Deletes a peak and its ridges. Its neighbours stay connected: each joins the highest of
    /// them through the lower of the two saddles on the old path, placed at that saddle.
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] for an unknown peak.
    pub fn delete_peak(&mut self, k: u32) -> Result<(), OrometryError> {
        if k as usize >= self.peaks.len() {
            return Err(OrometryError::InvalidTree(format!("no peak {k}")));
        }
        let incident: Vec<usize> = (0..self.saddles.len()).filter(|&s| self.saddles[s].peaks.contains(&k)).collect();
        let other = |s: &TreeSaddle| if s.peaks[0] == k { s.peaks[1] } else { s.peaks[0] };
        let hub = incident.iter().copied().max_by(|&a, &b| {
            let (pa, pb) = (other(&self.saddles[a]), other(&self.saddles[b]));
            self.peaks[pa as usize].elevation.total_cmp(&self.peaks[pb as usize].elevation).then(pb.cmp(&pa))
        });
        let mut saddles_alive = vec![true; self.saddles.len()];
        if let Some(hub) = hub {
            let hub_saddle = self.saddles[hub];
            let hub_peak = other(&hub_saddle);
            saddles_alive[hub] = false;
            for &s in incident.iter().filter(|&&s| s != hub) {
                let saddle = &mut self.saddles[s];
                let end = other(saddle);
                let lower = if saddle.elevation <= hub_saddle.elevation { *saddle } else { hub_saddle };
                *saddle = TreeSaddle { position: lower.position, elevation: lower.elevation, peaks: [end, hub_peak] };
            }
        }
        let mut alive = vec![true; self.peaks.len()];
        alive[k as usize] = false;
        self.retain(&alive, &saddles_alive);
        Ok(())
    }
}
