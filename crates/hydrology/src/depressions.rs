//! Depression detection, filling and labelling (Priority-Flood, Barnes, Lehman & Mulla 2014), and
//! the endorheic-basin check on grids and on graphs such as TINs.

use relief_heightfield::{FillRules, Heightfield, fill_depressions_with};
use serde::{Deserialize, Serialize};

use crate::HydrologyError;
use crate::grid8::Grid8;

/// What no-data cells mean for drainage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoData {
    /// No-data is sea (or off-map): a cell next to it drains there. The usual reading of a
    /// masked island or a DEM tile with holes at its edges.
    #[default]
    Outlet,
    /// No-data is a wall water cannot cross; only the grid border (and sea level) drains.
    Wall,
}

/// Where water may leave the terrain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Outlets {
    /// The grid border drains (default `true`).
    pub border: bool,
    /// What no-data cells mean (default [`NoData::Outlet`]).
    pub no_data: NoData,
    /// Cells at or below this elevation are sea and drain (default: none).
    pub sea_level: Option<f32>,
}

impl Default for Outlets {
    fn default() -> Self {
        Self { border: true, no_data: NoData::Outlet, sea_level: None }
    }
}

impl Outlets {
    /// Border and no-data drain, no sea level: the default.
    pub fn new() -> Self {
        Self::default()
    }

    /// With cells at or below `level` treated as sea.
    #[must_use]
    pub fn with_sea_level(mut self, level: f32) -> Self {
        self.sea_level = Some(level);
        self
    }

    /// With the given meaning of no-data.
    #[must_use]
    pub fn with_no_data(mut self, no_data: NoData) -> Self {
        self.no_data = no_data;
        self
    }

    /// With or without the grid border as an outlet.
    #[must_use]
    pub fn with_border(mut self, border: bool) -> Self {
        self.border = border;
        self
    }

    fn rules(self, epsilon: bool) -> FillRules {
        FillRules { border_drains: self.border, no_data_drains: self.no_data == NoData::Outlet, epsilon }
    }

    fn check(self) -> Result<(), HydrologyError> {
        match self.sea_level {
            Some(s) if !s.is_finite() => Err(HydrologyError::InvalidParameter {
                name: "sea_level",
                value: f64::from(s),
                reason: "must be finite",
            }),
            _ => Ok(()),
        }
    }

    /// Runs the flood on a copy of `hf`.
    fn flood(self, hf: &Heightfield, epsilon: bool) -> Result<(Heightfield, usize), HydrologyError> {
        self.check()?;
        if hf.no_data_count() == hf.grid().len() {
            return Err(HydrologyError::AllNoData { cells: hf.grid().len() });
        }
        let mut out = hf.clone();
        let sea = self.sea_level;
        let raised = fill_depressions_with(&mut out, self.rules(epsilon), |i, j| {
            sea.is_some_and(|s| hf.get(i, j).is_some_and(|v| v <= s))
        });
        Ok((out, raised))
    }
}

/// The depression-free DEM: Priority-Flood+ε, so every valid cell that can drain at all has a
/// strictly descending 8-connected path to an outlet and D8/MFD routing never stalls on a flat.
/// Cells are only ever raised, never lowered; filling twice changes nothing.
///
/// # Errors
/// [`HydrologyError::AllNoData`], or [`HydrologyError::InvalidParameter`] for a non-finite sea level.
pub fn fill(hf: &Heightfield, outlets: Outlets) -> Result<Heightfield, HydrologyError> {
    Ok(outlets.flood(hf, true)?.0)
}

/// Whether some valid cell has no non-ascending 8-connected path to an outlet (border and, with
/// [`NoData::Outlet`], cells next to no-data): a closed basin water cannot leave. Flats that reach an
/// outlet are not basins. This is the check behind "generated terrains have no endorheic basins".
///
/// An all-no-data field has no basins.
pub fn has_endorheic_basins(hf: &Heightfield, no_data: NoData) -> bool {
    Outlets::new().with_no_data(no_data).flood(hf, false).is_ok_and(|(_, raised)| raised > 0)
}

/// One closed depression: a connected set of cells that the plain (ε-free) fill raises to one level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Basin {
    /// Number of cells under the fill level.
    pub cells: usize,
    /// The lowest cell `(i, j)` (first in row-major order on ties).
    pub pit: (usize, usize),
    /// Its elevation.
    pub pit_elevation: f32,
    /// The level the depression fills to before it spills.
    pub fill_level: f32,
    /// Where it spills: the lowest cell bordering the depression (first in row-major order on
    /// ties), `None` if the depression borders only walls.
    pub spill: Option<(usize, usize)>,
    /// Water volume held to the fill level, m³.
    pub volume_m3: f64,
}

impl Basin {
    /// Depth from the fill level to the pit.
    pub fn depth(&self) -> f32 {
        self.fill_level - self.pit_elevation
    }
}

/// The closed depressions of a DEM with a label per cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Depressions {
    /// Per cell: 0 where water drains away, `b + 1` inside basin `b`.
    pub labels: Vec<u32>,
    /// The basins, in row-major order of their first cell.
    pub basins: Vec<Basin>,
    /// The DEM with every basin filled exactly to its level (no ε).
    pub filled: Heightfield,
}

/// Finds the closed depressions of `hf`: cells the ε-free Priority-Flood raises, grouped into
/// 8-connected basins (two touching raised cells always share one fill level), each with its pit,
/// fill level, spill cell and volume. O(N) for a drained DEM, O(N + D log D) for D cells in depressions.
///
/// # Errors
/// As [`fill`].
pub fn depressions(hf: &Heightfield, outlets: Outlets) -> Result<Depressions, HydrologyError> {
    let (filled, raised) = outlets.flood(hf, false)?;
    let n = hf.grid().len();
    let mut labels = vec![0u32; n];
    let mut basins = Vec::new();
    if raised == 0 {
        return Ok(Depressions { labels, basins, filled });
    }
    let g = Grid8::new(hf.grid());
    let (z, f) = (hf.samples(), filled.samples());
    let is_raised = |k: usize| f[k] > z[k];
    let mut stack = Vec::new();
    for start in 0..n {
        if labels[start] != 0 || !is_raised(start) {
            continue;
        }
        let id = basins.len() as u32 + 1;
        labels[start] = id;
        stack.push(start);
        let (mut cells, mut pit, mut volume) = (0usize, start, 0.0f64);
        let mut spill: Option<usize> = None;
        while let Some(k) = stack.pop() {
            cells += 1;
            volume += f64::from(f[k] - z[k]) * g.area(k);
            if (z[k], k) < (z[pit], pit) {
                pit = k;
            }
            g.each(k, |w, _, _| {
                if labels[w] == id || z[w].is_nan() {
                    return;
                }
                if is_raised(w) {
                    labels[w] = id;
                    stack.push(w);
                } else if spill.is_none_or(|s| (z[w], w) < (z[s], s)) {
                    spill = Some(w);
                }
            });
        }
        basins.push(Basin {
            cells,
            pit: hf.grid().coords(pit),
            pit_elevation: z[pit],
            fill_level: f[start],
            spill: spill.map(|s| hf.grid().coords(s)),
            volume_m3: volume,
        });
    }
    Ok(Depressions { labels, basins, filled })
}

/// The nodes of a graph (a TIN's CSR adjacency, say) that have no non-ascending path to an
/// outlet node, in increasing order. Outlets are typically the boundary nodes.
///
/// # Errors
/// [`HydrologyError::LengthMismatch`] or [`HydrologyError::InvalidGraph`] for inconsistent
/// arrays, [`HydrologyError::NonFinite`] for a NaN or infinite height.
pub fn endorheic_nodes(
    heights: &[f64],
    offsets: &[u32],
    adjacency: &[u32],
    outlet: &[bool],
) -> Result<Vec<u32>, HydrologyError> {
    let n = heights.len();
    if offsets.len() != n + 1 {
        return Err(HydrologyError::LengthMismatch {
            what: "adjacency offsets",
            expected: n + 1,
            found: offsets.len(),
        });
    }
    if outlet.len() != n {
        return Err(HydrologyError::LengthMismatch { what: "outlet flags", expected: n, found: outlet.len() });
    }
    if let Some((index, &value)) = heights.iter().enumerate().find(|(_, h)| !h.is_finite()) {
        return Err(HydrologyError::NonFinite { what: "node height", index, value });
    }
    if offsets[0] != 0 || offsets.windows(2).any(|w| w[0] > w[1]) || offsets[n] as usize != adjacency.len() {
        return Err(HydrologyError::InvalidGraph {
            reason: format!("offsets must rise from 0 to the adjacency length {}", adjacency.len()),
        });
    }
    if let Some(&v) = adjacency.iter().find(|&&v| v as usize >= n) {
        return Err(HydrologyError::InvalidGraph { reason: format!("neighbour {v} does not exist ({n} nodes)") });
    }
    let mut reached = outlet.to_vec();
    let mut stack: Vec<u32> = (0..n as u32).filter(|&v| outlet[v as usize]).collect();
    while let Some(v) = stack.pop() {
        let v = v as usize;
        for &w in &adjacency[offsets[v] as usize..offsets[v + 1] as usize] {
            if !reached[w as usize] && heights[w as usize] >= heights[v] {
                reached[w as usize] = true;
                stack.push(w);
            }
        }
    }
    Ok((0..n as u32).filter(|&v| !reached[v as usize]).collect())
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use relief_heightfield::GridSpec;

    use super::*;

    fn bowl() -> Heightfield {
        // Rim at 10, floor at 1 with a 0.5 pit at (2, 2), a notch at 5 on the west edge.
        let grid = GridSpec::new(7, 7, DVec2::ZERO, DVec2::splat(2.0)).unwrap();
        Heightfield::from_fn_indexed(grid, |i, j| match (i, j) {
            (0, 3) => 5.0,
            (2, 2) => 0.5,
            _ if i == 0 || j == 0 || i == 6 || j == 6 => 10.0,
            _ => 1.0,
        })
        .unwrap()
    }

    #[test]
    fn a_bowl_is_one_basin_spilling_through_its_notch() {
        let hf = bowl();
        assert!(has_endorheic_basins(&hf, NoData::Outlet));
        let d = depressions(&hf, Outlets::new()).unwrap();
        assert_eq!(d.basins.len(), 1);
        let b = &d.basins[0];
        assert_eq!((b.cells, b.pit, b.pit_elevation, b.fill_level, b.spill), (25, (2, 2), 0.5, 5.0, Some((0, 3))));
        // 24 cells 4 deep, one 4.5 deep, 4 m² each.
        assert!((b.volume_m3 - (24.0 * 4.0 + 4.5) * 4.0).abs() < 1e-9);
        assert_eq!(b.depth(), 4.5);
        assert_eq!(d.labels.iter().filter(|&&l| l == 1).count(), 25);
        assert!(!has_endorheic_basins(&d.filled, NoData::Outlet));
        let f = fill(&hf, Outlets::new()).unwrap();
        assert!(f.samples().iter().zip(hf.samples()).all(|(a, b)| a >= b));
        assert!(!has_endorheic_basins(&f, NoData::Outlet));
    }

    #[test]
    fn sea_level_and_walls_change_what_drains() {
        let hf = bowl();
        // Everything at or below 1 is sea: the floor is an outlet, no basin is left.
        assert!(depressions(&hf, Outlets::new().with_sea_level(1.0)).unwrap().basins.is_empty());
        // A flat plateau drains over its border: not a basin.
        let flat = Heightfield::filled(GridSpec::new(9, 4, DVec2::ZERO, DVec2::ONE).unwrap(), 3.0).unwrap();
        assert!(!has_endorheic_basins(&flat, NoData::Wall));
        // Walled in with no border outlet, nothing drains and nothing can be filled.
        let closed = depressions(&hf, Outlets::new().with_border(false)).unwrap();
        assert!(closed.basins.is_empty());
        assert!(matches!(
            fill(&hf, Outlets::new().with_sea_level(f32::NAN)),
            Err(HydrologyError::InvalidParameter { name: "sea_level", .. })
        ));
    }

    #[test]
    fn no_data_is_sea_or_wall() {
        // A pit next to a no-data hole: drains into the hole only when no-data is an outlet.
        let grid = GridSpec::new(6, 6, DVec2::ZERO, DVec2::ONE).unwrap();
        let hf = Heightfield::from_fn_indexed(grid, |i, j| match (i, j) {
            (3, 3) => f32::NAN,
            (2, 3) => 1.0,
            _ => 5.0,
        })
        .unwrap();
        assert!(!has_endorheic_basins(&hf, NoData::Outlet));
        assert!(has_endorheic_basins(&hf, NoData::Wall));
        let d = depressions(&hf, Outlets::new().with_no_data(NoData::Wall)).unwrap();
        assert_eq!(d.basins[0].spill.map(|(i, j)| hf.get(i, j)), Some(Some(5.0)));
        assert!(d.filled.is_no_data(3, 3));
        let all = Heightfield::filled(grid, f32::NAN).unwrap();
        assert!(!has_endorheic_basins(&all, NoData::Outlet));
        assert!(matches!(fill(&all, Outlets::new()), Err(HydrologyError::AllNoData { cells: 36 })));
    }

    #[test]
    fn graph_check_finds_a_closed_node() {
        // A path 0 - 1 - 2 - 3 with node 0 the outlet; node 2 is a pit below node 1.
        let heights = [0.0, 2.0, 1.0, 3.0];
        let offsets = [0, 1, 3, 5, 6];
        let adjacency = [1, 0, 2, 1, 3, 2];
        let outlet = [true, false, false, false];
        assert_eq!(endorheic_nodes(&heights, &offsets, &adjacency, &outlet).unwrap(), vec![2, 3]);
        let drained = [0.0, 1.0, 2.0, 3.0];
        assert!(endorheic_nodes(&drained, &offsets, &adjacency, &outlet).unwrap().is_empty());
        assert!(matches!(
            endorheic_nodes(&drained, &offsets, &[1, 0, 2, 1, 3, 9], &outlet),
            Err(HydrologyError::InvalidGraph { .. })
        ));
        assert!(matches!(
            endorheic_nodes(&[0.0, f64::NAN, 1.0, 2.0], &offsets, &adjacency, &outlet),
            Err(HydrologyError::NonFinite { index: 1, .. })
        ));
    }
}
