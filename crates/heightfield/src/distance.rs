//! Exact Euclidean distance transforms (Felzenszwalb & Huttenlocher 2012): two separable passes of
//! a 1-D lower-envelope-of-parabolas transform, O(samples).

use glam::DVec2;

use crate::GridSpec;

/// Squared 1-D transform of `f` in place, for samples `spacing` apart:
/// `f[q] ← min_p (spacing·(q − p))² + f[p]`, with `label[q]` (if given) taken from the minimising `p`.
fn transform_1d(f: &mut [f64], label: Option<&mut [u32]>, spacing: f64, scratch: &mut Scratch) {
    let s2 = spacing * spacing;
    let half_inv = 0.5 / s2;
    let Scratch { v, z, g, out, lab } = scratch;
    // The lower envelope of the parabolas rooted at finite samples: parabola `r` is rooted at
    // `v[r]`, holds `f[v[r]]` in `out[r]` and `f + s²·v²` in `g[r]`, and is lowest from `z[r]` on.
    let mut k = 0;
    for (q, &fq) in f.iter().enumerate() {
        if !fq.is_finite() {
            continue;
        }
        let qf = q as f64;
        let gq = fq + s2 * qf * qf;
        // Where the parabolas rooted at the top and at q meet: (gq − gp) / (2s²(q − p)). The top
        // is hidden when that is at or left of where the top starts (compared without dividing).
        while k > 0 && (gq - g[k - 1]) * half_inv <= z[k - 1] * (qf - v[k - 1] as f64) {
            k -= 1;
        }
        z[k] = if k == 0 { f64::NEG_INFINITY } else { (gq - g[k - 1]) * half_inv / (qf - v[k - 1] as f64) };
        v[k] = q;
        g[k] = gq;
        out[k] = fq;
        if let Some(label) = label.as_deref() {
            lab[k] = label[q];
        }
        k += 1;
    }
    if k == 0 {
        return; // no seed on this line: everything stays infinite
    }
    z[k] = f64::INFINITY;
    let mut label = label;
    let mut r = 0;
    for (q, fq) in f.iter_mut().enumerate() {
        let qf = q as f64;
        while z[r + 1] < qf {
            r += 1;
        }
        let d = qf - v[r] as f64;
        *fq = s2 * d * d + out[r];
        if let Some(label) = label.as_deref_mut() {
            label[q] = lab[r];
        }
    }
}

#[derive(Debug)]
struct Scratch {
    v: Vec<usize>,
    z: Vec<f64>,
    g: Vec<f64>,
    out: Vec<f64>,
    lab: Vec<u32>,
}

impl Scratch {
    fn new(n: usize) -> Self {
        Self { v: vec![0; n], z: vec![0.0; n + 1], g: vec![0.0; n], out: vec![0.0; n], lab: vec![0; n] }
    }
}

/// Buffers reused across [`distance_transform_seeded_with`] calls: repeated transforms (one per
/// contour, per tile) then allocate nothing.
#[derive(Debug, Default)]
pub struct DistanceScratch {
    lines: Option<Scratch>,
    tsq: Vec<f64>,
    tlab: Vec<u32>,
}

/// Generalised distance transform on an `nx × ny` grid with cell size `cell`: on entry `sq` holds
/// each seed's own squared distance (0 at an exact seed, a small value for a seed near a curve,
/// `f64::INFINITY` elsewhere) and `label` (if given) each seed's label; on return `sq[p]` is
/// `min_q (|p − q|² + sq₀[q])` over seeds `q` and `label[p]` the label of the minimising seed.
///
/// Seeding pixels near a curve with their exact squared distance to it gives distances to the curve
/// itself, not to pixel centres, to within a fraction of a cell. Without labels the transform
/// moves a third less memory.
///
/// # Panics
/// If `sq` or `label` does not hold `nx · ny` values.
pub fn distance_transform_seeded(nx: usize, ny: usize, cell: DVec2, sq: &mut [f64], label: Option<&mut [u32]>) {
    distance_transform_seeded_with(&mut DistanceScratch::default(), nx, ny, cell, sq, label);
}

/// [`distance_transform_seeded`] with caller-provided buffers.
///
/// # Panics
/// If `sq` or `label` does not hold `nx · ny` values.
pub fn distance_transform_seeded_with(
    scratch: &mut DistanceScratch,
    nx: usize,
    ny: usize,
    cell: DVec2,
    sq: &mut [f64],
    mut label: Option<&mut [u32]>,
) {
    assert_eq!(sq.len(), nx * ny, "{} squared distances for {nx}x{ny}", sq.len());
    assert!(label.as_ref().is_none_or(|l| l.len() == nx * ny), "labels for {nx}x{ny}");
    let n = nx.max(ny);
    let lines = match &mut scratch.lines {
        Some(l) if l.v.len() >= n => l,
        slot => slot.insert(Scratch::new(n)),
    };
    match label.as_deref_mut() {
        Some(label) => {
            for (row, lab) in sq.chunks_exact_mut(nx).zip(label.chunks_exact_mut(nx)) {
                transform_1d(row, Some(lab), cell.x, lines);
            }
        }
        None => {
            for row in sq.chunks_exact_mut(nx) {
                transform_1d(row, None, cell.x, lines);
            }
        }
    }
    // Columns through a cache-blocked transpose, so the second pass also reads contiguous memory.
    scratch.tsq.resize(nx * ny, 0.0);
    transpose_into(sq, nx, ny, &mut scratch.tsq);
    match label {
        Some(label) => {
            scratch.tlab.resize(nx * ny, 0);
            transpose_into(label, nx, ny, &mut scratch.tlab);
            for (col, lab) in scratch.tsq.chunks_exact_mut(ny).zip(scratch.tlab.chunks_exact_mut(ny)) {
                transform_1d(col, Some(lab), cell.y, lines);
            }
            transpose_into(&scratch.tlab, ny, nx, label);
        }
        None => {
            for col in scratch.tsq.chunks_exact_mut(ny) {
                transform_1d(col, None, cell.y, lines);
            }
        }
    }
    transpose_into(&scratch.tsq, ny, nx, sq);
}

/// Writes the transpose of `src` (`h` rows of `w`) into `out` (`w` rows of `h`), in small square
/// blocks so that the rows a block reads and writes stay in L1 cache.
fn transpose_into<T: Copy>(src: &[T], w: usize, h: usize, out: &mut [T]) {
    const BLOCK: usize = 16;
    assert!(src.len() == w * h && out.len() == w * h, "transpose of {w}x{h}");
    for j0 in (0..h).step_by(BLOCK) {
        let j1 = (j0 + BLOCK).min(h);
        let band = &src[j0 * w..j1 * w];
        for i0 in (0..w).step_by(BLOCK) {
            for i in i0..(i0 + BLOCK).min(w) {
                // Output row i, columns j0..j1: down column i of the band.
                for (o, jj) in out[i * h + j0..i * h + j1].iter_mut().zip(0..) {
                    *o = band[jj * w + i];
                }
            }
        }
    }
}

/// Euclidean distance, in world units, from every sample of `grid` to the nearest sample where
/// `seed` is true (`f64::INFINITY` when there is none). Anisotropic cells are handled exactly.
///
/// # Panics
/// If `seed.len() != grid.len()`.
pub fn distance_transform(grid: &GridSpec, seed: &[bool]) -> Vec<f64> {
    assert_eq!(seed.len(), grid.len(), "mask of {} samples for a grid of {}", seed.len(), grid.len());
    let mut d: Vec<f64> = seed.iter().map(|&s| if s { 0.0 } else { f64::INFINITY }).collect();
    distance_transform_seeded(grid.nx(), grid.ny(), grid.cell_size(), &mut d, None);
    for v in &mut d {
        *v = v.sqrt();
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
    fn labels_follow_the_nearest_seed_and_offsets_add() {
        // Two seeds on a 9x1 line: label 7 at x = 0 (offset² 4), label 9 at x = 8 (offset 0).
        let mut sq = vec![f64::INFINITY; 9];
        let mut label = vec![0u32; 9];
        (sq[0], label[0]) = (4.0, 7);
        (sq[8], label[8]) = (0.0, 9);
        distance_transform_seeded(9, 1, DVec2::ONE, &mut sq, Some(&mut label));
        assert_eq!(sq[0], 4.0);
        assert_eq!((sq[3], label[3]), (13.0, 7)); // 3² + 4 = 13 < 5² = 25
        assert_eq!((sq[5], label[5]), (9.0, 9)); // 3² = 9 < 5² + 4
    }

    #[test]
    fn no_seed_means_infinite_distance() {
        let grid = GridSpec::new(4, 3, DVec2::ZERO, DVec2::ONE).unwrap();
        assert!(distance_transform(&grid, &[false; 12]).iter().all(|d| d.is_infinite()));
    }
}
