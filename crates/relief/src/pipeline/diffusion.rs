//! Feature curves diffused into a terrain (Hnaidi et al. 2010).

use std::ops::ControlFlow;

use super::inputs::{bounds, default_domain, raster_grid};
use super::progress::Timer;
use super::{Generated, Report};
use glam::DVec2;

use crate::diffusion::{self, Constraint, Elevation, FeatureCurve, Noise, SolveOptions, Stage, TerrainOptions};
use crate::error::SceneError;
use crate::heightfield::{GridSpec, Heightfield};
use crate::scene::{Border, DiffusionGenerator, Scene};
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.diffusion";

/// The diffusion generator's run: the curves are checked (they were as the scene was read; this
/// catches curves built in code), rasterized and diffused on the scene's grid.
pub(super) fn generate(scene: &Scene, g: &DiffusionGenerator, timer: &mut Timer<'_>) -> Result<Generated, ReliefError> {
    let (grid, options) = timer.step("inputs", || -> Result<_, ReliefError> {
        if g.curves.is_empty() && g.presets.is_empty() {
            return Err(E::at(format!("{GENERATOR}.curves"), SceneError::Missing("at least one curve or preset")));
        }
        for (k, c) in g.curves.iter().enumerate() {
            c.validate(k).map_err(|e| E::located(GENERATOR, e))?;
        }
        for (p, preset) in g.presets.iter().enumerate() {
            for (k, c) in preset.curves().iter().enumerate() {
                c.validate(k).map_err(|e| E::located(&format!("{GENERATOR}.presets[{p}]"), e))?;
            }
        }
        let extent = scene.domain.unwrap_or_else(|| {
            let points = bounds(g.all_curves().iter().flat_map(|c| c.points.iter().copied()));
            default_domain(points, scene.reconstruction.resolution)
        });
        let solve = SolveOptions { solver: g.solver, tolerance: g.tolerance, max_iterations: g.max_iterations };
        let options = TerrainOptions {
            solve,
            noise_wavelength: g.noise_wavelength.unwrap_or(0.0),
            noise_octaves: g.noise_octaves,
            seed: scene.seed,
        };
        Ok((raster_grid(scene, extent)?, options))
    })?;
    let curves = with_border(g, g.all_curves(), &grid)?;
    // Three units: the painted constraints with their holes filled, the elevation solve, the
    // noise solves (each iteration of them a chance to cancel).
    // The units are reported as they rise, not at every iteration.
    let terrain = timer.counted("diffusion", 3, |tick| {
        let mut reached = 0;
        diffusion::generate_observed(&curves, &grid, &options, |stage| {
            let unit = match stage {
                Stage::Holes { done, total } if done < total => 0,
                Stage::Holes { .. } | Stage::Elevation { .. } => 1,
                _ => 2,
            };
            if unit > reached {
                reached = unit;
                tick.reach(unit);
            }
            if tick.cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        })
        .inspect(|_| tick.reach(3))
        .map_err(|e| match e {
            diffusion::DiffusionError::Cancelled => E::Cancelled,
            e => E::located(GENERATOR, e),
        })
    })?;
    let warnings = noise_warning(&g.all_curves(), &terrain.smooth).into_iter().collect();
    Ok(Generated {
        heightfield: terrain.heightfield,
        sea_level: g.sea_level,
        contours: None,
        report: Report::Diffusion(terrain.report),
        warnings,
        vector: None,
        layers: None,
    })
}

/// The scene's curves (`curves`, presets expanded), plus a closed curve along the domain's border when it is held (see
/// [`DiffusionGenerator::border`] for the default).
fn with_border(
    g: &DiffusionGenerator,
    curves: Vec<FeatureCurve>,
    grid: &GridSpec,
) -> Result<Vec<FeatureCurve>, ReliefError> {
    let constraints = || curves.iter().flat_map(|c| c.constraints.iter());
    let (elevation, noise) = match g.border {
        Some(Border::Free) => return Ok(curves),
        Some(Border::Held { elevation, noise }) => (elevation, noise),
        None => {
            let mut heights = constraints().filter_map(|c| c.elevation.map(|e| e.h));
            let Some(first) = heights.next() else {
                // No elevation at all (noise or slopes only, the paper's Fig. 8): the border is
                // the base level the rest stands on, and leaves the noise to the curves.
                return Ok(with_ring(curves, grid, g.sea_level.unwrap_or(0.0), None));
            };
            let flat = heights.all(|h| h == first) && constraints().all(|c| c.slope.is_none());
            if !flat {
                return Ok(curves);
            }
            (g.sea_level.unwrap_or(0.0), Some(0.0))
        }
    };
    if !elevation.is_finite() || noise.is_some_and(|a| !(a.is_finite() && a >= 0.0)) {
        let error = SceneError::OutOfRange {
            value: format!("{elevation}, noise {noise:?}"),
            rule: "must be finite, the noise ≥ 0",
        };
        return Err(E::at(format!("{GENERATOR}.border"), error));
    }
    Ok(with_ring(curves, grid, elevation, noise))
}

/// `curves` and a closed curve round the domain at `elevation`, with detail-noise amplitude
/// `noise` (free if `None`).
fn with_ring(mut curves: Vec<FeatureCurve>, grid: &GridSpec, elevation: f64, noise: Option<f64>) -> Vec<FeatureCurve> {
    let e = grid.extent();
    let ring = [e.min, DVec2::new(e.max.x, e.min.y), e.max, DVec2::new(e.min.x, e.max.y), e.min];
    let constraint = Constraint {
        u: 0.0,
        elevation: Some(Elevation { h: elevation, r: 0.0 }),
        slope: None,
        noise: noise.map(|amplitude| Noise { amplitude, roughness: 0.5 }),
    };
    curves.push(FeatureCurve::polyline(&ring, vec![constraint]));
    curves
}

/// A warning when the detail noise is as tall as the relief the curves give, which hides them;
/// none when no curve carries an elevation (then the noise is the terrain, as in Fig. 8).
fn noise_warning(curves: &[FeatureCurve], smooth: &Heightfield) -> Option<String> {
    if !curves.iter().any(FeatureCurve::has_elevation) {
        return None;
    }
    let amplitude =
        curves.iter().flat_map(|c| &c.constraints).filter_map(|c| c.noise.map(|n| n.amplitude)).fold(0.0, f64::max);
    let (lo, hi) = smooth.min_max()?;
    let relief = f64::from(hi - lo);
    (amplitude > 0.0 && amplitude >= 0.5 * relief).then(|| {
        format!(
            "{GENERATOR}: the detail noise (amplitude up to {amplitude}) is as tall as the relief the curves give \
             ({relief:.1}), so it hides them: lower the noise amplitudes, or give the curves more relief (elevations \
             apart, slope constraints)"
        )
    })
}
