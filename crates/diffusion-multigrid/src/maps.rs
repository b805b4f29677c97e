//! The constraint maps (§4.1): the plain per-sample data that rasterization produces and the
//! equations of §5.2 consume. Kept apart from both so that `raster` (which diffuses the holes with
//! the solver) and `solver` (which builds the elevation equation from the maps) depend on this
//! module and not on each other.

use relief_heightfield::GridSpec;
use serde::{Deserialize, Serialize};

/// Which equation a sample obeys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CellKind {
    /// No constraint: Laplace (α = 1, β = 0).
    Free,
    /// Strict elevation: identification (α = β = 0).
    Elevation,
    /// Slope constraint: half Laplace, half gradient (α = β = ½).
    Gradient,
    /// Where slope constraints of different curve sides overlap: left empty, the gradient filled
    /// in by diffusion, then treated as [`CellKind::Gradient`].
    Hole,
}

/// The constraints of a set of curves on one grid, built by [`ConstraintMaps::rasterize`].
/// Per-sample arrays are row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintMaps {
    /// The grid.
    pub grid: GridSpec,
    /// Equation per sample.
    pub kind: Vec<CellKind>,
    /// Strict elevation (averaged where curves overlap); NaN where none.
    pub elevation: Vec<f32>,
    /// Gradient step G of the gradient equation `F = F_N + G` (elevation change per grid step along
    /// `normal`); 0 where none.
    pub gradient: Vec<f32>,
    /// Unit direction n of the gradient equation (the way the elevation is propagated).
    pub normal: Vec<[f32; 2]>,
    /// Noise amplitude (averaged); NaN where none.
    pub amplitude: Vec<f32>,
    /// Noise roughness (averaged); NaN where none.
    pub roughness: Vec<f32>,
}

impl ConstraintMaps {
    /// Number of samples of each kind `(free, elevation, gradient, hole)`.
    pub fn counts(&self) -> (usize, usize, usize, usize) {
        let mut c = (0, 0, 0, 0);
        for k in &self.kind {
            match k {
                CellKind::Free => c.0 += 1,
                CellKind::Elevation => c.1 += 1,
                CellKind::Gradient => c.2 += 1,
                CellKind::Hole => c.3 += 1,
            }
        }
        c
    }
}
