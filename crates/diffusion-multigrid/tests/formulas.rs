//! The formulas of §3–4 pinned to their values: the slope step with its |n|³ reach (exact on
//! diagonals), slope extents a and b and their linear fade, θ and φ on their own sides, the
//! plateau radius r, the Catmull-Rom cubic of h along a curve, Bézier pieces painted along the
//! curve, and the multi-fractal detail N = A·Σₖ 2^(−k(1−R))·S(2ᵏ·p). Each fails if its formula is
//! replaced by a simpler one.

use glam::DVec2;
use relief_diffusion_multigrid::{
    CellKind, Constraint, ConstraintMaps, Elevation, FeatureCurve, Noise, Slope, TerrainOptions, generate,
};
use relief_heightfield::GridSpec;
use relief_heightfield::noise::gradient_noise;

/// 101 × 101 samples, 10 m apart, over [0, 1000]².
fn grid() -> GridSpec {
    GridSpec::new(101, 101, DVec2::ZERO, DVec2::splat(10.0)).unwrap()
}

const CELL: f64 = 10.0;

/// The elevation band's least half-width: ¾ of a cell.
const MIN_R: f64 = 0.75 * CELL;

fn curve(points: &[[f64; 2]], h: f64, r: f64, slope: Option<Slope>) -> FeatureCurve {
    let points: Vec<DVec2> = points.iter().copied().map(DVec2::from).collect();
    let elevation = Some(Elevation { h, r });
    FeatureCurve::polyline(&points, vec![Constraint { u: 0.0, elevation, slope, ..Constraint::default() }])
}

fn slope(a: f64, b: f64, theta: f64, phi: f64) -> Slope {
    Slope { a, b, theta, phi }
}

/// The slope step G the maps must hold at distance `d` from an anchored curve: the slope
/// tan(angle) fading linearly from the band's inner edge (`r`) to its outer one (`r + extent`),
/// times the distance one upwind grid step covers along the normal n: |nx|³·dx + |ny|³·dy.
fn expected_step(angle: f64, d: f64, r: f64, extent: f64, n: DVec2) -> f64 {
    let fade = 1.0 - (d - r) / extent;
    -angle.to_radians().tan() * fade * (n.x.abs().powi(3) + n.y.abs().powi(3)) * CELL
}

fn index(i: usize, j: usize) -> usize {
    j * 101 + i
}

#[test]
fn slope_steps_carry_the_cubed_normal_on_diagonals() {
    // A level ridge along the diagonal: its left normal is (−1, 1)/√2, where one upwind step
    // covers (2·2^(−3/2))·10 m ≈ 7.07 m of distance along n, not 10 m.
    let ridge = curve(&[[-50.0, -50.0], [1050.0, 1050.0]], 500.0, 0.0, Some(slope(200.0, 200.0, 30.0, 30.0)));
    let maps = ConstraintMaps::rasterize(&[ridge], &grid()).unwrap();
    let left = DVec2::new(-1.0, 1.0).normalize();
    for (i, j) in [(40, 60), (45, 55), (35, 60)] {
        let k = index(i, j);
        let d = (j as f64 - i as f64) * CELL / 2f64.sqrt();
        assert_eq!(maps.kind[k], CellKind::Gradient, "({i}, {j})");
        let want = expected_step(30.0, d, MIN_R, 200.0, left);
        let got = f64::from(maps.gradient[k]);
        assert!((got - want).abs() < 1e-4 * want.abs(), "({i}, {j}) at {d:.1} m: step {got:.5}, want {want:.5}");
        let n = DVec2::new(f64::from(maps.normal[k][0]), f64::from(maps.normal[k][1]));
        assert!((n - left).length() < 1e-6, "normal {n}");
    }
}

/// The smooth terrain's slope (drop per metre) along `n` from `p + n·d0` to `p + n·d1`.
fn slope_along(t: &relief_heightfield::Heightfield, p: DVec2, n: DVec2, d0: f64, d1: f64) -> f64 {
    let (a, b) = (t.sample_bilinear(p + n * d0).unwrap(), t.sample_bilinear(p + n * d1).unwrap());
    f64::from(a - b) / (d1 - d0)
}

#[test]
fn a_diagonal_ridge_keeps_its_slope_angle() {
    // With the reach taken as one cell whatever the direction, the diagonal flanks came out √2
    // too steep; with |nx|³ + |ny|³ they keep tan 30° (fading as the band goes).
    let ridge = curve(&[[-50.0, -50.0], [1050.0, 1050.0]], 500.0, 0.0, Some(slope(200.0, 200.0, 30.0, 30.0)));
    let low = |c: f64| curve(&[[-50.0, -50.0 + c], [1050.0, 1050.0 + c]], 0.0, 0.0, None);
    let t = generate(&[ridge, low(600.0), low(-600.0)], &grid(), &TerrainOptions::default()).unwrap();
    assert!(t.report.converged);
    let tan = 30f64.to_radians().tan();
    let fade = 1.0 - (40.0 - MIN_R) / 200.0;
    for n in [DVec2::new(-1.0, 1.0).normalize(), DVec2::new(1.0, -1.0).normalize()] {
        let s = slope_along(&t.smooth, DVec2::splat(500.0), n, 20.0, 60.0);
        assert!((s - tan * fade).abs() < 0.12 * tan * fade, "slope {s:.3} along {n}, want {:.3}", tan * fade);
    }
}

#[test]
fn slope_bands_reach_their_extent_and_fade_linearly() {
    // A level ridge along y = 500, 200 m of slope band on its left (north), 100 m on its right.
    let ridge = curve(&[[-50.0, 500.0], [1050.0, 500.0]], 500.0, 0.0, Some(slope(200.0, 100.0, 30.0, 30.0)));
    let maps = ConstraintMaps::rasterize(&[ridge], &grid()).unwrap();
    assert_eq!(maps.kind[index(50, 50)], CellKind::Elevation);
    for (dir, extent) in [(1i64, 200.0), (-1, 100.0)] {
        let n = DVec2::new(0.0, dir as f64);
        for step in 1..=25i64 {
            let (j, d) = ((50 + dir * step) as usize, step as f64 * CELL);
            let k = index(50, j);
            if d > MIN_R + extent {
                assert_eq!(maps.kind[k], CellKind::Free, "{d} m beyond a {extent} m band");
                continue;
            }
            assert_eq!(maps.kind[k], CellKind::Gradient, "{d} m inside a {extent} m band");
            let want = expected_step(30.0, d, MIN_R, extent, n);
            let got = f64::from(maps.gradient[k]);
            assert!((got - want).abs() < 1e-4, "{d} m: step {got:.5}, want {want:.5} (a linear fade)");
        }
    }
}

#[test]
fn left_and_right_slopes_follow_theta_and_phi() {
    // θ = 30° on the left (north, travelling east), φ = 10° on the right.
    let ridge = curve(&[[-50.0, 500.0], [1050.0, 500.0]], 500.0, 0.0, Some(slope(200.0, 200.0, 30.0, 10.0)));
    let edge = |y: f64| curve(&[[-50.0, y], [1050.0, y]], 0.0, 0.0, None);
    let curves = [ridge, edge(0.0), edge(1000.0)];
    let maps = ConstraintMaps::rasterize(&curves, &grid()).unwrap();
    for (j, angle, n) in [(60usize, 30.0, DVec2::Y), (40, 10.0, DVec2::NEG_Y)] {
        let want = expected_step(angle, 100.0, MIN_R, 200.0, n);
        let got = f64::from(maps.gradient[index(50, j)]);
        assert!((got - want).abs() < 1e-4, "row {j}: step {got:.5}, want {want:.5}");
    }
    let t = generate(&curves, &grid(), &TerrainOptions::default()).unwrap();
    let p = DVec2::splat(500.0);
    let (north, south) =
        (slope_along(&t.smooth, p, DVec2::Y, 20.0, 60.0), slope_along(&t.smooth, p, DVec2::NEG_Y, 20.0, 60.0));
    let want = 30f64.to_radians().tan() / 10f64.to_radians().tan();
    assert!((north / south - want).abs() < 0.15 * want, "slopes {north:.3} / {south:.3}, want a ratio of {want:.2}");
}

#[test]
fn free_standing_curves_propagate_inwards() {
    // A crack has no elevation: its slope bands carry the elevation towards the curve (the normal
    // points at it) and the step rises by the slope, where an anchored curve's falls away.
    let crack = FeatureCurve::polyline(
        &[DVec2::new(-50.0, 500.0), DVec2::new(1050.0, 500.0)],
        vec![Constraint { u: 0.0, slope: Some(slope(100.0, 100.0, 20.0, 20.0)), ..Constraint::default() }],
    );
    let maps = ConstraintMaps::rasterize(&[crack], &grid()).unwrap();
    for (j, n) in [(55usize, DVec2::NEG_Y), (45, DVec2::Y)] {
        let k = index(50, j);
        let want = -expected_step(20.0, 50.0, MIN_R, 100.0, n);
        let got = f64::from(maps.gradient[k]);
        assert!((got - want).abs() < 1e-4, "row {j}: step {got:.5}, want {want:.5}");
        assert_eq!(maps.normal[k], [n.x as f32, n.y as f32], "row {j}: the normal points at the curve");
    }
}

#[test]
fn the_plateau_radius_holds_the_elevation() {
    let plateau = curve(&[[-50.0, 500.0], [1050.0, 500.0]], 300.0, 50.0, Some(slope(100.0, 100.0, 20.0, 20.0)));
    let maps = ConstraintMaps::rasterize(&[plateau], &grid()).unwrap();
    for step in -7i64..=7 {
        let k = index(50, (50 + step) as usize);
        if step.abs() <= 5 {
            assert_eq!(maps.kind[k], CellKind::Elevation, "{} m from the curve, within r = 50 m", step * 10);
            assert!((maps.elevation[k] - 300.0).abs() < 1e-3, "{}", maps.elevation[k]);
        } else {
            assert_eq!(maps.kind[k], CellKind::Gradient, "{} m from the curve, beyond r", step * 10);
        }
    }
}

#[test]
fn elevation_along_a_curve_is_a_catmull_rom_cubic() {
    // Keys h = 0, 100, 0 at u = 0, ½, 1: the cubic with Catmull-Rom tangents (one-sided at the
    // ends) gives 23.2 at u = 0.1 and 62.5 at u = ¼, where a linear interpolation gives 20 and 50.
    let keys = [(0.0, 0.0), (0.5, 100.0), (1.0, 0.0)];
    let constraints =
        keys.iter().map(|&(u, h)| Constraint { u, elevation: Some(Elevation { h, r: 0.0 }), ..Constraint::default() });
    let c = FeatureCurve::polyline(&[DVec2::new(0.0, 500.0), DVec2::new(1000.0, 500.0)], constraints.collect());
    let maps = ConstraintMaps::rasterize(&[c], &grid()).unwrap();
    for (i, want) in [(10, 23.2), (25, 62.5), (50, 100.0), (75, 62.5), (90, 23.2)] {
        let got = maps.elevation[index(i, 50)];
        assert!((f64::from(got) - want).abs() < 1e-3, "u = {}: h {got}, want {want}", i as f64 / 100.0);
    }
}

#[test]
fn a_cubic_bezier_is_painted_along_the_curve_not_its_chord() {
    let p = [DVec2::new(100.0, 500.0), DVec2::new(300.0, 900.0), DVec2::new(700.0, 900.0), DVec2::new(900.0, 500.0)];
    let c = FeatureCurve {
        points: p.to_vec(),
        constraints: vec![Constraint {
            u: 0.0,
            elevation: Some(Elevation { h: 100.0, r: 0.0 }),
            ..Constraint::default()
        }],
    };
    let maps = ConstraintMaps::rasterize(&[c], &grid()).unwrap();
    let g = grid();
    for t in [0.1, 0.25, 0.5, 0.75, 0.9] {
        let s = 1.0 - t;
        let b = p[0] * s * s * s + p[1] * 3.0 * s * s * t + p[2] * 3.0 * s * t * t + p[3] * t * t * t;
        let q = g.grid_coords(b).round();
        let k = index(q.x as usize, q.y as usize);
        assert_eq!(maps.kind[k], CellKind::Elevation, "the sample nearest B({t}) = {b}");
    }
    // B(½) = (500, 800); the chord's midpoint (500, 500) is 300 m away from the curve.
    assert_eq!(maps.kind[index(50, 80)], CellKind::Elevation);
    assert_eq!(maps.kind[index(50, 50)], CellKind::Free);
}

#[test]
fn noise_parameters_run_linearly_along_a_curve() {
    let key = |u: f64, amplitude: f64, roughness: f64| Constraint {
        u,
        noise: Some(Noise { amplitude, roughness }),
        ..Constraint::default()
    };
    // A 50 m plateau: the noise band is as wide, the same across it.
    let mut c = curve(&[[0.0, 500.0], [1000.0, 500.0]], 0.0, 50.0, None);
    c.constraints.extend([key(0.0, 0.0, 1.0), key(1.0, 100.0, 0.0)]);
    let maps = ConstraintMaps::rasterize(&[c], &grid()).unwrap();
    for i in [10usize, 25, 60, 90] {
        let u = i as f32 / 100.0;
        for j in [46, 50, 53] {
            let (a, r) = (maps.amplitude[index(i, j)], maps.roughness[index(i, j)]);
            assert!((a - 100.0 * u).abs() < 1e-3 && (r - (1.0 - u)).abs() < 1e-5, "u = {u}, row {j}: A {a}, R {r}");
        }
    }
}

/// The terrain of a flat line at 0 along y = 0 carrying noise (A, R) everywhere, and its detail
/// (terrain minus smooth part).
fn detail(amplitude: f64, roughness: f64) -> (Vec<f32>, TerrainOptions) {
    detail_at(amplitude, roughness, 250.0)
}

/// [`detail`] with the first octave's `wavelength`.
fn detail_at(amplitude: f64, roughness: f64, wavelength: f64) -> (Vec<f32>, TerrainOptions) {
    let noise = Some(Noise { amplitude, roughness });
    let c = FeatureCurve::polyline(
        &[DVec2::new(-50.0, 0.0), DVec2::new(1050.0, 0.0)],
        vec![Constraint { u: 0.0, elevation: Some(Elevation { h: 0.0, r: 0.0 }), noise, ..Constraint::default() }],
    );
    let options = TerrainOptions { noise_wavelength: wavelength, seed: 3, ..TerrainOptions::default() };
    let t = generate(&[c], &grid(), &options).unwrap();
    let d = t.heightfield.samples().iter().zip(t.smooth.samples()).map(|(a, b)| a - b).collect();
    (d, options)
}

#[test]
fn detail_is_the_papers_multifractal_sum() {
    let (a, r) = (40.0, 0.3);
    // 250 m: every octave's gradients come from a precomputed lattice; 5 m (finer than the
    // grid): they are hashed per sample.
    for wavelength in [250.0, 5.0] {
        check_multifractal(a, r, wavelength);
    }
}

fn check_multifractal(a: f64, r: f64, wavelength: f64) {
    let (d, options) = detail_at(a, r, wavelength);
    let g = grid();
    for (i, j) in [(3, 7), (50, 50), (77, 12), (99, 100)] {
        let q = g.position(i, j) / options.noise_wavelength;
        let want: f64 = (0..4u32)
            .map(|k| {
                let f = f64::from(1u32 << k);
                2f64.powf(-f64::from(k) * (1.0 - r)) * gradient_noise(q * f, options.seed + u64::from(k))
            })
            .sum::<f64>()
            * a;
        let got = f64::from(d[index(i, j)]);
        assert!((got - want).abs() < 1e-3 * a, "({i}, {j}): detail {got:.4}, want {want:.4}");
    }
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
}

/// The detail's second differences along x, against the detail itself: how much of it is fine.
fn fine_share(d: &[f32]) -> f64 {
    let second: Vec<f64> = (0..101 * 101)
        .filter(|k| (1..100).contains(&(k % 101)))
        .map(|k| f64::from(d[k - 1] - 2.0 * d[k] + d[k + 1]))
        .collect();
    rms(&second) / rms(&d.iter().map(|&v| f64::from(v)).collect::<Vec<_>>())
}

#[test]
fn amplitude_scales_the_detail_and_roughness_roughens_it() {
    let (base, _) = detail(40.0, 0.3);
    let (double, _) = detail(80.0, 0.3);
    for (a, b) in base.iter().zip(&double) {
        assert!((2.0 * a - b).abs() < 1e-3 * 80.0, "{a} doubled is not {b}");
    }
    let smooth = fine_share(&detail(40.0, 0.1).0);
    let rough = fine_share(&detail(40.0, 0.9).0);
    assert!(rough > 1.5 * smooth, "roughness 0.9 keeps {rough:.4} of fine detail, 0.1 keeps {smooth:.4}");
}

#[test]
fn a_slope_band_ends_at_the_grid_edge() {
    // A ridge 50 m from the west edge: its west slope band (30° over 200 m) runs off the grid.
    let ridge = curve(&[[50.0, -50.0], [50.0, 1050.0]], 500.0, 0.0, Some(slope(200.0, 200.0, 30.0, 30.0)));
    let t = generate(&[ridge], &grid(), &TerrainOptions::default()).unwrap();
    let h = |i: usize| f64::from(t.smooth.get(i, 50).unwrap());
    let (edge, inside) = (h(1) - h(0), h(2) - h(1));
    // The edge samples obey Laplace, mirrored by the reflecting border: level with their inner
    // neighbours (0.02 m) while the band still falls 3.9 m a step just inside. As gradient rows
    // they would read their upwind neighbour from inside the grid and keep falling (3.0 m).
    assert!(inside > 3.0, "the band falls {inside:.2} m a step inside the grid");
    assert!(edge.abs() < 0.1 * inside, "the edge falls {edge:.2} m, {inside:.2} m just inside");
}
