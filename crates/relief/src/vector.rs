//! Vector terrains (Perche et al. 2025) beside hydrology: the crest skeleton of the crest tools
//! needs flow routing on the inverted DEM, and `relief-gaussian-terrain` sits below
//! `relief-hydrology`, so the facade joins them.

use relief_gaussian_terrain::Skeleton;
use relief_heightfield::Heightfield;
use relief_hydrology::{D8, NO_RECEIVER, Outlets};

use crate::ReliefError;

/// The crest skeleton of `hf` (§5.1): crest cells are those where the flow accumulation of the
/// inverted, depression-filled DEM reaches `min_cells` cells; each links to its downstream crest
/// neighbour; the graph is then simplified by edge collapse at spacing `d0`.
///
/// # Errors
/// [`ReliefError::Pipeline`] for an all-no-data field.
pub fn crest_skeleton(hf: &Heightfield, min_cells: u32, d0: f64) -> Result<Skeleton, ReliefError> {
    let inverted = hf.map(|v| -v).map_err(|e| ReliefError::step("skeleton", e))?;
    let filled = relief_hydrology::fill(&inverted, Outlets::new()).map_err(|e| ReliefError::step("skeleton", e))?;
    let routed = D8::new(&filled).map_err(|e| ReliefError::step("skeleton", e))?;
    let accumulation = routed.accumulation();
    let grid = hf.grid();
    let mut index = vec![usize::MAX; grid.len()];
    let mut points = Vec::new();
    for (k, &a) in accumulation.iter().enumerate() {
        if a >= min_cells.max(1) {
            index[k] = points.len();
            let (i, j) = grid.coords(k);
            points.push(grid.position(i, j));
        }
    }
    let down: Vec<Option<usize>> = (0..grid.len())
        .filter(|&k| index[k] != usize::MAX)
        .map(|k| {
            let r = routed.receivers()[k];
            (r != NO_RECEIVER && index[r as usize] != usize::MAX).then(|| index[r as usize])
        })
        .collect();
    let full = Skeleton::from_flow(&points, &down).map_err(|e| ReliefError::step("skeleton", e))?;
    Ok(full.simplified(d0))
}
