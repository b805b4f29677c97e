//! Measures of the artefacts a generated terrain can show and real ground does not: a trench
//! along the border, closed pits nobody asked for, one-cell slots, and planar facets. Each is a
//! count or a median that a regression moves, so `cargo xtask artefacts` can print them for every
//! gallery scene beside a real DEM's.

use serde::{Deserialize, Serialize};

use crate::{Basin, HydrologyError, Outlets, depressions};
use relief_heightfield::Heightfield;

/// What [`measure`] found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Artefacts {
    /// Median |step| between each land border sample and its neighbour one sample inward, metres
    /// (`None` without land on the border).
    pub border_step_m: Option<f64>,
    /// Median |step| one sample further in (the first and second inward neighbours) over the
    /// same border samples: what the border step should be without a trench.
    pub next_step_m: Option<f64>,
    /// Closed pits (basins that do not drain to the border, the sea or no-data) deeper than 1 m.
    pub pits_over_1m: usize,
    /// Of those, deeper than 20 m.
    pub pits_over_20m: usize,
    /// The deepest closed pit, metres (0 without one).
    pub deepest_pit_m: f64,
    /// Land samples lower than both neighbours along a row or a column, each rising more
    /// steeply than 30° (a slot one sample wide).
    pub slots: usize,
    /// Share of sloping land samples (gradient over 1 %) whose 3 × 3 neighbourhood is a plane to
    /// within 1 cm: the flat facets of a surface interpolated over large triangles.
    pub planar_share: f64,
}

/// Measures `hf`'s artefacts; ground at or below `sea_level` is sea (neither land nor a pit).
///
/// # Errors
/// [`HydrologyError`] when the depressions cannot be found (a grid without valid samples).
pub fn measure(hf: &Heightfield, sea_level: Option<f64>) -> Result<Artefacts, HydrologyError> {
    let outlets = sea_level.map_or_else(Outlets::new, |s| Outlets::new().with_sea_level(s as f32));
    Ok(measure_with_basins(hf, sea_level, &depressions(hf, outlets)?.basins))
}

/// [`measure`] with `hf`'s closed basins already found (by [`depressions`] with the sea at
/// `sea_level` as outlet), for callers that need them anyway: nothing is searched twice.
pub fn measure_with_basins(hf: &Heightfield, sea_level: Option<f64>, basins: &[Basin]) -> Artefacts {
    let depth = |d: f64| basins.iter().filter(|b| f64::from(b.depth()) > d).count();
    let sea = sea_level.map_or(f32::NEG_INFINITY, |s| s as f32);
    let land = |v: f32| v.is_finite() && v > sea;
    let (border_step_m, next_step_m) = border_steps(hf, &land);
    Artefacts {
        border_step_m,
        next_step_m,
        pits_over_1m: depth(1.0),
        pits_over_20m: depth(20.0),
        deepest_pit_m: basins.iter().map(|b| f64::from(b.depth())).fold(0.0, f64::max),
        slots: slots(hf, &land),
        planar_share: planar_share(hf, &land),
    }
}

/// Median of `values` (`None` when empty).
fn median(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mid = values.len() / 2;
    values.select_nth_unstable_by(mid, f64::total_cmp);
    Some(values[mid])
}

/// The medians of the border step and of the next step in, over border samples whose three
/// inward samples are land.
fn border_steps(hf: &Heightfield, land: &impl Fn(f32) -> bool) -> (Option<f64>, Option<f64>) {
    let (nx, ny) = (hf.nx(), hf.ny());
    if nx < 3 || ny < 3 {
        return (None, None);
    }
    let z = |i: usize, j: usize| hf.value(i, j);
    // Each border sample with its two inward neighbours: (edge, first in, second in).
    let mut lines: Vec<[f32; 3]> = Vec::with_capacity(2 * (nx + ny));
    for i in 1..nx - 1 {
        lines.push([z(i, 0), z(i, 1), z(i, 2)]);
        lines.push([z(i, ny - 1), z(i, ny - 2), z(i, ny - 3)]);
    }
    for j in 1..ny - 1 {
        lines.push([z(0, j), z(1, j), z(2, j)]);
        lines.push([z(nx - 1, j), z(nx - 2, j), z(nx - 3, j)]);
    }
    lines.retain(|l| l.iter().all(|&v| land(v)));
    let border = lines.iter().map(|[a, b, _]| f64::from((a - b).abs())).collect();
    let next = lines.iter().map(|[_, b, c]| f64::from((b - c).abs())).collect();
    (median(border), median(next))
}

/// Ground distance between neighbouring samples along x and along y in row `j`, metres.
fn spacing(hf: &Heightfield, j: usize) -> (f64, f64) {
    let grid = hf.grid();
    let metres = grid.metres_per_unit(j);
    (grid.cell_size().x.abs() * metres.x, grid.cell_size().y.abs() * metres.y)
}

/// Land samples lower than both row or both column neighbours by more than tan 30° × spacing.
fn slots(hf: &Heightfield, land: &impl Fn(f32) -> bool) -> usize {
    let (nx, ny) = (hf.nx(), hf.ny());
    let tan30 = 30f64.to_radians().tan();
    let mut count = 0;
    for j in 1..ny.saturating_sub(1) {
        let (dx, dy) = spacing(hf, j);
        for i in 1..nx - 1 {
            let v = hf.value(i, j);
            if !land(v) {
                continue;
            }
            let rise = |a: f32, b: f32| f64::from(a.min(b) - v);
            let across_x = rise(hf.value(i - 1, j), hf.value(i + 1, j)) > tan30 * dx;
            let across_y = rise(hf.value(i, j - 1), hf.value(i, j + 1)) > tan30 * dy;
            count += usize::from(across_x || across_y);
        }
    }
    count
}

/// The share of sloping interior land samples whose 3 × 3 neighbourhood is planar: every second
/// difference (along x, y and both diagonals) within 1 cm.
fn planar_share(hf: &Heightfield, land: &impl Fn(f32) -> bool) -> f64 {
    let (nx, ny) = (hf.nx(), hf.ny());
    let (mut sloping, mut planar) = (0usize, 0usize);
    for j in 1..ny.saturating_sub(1) {
        let (dx, dy) = spacing(hf, j);
        for i in 1..nx - 1 {
            let z = |di: isize, dj: isize| f64::from(hf.value(i.wrapping_add_signed(di), j.wrapping_add_signed(dj)));
            if !(-1..=1).all(|dj| (-1..=1).all(|di| land(z(di, dj) as f32))) {
                continue;
            }
            let gradient = ((z(1, 0) - z(-1, 0)) / (2.0 * dx)).hypot((z(0, 1) - z(0, -1)) / (2.0 * dy));
            if gradient <= 0.01 {
                continue;
            }
            sloping += 1;
            let second = [((1, 0), (-1, 0)), ((0, 1), (0, -1)), ((1, 1), (-1, -1)), ((1, -1), (-1, 1))];
            let flat = second.iter().all(|&((a, b), (c, d))| (z(a, b) + z(c, d) - 2.0 * z(0, 0)).abs() <= 0.01);
            planar += usize::from(flat);
        }
    }
    if sloping == 0 { 0.0 } else { planar as f64 / sloping as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_heightfield::{GridSpec, Units};

    /// A grid of `nx × ny` samples 10 m apart from `f(i, j)`.
    fn grid_of(nx: usize, ny: usize, f: impl Fn(usize, usize) -> f32) -> Heightfield {
        let spec = GridSpec::new(nx, ny, glam::DVec2::ZERO, glam::DVec2::splat(10.0)).unwrap();
        Heightfield::from_samples(spec, (0..nx * ny).map(|k| f(k % nx, k / nx)).collect()).unwrap()
    }

    fn grid(n: usize, f: impl Fn(usize, usize) -> f32) -> Heightfield {
        grid_of(n, n, f)
    }

    #[test]
    fn a_trench_along_the_border_shows_against_the_next_step_in() {
        // A ramp rising 2 m a sample eastward, 100 m up; the border samples 50 m lower.
        let ramp = |i: usize, j: usize| 100.0 + 2.0 * i as f32 + 0.5 * j as f32;
        let smooth = measure(&grid(32, ramp), None).unwrap();
        let trench = grid(32, |i, j| ramp(i, j) - if i == 0 || j == 0 || i == 31 || j == 31 { 50.0 } else { 0.0 });
        let trenched = measure(&trench, None).unwrap();
        assert_eq!(smooth.border_step_m, smooth.next_step_m);
        assert!((trenched.border_step_m.unwrap() - 50.0).abs() < 2.5, "{trenched:?}");
        assert!(trenched.next_step_m.unwrap() <= 2.0, "{trenched:?}");
        // Sea on the border is not land, nor is ground exactly at sea level.
        assert_eq!(measure(&trench, Some(170.0)).unwrap().border_step_m, None);
        assert_eq!(measure(&grid(8, |_, _| 100.0), Some(100.0)).unwrap().border_step_m, None);
    }

    #[test]
    fn each_side_of_the_border_is_measured_against_its_own_next_step() {
        // Land along one side only (a strip four samples deep and 12 long, away from the
        // corners; the rest sea at 0): its border samples sit 22.7 to 54.7 m below the ground
        // inward (41.3 m at the median), which rises 1 m a sample inward and then 3 m.
        let n = 16;
        for side in 0..4 {
            let inward = |i: usize, j: usize| [i, j, n - 1 - i, n - 1 - j][side];
            let along = |i: usize, j: usize| [j, i, j, i][side];
            let hf = grid(n, |i, j| {
                let (d, a) = (inward(i, j), along(i, j));
                match d {
                    _ if !(2..n - 2).contains(&a) => 0.0,
                    0 => 500.0 - 20.0 - 40.0 * a as f32 / (n - 1) as f32,
                    1 => 500.0,
                    2 => 501.0,
                    3 => 504.0,
                    _ => 0.0,
                }
            });
            let a = measure(&hf, Some(0.0)).unwrap();
            assert!((a.border_step_m.unwrap() - (20.0 + 40.0 * 8.0 / 15.0)).abs() < 1e-3, "side {side}: {a:?}");
            assert_eq!(a.next_step_m, Some(1.0), "side {side}: {a:?}");
        }
        // Grids too small to have a first and second sample inward have no border step.
        assert_eq!(measure(&grid(3, |i, _| i as f32), None).unwrap().border_step_m, Some(1.0));
        for (nx, ny) in [(2, 5), (5, 2)] {
            assert_eq!(measure(&grid_of(nx, ny, |i, j| (i + j) as f32), None).unwrap().border_step_m, None);
        }
    }

    #[test]
    fn pits_slots_and_facets_are_counted() {
        // A plane tilted 2 % with a pit 30 m deep at (10, 10) (one sample), a one-sample slot
        // 25 m deep along column 20, a 5 m dip at (5, 25), a slot 8 m deep along row 28, and a
        // ledge along column 26 (3 m below its west neighbour, 30 m below its east one).
        let f = |i: usize, j: usize| {
            let mut z = 100.0 + 0.2 * i as f32 + 0.1 * j as f32;
            if (i, j) == (10, 10) {
                z -= 30.0;
            }
            if i == 20 && (5..15).contains(&j) {
                z -= 25.0;
            }
            if (i, j) == (5, 25) {
                z -= 5.0;
            }
            if j == 28 && (3..9).contains(&i) {
                z -= 8.0;
            }
            if i > 26 && (16..24).contains(&j) {
                z += 27.0;
            }
            if i == 26 && (16..24).contains(&j) {
                z -= 3.0;
            }
            // A ledge facing the other way: 30 m below its west neighbour, 3 m below its east one.
            if i < 3 && (16..24).contains(&j) {
                z += 27.0;
            }
            if i == 3 && (16..24).contains(&j) {
                z -= 3.0;
            }
            z
        };
        let a = measure(&grid(32, f), None).unwrap();
        assert!((a.deepest_pit_m - 30.0).abs() < 0.5, "{a:?}");
        // The pit, the 25 m slot and the 8 m slot are steeper than 30° on both sides (tan 30° ×
        // 10 m = 5.8 m); the 5 m dip and the ledges are not.
        assert_eq!(a.slots, 1 + 10 + 6, "{a:?}");
        // Away from them, the tilted plane is planar everywhere.
        assert!(a.planar_share > 0.8 && a.planar_share < 1.0, "{a:?}");
        let bump = |i: usize, j: usize| 0.5 * (1.7 * i as f32).sin() * (2.3 * j as f32).cos();
        let bumpy = measure(&grid(32, |i, j| f(i, j) + bump(i, j)), None).unwrap();
        assert!(bumpy.planar_share < 0.05, "{bumpy:?}");
    }

    #[test]
    fn pits_count_beyond_exactly_1_and_20_m() {
        // Flat ground at 100 m with single-sample pits exactly 1, 20 and 21 m deep and one 0.5 m.
        let hf = grid(16, |i, j| match (i, j) {
            (3, 3) => 99.0,
            (8, 3) => 80.0,
            (3, 8) => 79.0,
            (8, 8) => 99.5,
            _ => 100.0,
        });
        let a = measure(&hf, None).unwrap();
        assert_eq!((a.pits_over_1m, a.pits_over_20m, a.deepest_pit_m), (2, 1, 21.0), "{a:?}");
    }

    #[test]
    fn gentle_and_steep_ground_are_told_apart_along_either_axis() {
        // A plane sloping 0.8 % (under the 1 % a facet needs) counts no sloping sample along x
        // or y; at 2 % every interior sample is sloping and planar.
        for (sx, sy) in [(0.08, 0.0), (0.0, 0.08)] {
            let gentle = grid(12, |i, j| 100.0 + sx * i as f32 + sy * j as f32);
            assert_eq!(measure(&gentle, None).unwrap().planar_share, 0.0, "{sx} {sy}");
            let steep = grid(12, |i, j| 100.0 + 2.5 * sx * i as f32 + 2.5 * sy * j as f32);
            assert_eq!(measure(&steep, None).unwrap().planar_share, 1.0, "{sx} {sy}");
        }
        // A sample with the sea in its 3 × 3 neighbourhood is not counted: a plane with one sea
        // sample stays wholly planar.
        let holed = grid(12, |i, j| if (i, j) == (5, 5) { -5.0 } else { 100.0 + 0.2 * i as f32 });
        assert_eq!(measure(&holed, Some(0.0)).unwrap().planar_share, 1.0);
    }

    #[test]
    fn slots_are_measured_in_metres_on_geographic_grids() {
        // 0.0001° samples at the equator: about 11.1 m apart, so a slot needs more than 6.4 m
        // on both sides. Column 8 and row 1 are 7 m deep, column 4 and row 14 only 6 m.
        let spec = GridSpec::new(16, 16, glam::DVec2::ZERO, glam::DVec2::splat(0.0001)).unwrap();
        let spec = spec.with_units(Units::Degrees).unwrap();
        let samples = (0..256)
            .map(|k| {
                let (i, j) = (k % 16, k / 16);
                let depth = if (4..12).contains(&j) {
                    [(8, 7.0), (4, 6.0)].iter().find(|s| s.0 == i).map_or(0.0, |s| s.1)
                } else {
                    0.0
                };
                let row = match j {
                    14 if (2..6).contains(&i) => 6.0,
                    1 if (9..13).contains(&i) => 7.0,
                    _ => 0.0,
                };
                100.0 - depth - row
            })
            .collect();
        let a = measure(&Heightfield::from_samples(spec, samples).unwrap(), None).unwrap();
        assert_eq!(a.slots, 8 + 4, "{a:?}");
    }
}
