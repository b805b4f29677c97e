//! Exact Euclidean distance transform of a sample mask (Felzenszwalb & Huttenlocher 2012): two
//! separable passes of a 1-D lower-envelope-of-parabolas transform, O(samples).

use crate::GridSpec;

/// Squared 1-D distance transform of `f` in place, for samples `spacing` apart:
/// `out[q] = min_p (spacing·(q − p))² + f[p]`. `v`, `z` are scratch buffers (≥ n, n + 1).
fn transform_1d(f: &mut [f64], spacing: f64, v: &mut [usize], z: &mut [f64], out: &mut [f64]) {
    let n = f.len();
    let s2 = spacing * spacing;
    // The lower envelope of parabolas rooted at finite samples.
    let mut k = usize::MAX;
    for q in 0..n {
        if !f[q].is_finite() {
            continue;
        }
        loop {
            if k == usize::MAX {
                k = 0;
                v[0] = q;
                z[0] = f64::NEG_INFINITY;
                z[1] = f64::INFINITY;
                break;
            }
            let p = v[k];
            // Intersection of the parabolas rooted at p and q.
            let s = ((f[q] + s2 * (q * q) as f64) - (f[p] + s2 * (p * p) as f64)) / (2.0 * s2 * (q as f64 - p as f64));
            if s <= z[k] {
                if k == 0 {
                    k = usize::MAX;
                    continue;
                }
                k -= 1;
            } else {
                k += 1;
                v[k] = q;
                z[k] = s;
                z[k + 1] = f64::INFINITY;
                break;
            }
        }
    }
    if k == usize::MAX {
        out[..n].fill(f64::INFINITY);
    } else {
        let mut j = 0;
        for (q, o) in out.iter_mut().enumerate().take(n) {
            while z[j + 1] < q as f64 {
                j += 1;
            }
            let d = q as f64 - v[j] as f64;
            *o = s2 * d * d + f[v[j]];
        }
    }
    f.copy_from_slice(&out[..n]);
}

/// Euclidean distance, in world units, from every sample of `grid` to the nearest sample where
/// `seed` is true (`f64::INFINITY` when there is none). Anisotropic cells are handled exactly.
///
/// # Panics
/// If `seed.len() != grid.len()`.
pub fn distance_transform(grid: &GridSpec, seed: &[bool]) -> Vec<f64> {
    assert_eq!(seed.len(), grid.len(), "mask of {} samples for a grid of {}", seed.len(), grid.len());
    let (nx, ny) = (grid.nx(), grid.ny());
    let cell = grid.cell_size();
    let mut d: Vec<f64> = seed.iter().map(|&s| if s { 0.0 } else { f64::INFINITY }).collect();
    let n = nx.max(ny);
    let (mut v, mut z, mut out) = (vec![0usize; n], vec![0.0f64; n + 1], vec![0.0f64; n]);
    for row in d.chunks_exact_mut(nx) {
        transform_1d(row, cell.x, &mut v, &mut z, &mut out);
    }
    let mut col = vec![0.0f64; ny];
    for i in 0..nx {
        for j in 0..ny {
            col[j] = d[j * nx + i];
        }
        transform_1d(&mut col, cell.y, &mut v, &mut z, &mut out);
        for j in 0..ny {
            d[j * nx + i] = col[j].sqrt();
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;

    #[test]
    fn matches_brute_force() {
        let grid = GridSpec::new(23, 17, DVec2::ZERO, DVec2::new(1.5, 0.7)).unwrap();
        let seed: Vec<bool> = (0..grid.len()).map(|k| (k * 7919) % 37 == 0).collect();
        let d = distance_transform(&grid, &seed);
        for (k, &dk) in d.iter().enumerate() {
            let (i, j) = grid.coords(k);
            let p = grid.position(i, j);
            let best = (0..grid.len())
                .filter(|&s| seed[s])
                .map(|s| {
                    let (a, b) = grid.coords(s);
                    p.distance(grid.position(a, b))
                })
                .fold(f64::INFINITY, f64::min);
            assert!((dk - best).abs() < 1e-9, "sample ({i}, {j}): {dk} vs {best}");
        }
    }

    #[test]
    fn no_seed_means_infinite_distance() {
        let grid = GridSpec::new(4, 3, DVec2::ZERO, DVec2::ONE).unwrap();
        assert!(distance_transform(&grid, &[false; 12]).iter().all(|d| d.is_infinite()));
    }
}
