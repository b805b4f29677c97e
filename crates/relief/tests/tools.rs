//! The contour tools: pick, fill, delete, paste and cut, as library calls and as scene edits.

use std::path::Path;

use glam::DVec2;
use relief::contours::{ContourSet, Histogram, Ranking, assign_heights, extract_tin};
use relief::eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
use relief::pipeline::{generate, load_scene};
use relief::poisson_sampling::Polygon;
use relief::scene::{ContourMove, ContourPick, Edit};
use relief::tools;

const LEVELS: [f64; 6] = [50.0, 150.0, 250.0, 350.0, 450.0, 550.0];

/// An island with a hill in the east, its node heights and contours.
fn island() -> (Graph, Vec<f64>, ContourSet) {
    let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64).unwrap());
    let hill = Region::new(Polygon::circle(DVec2::new(400.0, 0.0), 300.0, 32).unwrap());
    let graph =
        Graph::from_regions(&RegionTree::new(vec![coast, hill]).unwrap(), &GraphOptions::particles(6_000)).unwrap();
    let growth = grow(&graph, &Uniform, 1).unwrap();
    let ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
    let ranking = Ranking { order: growth.order(), level_ends: &ends, level_heights: &graph.level_heights()[1..] };
    let heights =
        assign_heights(graph.tin().num_points(), &ranking, &Histogram::uniform(0.0, 600.0).unwrap()).unwrap().heights;
    let set = extract_tin(graph.tin(), &heights, &LEVELS).unwrap();
    (graph, heights, set)
}

fn inside(graph: &Graph, set: &ContourSet, k: usize, offset: DVec2) -> Vec<bool> {
    let polygon = Polygon::from_exterior(set.contours()[k].points.clone()).unwrap();
    graph.tin().points().iter().map(|&q| polygon.contains(q - offset)).collect()
}

#[test]
fn pick_takes_the_contour_around_a_point_nearest_a_height() {
    let (_, _, set) = island();
    let at = DVec2::new(400.0, 0.0);
    let innermost = tools::pick(&set, at, None).unwrap();
    let k = tools::pick(&set, at, Some(240.0)).unwrap();
    assert_eq!(set.contours()[k].height, 250.0);
    assert!(set.contours()[innermost].height > 250.0, "the innermost contour is the highest around the summit");
    assert_eq!(tools::pick(&set, DVec2::new(5000.0, 0.0), None), None, "nothing around a point at sea");
}

#[test]
fn fill_regrows_the_inside_with_the_same_elevations() {
    let (graph, before, set) = island();
    let k = tools::pick(&set, DVec2::new(400.0, 0.0), Some(250.0)).unwrap();
    let members = inside(&graph, &set, k, DVec2::ZERO);
    let mut after = before.clone();
    let changed = tools::fill(graph.tin(), &mut after, &set, k, &Uniform, 9).unwrap();
    assert!(changed > 50, "{changed}");
    let sorted = |h: &[f64]| {
        let mut v: Vec<f64> = h.iter().zip(&members).filter(|(_, m)| **m).map(|(h, _)| *h).collect();
        v.sort_by(f64::total_cmp);
        v
    };
    assert_eq!(sorted(&before), sorted(&after), "the inside keeps its distribution");
    for (v, m) in members.iter().enumerate() {
        if !m {
            assert_eq!(before[v], after[v], "node {v} outside the contour changed");
        }
    }
    // Every refilled node but those on the contour has a lower neighbour: no new pit.
    let tin = graph.tin();
    for v in (0..tin.num_points() as u32).filter(|&v| members[v as usize]) {
        assert!(tin.neighbors(v).iter().any(|&w| after[w as usize] < after[v as usize]), "node {v} is a pit");
    }
}

#[test]
fn delete_removes_a_contour_and_everything_inside() {
    let (graph, before, set) = island();
    let k = tools::pick(&set, DVec2::new(400.0, 0.0), Some(250.0)).unwrap();
    let members = inside(&graph, &set, k, DVec2::ZERO);
    let mut after = before.clone();
    tools::delete(graph.tin(), &mut after, &set, k, &Uniform, 9).unwrap();
    for (v, m) in members.iter().enumerate() {
        if *m {
            assert!(after[v] >= 250.0 && after[v] < 350.0, "node {v} at {}", after[v]);
        } else {
            assert_eq!(before[v], after[v]);
        }
    }
    let again = extract_tin(graph.tin(), &after, &LEVELS).unwrap();
    let top = tools::pick(&again, DVec2::new(400.0, 0.0), None).unwrap();
    assert_eq!(again.contours()[top].height, 250.0, "no contour is left inside the deleted one");
}

#[test]
fn paste_adds_the_relief_above_the_contour_elsewhere() {
    let (graph, before, set) = island();
    let k = tools::pick(&set, DVec2::new(400.0, 0.0), Some(350.0)).unwrap();
    let offset = DVec2::new(-700.0, 100.0);
    let targets = inside(&graph, &set, k, offset);
    let mut after = before.clone();
    let changed = tools::paste(graph.tin(), &mut after, &before, &set, k, offset);
    assert!(changed > 20, "{changed}");
    let (mut raised, mut total) = (0.0, 0.0);
    for (v, t) in targets.iter().enumerate() {
        if *t {
            assert!(after[v] >= before[v]);
            raised += after[v] - before[v];
            total += 1.0;
        } else {
            assert_eq!(after[v], before[v]);
        }
    }
    // The hill above 350 m rises up to 250 m higher: on average well above nothing.
    assert!(raised / total > 30.0, "mean rise {}", raised / total);
}

#[test]
fn scene_tools_edit_the_terrain_and_name_what_they_miss() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut scene = load_scene(scenes.join("editing-session-4-histogram.json")).unwrap();
    scene.reconstruction.resolution = [128, 128];
    let plain = generate(&scene, &scenes, &mut ()).unwrap();
    // Cut the right range's summit above its 1400 m contour onto the left range's flank.
    scene.edits = vec![Edit::Cut(ContourMove { at: [1950.0, 2050.0], height: Some(1400.0), to: [-1500.0, -2500.0] })];
    let cut = generate(&scene, &scenes, &mut ()).unwrap();
    let at = |t: &relief::Terrain, x: f64, y: f64| t.heightfield.sample_bilinear(DVec2::new(x, y)).unwrap();
    assert!(at(&cut, 1950.0, 2050.0) < at(&plain, 1950.0, 2050.0) - 50.0, "the summit is gone from its place");
    assert!(at(&cut, 1950.0, 2050.0) >= 1400.0 - 1.0, "down to its contour");
    assert!(at(&cut, -1500.0, -2500.0) > at(&plain, -1500.0, -2500.0) + 50.0, "and stands where it went");
    // A tool that picks nothing names where it looked.
    scene.edits = vec![Edit::Fill(ContourPick { at: [20000.0, 0.0], height: None })];
    let err = generate(&scene, &scenes, &mut ()).unwrap_err();
    assert!(err.to_string().starts_with("edits[0].fill.at: no closed contour around (20000, 0)"), "{err}");
}
