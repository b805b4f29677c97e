//! Orometric synthesis (Argudo et al. 2019): the target descriptor, a divide tree, its edits,
//! then the terrain.

use super::contours::growth_seed;
use super::inputs::{Env, raster_grid};
use super::progress::Timer;
use super::summary::{OrometrySummary, TerrainOrometry};
use super::{Generated, Report};
use crate::error::SceneError;
use crate::heightfield::Extent;
use crate::orometry::{
    AnalysisOptions, ControlMaps, Descriptor, DivideTree, FractionHistogram, TerrainOptions, TreeOptions, TypeMap,
    generate_tree, generate_typed_tree, terrain_from_tree,
};
use crate::scene::{OrometryGenerator, OrometrySource, OrometryTypes, Scene};
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.orometry";

/// The orometry generator's run.
pub(super) fn generate(
    scene: &Scene,
    g: &OrometryGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Generated, ReliefError> {
    let Some(extent) = scene.domain else {
        return Err(E::at("domain", SceneError::NeedsDomain("orometry")));
    };
    let grid = raster_grid(scene, extent)?;
    let (target, real_tree) =
        timer.step("inputs", || target(&g.source, extent, env, &format!("{GENERATOR}.source")))?;
    let tree = timer.step("divide tree", || divide_tree(scene, g, &target, real_tree, extent, env))?;
    let base = target.domain.min_elevation;
    let options = TerrainOptions { seed: growth_seed(scene.seed), ..g.terrain.clone() };
    // The label raster at λ/2 and the refined ridges count as cells (an invalid λ is left to the
    // synthesis's own check, which names it).
    let lambda = options.lambda_m;
    if lambda.is_finite() && lambda > 0.0 {
        let mesh = options.mesh_samples(&tree, grid.extent());
        let mesh = if mesh.is_finite() { mesh as u64 } else { u64::MAX };
        env.budget.cells(mesh, &format!("{GENERATOR}.terrain.lambda_m"))?;
    }
    let heightfield = timer.step("terrain", || {
        terrain_from_tree(&tree, base, &grid, &options, |_, _| {}).map_err(|e| E::at(GENERATOR, e))
    })?;
    // The terrain is analysed as the target was: at its threshold and sea level.
    let analysis = match &g.source {
        OrometrySource::Dem { min_prominence, sea_level, .. } => {
            AnalysisOptions { min_prominence: *min_prominence, sea_level: *sea_level, ..AnalysisOptions::default() }
        }
        OrometrySource::Descriptor { .. } => {
            AnalysisOptions { min_prominence: least_prominence(&tree, base), ..AnalysisOptions::default() }
        }
    };
    let terrain = timer.step("terrain orometry", || Ok(terrain_orometry(&heightfield, &target, &analysis)))?;
    let types = g.types.as_ref().map_or(1, |t| t.sources.len() + 1);
    let report = Report::Orometry(summary(tree, &target, types, terrain));
    Ok(Generated {
        heightfield,
        sea_level: None,
        contours: None,
        report,
        warnings: Vec::new(),
        vector: None,
        layers: None,
    })
}

/// The prominence of the tree's least prominent peak (not counting its tops).
fn least_prominence(tree: &DivideTree, base: f64) -> f64 {
    let oro = tree.orometry(base);
    let least = oro.prominence.iter().zip(&oro.key_saddle).filter(|(_, k)| k.is_some()).map(|(&p, _)| p);
    let least = least.fold(f64::INFINITY, f64::min);
    if least.is_finite() { least.max(0.0) } else { 0.0 }
}

/// The generated terrain analysed with `options`, its descriptor at the target's radius compared
/// with the target; `None` when it has no land.
fn terrain_orometry(
    heightfield: &crate::heightfield::Heightfield,
    target: &Descriptor,
    options: &AnalysisOptions,
) -> Option<TerrainOrometry> {
    let (_, terrain) = Descriptor::with_radius(heightfield, options, Some(target.domain.radius_m)).ok()?;
    let distance = terrain.distance(target).ok()?;
    Some(TerrainOrometry {
        min_prominence: options.min_prominence,
        sea_level: options.sea_level,
        peaks: terrain.peaks,
        target_peaks: target.peaks,
        density_per_km2: terrain.density_per_km2,
        target_density_per_km2: target.density_per_km2,
        features: distance.features,
    })
}

/// The target orometry: a DEM analysed, or a saved descriptor; and, when the scene asks for it,
/// the DEM's own divide tree stretched over the domain.
fn target(
    source: &OrometrySource,
    domain: Extent,
    env: &Env<'_>,
    at: &str,
) -> Result<(Descriptor, Option<DivideTree>), ReliefError> {
    match source {
        OrometrySource::Dem { path, min_prominence, sea_level, use_tree } => {
            let dem = env.read(path).map_err(|e| E::at(at, e))?;
            let options = AnalysisOptions {
                sea_level: *sea_level,
                min_prominence: *min_prominence,
                ..AnalysisOptions::default()
            };
            let (oro, descriptor) = Descriptor::of(&dem, &options).map_err(|e| E::at(at, e))?;
            let tree = use_tree.then(|| stretched(DivideTree::from_orometry(&oro), dem.grid().extent(), domain));
            Ok((descriptor, tree))
        }
        OrometrySource::Descriptor { path } => Ok((env.read_json(path, at)?, None)),
    }
}

/// `tree` with its positions mapped linearly from `from` onto `to`.
fn stretched(mut tree: DivideTree, from: Extent, to: Extent) -> DivideTree {
    let scale = to.size() / from.size().max(glam::DVec2::splat(f64::MIN_POSITIVE));
    let map = |p: glam::DVec2| to.min + (p - from.min) * scale;
    for p in &mut tree.peaks {
        p.position = map(p.position);
    }
    for s in &mut tree.saddles {
        s.position = map(s.position);
    }
    tree
}

/// The divide tree generated from `target` under the control maps and pinned peaks (its peak
/// count checked against the budget first), then edited.
fn divide_tree(
    scene: &Scene,
    g: &OrometryGenerator,
    target: &Descriptor,
    real: Option<DivideTree>,
    extent: Extent,
    env: &Env<'_>,
) -> Result<DivideTree, ReliefError> {
    if let Some(mut tree) = real {
        if !g.pinned.is_empty() || g.peak_density.is_some() || g.elevation.is_some() || g.types.is_some() {
            // The DEM's own tree is used as it is: nothing can shape it.
            return Err(E::at(
                GENERATOR,
                SceneError::Conflict("source.use_tree", "pinned, peak_density, elevation or types"),
            ));
        }
        for (i, edit) in g.edits.iter().enumerate() {
            tree.apply(edit).map_err(|e| E::at(format!("{GENERATOR}.edits[{i}]"), e))?;
        }
        return Ok(tree);
    }
    let map = |path: &Option<std::path::PathBuf>, field: &str| {
        path.as_ref().map(|p| env.control_map(p, extent, &format!("{GENERATOR}.{field}"))).transpose()
    };
    let controls =
        ControlMaps { peak_density: map(&g.peak_density, "peak_density")?, elevation: map(&g.elevation, "elevation")? };
    let options = TreeOptions { seed: scene.seed, ..g.tree.clone() };
    let mut tree = match &g.types {
        None => {
            let peaks = options.peak_count(target, extent, g.pinned.len());
            env.budget.peaks(peaks as u64, &format!("{GENERATOR}.tree.peaks"))?;
            generate_tree(target, extent, &controls, &g.pinned, &options)
        }
        Some(types) => {
            let types = type_map(types, target, extent, env)?;
            // At most the densest type's count over the whole domain.
            let densest = types.descriptors.iter().max_by(|a, b| a.density_per_km2.total_cmp(&b.density_per_km2));
            let peaks = densest.map_or(0, |d| options.peak_count(d, extent, g.pinned.len()));
            env.budget.peaks(peaks as u64, &format!("{GENERATOR}.tree.peaks"))?;
            generate_typed_tree(&types, extent, &controls, &g.pinned, &options)
        }
    }
    .map_err(|e| E::at(GENERATOR, e))?;
    for (i, edit) in g.edits.iter().enumerate() {
        tree.apply(edit).map_err(|e| E::at(format!("{GENERATOR}.edits[{i}]"), e))?;
    }
    Ok(tree)
}

/// The scene's type map `C_T`: the map's values in as many equal bands as there are types
/// (`first` the lowest band's, then each of `types.sources`' descriptor in order), each sample
/// holding its band's index.
fn type_map(types: &OrometryTypes, first: &Descriptor, extent: Extent, env: &Env<'_>) -> Result<TypeMap, ReliefError> {
    let at = format!("{GENERATOR}.types");
    let mut descriptors = vec![first.clone()];
    for (i, source) in types.sources.iter().enumerate() {
        let at = format!("{at}.sources[{i}]");
        if let OrometrySource::Dem { use_tree: true, .. } = source {
            return Err(E::at(&at, SceneError::Conflict("use_tree", "types")));
        }
        descriptors.push(target(source, extent, env, &at)?.0);
    }
    let mut map = env.control_map(&types.map, extent, &format!("{at}.map"))?;
    let (lo, hi) = map.min_max().map_or((0.0, 0.0), |(lo, hi)| (f64::from(lo), f64::from(hi)));
    let bands = descriptors.len() as f64;
    for v in map.samples_mut() {
        let t = if hi > lo { (f64::from(*v) - lo) / (hi - lo) } else { 0.0 };
        *v = (t * bands).floor().clamp(0.0, bands - 1.0) as f32;
    }
    Ok(TypeMap { map, descriptors })
}

/// The tree's counts and how its prominence and dominance histograms match the target's.
fn summary(tree: DivideTree, target: &Descriptor, types: usize, terrain: Option<TerrainOrometry>) -> OrometrySummary {
    let oro = tree.orometry(target.domain.min_elevation);
    let prominence = FractionHistogram::uniform(0.0, 2000.0, 20).filled(oro.prominence.iter().copied());
    let dominance = FractionHistogram::uniform(0.0, 1.0, 20).filled(oro.dominance(&tree, target.domain.datum));
    OrometrySummary {
        peaks: tree.peaks.len(),
        saddles: tree.saddles.len(),
        types,
        prominence_emd: prominence.emd(&target.prominence).unwrap_or(f64::NAN),
        prominence_max_bin_error: prominence.max_bin_error(&target.prominence).unwrap_or(f64::NAN),
        dominance_max_bin_error: dominance.max_bin_error(&target.dominance).unwrap_or(f64::NAN),
        terrain,
        tree,
    }
}
