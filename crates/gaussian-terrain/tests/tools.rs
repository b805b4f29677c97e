//! Editing tools (§5): region tools keep the terrain continuous and leave primitives outside
//! their influence bit-for-bit untouched; the skeleton simplifies, moves and rescales with the
//! graph attenuation.

use glam::DVec2;
use proptest::prelude::*;
use relief_fixtures::random_terrain;
use relief_gaussian_terrain::{
    GaussianError, Heightfield, Placement, RasterOptions, Region, Skeleton, StampMode, VectorTerrain, copy, cut,
    delete, paste, rasterize, squeeze, stamp, twist,
};
use relief_heightfield::{Extent, GridSpec};

fn grid() -> GridSpec {
    GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap()
}

fn terrain() -> VectorTerrain {
    random_terrain(400, 1000.0, 8.0, 11)
}

fn raster(t: &VectorTerrain) -> Heightfield {
    rasterize(t, &grid(), &RasterOptions::default()).unwrap()
}

/// The largest step between neighbouring samples.
fn max_step(h: &Heightfield) -> f32 {
    let (nx, ny) = (h.nx(), h.ny());
    let mut worst = 0.0f32;
    for j in 0..ny {
        for i in 0..nx {
            if i + 1 < nx {
                worst = worst.max((h.value(i + 1, j) - h.value(i, j)).abs());
            }
            if j + 1 < ny {
                worst = worst.max((h.value(i, j + 1) - h.value(i, j)).abs());
            }
        }
    }
    worst
}

/// Indices of primitives whose centre is farther than `margin` from every point of `region`'s
/// interior-or-boundary band, i.e. outside any tool's influence.
fn far_from(t: &VectorTerrain, region: &Region, margin: f64) -> Vec<usize> {
    (0..t.primitives.len())
        .filter(|&k| {
            let c = DVec2::from(t.primitives[k].center);
            !region.contains(c) && region.boundary_distance(c) > margin
        })
        .collect()
}

fn circle(x: f64, y: f64, r: f64) -> Region {
    Region::Circle { center: [x, y], radius: r }
}

#[test]
fn regions_select_by_centre() {
    let lasso = Region::Lasso { points: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]] };
    assert!(lasso.contains(DVec2::new(5.0, 5.0)));
    assert!(!lasso.contains(DVec2::new(11.0, 5.0)));
    assert!((lasso.boundary_distance(DVec2::new(5.0, 3.0)) - 3.0).abs() < 1e-12);
    assert!((circle(0.0, 0.0, 2.0).boundary_distance(DVec2::new(5.0, 0.0)) - 3.0).abs() < 1e-12);
    for bad in [
        circle(0.0, 0.0, 0.0),
        circle(f64::NAN, 0.0, 1.0),
        Region::Lasso { points: vec![[0.0, 0.0], [1.0, 1.0]] },
        Region::Lasso { points: vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]] },
    ] {
        assert!(matches!(bad.validate(), Err(GaussianError::InvalidRegion { .. })), "{bad:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Stamping moves or copies `P(Ω)`, damps what lies under the destination, keeps every
    /// primitive beyond the damping radius exactly, and adds no jump.
    #[test]
    fn stamps_are_local_and_continuous(
        x in 250.0..750.0f64, y in 250.0..750.0f64, r in 60.0..200.0f64,
        tx in 200.0..800.0f64, ty in 200.0..800.0f64, rotation in -3.0..3.0f64,
        copy_mode in any::<bool>(), damping in 20.0..150.0f64,
    ) {
        let before = terrain();
        let mut after = before.clone();
        let region = circle(x, y, r);
        let placement = Placement { to: [tx, ty], rotation, scale: 1.0 };
        let mode = if copy_mode { StampMode::Copy } else { StampMode::Move };
        let selected = region.select(&before);
        let placed = stamp(&mut after, &region, &placement, mode, damping).unwrap();
        prop_assert_eq!(placed.len(), selected.len());
        // Primitives wholly under the stamp are gone, not left at zero amplitude; the placed ones
        // are the last, as returned (none when Ω selects nothing: the stamp then only damps).
        prop_assert!(after.primitives.iter().all(|g| g.amplitude != 0.0));
        let n = after.primitives.len();
        prop_assert_eq!(&placed, &(n - selected.len()..n).collect::<Vec<_>>());
        let kept = if mode == StampMode::Copy { before.primitives.len() } else { before.primitives.len() - selected.len() };
        prop_assert!(after.primitives.len() <= kept + placed.len(), "{} > {} + {}", after.primitives.len(), kept, placed.len());

        let destination = circle(tx, ty, r);
        // Untouched: outside the damping band of the destination and not selected (or copied).
        for k in far_from(&before, &destination, damping) {
            if mode == StampMode::Copy || !region.contains(DVec2::from(before.primitives[k].center)) {
                prop_assert!(after.primitives.contains(&before.primitives[k]));
            }
        }
        // A rigid move cannot steepen the terrain beyond the steepest of the two terrains summed
        // in the overlap band; damping only scales amplitudes down.
        let (a, b) = (max_step(&raster(&before)), max_step(&raster(&after)));
        prop_assert!(b <= 2.0 * a + 1e-3, "steepest step {a} → {b}");
    }

    /// Twist and squeeze change nothing outside Ω: those samples are bit-identical.
    #[test]
    fn warps_leave_the_outside_untouched(
        x in 300.0..700.0f64, y in 300.0..700.0f64, r in 100.0..250.0f64,
        angle in -2.0..2.0f64, vx in -80.0..80.0f64, vy in -80.0..80.0f64,
    ) {
        let before = terrain();
        let region = circle(x, y, r);
        for squeezed in [false, true] {
            let mut after = before.clone();
            let moved = if squeezed {
                squeeze(&mut after, &region, DVec2::new(vx, vy), 0.5 * r).unwrap()
            } else {
                twist(&mut after, &region, angle, 0.5 * r).unwrap()
            };
            prop_assert!(moved <= region.select(&before).len());
            for (k, (p, q)) in before.primitives.iter().zip(&after.primitives).enumerate() {
                if !region.contains(DVec2::from(p.center)) {
                    prop_assert_eq!(p, q, "primitive {} outside Ω changed", k);
                }
            }
            let (a, b) = (max_step(&raster(&before)), max_step(&raster(&after)));
            prop_assert!(b <= 3.0 * a + 1e-3, "steepest step {a} → {b}");
        }
    }
}

#[test]
fn copy_cut_paste_and_delete() {
    let before = terrain();
    let region = circle(500.0, 500.0, 150.0);
    let inside = region.select(&before).len();
    assert!(inside > 5);
    let landform = copy(&before, &region, "massif").unwrap();
    assert_eq!(landform.primitives.len(), inside);

    let mut t = before.clone();
    let cut_out = cut(&mut t, &region, "massif").unwrap();
    assert_eq!(cut_out, landform);
    assert_eq!(t.primitives.len(), before.primitives.len() - inside);
    assert!(region.select(&t).is_empty());

    // Paste it back where it was with no damping reach: the same primitives return.
    let footprint = Region::Circle { center: [0.0, 0.0], radius: 150.0 };
    let placement = Placement { to: [500.0, 500.0], rotation: 0.0, scale: 1.0 };
    paste(&mut t, &landform, &footprint, &placement, 1e-9).unwrap();
    let h0 = raster(&before);
    let h1 = raster(&t);
    let worst = h0.samples().iter().zip(h1.samples()).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    assert!(worst < 1e-2, "cut + paste back differs by {worst}");

    let mut t = before.clone();
    assert_eq!(delete(&mut t, &region).unwrap(), inside);
    assert_eq!(t.primitives.len(), before.primitives.len() - inside);
    let err = stamp(&mut t, &region, &Placement { to: [0.0, 0.0], rotation: 0.0, scale: -1.0 }, StampMode::Move, 10.0);
    assert!(matches!(err, Err(GaussianError::InvalidRegion { .. })));
    let err = stamp(&mut t, &region, &placement, StampMode::Move, f64::NAN);
    assert!(matches!(err, Err(GaussianError::InvalidOption { .. })));
}

/// A Y-shaped crest: a trunk from (0, 0) to (0, 100) and two branches, one cell per unit.
fn crest() -> Skeleton {
    let mut points = Vec::new();
    let mut down = Vec::new();
    for k in 0..=100 {
        points.push(DVec2::new(0.0, f64::from(k)));
        down.push(if k == 0 { None } else { Some(k as usize - 1) });
    }
    for side in [-1.0, 1.0] {
        for k in 1..=60 {
            let n = points.len();
            points.push(DVec2::new(side * f64::from(k) * 0.7, 100.0 + f64::from(k) * 0.7));
            down.push(Some(if k == 1 { 100 } else { n - 1 }));
        }
    }
    Skeleton::from_flow(&points, &down).unwrap()
}

#[test]
fn skeleton_simplifies_to_evenly_spaced_nodes() {
    let full = crest();
    assert_eq!(full.nodes.len(), 221);
    assert_eq!(full.edges.len(), 220);
    let simple = full.simplified(10.0);
    simple.validate().unwrap();
    assert!(simple.nodes.len() < 40 && simple.nodes.len() >= 10, "{} nodes", simple.nodes.len());
    for &[a, b] in &simple.edges {
        let l = DVec2::from(simple.nodes[a]).distance(DVec2::from(simple.nodes[b]));
        assert!(l >= 10.0, "edge of {l}");
    }
    // Still one connected tree.
    assert_eq!(simple.edges.len(), simple.nodes.len() - 1);
    let d = simple.graph_distances(0);
    assert!(d.iter().all(|d| d.is_finite()));
    let bad = Skeleton::from_flow(&[DVec2::ZERO], &[Some(3)]);
    assert!(matches!(bad, Err(GaussianError::InvalidSkeleton { .. })));
}

#[test]
fn skeleton_moves_attenuate_along_the_graph() {
    let mut skeleton = crest().simplified(10.0);
    // Primitives along the crest.
    let mut t = VectorTerrain::new(
        skeleton
            .nodes
            .iter()
            .map(|&p| relief_gaussian_terrain::Gaussian::round(DVec2::from(p) + DVec2::new(3.0, 0.0), 8.0, 50.0))
            .collect(),
    );
    let attached = skeleton.attach(&t);
    assert!(attached.iter().all(|a| a.is_some_and(|a| a.distance <= 3.0 + 1e-9)));
    let tip = skeleton.nearest_node(DVec2::new(42.0, 142.0)).unwrap();
    let root = skeleton.nearest_node(DVec2::ZERO).unwrap();
    let before_nodes = skeleton.nodes.clone();
    let before = t.clone();
    let v = DVec2::new(20.0, 5.0);
    // Reach: half the way down the trunk.
    let reach = 90.0;
    let moved = skeleton.move_node(&mut t, &attached, tip, v, Some(reach)).unwrap();
    assert!(moved > 0);
    // The tip moves by v, nodes beyond the reach not at all.
    let tip_moved = DVec2::from(skeleton.nodes[tip]) - DVec2::from(before_nodes[tip]);
    assert!((tip_moved - v).length() < 1e-9);
    assert_eq!(skeleton.nodes[root], before_nodes[root]);
    let dist = crest().simplified(10.0).graph_distances(tip);
    for (k, d) in dist.iter().enumerate() {
        if *d >= reach {
            assert_eq!(skeleton.nodes[k], before_nodes[k], "node {k} at {d} moved");
        }
    }
    // Primitives on edges that did not move are bit-identical; the others followed.
    let unmoved = t.primitives.iter().zip(&before.primitives).filter(|(a, b)| a == b).count();
    assert_eq!(unmoved + moved, t.primitives.len());

    // Amplitude: u = 1 doubles the primitives at the node, leaves the far ones.
    let mut t2 = before.clone();
    let skeleton2 = crest().simplified(10.0);
    let attached2 = skeleton2.attach(&t2);
    skeleton2.scale_amplitude(&mut t2, &attached2, tip, 1.0, Some(reach)).unwrap();
    let nearest = (0..t2.primitives.len())
        .min_by(|&a, &b| {
            let d = |k: usize| DVec2::from(before.primitives[k].center).distance(DVec2::from(skeleton2.nodes[tip]));
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    assert!(t2.primitives[nearest].amplitude > 1.8 * before.primitives[nearest].amplitude);
    let far = skeleton2.nearest_node(DVec2::ZERO).unwrap();
    let far_prim = (0..t2.primitives.len())
        .min_by(|&a, &b| {
            let d = |k: usize| DVec2::from(before.primitives[k].center).distance(DVec2::from(skeleton2.nodes[far]));
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    assert_eq!(t2.primitives[far_prim], before.primitives[far_prim]);
    assert!(skeleton2.scale_amplitude(&mut t2, &attached2, tip, -2.0, None).is_err());
    assert!(skeleton2.scale_amplitude(&mut t2, &attached2, 10_000, 1.0, None).is_err());
}

/// The context a tool replay gets in this test: one in-memory atlas, and the crest skeleton.
struct Session {
    atlas: relief_gaussian_terrain::Atlas,
    skeleton: Option<Skeleton>,
    skeletons_extracted: usize,
    /// What `copy` and `cut` kept.
    kept: relief_gaussian_terrain::Atlas,
}

impl relief_gaussian_terrain::ToolContext for Session {
    type Error = String;

    fn landform(
        &mut self,
        atlas: Option<&std::path::Path>,
        name: &str,
        _: &VectorTerrain,
    ) -> Result<relief_gaussian_terrain::Landform, String> {
        match atlas {
            None => self.kept.get(name).cloned().map_err(|e| e.to_string()),
            Some(a) if a == std::path::Path::new("atlas.json") => {
                self.atlas.get(name).cloned().map_err(|e| e.to_string())
            }
            Some(a) => Err(format!("no atlas {}", a.display())),
        }
    }

    fn keep(&mut self, landform: relief_gaussian_terrain::Landform) -> Result<(), String> {
        self.kept.landforms.retain(|l| l.name != landform.name);
        self.kept.landforms.push(landform);
        Ok(())
    }

    fn skeleton(&mut self, _: &VectorTerrain) -> Result<&mut Skeleton, String> {
        if self.skeleton.is_none() {
            self.skeletons_extracted += 1;
        }
        Ok(self.skeleton.get_or_insert_with(|| crest().simplified(10.0)))
    }
}

/// A replayed list of `Tool`s (read from JSON, as scenes store them) does exactly what calling
/// the tool functions in the same order does; the crest skeleton is extracted once and then
/// edited in place; tool and context errors come back apart.
#[test]
fn tools_replayed_from_json_equal_the_tool_functions() {
    use relief_gaussian_terrain::{Atlas, Landform, Tool, ToolError};
    let base = terrain();
    let atlas = Atlas {
        landforms: vec![Landform::new("hill", &base.primitives[..5], DVec2::splat(500.0))],
        ..Atlas::default()
    };
    let tools: Vec<Tool> = serde_json::from_str(
        r#"[
            { "op": "stamp", "region": { "shape": "circle", "center": [300, 300], "radius": 120 },
              "placement": { "to": [700, 600], "rotation": 0.4 }, "mode": "copy", "damping": 50 },
            { "op": "paste", "atlas": "atlas.json", "landform": "hill", "footprint": 200,
              "placement": { "to": [200, 800] }, "damping": 30 },
            { "op": "delete", "region": { "shape": "circle", "center": [800, 200], "radius": 80 } },
            { "op": "twist", "region": { "shape": "circle", "center": [500, 500], "radius": 150 }, "angle": 0.6, "falloff": 40 },
            { "op": "squeeze", "region": { "shape": "circle", "center": [400, 700], "radius": 100 }, "by": [30, -10], "falloff": 30 },
            { "op": "move_crest", "near": [42, 142], "by": [20, 5], "reach": 90 },
            { "op": "raise_crest", "near": [0, 50], "factor": 0.5 }
        ]"#,
    )
    .unwrap();
    let mut session = Session { atlas: atlas.clone(), skeleton: None, skeletons_extracted: 0, kept: Atlas::default() };
    let mut replayed = base.clone();
    for tool in &tools {
        assert!(tool.apply(&mut replayed, &mut session).is_ok(), "{tool:?}");
    }
    assert_eq!(session.skeletons_extracted, 1, "the skeleton is extracted once");

    let mut direct = base.clone();
    let placement = |to: [f64; 2], rotation| Placement { to, rotation, scale: 1.0 };
    stamp(&mut direct, &circle(300.0, 300.0, 120.0), &placement([700.0, 600.0], 0.4), StampMode::Copy, 50.0).unwrap();
    let hill = atlas.get("hill").unwrap();
    paste(&mut direct, hill, &circle(0.0, 0.0, 200.0), &placement([200.0, 800.0], 0.0), 30.0).unwrap();
    delete(&mut direct, &circle(800.0, 200.0, 80.0)).unwrap();
    twist(&mut direct, &circle(500.0, 500.0, 150.0), 0.6, 40.0).unwrap();
    squeeze(&mut direct, &circle(400.0, 700.0, 100.0), DVec2::new(30.0, -10.0), 30.0).unwrap();
    let mut skeleton = crest().simplified(10.0);
    let attached = skeleton.attach(&direct);
    let tip = skeleton.nearest_node(DVec2::new(42.0, 142.0)).unwrap();
    skeleton.move_node(&mut direct, &attached, tip, DVec2::new(20.0, 5.0), Some(90.0)).unwrap();
    let attached = skeleton.attach(&direct);
    let node = skeleton.nearest_node(DVec2::new(0.0, 50.0)).unwrap();
    skeleton.scale_amplitude(&mut direct, &attached, node, 0.5, None).unwrap();
    assert_eq!(replayed, direct);
    assert_eq!(session.skeleton.as_ref(), Some(&skeleton), "crest edits move the kept skeleton");

    // A tool's own error and the context's come back apart.
    let bad: Tool = serde_json::from_str(
        r#"{ "op": "twist", "region": { "shape": "circle", "center": [0, 0], "radius": -1 }, "angle": 1, "falloff": 1 }"#,
    )
    .unwrap();
    assert!(matches!(
        bad.apply(&mut replayed, &mut session),
        Err(ToolError::Tool(GaussianError::InvalidRegion { .. }))
    ));
    let elsewhere: Tool = serde_json::from_str(
        r#"{ "op": "paste", "atlas": "other.json", "landform": "hill", "footprint": 10, "placement": { "to": [0, 0] }, "damping": 1 }"#,
    )
    .unwrap();
    assert!(
        matches!(elsewhere.apply(&mut replayed, &mut session), Err(ToolError::Context(e)) if e.contains("other.json"))
    );
    assert_eq!(replayed, direct, "refused tools change nothing");
}

/// Twist turns each primitive in Ω about the anchor by exactly
/// `φ = angle·|c − anchor|/R·s(d(∂Ω, c)/r)`, centre and orientation alike, and nothing else;
/// deep inside, the turn is most of `angle` (a twist that did nothing, or turned everything
/// rigidly, fails).
#[test]
fn twist_turns_by_the_paper_angle() {
    let before = terrain();
    let mut after = before.clone();
    let region = circle(500.0, 480.0, 220.0);
    let (angle, falloff) = (0.9, 80.0);
    let moved = twist(&mut after, &region, angle, falloff).unwrap();
    let anchor = region.anchor();
    let mut turned = Vec::new();
    for (g, h) in before.primitives.iter().zip(&after.primitives) {
        let c = DVec2::from(g.center);
        let f = region.inner_falloff(c, falloff);
        if f <= 0.0 {
            assert_eq!(g, h);
            continue;
        }
        let phi = angle * c.distance(anchor) / 220.0 * f;
        let want = anchor + DVec2::from_angle(phi).rotate(c - anchor);
        assert!((DVec2::from(h.center) - want).length() < 1e-9, "{:?} vs {want}", h.center);
        assert!((h.theta - (g.theta + phi)).abs() < 1e-12);
        assert_eq!((h.sigma, h.amplitude, h.beta), (g.sigma, g.amplitude, g.beta));
        turned.push(phi);
    }
    assert_eq!(moved, turned.len());
    assert!(turned.len() >= 20, "{} primitives turned", turned.len());
    assert!(
        turned.iter().any(|&phi| phi > 0.5 * angle),
        "largest turn {:?}",
        turned.iter().copied().fold(0.0, f64::max)
    );
}

/// Squeeze moves each primitive in Ω by exactly `f(c)·v` and stretches it along `v` by
/// `f(c) − f(c') + 1` about its new centre: the new primitive at `m·p + t` equals the old at `p`.
#[test]
fn squeeze_moves_and_stretches_by_the_paper_factor() {
    let before = terrain();
    let mut after = before.clone();
    let region = circle(480.0, 520.0, 230.0);
    let (v, falloff) = (DVec2::new(70.0, -25.0), 120.0);
    let moved = squeeze(&mut after, &region, v, falloff).unwrap();
    let dir = v.normalize();
    let (mut count, mut full, mut stretched) = (0, 0, 0);
    for (g, h) in before.primitives.iter().zip(&after.primitives) {
        let c = DVec2::from(g.center);
        let f = region.inner_falloff(c, falloff);
        if f <= 0.0 {
            assert_eq!(g, h);
            continue;
        }
        count += 1;
        let to = c + v * f;
        assert!((DVec2::from(h.center) - to).length() < 1e-9);
        let k = (f - region.inner_falloff(to, falloff) + 1.0).max(0.05);
        let m = glam::DMat2::IDENTITY + glam::DMat2::from_cols(dir * dir.x, dir * dir.y) * (k - 1.0);
        for (a, b) in [(0.0, 0.0), (0.7, 0.2), (-0.4, 1.1), (1.3, -0.9)] {
            let p = c + DVec2::new(a * g.sigma[0], b * g.sigma[1]);
            let (want, got) = (g.value(p), h.value(m * (p - c) + to));
            assert!((want - got).abs() < 1e-9 * g.amplitude.abs().max(1.0), "{want} vs {got}");
        }
        full += usize::from(f == 1.0);
        stretched += usize::from((k - 1.0).abs() > 0.05);
    }
    assert_eq!(moved, count);
    assert!(full > 0 && stretched > 0, "{full} moved by the whole v, {stretched} stretched");
}

/// A stamp places each selected primitive exactly where the similarity sends it (centre, σ
/// scaled, θ turned, amplitude and β kept) and multiplies every other one by the destination's
/// outer fall-off, dropping those it zeroes.
#[test]
fn stamps_place_and_damp_exactly() {
    let before = terrain();
    let region = circle(300.0, 320.0, 140.0);
    let placement = Placement { to: [680.0, 640.0], rotation: 0.7, scale: 1.3 };
    let damping = 90.0;
    for mode in [StampMode::Copy, StampMode::Move] {
        let mut after = before.clone();
        let placed = stamp(&mut after, &region, &placement, mode, damping).unwrap();
        let selected = region.select(&before);
        assert_eq!(placed.len(), selected.len());
        assert!(selected.len() >= 5);
        let anchor = region.anchor();
        for (&k, &n) in selected.iter().zip(&placed) {
            let (g, h) = (before.primitives[k], after.primitives[n]);
            let want =
                DVec2::from(placement.to) + DVec2::from_angle(0.7).rotate((DVec2::from(g.center) - anchor) * 1.3);
            assert!((DVec2::from(h.center) - want).length() < 1e-9);
            assert!((h.sigma[0] - 1.3 * g.sigma[0]).abs() < 1e-12 && (h.sigma[1] - 1.3 * g.sigma[1]).abs() < 1e-12);
            assert!((h.theta - (g.theta + 0.7)).abs() < 1e-12);
            assert_eq!((h.amplitude, h.beta), (g.amplitude, g.beta));
        }
        let destination = circle(680.0, 640.0, 140.0 * 1.3);
        let expected: Vec<_> = before
            .primitives
            .iter()
            .enumerate()
            .filter(|(k, _)| mode == StampMode::Copy || !selected.contains(k))
            .map(|(_, g)| {
                let f = destination.outer_falloff(DVec2::from(g.center), damping);
                let mut g = *g;
                if f < 1.0 {
                    g.amplitude *= f;
                }
                g
            })
            .filter(|g| g.amplitude != 0.0)
            .collect();
        let damped = expected.iter().zip(&before.primitives).filter(|(a, b)| a.amplitude != b.amplitude).count();
        assert_eq!(&after.primitives[..after.primitives.len() - placed.len()], &expected[..]);
        assert!(damped > 0 || mode == StampMode::Move, "nothing was damped");
    }
}

/// A crest move sends every node by exactly `α·v`, `α = s(1 − l/d_m)`, and each attached
/// primitive within the reach with its edge: the centre keeps its offset from its projection,
/// turned by the edge's rotation and stretched by its change of length.
#[test]
fn crest_moves_follow_the_attenuation_exactly() {
    let mut skeleton = crest().simplified(10.0);
    let mut t = VectorTerrain::new(
        skeleton
            .nodes
            .iter()
            .flat_map(|&p| {
                let p = DVec2::from(p);
                [
                    relief_gaussian_terrain::Gaussian::round(p + DVec2::new(3.0, 1.0), 8.0, 50.0),
                    relief_gaussian_terrain::Gaussian {
                        center: (p + DVec2::new(-2.0, 4.0)).to_array(),
                        sigma: [9.0, 4.0],
                        theta: 0.4,
                        amplitude: 30.0,
                        beta: 2.5,
                    },
                ]
            })
            .collect(),
    );
    let before_nodes = skeleton.clone();
    let before = t.clone();
    let attached = skeleton.attach(&t);
    let tip = skeleton.nearest_node(DVec2::new(42.0, 142.0)).unwrap();
    let (v, reach) = (DVec2::new(20.0, 5.0), 90.0);
    skeleton.move_node(&mut t, &attached, tip, v, Some(reach)).unwrap();
    let dist = before_nodes.graph_distances(tip);
    for (k, d) in dist.iter().enumerate() {
        let alpha = if d.is_finite() { relief_gaussian_terrain::smoothstep(1.0 - d / reach) } else { 0.0 };
        let want = DVec2::from(before_nodes.nodes[k]) + v * alpha;
        assert!((DVec2::from(skeleton.nodes[k]) - want).length() < 1e-12, "node {k}");
    }
    let node = |s: &Skeleton, k: usize| DVec2::from(s.nodes[k]);
    let mut far_moves = 0;
    for ((g, h), a) in before.primitives.iter().zip(&t.primitives).zip(&attached) {
        let a = a.unwrap();
        let [p, q] = before_nodes.edges[a.edge];
        let (p0, q0, p1, q1) = (node(&before_nodes, p), node(&before_nodes, q), node(&skeleton, p), node(&skeleton, q));
        let (e0, e1) = (q0 - p0, q1 - p1);
        // A primitive whose projection lies beyond the reach stays, even on a moving edge.
        let l = (dist[p] + a.t * e0.length()).min(dist[q] + (1.0 - a.t) * e0.length());
        if l >= reach {
            assert_eq!(g, h);
            continue;
        }
        let (pi0, pi1) = (p0 + e0 * a.t, p1 + e1 * a.t);
        let offset = DVec2::from(g.center) - pi0;
        // The offset turned with the edge and stretched along it by the length ratio.
        let along = e0.normalize();
        let stretched = offset + along * offset.dot(along) * (e1.length() / e0.length() - 1.0);
        let want = pi1 + DVec2::from_angle(e0.angle_to(e1)).rotate(stretched);
        assert!((DVec2::from(h.center) - want).length() < 1e-9, "{:?} vs {want}", h.center);
        far_moves += usize::from(DVec2::from(h.center).distance(DVec2::from(g.center)) > 0.5 * v.length());
    }
    assert!(far_moves >= 2, "{far_moves} primitives moved by more than half the move");
}

/// `copy` and `cut` keep landforms in the session's atlas; a `paste` without `atlas` takes them
/// from there, as the tool functions do by hand.
#[test]
fn copy_and_cut_fill_the_session_atlas() {
    use relief_gaussian_terrain::{Atlas, Tool};
    let base = terrain();
    let tools: Vec<Tool> = serde_json::from_str(
        r#"[
            { "op": "copy", "region": { "shape": "circle", "center": [300, 300], "radius": 120 }, "name": "a" },
            { "op": "cut", "region": { "shape": "circle", "center": [700, 300], "radius": 100 }, "name": "b" },
            { "op": "paste", "landform": "b", "footprint": 100, "placement": { "to": [300, 750], "rotation": 0.5 }, "damping": 40 },
            { "op": "paste", "landform": "a", "footprint": 120, "placement": { "to": [750, 750] }, "damping": 40 }
        ]"#,
    )
    .unwrap();
    let mut session =
        Session { atlas: Atlas::default(), skeleton: None, skeletons_extracted: 0, kept: Atlas::default() };
    let mut replayed = base.clone();
    for tool in &tools {
        tool.apply(&mut replayed, &mut session).unwrap();
    }
    let mut direct = base.clone();
    let a = copy(&direct, &circle(300.0, 300.0, 120.0), "a").unwrap();
    let b = cut(&mut direct, &circle(700.0, 300.0, 100.0), "b").unwrap();
    let to = |to: [f64; 2], rotation| Placement { to, rotation, scale: 1.0 };
    paste(&mut direct, &b, &circle(0.0, 0.0, 100.0), &to([300.0, 750.0], 0.5), 40.0).unwrap();
    paste(&mut direct, &a, &circle(0.0, 0.0, 120.0), &to([750.0, 750.0], 0.0), 40.0).unwrap();
    assert_eq!(replayed, direct);
    assert_eq!(session.kept.landforms, vec![a.clone(), b]);
    assert!(!a.primitives.is_empty());
    let missing: Tool = serde_json::from_str(
        r#"{ "op": "paste", "landform": "c", "footprint": 10, "placement": { "to": [0, 0] }, "damping": 1 }"#,
    )
    .unwrap();
    assert!(
        matches!(missing.apply(&mut replayed, &mut session), Err(relief_gaussian_terrain::ToolError::Context(e)) if e.contains("\"c\""))
    );
}

/// The influence region of combined edits: the convex hull of the moved primitives damps the
/// others by exactly its outer fall-off (those inside vanish and go), the moved ones keep their
/// bits, and a crest move with `damping` applies it.
#[test]
fn combined_edits_damp_around_the_convex_hull() {
    use relief_gaussian_terrain::{Tool, damp_around};
    let square = [DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(10.0, 10.0), DVec2::new(0.0, 10.0), DVec2::splat(5.0)];
    let Some(Region::Lasso { points }) = Region::convex_hull(&square) else { panic!("a hull") };
    assert_eq!(points.len(), 4);
    assert!(Region::convex_hull(&[DVec2::ZERO, DVec2::ONE, DVec2::splat(2.0)]).is_none());

    let before = terrain();
    let moved: Vec<usize> = circle(500.0, 500.0, 160.0).select(&before);
    let hull =
        Region::convex_hull(&moved.iter().map(|&k| DVec2::from(before.primitives[k].center)).collect::<Vec<_>>())
            .unwrap();
    let mut after = before.clone();
    let damped = damp_around(&mut after, &moved, 60.0).unwrap();
    let mut expected = Vec::new();
    for (k, g) in before.primitives.iter().enumerate() {
        let mut g = *g;
        if !moved.contains(&k) {
            let f = hull.outer_falloff(DVec2::from(g.center), 60.0);
            if f < 1.0 {
                g.amplitude *= f;
            }
        }
        if g.amplitude != 0.0 {
            expected.push(g);
        }
    }
    assert_eq!(after.primitives, expected);
    assert!(damped >= 3, "{damped} damped");

    let tool = |damping: Option<f64>| {
        let json = serde_json::json!({ "op": "move_crest", "near": [42, 142], "by": [20, 5], "reach": 90, "damping": damping });
        serde_json::from_value::<Tool>(json).unwrap()
    };
    let session = || Session {
        atlas: relief_gaussian_terrain::Atlas::default(),
        skeleton: None,
        skeletons_extracted: 0,
        kept: relief_gaussian_terrain::Atlas::default(),
    };
    // Primitives along the crest: those beyond the move's reach stay, and the ones next to the
    // moved part are damped.
    let mut crest_terrain = VectorTerrain::new(
        crest()
            .simplified(10.0)
            .nodes
            .iter()
            .map(|&p| relief_gaussian_terrain::Gaussian::round(DVec2::from(p), 8.0, 50.0))
            .collect(),
    );
    let mut plain = crest_terrain.clone();
    tool(None).apply(&mut plain, &mut session()).unwrap();
    tool(Some(40.0)).apply(&mut crest_terrain, &mut session()).unwrap();
    let amplitude = |t: &VectorTerrain| t.primitives.iter().map(|g| g.amplitude.abs()).sum::<f64>();
    assert!(amplitude(&crest_terrain) < amplitude(&plain), "damping removed nothing");
}
