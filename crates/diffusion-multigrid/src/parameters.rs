//! The noise amplitude and roughness maps of §4.3: the values painted along the curves, diffused
//! by Laplace over the rest of the grid.
//!
//! Both maps only scale the detail, and a Laplace solution away from its data is smooth, so on a
//! large grid they are diffused on a grid of half the resolution and interpolated back, with the
//! painted samples keeping their painted values exactly. That is a quarter of the samples to set
//! up and solve, twice over: in a whole `relief diffuse` of `mountain-ridges` at 2048² the two
//! solves took 250–290 ms at full resolution and take 85 ms. The price is accuracy next to sharp
//! changes of the painted values: the coarse grid places a painted edge up to a sample off, so
//! beside a calm crack crossing a rough ridge one sample's amplitude is off by a third of the
//! painted range, while the mean error stays under 0.6 % of it (the test below). On the fixture
//! scenes at 2048² the final terrains move by under 1 m at the 99.9th percentile, by 19 m at most
//! (one sample of `mountain`, whose relief is 2.2 km). Below
//! [`HALF_RESOLUTION_FROM`] samples a side the saving is a few milliseconds, and the maps are
//! solved at full resolution as the paper does.

use std::ops::ControlFlow;

use rayon::prelude::*;

use crate::DiffusionError;
use crate::maps::ConstraintMaps;
use crate::solver::{DiffusionProblem, SolveOptions};

/// The shortest side, in samples, from which the maps are diffused at half resolution.
pub(crate) const HALF_RESOLUTION_FROM: usize = 256;

/// The relative residual the maps are solved to, or the elevation's tolerance where that is
/// looser. The maps only scale the detail, and a tighter solve of them moves a terrain by less than
/// its elevation solve's own error: at 2048², against the elevation's default tolerance (10⁻⁴)
/// applied to the maps too, the final terrains of `volcanic-island-48`, `mountain`, `lake` and
/// `desert` moved by 3.3, 3.9, 2.5 and 0.15 cm on average and 0.42, 1.26, 0.68 and 0.19 m at
/// most (reliefs of 1.5, 2.2, 1.0 and 0.4 km), while the two solves took one cycle after their
/// starts instead of six (the volcanic island's 184–216 ms → 82–99 ms, a twelfth of its
/// generation). The hole fills are solved to the same tolerance.
pub(crate) const NOISE_TOLERANCE: f64 = 1e-3;

/// The diffused amplitude and roughness of `maps` (row-major, on `maps.grid`), or `None` when no
/// sample carries an amplitude (then there is no detail to drive), solved to `solve`'s tolerance
/// or [`NOISE_TOLERANCE`], whichever is looser. The roughness is 0.5 where no sample carries one.
/// `observe` gets the field (0: amplitude, 1: roughness) and the solve's iteration, as
/// [`DiffusionProblem::solve_observed`] counts them.
pub(crate) fn noise_parameters(
    maps: &ConstraintMaps,
    solve: &SolveOptions,
    observe: &mut dyn FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<Option<[Vec<f32>; 2]>, DiffusionError> {
    let solve = &SolveOptions { tolerance: solve.tolerance.max(NOISE_TOLERANCE), ..*solve };
    let (nx, ny) = (maps.grid.nx(), maps.grid.ny());
    let half = nx.min(ny) >= HALF_RESOLUTION_FROM;
    let (sx, sy) = if half { (nx.div_ceil(2), ny.div_ceil(2)) } else { (nx, ny) };
    let coarse = |values: &[f32]| if half { halve(nx, ny, values) } else { values.to_vec() };
    let amplitude_values = coarse(&maps.amplitude);
    let Some(amplitude_problem) = DiffusionProblem::laplace(sx, sy, &amplitude_values) else {
        return Ok(None);
    };
    // Amplitude and roughness are painted together, so they share their free samples and one
    // hierarchy (the paper diffuses them in one shader for the same reason).
    let roughness_values = coarse(&maps.roughness);
    let roughness_problem = amplitude_problem
        .laplace_like(&roughness_values)
        .or_else(|| DiffusionProblem::laplace(sx, sy, &roughness_values));
    let amplitude = amplitude_problem.solve_observed(solve, &mut |iteration| observe(0, iteration))?.0;
    let roughness = match roughness_problem {
        Some(p) => p.solve_observed(solve, &mut |iteration| observe(1, iteration))?.0,
        None => vec![0.5; sx * sy],
    };
    if !half {
        return Ok(Some([amplitude, roughness]));
    }
    Ok(Some([double(nx, ny, &amplitude, &maps.amplitude), double(nx, ny, &roughness, &maps.roughness)]))
}

/// The painted `values` of an `nx × ny` grid (NaN where free) on the vertex-centred grid of half
/// the resolution, `⌈nx/2⌉ × ⌈ny/2⌉`: coarse sample (I, J) sits on fine sample (2I, 2J) and
/// holds the full-weighting mean (weights 4, 2, 1 by distance) of the painted samples of its
/// 3 × 3 neighbourhood, NaN when none is painted. Every fine sample lies in some neighbourhood,
/// so no painted value is dropped, even an isolated one.
pub(crate) fn halve(nx: usize, ny: usize, values: &[f32]) -> Vec<f32> {
    let (cx, cy) = (nx.div_ceil(2), ny.div_ceil(2));
    let mut out = vec![f32::NAN; cx * cy];
    out.par_chunks_mut(cx).enumerate().for_each(|(jc, row)| {
        let rows = (2 * jc).saturating_sub(1)..(2 * jc + 2).min(ny);
        for (ic, o) in row.iter_mut().enumerate() {
            let (mut sum, mut weight) = (0.0f32, 0.0f32);
            for j in rows.clone() {
                let wj = if j == 2 * jc { 2.0 } else { 1.0 };
                for i in (2 * ic).saturating_sub(1)..(2 * ic + 2).min(nx) {
                    let v = values[j * nx + i];
                    if !v.is_nan() {
                        let w = wj * if i == 2 * ic { 2.0 } else { 1.0 };
                        sum += w * v;
                        weight += w;
                    }
                }
            }
            if weight > 0.0 {
                *o = sum / weight;
            }
        }
    });
    out
}

/// `coarse`, a field on the half-resolution grid of [`halve`], interpolated bilinearly onto the
/// `nx × ny` grid, with the samples `painted` (not NaN) keeping their painted value. A fine
/// sample past the last coarse one (an even side) takes the last one's value.
pub(crate) fn double(nx: usize, ny: usize, coarse: &[f32], painted: &[f32]) -> Vec<f32> {
    let (cx, cy) = (nx.div_ceil(2), ny.div_ceil(2));
    // The two coarse indices a fine index falls between (the same one on an even index).
    let span = |i: usize, n: usize| (i / 2, (i.div_ceil(2)).min(n - 1));
    let mut out = vec![0.0f32; nx * ny];
    out.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        let (j0, j1) = span(j, cy);
        let (south, north) = (&coarse[j0 * cx..(j0 + 1) * cx], &coarse[j1 * cx..(j1 + 1) * cx]);
        for (i, (o, &p)) in row.iter_mut().zip(&painted[j * nx..(j + 1) * nx]).enumerate() {
            *o = if p.is_nan() {
                let (i0, i1) = span(i, cx);
                0.25 * ((south[i0] + south[i1]) + (north[i0] + north[i1]))
            } else {
                p
            };
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halving_keeps_every_painted_value_and_weighs_by_distance() {
        // 5 × 3: one painted sample at (3, 1), odd on both axes, is kept by the coarse samples
        // whose neighbourhoods hold it: (1, 0), (2, 0), (1, 1), (2, 1) of the 3 × 2 coarse grid.
        let mut v = vec![f32::NAN; 15];
        v[5 + 3] = 7.0;
        let c = halve(5, 3, &v);
        assert_eq!(c.len(), 6);
        for (k, &x) in c.iter().enumerate() {
            let held = matches!(k, 1 | 2 | 4 | 5);
            assert_eq!(x.is_nan(), !held, "coarse sample {k}: {x}");
            if held {
                assert_eq!(x, 7.0);
            }
        }
        // A centre weighs 4, an edge neighbour 2, a corner 1.
        let mut v = vec![f32::NAN; 9];
        (v[0], v[1], v[4]) = (1.0, 2.0, 4.0);
        let c = halve(3, 3, &v);
        assert_eq!(c[0], (4.0 * 1.0 + 2.0 * 2.0 + 4.0) / 7.0);
    }

    #[test]
    fn doubling_interpolates_bilinearly_and_keeps_painted_samples() {
        // Coarse 3 × 2 holding a plane a + b·I + c·J: the fine 5 × 4 samples between get the
        // plane at half indices, the last fine row (past the coarse grid) copies the last one.
        let plane = |i: f32, j: f32| 1.0 + 2.0 * i + 8.0 * j;
        let coarse: Vec<f32> = (0..2).flat_map(|j| (0..3).map(move |i| plane(i as f32, j as f32))).collect();
        let mut painted = vec![f32::NAN; 20];
        painted[5 + 1] = -3.0;
        let fine = double(5, 4, &coarse, &painted);
        for j in 0..4 {
            for i in 0..5 {
                let want = if (i, j) == (1, 1) { -3.0 } else { plane(i as f32 / 2.0, (j.min(2) as f32) / 2.0) };
                assert_eq!(fine[j * 5 + i], want, "({i}, {j})");
            }
        }
    }

    /// Three noisy curves of different amplitudes and roughnesses on a `n × n` grid of 1 km.
    fn maps(n: usize) -> ConstraintMaps {
        use crate::presets;
        use glam::DVec2;
        let grid = relief_heightfield::GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(1000.0 / (n - 1) as f64)).unwrap();
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let curves = [
            presets::with_noise(
                presets::ridge(&[p(100.0, 300.0), p(900.0, 420.0)], 200.0, 600.0, 200.0, 30.0, 150.0),
                60.0,
                0.8,
            ),
            presets::with_noise(presets::crack(&[p(480.0, 40.0), p(560.0, 960.0)], 20.0, 60.0), 0.0, 0.2),
            presets::with_noise(presets::hill(&[p(150.0, 800.0), p(850.0, 860.0)], 50.0, 100.0), 25.0, 0.5),
        ];
        ConstraintMaps::rasterize(&curves, &grid).unwrap()
    }

    #[test]
    fn half_resolution_stays_close_to_the_full_solve() {
        let n = 320;
        let m = maps(n);
        let [amplitude, roughness] =
            noise_parameters(&m, &SolveOptions::default(), &mut |_, _| ControlFlow::Continue(())).unwrap().unwrap();
        for (field, got, values, range) in
            [("amplitude", &amplitude, &m.amplitude, 60.0), ("roughness", &roughness, &m.roughness, 0.6)]
        {
            let converged = SolveOptions { tolerance: 1e-7, max_iterations: Some(60), ..SolveOptions::default() };
            let (full, _) = DiffusionProblem::laplace(n, n, values).unwrap().solve(&converged).unwrap();
            let error = |x: &[f32]| {
                let d: Vec<f32> = x.iter().zip(&full).map(|(a, b)| (a - b).abs() / range).collect();
                (d.iter().sum::<f32>() / d.len() as f32, d.iter().copied().fold(0.0, f32::max))
            };
            // Measured: 5.4e-3 (amplitude) and 5.7e-3 (roughness) of the painted range on average
            // (3.9e-3 and 4.1e-3 when the maps were solved to the elevation's 1e-4), against
            // 0.8e-3 and 1.3e-3 for the full-resolution solve at 1e-4; the worst, 0.35, one sample
            // beside the calm crack where it crosses the rough ridge (the coarse grid places that
            // edge a sample off).
            let (mean, worst) = error(got);
            assert!(mean < 7e-3, "{field}: mean error {mean:.2e} of the range");
            assert!(worst < 0.4, "{field}: worst error {worst:.2e} of the range");
            for (k, (g, v)) in got.iter().zip(values.iter()).enumerate() {
                if !v.is_nan() {
                    assert_eq!(g, v, "{field} sample {k}");
                }
            }
        }
    }

    /// The maps are solved to [`NOISE_TOLERANCE`] whatever tighter tolerance the elevation asks
    /// for (the half-resolution solve at that tolerance, bit for bit), and to a looser one when
    /// asked.
    #[test]
    fn the_maps_are_solved_to_their_own_tolerance() {
        let n = HALF_RESOLUTION_FROM;
        let m = maps(n);
        let run = |tolerance: f64| {
            let solve = SolveOptions { tolerance, ..SolveOptions::default() };
            noise_parameters(&m, &solve, &mut |_, _| ControlFlow::Continue(())).unwrap().unwrap()
        };
        let tight = run(1e-6);
        assert!(tight == run(NOISE_TOLERANCE));
        let s = n.div_ceil(2);
        let own = SolveOptions { tolerance: NOISE_TOLERANCE, ..SolveOptions::default() };
        let problem = DiffusionProblem::laplace(s, s, &halve(n, n, &m.amplitude)).unwrap();
        let (coarse, report) = problem.solve(&own).unwrap();
        assert!(report.converged && report.relative_residual > 1e-4, "{report:?}");
        assert!(tight[0] == double(n, n, &coarse, &m.amplitude));
        assert!(run(0.3)[0] != tight[0], "a looser tolerance stops sooner");
    }

    #[test]
    fn only_grids_from_the_threshold_are_halved() {
        let solve = SolveOptions::default();
        for (n, halved) in [(HALF_RESOLUTION_FROM - 1, false), (HALF_RESOLUTION_FROM, true)] {
            let m = maps(n);
            let [amplitude, _] = noise_parameters(&m, &solve, &mut |_, _| ControlFlow::Continue(())).unwrap().unwrap();
            let noise = SolveOptions { tolerance: NOISE_TOLERANCE, ..solve };
            let (full, _) = DiffusionProblem::laplace(n, n, &m.amplitude).unwrap().solve(&noise).unwrap();
            assert_eq!(amplitude != full, halved, "{n}² grid");
        }
    }
}
