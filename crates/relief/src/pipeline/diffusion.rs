//! Feature curves diffused into a terrain (Hnaidi et al. 2010).

use super::inputs::{bounds, default_domain, raster_grid};
use super::progress::Timer;
use super::{Generated, Report};
use crate::diffusion::{self, SolveOptions, TerrainOptions};
use crate::error::SceneError;
use crate::scene::{DiffusionGenerator, Scene};
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.diffusion";

/// The diffusion generator's run: the curves are checked (they were as the scene was read; this
/// catches curves built in code), rasterized and diffused on the scene's grid.
pub(super) fn generate(scene: &Scene, g: &DiffusionGenerator, timer: &mut Timer<'_>) -> Result<Generated, ReliefError> {
    let (grid, options) = timer.step("inputs", || -> Result<_, ReliefError> {
        if g.curves.is_empty() {
            return Err(E::at(format!("{GENERATOR}.curves"), SceneError::Missing("at least one curve")));
        }
        for (k, c) in g.curves.iter().enumerate() {
            c.validate(k).map_err(|e| E::located(GENERATOR, e))?;
        }
        let extent = scene.domain.unwrap_or_else(|| {
            let points = bounds(g.curves.iter().flat_map(|c| c.points.iter().copied()));
            default_domain(points, scene.reconstruction.resolution)
        });
        let solve = SolveOptions { solver: g.solver, tolerance: g.tolerance, max_iterations: None };
        let options = TerrainOptions {
            solve,
            noise_wavelength: g.noise_wavelength.unwrap_or(0.0),
            noise_octaves: g.noise_octaves,
            seed: scene.seed,
        };
        Ok((raster_grid(scene, extent)?, options))
    })?;
    let terrain = timer
        .step("diffusion", || diffusion::generate(&g.curves, &grid, &options))
        .map_err(|e| E::located(GENERATOR, e))?;
    Ok(Generated {
        heightfield: terrain.heightfield,
        sea_level: g.sea_level,
        contours: None,
        report: Report::Diffusion(terrain.report),
        warnings: Vec::new(),
    })
}
