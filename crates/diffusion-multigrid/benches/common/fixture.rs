//! A `relief` scene file's feature curves, read without the facade: what the diffusion bench and
//! the `generate_timing` example both run.

use std::path::Path;

use glam::DVec2;
use relief_diffusion_multigrid::presets::Preset;
use relief_diffusion_multigrid::{FeatureCurve, TerrainOptions};

/// A scene's curves (its presets expanded after them), its domain's corners and its noise and
/// solver options.
pub(crate) type Fixture = (Vec<FeatureCurve>, [DVec2; 2], TerrainOptions);

/// The [`Fixture`] of the scene file at `path`.
pub(crate) fn load(path: &Path) -> Result<Fixture, Box<dyn std::error::Error>> {
    let scene: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path)?)?;
    let generator = &scene["generator"]["diffusion"];
    let mut curves: Vec<FeatureCurve> = serde_json::from_value(generator["curves"].clone())?;
    let presets: Vec<Preset> = serde_json::from_value(generator["presets"].clone()).unwrap_or_default();
    curves.extend(presets.iter().flat_map(Preset::curves));
    let mut options = TerrainOptions {
        noise_wavelength: generator["noise_wavelength"].as_f64().unwrap_or(0.0),
        seed: scene["seed"].as_u64().unwrap_or(0),
        ..TerrainOptions::default()
    };
    if let Some(solver) = generator.get("solver") {
        options.solve.solver = serde_json::from_value(solver.clone())?;
    }
    if let Some(tolerance) = generator["tolerance"].as_f64() {
        options.solve.tolerance = tolerance;
    }
    if let Some(max) = generator["max_iterations"].as_u64() {
        options.solve.max_iterations = Some(usize::try_from(max)?);
    }
    let corner = |k: &str| serde_json::from_value::<[f64; 2]>(scene["domain"][k].clone()).map(DVec2::from);
    Ok((curves, [corner("min")?, corner("max")?], options))
}
