//! The mountain scene the diffusion bench and the `convergence` example both solve: three ridges
//! sharing a 1200 m peak and a riverbed, on a 4 km square.

use glam::DVec2;
use relief_diffusion_multigrid::{FeatureCurve, presets};

/// The curves with slope bands of `slope_extent` on the ridges (0: elevations only; the bench
/// uses 600 m).
pub(crate) fn scene_with(slope_extent: f64) -> Vec<FeatureCurve> {
    let mut curves = presets::multiple_ridges(
        DVec2::splat(2000.0),
        1200.0,
        &[DVec2::new(500.0, 800.0), DVec2::new(3500.0, 1200.0), DVec2::new(2000.0, 3600.0)],
        200.0,
        &[30.0, 20.0, 35.0],
        slope_extent,
    );
    curves.push(presets::riverbed(&[DVec2::new(0.0, 200.0), DVec2::new(4000.0, 400.0)], 50.0, 0.0, 60.0, 5.0, 100.0));
    curves
}
