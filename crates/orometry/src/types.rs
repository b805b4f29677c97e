//! Several terrain types in one synthesis (§7.2, Fig. 24): a type map `C_T` splits the domain
//! into regions, each with its own target orometry. Each type's peaks are drawn from its own
//! elevation histogram and placed by its own dart throwing, confined to its region (the type's
//! mask times any peak-density map); the ridges are then one Eq. 1 spanning tree over every peak
//! ("fused during ridge line Delaunay triangulation, which is independent of `C_T`"), and each
//! saddle-elevation round assigns every type's targets to the peaks of that type.

use glam::DVec2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use relief_heightfield::{Extent, Heightfield};

use crate::generate::{
    Placement, assign_saddles, check_control, check_pinned, lift_below_threshold, peak_elevations, spanning_ridges,
    split_ridges,
};
use crate::tree::{DivideTree, TreePeak};
use crate::{ControlMaps, Descriptor, MAX_PEAKS, OrometryError, TreeOptions};

/// Most terrain types a type map may name.
pub const MAX_TYPES: usize = 64;

/// A type map `C_T`: which target orometry applies where.
#[derive(Debug, Clone)]
pub struct TypeMap {
    /// The type of each place, spanning the domain: sample values are type indices (rounded to
    /// the nearest whole number, clamped to the descriptors), read at the nearest sample.
    pub map: Heightfield,
    /// The target orometry of each type, type 0 first.
    pub descriptors: Vec<Descriptor>,
}

impl TypeMap {
    /// The type at `p` (the nearest sample's; type 0 outside the map).
    #[must_use]
    pub fn type_at(&self, p: DVec2) -> usize {
        let grid = self.map.grid();
        grid.nearest_sample(p).map_or(0, |(i, j)| self.index(self.map.samples()[grid.index(i, j)]))
    }

    fn index(&self, v: f32) -> usize {
        (v.round().max(0.0) as usize).min(self.descriptors.len().saturating_sub(1))
    }

    /// The share of the map's samples of each type.
    fn shares(&self) -> Vec<f64> {
        let mut counts = vec![0usize; self.descriptors.len()];
        for &v in self.map.samples() {
            counts[self.index(v)] += 1;
        }
        let total = self.map.samples().len().max(1) as f64;
        counts.into_iter().map(|c| c as f64 / total).collect()
    }

    /// Type `k`'s peak-density map: 1 on its samples, 0 elsewhere, times `density` where given.
    fn density(&self, k: usize, density: Option<&Heightfield>) -> Heightfield {
        let grid = *self.map.grid();
        let mut mask = self.map.clone();
        for (at, v) in mask.samples_mut().iter_mut().enumerate() {
            let (i, j) = grid.coords(at);
            let scale = density.and_then(|d| d.sample_bilinear_clamped(grid.position(i, j))).unwrap_or(1.0);
            *v = if self.index(*v) == k { scale } else { 0.0 };
        }
        mask
    }
}

/// Generates a divide tree over `extent` whose orometry follows, in each region of `types`, that
/// region's descriptor (see the module's docs). [`TreeOptions::peaks`], when given, is the total,
/// shared among the types in proportion to their density × area; otherwise each type gets its
/// density × its area. Pinned peaks count towards the type at their position. The tree's base is
/// the lowest of the descriptors' lowest elevations.
///
/// # Errors
/// The errors of [`crate::generate_tree`], plus [`OrometryError::InvalidOption`] for a type map
/// without descriptors or with more than [`MAX_TYPES`], and [`OrometryError::ControlMapExtent`]
/// or [`OrometryError::InvalidControlMap`] (named `types`) for a map that does not span the
/// domain or holds no-data.
pub fn generate_typed_tree(
    types: &TypeMap,
    extent: Extent,
    controls: &ControlMaps,
    pinned: &[TreePeak],
    options: &TreeOptions,
) -> Result<DivideTree, OrometryError> {
    let counts = check_inputs(types, extent, controls, pinned, options)?;
    let base = types.descriptors.iter().map(|d| d.domain.min_elevation).fold(f64::INFINITY, f64::min);
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    // Every type's peaks, placed in its region: (elevation, position, type).
    let mut peaks: Vec<(f64, DVec2, usize)> = Vec::new();
    for (k, descriptor) in types.descriptors.iter().enumerate() {
        let own: Vec<TreePeak> = pinned.iter().filter(|p| types.type_at(p.position) == k).copied().collect();
        let n = counts[k] + own.len();
        if n == 0 {
            continue;
        }
        let region = ControlMaps {
            peak_density: Some(types.density(k, controls.peak_density.as_ref())),
            elevation: controls.elevation.clone(),
        };
        let heights = peak_elevations(descriptor, &own, n, &mut rng);
        let (positions, _) = Placement::new(descriptor, extent, &region, options).place(&heights, &mut rng);
        peaks.extend(heights.iter().zip(positions).map(|(&(h, _), p)| (h, p, k)));
    }
    // Highest first, as a generated tree's peaks are; equal heights keep the types' order.
    peaks.sort_by(|a, b| b.0.total_cmp(&a.0));
    let positions: Vec<DVec2> = peaks.iter().map(|p| p.1).collect();
    let heights: Vec<f64> = peaks.iter().map(|p| p.0).collect();
    let kind: Vec<usize> = peaks.iter().map(|p| p.2).collect();
    let ridges = spanning_ridges(&positions, &heights, base, options.rho, &[]);
    let mut tree = DivideTree {
        peaks: peaks.iter().map(|&(elevation, position, _)| TreePeak { position, elevation }).collect(),
        saddles: Vec::with_capacity(ridges.len()),
    };
    split_ridges(&mut tree, &ridges, base, extent, &mut rng);
    for round in 0..options.saddle_rounds {
        for (k, descriptor) in types.descriptors.iter().enumerate() {
            assign_saddles(&mut tree, descriptor, base, round % 2 == 0, &mut rng, &|p| kind[p] == k);
        }
    }
    for (k, descriptor) in types.descriptors.iter().enumerate() {
        lift_below_threshold(&mut tree, descriptor, base, &mut rng, &|p| kind[p] == k);
    }
    Ok(tree)
}

/// Checks the inputs and returns the free (not pinned) peaks of each type.
fn check_inputs(
    types: &TypeMap,
    extent: Extent,
    controls: &ControlMaps,
    pinned: &[TreePeak],
    options: &TreeOptions,
) -> Result<Vec<usize>, OrometryError> {
    let count = types.descriptors.len();
    if count == 0 || count > MAX_TYPES {
        return Err(OrometryError::InvalidOption {
            name: "types",
            value: count as f64,
            reason: "a type map needs between 1 and 64 descriptors",
        });
    }
    for d in &types.descriptors {
        d.validate()?;
    }
    // The single-type checks (options, extent, control maps, the peak budget) on type 0.
    let first = &types.descriptors[0];
    crate::generate::check_inputs(first, extent, controls, &[], &TreeOptions { peaks: Some(1), ..options.clone() })?;
    check_control("types", Some(&types.map), &extent, false)?;
    let base = types.descriptors.iter().map(|d| d.domain.min_elevation).fold(f64::INFINITY, f64::min);
    check_pinned(pinned, &extent, base)?;
    let size = extent.size();
    let area_km2 = size.x * size.y / 1e6;
    let weights: Vec<f64> =
        types.descriptors.iter().zip(types.shares()).map(|(d, share)| d.density_per_km2 * share * area_km2).collect();
    let mut pinned_per_type = vec![0usize; count];
    for p in pinned {
        pinned_per_type[types.type_at(p.position)] += 1;
    }
    let free: Vec<usize> = match options.peaks {
        Some(total) => {
            let total_weight: f64 = weights.iter().sum();
            let free = total.saturating_sub(pinned.len()) as f64;
            weights
                .iter()
                .map(|w| if total_weight > 0.0 { (free * w / total_weight).round() as usize } else { 0 })
                .collect()
        }
        None => weights.iter().zip(&pinned_per_type).map(|(w, &p)| (w.round() as usize).saturating_sub(p)).collect(),
    };
    if free.iter().zip(&types.descriptors).any(|(&k, d)| k > 0 && d.normalized_elevation.is_empty()) {
        return Err(OrometryError::InvalidDescriptor {
            feature: "normalized_elevation",
            reason: "is empty for a type with peaks to place, so there are no peak elevations to sample",
        });
    }
    let n = free.iter().sum::<usize>() + pinned.len();
    if n > MAX_PEAKS {
        return Err(OrometryError::TooManyPeaks { peaks: n, limit: MAX_PEAKS });
    }
    if n == 0 {
        return Err(OrometryError::InvalidOption {
            name: "peaks",
            value: 0.0,
            reason: "no peaks to place: the types' descriptors have none and none were asked for",
        });
    }
    Ok(free)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisOptions;
    use relief_heightfield::GridSpec;

    /// The descriptor of an egg-box DEM of `amplitude` metres above `floor`, bumps every
    /// `wavelength` metres (peaks of about `2·amplitude` prominence).
    fn egg_box(floor: f32, amplitude: f32, wavelength: f32) -> Descriptor {
        let grid = GridSpec::new(201, 201, DVec2::ZERO, DVec2::splat(50.0)).unwrap();
        let k = std::f32::consts::TAU / wavelength;
        let dem = Heightfield::from_fn(grid, |p| {
            let (x, y) = (p.x as f32, p.y as f32);
            floor + amplitude * (1.0 + (k * x).sin() * (k * y).sin() + 0.3 * (0.37 * k * x + 1.3).sin())
        })
        .unwrap();
        Descriptor::of(&dem, &AnalysisOptions { min_prominence: 10.0, ..AnalysisOptions::default() }).unwrap().1
    }

    fn halves(extent: Extent) -> Heightfield {
        let grid = GridSpec::from_extent(41, 41, extent).unwrap();
        Heightfield::from_fn_indexed(grid, |i, _| if i < 20 { 0.0 } else { 1.0 }).unwrap()
    }

    #[test]
    fn each_region_takes_its_types_peaks_and_one_tree_joins_them() {
        let extent = Extent::new(DVec2::ZERO, DVec2::splat(20_000.0));
        // West: low hills, sparse; east: high mountains, dense.
        let (hills, mountains) = (egg_box(100.0, 40.0, 2500.0), egg_box(800.0, 300.0, 1250.0));
        assert!(mountains.density_per_km2 > 2.0 * hills.density_per_km2);
        let types = TypeMap { map: halves(extent), descriptors: vec![hills.clone(), mountains.clone()] };
        let options = TreeOptions { seed: 5, ..TreeOptions::default() };
        let tree = generate_typed_tree(&types, extent, &ControlMaps::default(), &[], &options).unwrap();
        tree.validate().unwrap();
        assert_eq!(tree.saddles.len(), tree.peaks.len() - 1, "one tree over both regions");
        // Each region holds its own type's peaks, at its elevations and about its density (the
        // density is read bilinearly, so within a cell of the border either type may be found).
        for (k, d) in types.descriptors.iter().enumerate() {
            let (lo, hi) = (d.domain.min_elevation, d.domain.max_elevation);
            let peaks: Vec<&TreePeak> = tree.peaks.iter().filter(|p| types.type_at(p.position) == k).collect();
            let out: Vec<_> = peaks
                .iter()
                .filter(|p| (p.position.x - 10_000.0).abs() > 500.0)
                .filter(|p| p.elevation < lo || p.elevation > hi + 1e-9)
                .map(|p| (p.position, p.elevation))
                .collect();
            assert!(out.is_empty(), "type {k} [{lo}, {hi}]: {out:?} of {}", peaks.len());
            let expected = d.density_per_km2 * 200.0;
            let n = peaks.len() as f64;
            assert!((n / expected - 1.0).abs() < 0.15, "type {k}: {n} peaks for {expected}");
        }
        // Dominance and prominence targets were assigned per type, alternating: each type's
        // peaks (away from the border) follow its own two histograms.
        let oro = tree.orometry(100.0);
        let dominance = oro.dominance(&tree, 0.0);
        for (k, d) in types.descriptors.iter().enumerate() {
            let own: Vec<usize> = (0..tree.peaks.len())
                .filter(|&p| oro.key_saddle[p].is_some() && types.type_at(tree.peaks[p].position) == k)
                .filter(|&p| (tree.peaks[p].position.x - 10_000.0).abs() > 500.0)
                .collect();
            let histogram = |target: &crate::FractionHistogram, values: Vec<f64>| {
                let empty = crate::FractionHistogram { fractions: vec![0.0; target.fractions.len()], ..target.clone() };
                empty.filled(values).max_bin_error(target).unwrap()
            };
            let prominence = histogram(&d.prominence, own.iter().map(|&p| oro.prominence[p]).collect());
            let dom = histogram(&d.dominance, own.iter().map(|&p| dominance[p]).collect());
            // Measured 0 and 3.7 % (hills), 3.3 and 1.2 % (mountains); giving each type's targets
            // to the other's peaks makes them 10–89 %, rounds that do not alternate 3.8–4.2 %.
            assert!(prominence <= 0.035 && dom <= 0.04, "type {k}: {prominence} and {dom} ({} peaks)", own.len());
        }
    }

    #[test]
    fn pinned_peaks_stay_and_count_towards_the_type_at_their_position() {
        let extent = Extent::new(DVec2::ZERO, DVec2::splat(20_000.0));
        let (hills, mountains) = (egg_box(100.0, 40.0, 2500.0), egg_box(800.0, 300.0, 1250.0));
        let types = TypeMap { map: halves(extent), descriptors: vec![hills, mountains] };
        let options = TreeOptions { seed: 5, ..TreeOptions::default() };
        let free = generate_typed_tree(&types, extent, &ControlMaps::default(), &[], &options).unwrap();
        // Two summits pinned in the east: they are kept, and the east gets two free peaks fewer.
        let pinned = [
            TreePeak { position: DVec2::new(15_000.0, 10_000.0), elevation: 1500.0 },
            TreePeak { position: DVec2::new(17_000.0, 4_000.0), elevation: 1450.0 },
        ];
        let tree = generate_typed_tree(&types, extent, &ControlMaps::default(), &pinned, &options).unwrap();
        for p in &pinned {
            assert!(tree.peaks.iter().any(|q| q.position == p.position && q.elevation == p.elevation));
        }
        let east = |t: &DivideTree| t.peaks.iter().filter(|p| types.type_at(p.position) == 1).count();
        assert_eq!(tree.peaks.len(), free.peaks.len());
        assert!(east(&tree).abs_diff(east(&free)) <= 1, "{} against {}", east(&tree), east(&free));
        // The pinned summits belong to the mountains' saddle rounds: the lower one's prominence
        // is a mountain's (355 m measured), not a hill's (every hill is under 100 m).
        assert_eq!(tree.peaks[0].elevation, 1500.0);
        assert!(types.descriptors[0].prominence.fractions[1..].iter().all(|&f| f == 0.0));
        let oro = tree.orometry(100.0);
        let k = tree.peaks.iter().position(|p| p.elevation == 1450.0).unwrap();
        assert!(oro.prominence[k] > 100.0, "{}", oro.prominence[k]);
    }

    #[test]
    fn an_asked_for_count_is_shared_by_density_times_area() {
        let extent = Extent::new(DVec2::ZERO, DVec2::splat(20_000.0));
        let (hills, mountains) = (egg_box(100.0, 40.0, 2500.0), egg_box(800.0, 300.0, 1250.0));
        let share = mountains.density_per_km2 / (hills.density_per_km2 + mountains.density_per_km2);
        let types = TypeMap { map: halves(extent), descriptors: vec![hills, mountains] };
        let options = TreeOptions { peaks: Some(120), seed: 2, ..TreeOptions::default() };
        let tree = generate_typed_tree(&types, extent, &ControlMaps::default(), &[], &options).unwrap();
        assert!(tree.peaks.len().abs_diff(120) <= 1, "{}", tree.peaks.len());
        // Both halves are half the map (the map's middle column goes east): the east's share is
        // its density's.
        let east = tree.peaks.iter().filter(|p| types.type_at(p.position) == 1).count() as f64;
        assert!((east / 120.0 - share).abs() < 0.08, "{east} of 120 for a share of {share}");
    }

    #[test]
    fn bad_type_maps_are_refused() {
        let extent = Extent::new(DVec2::ZERO, DVec2::splat(20_000.0));
        let hills = egg_box(100.0, 40.0, 2500.0);
        let none = TypeMap { map: halves(extent), descriptors: vec![] };
        let options = TreeOptions::default();
        let err = generate_typed_tree(&none, extent, &ControlMaps::default(), &[], &options).unwrap_err();
        assert!(matches!(err, OrometryError::InvalidOption { name: "types", .. }), "{err}");
        let many = TypeMap { map: halves(extent), descriptors: vec![hills.clone(); MAX_TYPES + 1] };
        let err = generate_typed_tree(&many, extent, &ControlMaps::default(), &[], &options).unwrap_err();
        assert!(matches!(err, OrometryError::InvalidOption { name: "types", .. }), "{err}");
        let elsewhere = Extent::new(DVec2::splat(5000.0), DVec2::splat(25_000.0));
        let shifted = TypeMap { map: halves(elsewhere), descriptors: vec![hills] };
        let err = generate_typed_tree(&shifted, extent, &ControlMaps::default(), &[], &options).unwrap_err();
        assert!(matches!(err, OrometryError::ControlMapExtent { name: "types", .. }), "{err}");
        // A type with peaks to place but no elevations to draw them from.
        let mut flat = egg_box(100.0, 40.0, 2500.0);
        flat.normalized_elevation.fractions.iter_mut().for_each(|f| *f = 0.0);
        let types = TypeMap { map: halves(extent), descriptors: vec![egg_box(100.0, 40.0, 2500.0), flat] };
        let err = generate_typed_tree(&types, extent, &ControlMaps::default(), &[], &options).unwrap_err();
        assert!(matches!(err, OrometryError::InvalidDescriptor { feature: "normalized_elevation", .. }), "{err}");
    }
}
