//! Properties of graph creation and inward Open Eden Growth.

use glam::DVec2;
use proptest::prelude::*;
use relief_eden_growth::{
    CoarseOrder, EdenError, FbmProbability, Fronts, Graph, GraphOptions, Growth, LabelMap, ProbabilityMap, Region,
    RegionTree, UNRANKED, Uniform, grow, grow_with,
};
use relief_fixtures::star;
use relief_tin::heightfield::GridSpec;
use relief_tin::heightfield::noise::Fbm;
use relief_tin::poisson_sampling::{Polygon, Rect};

/// Checks the invariants every growth must satisfy ([`Growth::check_invariants`]).
#[track_caller]
fn check_growth(graph: &Graph, growth: &Growth) {
    if let Err(e) = growth.check_invariants(graph) {
        panic!("{e}");
    }
}

fn regions() -> impl Strategy<Value = Vec<Region>> {
    (
        proptest::collection::vec(0.0f64..1.0, 5..24),
        proptest::collection::vec((0.0f64..1.0, proptest::collection::vec(0.0f64..1.0, 4..10)), 0..3),
        0u8..3,
    )
        .prop_map(|(coast, inner, top)| {
            let mut out = vec![Region::new(star(DVec2::ZERO, 1000.0, &coast))];
            // Up to three ranges on a ring of radius 330, each of radius ≤ 150: inside the coast
            // (which reaches at least 600) and apart from each other.
            for (k, (_, shape)) in inner.iter().enumerate() {
                let t = std::f64::consts::TAU * k as f64 / 3.0;
                let c = 330.0 * DVec2::new(t.cos(), t.sin());
                out.push(Region::new(star(c, 150.0, shape)));
                // On the first range: nothing, a summit, or a marked crater (range radius ≥ 90).
                match (k, top) {
                    (0, 1) => out.push(Region::new(star(c, 50.0, shape))),
                    (0, 2) => out.push(Region::new(Polygon::circle(c, 40.0, 16).unwrap()).as_depression()),
                    _ => {}
                }
            }
            out
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn growth_invariants_hold_on_random_regions(regs in regions(), seed in any::<u64>(), fbm in any::<bool>()) {
        let tree = RegionTree::new(regs).unwrap();
        let graph = Graph::from_regions(&tree, &GraphOptions::particles(3_000).with_seed(seed)).unwrap();
        let growth = if fbm {
            let p = FbmProbability::new(Fbm { frequency: 1.0 / 300.0, seed, ..Fbm::default() }, 4.0).unwrap();
            grow(&graph, &p, seed).unwrap()
        } else {
            grow(&graph, &Uniform, seed).unwrap()
        };
        check_growth(&graph, &growth);
        prop_assert_eq!(graph.max_level(), tree.max_level());
        // Same seed, same order.
        let again = if fbm {
            let p = FbmProbability::new(Fbm { frequency: 1.0 / 300.0, seed, ..Fbm::default() }, 4.0).unwrap();
            grow(&graph, &p, seed).unwrap()
        } else {
            grow(&graph, &Uniform, seed).unwrap()
        };
        prop_assert_eq!(&again, &growth);
    }
}

#[test]
fn different_seeds_give_different_orders_and_graphs_are_reproducible() {
    let tree = RegionTree::new(vec![Region::new(Polygon::circle(DVec2::ZERO, 500.0, 48).unwrap())]).unwrap();
    let opts = GraphOptions::particles(2_000).with_seed(3);
    let g1 = Graph::from_regions(&tree, &opts).unwrap();
    let g2 = Graph::from_regions(&tree, &opts).unwrap();
    assert_eq!(g1.tin(), g2.tin());
    let a = grow(&g1, &Uniform, 1).unwrap();
    let b = grow(&g1, &Uniform, 2).unwrap();
    assert_ne!(a.order(), b.order());
    let inside = g1.inside_count() as f64;
    assert!((inside / 2_000.0 - 1.0).abs() < 0.08, "{inside} inside nodes for 2000 requested");
}

#[test]
fn probability_steers_the_growth() {
    // P high in the west: the west half is reached earlier on average.
    let tree = RegionTree::new(vec![Region::new(Polygon::circle(DVec2::ZERO, 500.0, 48).unwrap())]).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(4_000).with_seed(5)).unwrap();
    let growth = grow(&graph, &|p: DVec2| if p.x < 0.0 { 50.0 } else { 1.0 }, 9).unwrap();
    check_growth(&graph, &growth);
    let pts = graph.tin().points();
    let mean = |west: bool| {
        let r: Vec<f64> = growth
            .order()
            .iter()
            .enumerate()
            .filter(|(_, v)| (pts[**v as usize].x < 0.0) == west)
            .map(|(k, _)| k as f64)
            .collect();
        r.iter().sum::<f64>() / r.len() as f64
    };
    assert!(mean(true) < 0.8 * mean(false), "west {} vs east {}", mean(true), mean(false));
}

#[test]
fn a_marked_crater_is_the_only_basin() {
    let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64).unwrap());
    let mountain = Region::new(Polygon::circle(DVec2::ZERO, 600.0, 48).unwrap());
    let crater = Region::new(Polygon::circle(DVec2::ZERO, 200.0, 32).unwrap()).as_depression();
    let tree = RegionTree::new(vec![coast, mountain, crater]).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(6_000).with_seed(2)).unwrap();
    let growth = grow(&graph, &Uniform, 4).unwrap();
    check_growth(&graph, &growth);
    assert_eq!(graph.filled_nodes(), 0);
    // Crater nodes are level 1 (as low as the coast band) but ranked within level 1 by their own
    // downward order: at least one of them has no lower neighbour (the crater floor).
    let pts = graph.tin().points();
    let ranks = growth.ranks();
    let crater: Vec<u32> = (0..pts.len() as u32).filter(|&v| pts[v as usize].length() < 190.0).collect();
    assert!(crater.iter().all(|&v| graph.levels()[v as usize] == 1 && graph.depressions()[v as usize]));
    let floors = crater
        .iter()
        .filter(|&&v| {
            graph
                .tin()
                .neighbors(v)
                .iter()
                .all(|&w| ranks[w as usize] != UNRANKED && ranks[w as usize] > ranks[v as usize])
        })
        .count();
    assert!(floors >= 1, "the crater should hold a local minimum");
}

#[test]
fn enclosed_lower_labels_are_filled_unless_depressions_are_allowed() {
    // Label 1 island, label 2 ring, label 1 again inside the ring: an enclosed basin.
    let grid = GridSpec::new(101, 101, DVec2::ZERO, DVec2::splat(10.0)).unwrap();
    let depth: Vec<u16> = (0..grid.len())
        .map(|k| {
            let (i, j) = grid.coords(k);
            let r = grid.position(i, j).distance(DVec2::splat(500.0));
            match r {
                r if r < 150.0 => 1,
                r if r < 300.0 => 2,
                r if r < 450.0 => 1,
                _ => 0,
            }
        })
        .collect();
    let opts = GraphOptions::particles(5_000).with_seed(8);
    let filled = Graph::from_labels(&LabelMap::new(grid, depth.clone()).unwrap(), &opts).unwrap();
    assert!(filled.filled_nodes() > 100, "{} nodes filled", filled.filled_nodes());
    assert!(filled.depressions().iter().all(|&d| !d));
    check_growth(&filled, &grow(&filled, &Uniform, 1).unwrap());
    let kept = Graph::from_labels(&LabelMap::new(grid, depth).unwrap().with_depressions(true), &opts).unwrap();
    assert_eq!(kept.filled_nodes(), 0);
    assert!(kept.depressions().iter().filter(|&&d| d).count() > 100);
    check_growth(&kept, &grow(&kept, &Uniform, 1).unwrap());
}

/// Land that reaches the image's edge goes on beyond it: the growth's seeds (∂G, land next to
/// the sea) lie in the outer half of the margin beyond the frame, never on it, while the sea
/// inside the image still seeds its own coast. Seeding from the frame put every level's contour
/// within a fraction of a sample beyond the border: a trench along it.
#[test]
fn land_at_the_image_edge_is_cut_by_the_frame_not_a_coast() {
    // 100 × 100 samples 10 m apart: land everywhere but a lake of sea in the middle.
    let grid = GridSpec::new(101, 101, DVec2::ZERO, DVec2::splat(10.0)).unwrap();
    let depth: Vec<u16> = (0..grid.len())
        .map(|k| {
            let (i, j) = grid.coords(k);
            u16::from(grid.position(i, j).distance(DVec2::splat(500.0)) >= 100.0)
        })
        .collect();
    let opts = GraphOptions::particles(5_000).with_seed(3);
    let graph = Graph::from_labels(&LabelMap::new(grid, depth).unwrap(), &opts).unwrap();
    let (r, extent) = (graph.radius(), grid.extent());
    let beyond = |p: DVec2| p.distance(p.clamp(extent.min, extent.max));
    let mut at_lake = 0;
    for &v in graph.boundary() {
        let p = graph.tin().points()[v as usize];
        if p.distance(DVec2::splat(500.0)) < 150.0 {
            at_lake += 1;
        } else {
            assert!(beyond(p) > 0.5 * opts.margin * r - 2.0 * r, "a seed {} beyond the frame", beyond(p));
        }
    }
    assert!(at_lake > 10, "{at_lake} seeds on the lake's shore");
    check_growth(&graph, &grow(&graph, &Uniform, 1).unwrap());
}

#[test]
fn label_maps_from_gray_values() {
    let grid = GridSpec::new(50, 50, DVec2::ZERO, DVec2::ONE).unwrap();
    let values: Vec<f32> = (0..grid.len())
        .map(|k| {
            let (i, j) = grid.coords(k);
            let r = grid.position(i, j).distance(DVec2::splat(25.0));
            if r < 10.0 {
                0.8
            } else if r < 20.0 {
                0.4
            } else {
                0.0
            }
        })
        .collect();
    let labels = LabelMap::from_values(grid, &values).unwrap();
    assert_eq!(labels.max_level(), 2);
    let continuous: Vec<f32> = (0..grid.len()).map(|k| k as f32).collect();
    assert!(matches!(LabelMap::from_values(grid, &continuous), Err(EdenError::InvalidLabelMap { .. })));
    assert!(matches!(LabelMap::from_values(grid, &vec![0.5; grid.len()]), Err(EdenError::InvalidLabelMap { .. })));
    assert!(matches!(LabelMap::new(grid, vec![0; 3]), Err(EdenError::InvalidLabelMap { .. })));
}

#[test]
fn bad_regions_are_typed_errors() {
    let c = |x: f64, r: f64| Polygon::circle(DVec2::new(x, 0.0), r, 32).unwrap();
    assert_eq!(RegionTree::new(vec![]).unwrap_err(), EdenError::NoRegions);
    let err = RegionTree::new(vec![Region::new(c(0.0, 100.0)), Region::new(c(150.0, 100.0))]).unwrap_err();
    assert!(matches!(err, EdenError::RegionsOverlap { a: 0, b: 1, .. }), "{err}");
    let ring = Polygon::new(c(0.0, 50.0).exterior().to_vec(), vec![c(0.0, 20.0).exterior().to_vec()]).unwrap();
    let err = RegionTree::new(vec![Region::new(c(0.0, 100.0)), Region::new(ring)]).unwrap_err();
    assert_eq!(err, EdenError::HoleInRaisedRegion { region: 1, depth: 2 });
    let err = RegionTree::new(vec![Region::new(c(0.0, 100.0)), Region::new(c(0.0, 50.0)).as_depression()]).unwrap_err();
    assert_eq!(err, EdenError::DepressionNotNested { region: 1, parent_depth: 1 });
    // The message says what to draw instead.
    assert!(err.to_string().contains("draw a region around it"), "{err}");
    let err = RegionTree::new(vec![
        Region::new(c(0.0, 100.0)),
        Region::new(c(0.0, 80.0)),
        Region::new(c(0.0, 50.0)).as_depression(),
        Region::new(c(0.0, 20.0)),
    ])
    .unwrap_err();
    assert_eq!(err, EdenError::DepressionWithChildren { region: 2, child: 3 });
    // A depression's height would be ignored (its rim is the level around it): refused.
    let err = RegionTree::new(vec![
        Region::new(c(0.0, 100.0)),
        Region::new(c(0.0, 80.0)),
        Region::new(c(0.0, 50.0)).as_depression().with_height(5.0),
    ])
    .unwrap_err();
    assert_eq!(err, EdenError::DepressionHeight { region: 2, height: 5.0 });
    assert!(err.to_string().contains("remove it"), "{err}");
    let err = RegionTree::new(vec![
        Region::new(c(0.0, 1000.0)),
        Region::new(c(-300.0, 100.0)).with_height(10.0),
        Region::new(c(300.0, 100.0)).with_height(20.0),
    ])
    .unwrap_err();
    assert!(matches!(err, EdenError::ConflictingHeights { depth: 2, .. }), "{err}");
    assert!(err.to_string().contains("give both 10 and draw a region at 20 inside region 2"), "{err}");
    let err = RegionTree::new(vec![
        Region::new(c(0.0, 100.0)).with_height(50.0),
        Region::new(c(0.0, 50.0)).with_height(40.0),
    ])
    .unwrap_err();
    assert!(matches!(err, EdenError::HeightsNotIncreasing { depth: 2, .. }), "{err}");
    let err = RegionTree::new(vec![Region::new(c(0.0, 100.0)).with_height(f64::NAN)]).unwrap_err();
    assert!(matches!(err, EdenError::InvalidHeight { region: 0, .. }));
    // A region far smaller than the sampling radius gets no node.
    let tree = RegionTree::new(vec![Region::new(c(0.0, 1000.0)), Region::new(c(0.0, 1.0))]).unwrap();
    let err = Graph::from_regions(&tree, &GraphOptions::particles(500)).unwrap_err();
    assert!(matches!(err, EdenError::RegionTooSmall { region: 1, .. }), "{err}");
}

#[test]
fn bad_parameters_are_typed_errors() {
    let tree = RegionTree::new(vec![Region::new(Polygon::circle(DVec2::ZERO, 100.0, 16).unwrap())]).unwrap();
    assert_eq!(
        Graph::from_regions(&tree, &GraphOptions::particles(0)).unwrap_err(),
        EdenError::InvalidParticleCount { count: 0 }
    );
    let mut opts = GraphOptions::particles(1_000_000);
    opts.max_particles = 10_000;
    assert!(matches!(
        Graph::from_regions(&tree, &opts).unwrap_err(),
        EdenError::TooManyParticles { limit: 10_000, .. }
    ));
    // A sliver 1000 km long and 1 mm wide at its base asks for 64 particles: its margin band
    // would take millions of samples at the radius those 64 imply. The sampler's budget follows
    // the request, so it fails at once instead of sampling (or allocating a grid for) the band.
    let sliver = Polygon::from_exterior(vec![DVec2::ZERO, DVec2::new(1.0e6, 0.0), DVec2::new(1.0e6, 1.0e-3)]).unwrap();
    let sliver = RegionTree::new(vec![Region::new(sliver)]).unwrap();
    match Graph::from_regions(&sliver, &GraphOptions::particles(64)).unwrap_err() {
        e @ EdenError::SparseDomain { .. } => assert!(e.to_string().contains("use at most"), "{e}"),
        other => panic!("{other:?}"),
    }
    let mut opts = GraphOptions::particles(100);
    opts.margin = 0.5;
    assert!(matches!(Graph::from_regions(&tree, &opts).unwrap_err(), EdenError::InvalidMargin { .. }));
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(300)).unwrap();
    assert_eq!(grow(&graph, &|_: DVec2| 0.0, 1).unwrap_err(), EdenError::ZeroProbability);
    assert!(matches!(
        grow(&graph, &|p: DVec2| if p.x > 0.0 { -1.0 } else { 1.0 }, 1),
        Err(EdenError::InvalidProbability { .. })
    ));
    assert!(matches!(grow(&graph, &|_: DVec2| f64::NAN, 1), Err(EdenError::InvalidProbability { .. })));
    assert!(FbmProbability::new(Fbm { octaves: 0, ..Fbm::default() }, 1.0).is_err());
    // Zero probability on part of the domain is allowed: growth still reaches every node.
    let half = grow(&graph, &|p: DVec2| if p.x > 0.0 { 0.0 } else { 1.0 }, 1).unwrap();
    check_growth(&graph, &half);
}

#[test]
fn siblings_grow_together_so_the_larger_range_reaches_higher() {
    // Two ranges at depth 2: the larger one holds the later (higher) ranks of level 2.
    let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64).unwrap());
    let big = Region::new(Polygon::circle(DVec2::new(-400.0, 0.0), 350.0, 48).unwrap());
    let small = Region::new(Polygon::circle(DVec2::new(450.0, 0.0), 120.0, 32).unwrap());
    let tree = RegionTree::new(vec![coast, big, small]).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(8_000).with_seed(1)).unwrap();
    let growth = grow(&graph, &Uniform, 3).unwrap();
    check_growth(&graph, &growth);
    let top = growth.order()[growth.level_range(2)].last().copied().unwrap();
    assert!(graph.tin().points()[top as usize].x < 0.0, "the highest node should be in the larger range");
    // The small range tops out in the lower part of level 2's ranks, whichever order the regions
    // come in (a growth taking siblings one after the other would put the second one on top).
    for regions in [tree.regions().to_vec(), tree.regions().iter().rev().cloned().collect()] {
        let tree = RegionTree::new(regions).unwrap();
        let graph = Graph::from_regions(&tree, &GraphOptions::particles(8_000).with_seed(1)).unwrap();
        let growth = grow(&graph, &Uniform, 3).unwrap();
        let range = growth.level_range(2);
        let small_top =
            growth.order()[range.clone()].iter().rposition(|&v| graph.tin().points()[v as usize].x > 0.0).unwrap();
        let share = small_top as f64 / range.len() as f64;
        assert!(share < 0.6, "the small range reaches {share:.2} of level 2's ranks");
    }
}

/// Fig. 12: a lowland (level 1) with a high range (level 2) near one end. Mean rank, as a share
/// of level 1's ranks, of the level-1 nodes near `at`.
fn lowland_rank_near(fronts: Fronts, at: DVec2) -> f64 {
    let rect = Rect::new(DVec2::ZERO, DVec2::new(2000.0, 1000.0));
    let coast = Region::new(Polygon::rectangle(rect).unwrap());
    let range = Region::new(Polygon::circle(DVec2::new(500.0, 500.0), 150.0, 48).unwrap());
    let tree = RegionTree::new(vec![coast, range]).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(20_000).with_seed(2)).unwrap();
    let growth = grow_with(&graph, &Uniform, 5, fronts).unwrap();
    check_growth(&graph, &growth);
    let l1 = growth.level_range(1);
    let near: Vec<f64> = growth.order()[l1.clone()]
        .iter()
        .enumerate()
        .filter(|&(_, &v)| graph.tin().points()[v as usize].distance(at) < 25.0)
        .map(|(k, _)| k as f64 / l1.len() as f64)
        .collect();
    assert!(near.len() >= 5);
    near.iter().sum::<f64>() / near.len() as f64
}

#[test]
fn the_double_front_raises_the_lowland_toward_the_range_inside_it() {
    // Two lowland spots 320 m from the coast: one just below the range, one far from it.
    let (by_range, far) = (DVec2::new(500.0, 320.0), DVec2::new(1500.0, 320.0));
    let double = lowland_rank_near(Fronts::Double, by_range) - lowland_rank_near(Fronts::Double, far);
    let single = lowland_rank_near(Fronts::PerRegion, by_range) - lowland_rank_near(Fronts::PerRegion, far);
    // Double front: the ground rises toward the range (n⁺ is small there); per region, both spots
    // are just as far from the coast and rank alike, leaving a cliff at the range's foot.
    assert!(double > 0.3, "double front: {double:.3}");
    assert!(single.abs() < 0.1, "per region: {single:.3}");
}

#[test]
fn a_hundred_thousand_node_growth_keeps_every_invariant() {
    // Three levels, two sibling ranges, a summit and a marked crater, fBm probability.
    let coast = Region::new(star(DVec2::ZERO, 5000.0, &[0.3, 0.9, 0.5, 0.7, 0.2, 0.8, 0.6, 0.4, 1.0, 0.5]));
    let west = Region::new(Polygon::circle(DVec2::new(-1500.0, 0.0), 1000.0, 64).unwrap());
    let east = Region::new(Polygon::circle(DVec2::new(1600.0, 300.0), 700.0, 64).unwrap());
    let summit = Region::new(Polygon::circle(DVec2::new(-1500.0, 200.0), 300.0, 32).unwrap());
    let crater = Region::new(Polygon::circle(DVec2::new(1600.0, 300.0), 200.0, 32).unwrap()).as_depression();
    let tree = RegionTree::new(vec![coast, west, east, summit, crater]).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(100_000).with_seed(7)).unwrap();
    assert!(graph.inside_count() > 95_000, "{}", graph.inside_count());
    let fbm = FbmProbability::new(Fbm { frequency: 1.0 / 2000.0, ..Fbm::default() }, 3.0).unwrap();
    for fronts in [Fronts::Double, Fronts::PerRegion] {
        let growth = grow_with(&graph, &fbm.with_seed(3), 11, fronts).unwrap();
        check_growth(&graph, &growth);
    }
}

/// Pearson correlation of two growths' ranks over the inside nodes.
fn rank_correlation(a: &Growth, b: &Growth) -> f64 {
    let pairs: Vec<(f64, f64)> = a
        .ranks()
        .iter()
        .zip(b.ranks())
        .filter(|(x, _)| **x != UNRANKED)
        .map(|(&x, &y)| (f64::from(x), f64::from(y)))
        .collect();
    let n = pairs.len() as f64;
    let (mx, my) = (pairs.iter().map(|p| p.0).sum::<f64>() / n, pairs.iter().map(|p| p.1).sum::<f64>() / n);
    let cov: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let (vx, vy): (f64, f64) =
        (pairs.iter().map(|p| (p.0 - mx).powi(2)).sum(), pairs.iter().map(|p| (p.1 - my).powi(2)).sum());
    cov / (vx * vy).sqrt()
}

#[test]
fn a_coarse_order_fixes_the_large_scale_structure_of_a_finer_growth() {
    // §6.6's multi-level generation: a coarse growth (2 000 nodes) steers fine ones (30 000).
    let coast = Region::new(Polygon::circle(DVec2::ZERO, 5000.0, 96).unwrap());
    let tree = RegionTree::new(vec![coast]).unwrap();
    let coarse_graph = Graph::from_regions(&tree, &GraphOptions::particles(2_000).with_seed(1)).unwrap();
    let fine = Graph::from_regions(&tree, &GraphOptions::particles(30_000).with_seed(2)).unwrap();
    let fbm = |seed: u64| {
        FbmProbability::new(Fbm { frequency: 1.0 / 3000.0, ..Fbm::default() }, 4.0).unwrap().with_seed(seed)
    };
    let coarse = grow(&coarse_graph, &fbm(7), 3).unwrap();
    let order = CoarseOrder::new(&coarse_graph, &coarse, 6.0).unwrap();
    let steered = |seed: u64| {
        let p = fbm(seed);
        grow(&fine, &|q: DVec2| p.probability(q) * order.probability(q), seed).unwrap()
    };
    let (a, b) = (steered(11), steered(12));
    check_growth(&fine, &a);
    let free = (grow(&fine, &fbm(11), 11).unwrap(), grow(&fine, &fbm(12), 12).unwrap());
    let (with, without) = (rank_correlation(&a, &b), rank_correlation(&free.0, &free.1));
    assert!(with > without + 0.1 && with > 0.8, "steered {with:.3}, free {without:.3}");
    // Contrast 0 is no preference; a negative one is refused.
    let flat = CoarseOrder::new(&coarse_graph, &coarse, 0.0).unwrap();
    assert_eq!(flat.probability(DVec2::new(100.0, 0.0)), 1.0);
    assert!(CoarseOrder::new(&coarse_graph, &coarse, -1.0).is_err());
}
