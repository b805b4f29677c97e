//! The diffusion equations of §5.2 as a linear system, and two solvers for it: the paper's
//! coarse-to-fine Jacobi pyramid and a multigrid (full multigrid start, V-cycles, red-black
//! Gauss–Seidel smoothing, rayon over rows).
//!
//! Every sample obeys `F = α·F_L + β·F_G + (1 − α − β)·F_I`, written here as
//! `F = wl·(F_W + F_E + F_S + F_N) + wx·F(i + ox, j) + wy·F(i, j + oy) + b` with `wl = α/4`,
//! `wx = β·nx²`, `wy = β·ny²`, the upwind offsets `ox = −sgn nx`, `oy = −sgn ny`, and
//! `b = β·G + (1 − α − β)·F_I`. Fixed samples (strict constraints) keep their value. The grid
//! border reflects (Neumann). All updates of one colour read only the other colour, so the
//! parallel smoother gives bit-identical results to a serial one.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::DiffusionError;
use crate::raster::{CellKind, ConstraintMaps};

/// Which solver to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Solver {
    /// Full multigrid then V-cycles with red-black Gauss–Seidel smoothing (2 + 2 sweeps, damped
    /// coarse-grid correction); `BiCGStab` preconditioned by the V-cycle takes over if a cycle cuts
    /// the residual by less than 30 %.
    #[default]
    Multigrid,
    /// The paper's pyramid: 5·(l − i) Jacobi iterations on level i from the coarsest (0) to the
    /// finest (l − 1), then Jacobi on the finest level until the tolerance.
    JacobiPyramid,
}

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolveOptions {
    /// The solver (default multigrid).
    pub solver: Solver,
    /// Stop once ‖r‖₂ / ‖r₀‖₂ falls below this (r₀: the residual of the constraints alone, zero
    /// elsewhere). Default 1e-4.
    pub tolerance: f64,
    /// At most this many V-cycles (multigrid, default 60) or finest-level Jacobi sweeps after the
    /// pyramid (default 20 000).
    pub max_iterations: Option<usize>,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self { solver: Solver::Multigrid, tolerance: 1e-4, max_iterations: None }
    }
}

impl SolveOptions {
    fn check(&self) -> Result<(), DiffusionError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(DiffusionError::InvalidOption {
                name: "tolerance",
                value: self.tolerance,
                reason: "must lie in (0, 1)",
            });
        }
        Ok(())
    }
}

/// How a solve went.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveReport {
    /// The solver that ran.
    pub solver: Solver,
    /// V-cycles, or finest-level Jacobi sweeps after the pyramid.
    pub iterations: usize,
    /// Final ‖r‖₂ / ‖r₀‖₂.
    pub relative_residual: f64,
    /// Whether it fell below the tolerance.
    pub converged: bool,
    /// Relative residual after the start (full multigrid or pyramid) and after each V-cycle (or
    /// every 50 Jacobi sweeps).
    pub history: Vec<f64>,
}

/// One level of the system.
#[derive(Debug, Clone)]
struct Level {
    nx: usize,
    ny: usize,
    wl: Vec<f32>,
    wx: Vec<f32>,
    wy: Vec<f32>,
    ox: Vec<i8>,
    oy: Vec<i8>,
    fixed: Vec<bool>,
    /// Right-hand side of this level's version of the problem.
    b: Vec<f32>,
    /// Factor applied to the restricted residual arriving at this level (coarse levels).
    scale: Vec<f32>,
}

/// A diffusion problem on a grid with its coarse versions.
#[derive(Debug, Clone)]
pub struct DiffusionProblem {
    levels: Vec<Level>,
}

impl DiffusionProblem {
    /// The elevation equation of `maps`: identification on elevation samples, half Laplace and half
    /// gradient on slope samples (and filled holes), Laplace elsewhere.
    ///
    /// # Errors
    /// [`DiffusionError::NoElevation`] when no sample carries an elevation.
    pub fn elevation(maps: &ConstraintMaps) -> Result<Self, DiffusionError> {
        if !maps.kind.contains(&CellKind::Elevation) {
            return Err(DiffusionError::NoElevation);
        }
        let (nx, ny) = (maps.grid.nx(), maps.grid.ny());
        let n = nx * ny;
        let mut level = Level::empty(nx, ny);
        for k in 0..n {
            let (i, j) = (k % nx, k / nx);
            let border = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            match maps.kind[k] {
                CellKind::Elevation => {
                    level.fixed[k] = true;
                    level.wl[k] = 0.0;
                    level.b[k] = maps.elevation[k];
                }
                CellKind::Gradient | CellKind::Hole if !border => {
                    let [x, y] = maps.normal[k];
                    level.wl[k] = 0.125;
                    level.wx[k] = 0.5 * x * x;
                    level.wy[k] = 0.5 * y * y;
                    // What the normal leaves (a zero normal) goes to the Laplacian.
                    level.wl[k] += 0.125 * (1.0 - x * x - y * y).max(0.0);
                    level.ox[k] = -sign(x);
                    level.oy[k] = -sign(y);
                    level.b[k] = 0.5 * maps.gradient[k];
                }
                _ => {}
            }
        }
        Ok(Self::with_coarse(level))
    }

    /// Plain Laplace diffusion of `values` (NaN where free): what the noise amplitude and
    /// roughness go through. `None` if no value is given.
    pub fn laplace(nx: usize, ny: usize, values: &[f32]) -> Option<Self> {
        if values.iter().all(|v| v.is_nan()) {
            return None;
        }
        let mut level = Level::empty(nx, ny);
        for (k, &v) in values.iter().enumerate() {
            if !v.is_nan() {
                level.fixed[k] = true;
                level.wl[k] = 0.0;
                level.b[k] = v;
            }
        }
        Some(Self::with_coarse(level))
    }

    fn with_coarse(finest: Level) -> Self {
        let mut levels = vec![finest];
        while levels.len() < 16 {
            let last = &levels[levels.len() - 1];
            if last.nx.min(last.ny) < 6 {
                break;
            }
            let coarse = last.coarsen();
            levels.push(coarse);
        }
        Self { levels }
    }

    /// Samples along x and y of the finest level.
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].nx, self.levels[0].ny)
    }

    /// Number of levels (the finest included).
    pub fn depth(&self) -> usize {
        self.levels.len()
    }

    /// Solves the system, returning the finest-level solution (row-major) and a report.
    ///
    /// # Errors
    /// [`DiffusionError::InvalidOption`] for a tolerance outside (0, 1).
    pub fn solve(&self, options: &SolveOptions) -> Result<(Vec<f32>, SolveReport), DiffusionError> {
        options.check()?;
        Ok(match options.solver {
            Solver::Multigrid => self.multigrid(options),
            Solver::JacobiPyramid => self.jacobi_pyramid(options),
        })
    }

    /// ‖r‖₂ of the constraints alone (fixed values, zero elsewhere): the reference of the
    /// relative residual.
    fn reference_norm(&self) -> f64 {
        let l = &self.levels[0];
        let start: Vec<f32> = (0..l.b.len()).map(|k| if l.fixed[k] { l.b[k] } else { 0.0 }).collect();
        let norm = l.residual_norm(&Field::from_full(l.nx, l.ny, &start), &l.b);
        if norm > 0.0 { norm } else { 1.0 }
    }

    fn multigrid(&self, options: &SolveOptions) -> (Vec<f32>, SolveReport) {
        let r0 = self.reference_norm();
        let top = self.levels.len() - 1;
        // Full multigrid: solve the coarsest version, then interpolate and cycle once per level.
        let coarsest = &self.levels[top];
        let mut x = Field::from_full(coarsest.nx, coarsest.ny, &coarsest.start());
        for _ in 0..100 {
            coarsest.smooth(&mut x, &coarsest.b);
        }
        for l in (0..top).rev() {
            let level = &self.levels[l];
            let mut finer = Field::from_full(level.nx, level.ny, &level.start());
            finer.add_interpolated(&x, &level.fixed, false);
            x = finer;
            self.vcycle(l, &mut x, &level.b);
        }
        let finest = &self.levels[0];
        let max = options.max_iterations.unwrap_or(60);
        // Plain V-cycles while each cuts the residual by at least 30 %; BiCGStab, preconditioned by
        // the same V-cycle, takes over from the first that does not (slope-dominated constraint
        // sets can make the cycles stall), restarting from the last good iterate.
        let mut history = vec![finest.residual_norm(&x, &finest.b) / r0];
        let mut cycles = 0;
        while history[history.len() - 1] >= options.tolerance && cycles < max {
            let before = x.clone();
            self.vcycle(0, &mut x, &finest.b);
            cycles += 1;
            let rel = finest.residual_norm(&x, &finest.b) / r0;
            if rel > 0.7 * history[history.len() - 1] {
                x = before;
                cycles -= 1;
                break;
            }
            history.push(rel);
        }
        let mut iterations = cycles;
        let mut solution = x.to_full();
        if history[history.len() - 1] >= options.tolerance && cycles < max {
            let (krylov, more, its) = self.bicgstab(solution, r0, options.tolerance, max - cycles);
            solution = krylov;
            history.extend_from_slice(&more[1..]);
            iterations += its;
        }
        let rel = history[history.len() - 1];
        let report = SolveReport {
            solver: Solver::Multigrid,
            iterations,
            relative_residual: rel,
            converged: rel < options.tolerance,
            history,
        };
        (solution, report)
    }

    /// The V-cycle as a preconditioner: z ≈ A⁻¹·r (zero on fixed samples).
    fn precondition(&self, r: &[f32]) -> Vec<f32> {
        let l = &self.levels[0];
        let mut z = Field::zeros(l.nx, l.ny);
        self.vcycle(0, &mut z, r);
        z.to_full()
    }

    /// `BiCGStab` (van der Vorst 1992), right-preconditioned by one V-cycle per application. The
    /// system is not symmetric (the gradient rows are upwind), and a V-cycle alone can stall on
    /// gradient-dominated constraint sets; wrapped in `BiCGStab` it converges robustly. Krylov
    /// vectors vanish on fixed samples, which therefore keep their values. Returns the solution,
    /// the relative residual after the start and after each iteration, and the iteration count.
    fn bicgstab(&self, mut x: Vec<f32>, r0: f64, tol: f64, max: usize) -> (Vec<f32>, Vec<f64>, usize) {
        let l = &self.levels[0];
        let mut r = l.residual_full(&x);
        let mut history = vec![norm(&r) / r0];
        if history[0] < tol {
            return (x, history, 0);
        }
        let hat = r.clone();
        let (mut rho, mut alpha, mut omega) = (1.0f64, 1.0f64, 1.0f64);
        let mut v = vec![0.0f32; r.len()];
        let mut p = vec![0.0f32; r.len()];
        let mut iterations = 0;
        while iterations < max {
            iterations += 1;
            let rho_new = dot(&hat, &r);
            if rho_new == 0.0 || omega == 0.0 {
                break;
            }
            let beta = (rho_new / rho) * (alpha / omega);
            rho = rho_new;
            axpy_update(&mut p, &r, &v, beta, omega);
            let y = self.precondition(&p);
            v = l.apply(&y);
            let hv = dot(&hat, &v);
            if hv == 0.0 {
                break;
            }
            alpha = rho / hv;
            let s: Vec<f32> = r.iter().zip(&v).map(|(&r, &v)| r - (alpha as f32) * v).collect();
            if norm(&s) / r0 < tol {
                add_scaled(&mut x, &y, alpha);
                r = l.residual_full(&x);
                history.push(norm(&r) / r0);
                break;
            }
            let z = self.precondition(&s);
            let t = l.apply(&z);
            let tt = dot(&t, &t);
            omega = if tt > 0.0 { dot(&t, &s) / tt } else { 0.0 };
            add_scaled(&mut x, &y, alpha);
            add_scaled(&mut x, &z, omega);
            // The true residual, not the recurrence: f32 recurrences drift.
            r = l.residual_full(&x);
            history.push(norm(&r) / r0);
            if history[history.len() - 1] < tol {
                break;
            }
        }
        (x, history, iterations)
    }

    /// One V-cycle on level `l` for `rhs`: 2 red-black sweeps, coarse-grid correction, 2 sweeps.
    fn vcycle(&self, l: usize, x: &mut Field, rhs: &[f32]) {
        let level = &self.levels[l];
        if l + 1 == self.levels.len() {
            for _ in 0..60 {
                level.smooth(x, rhs);
            }
            return;
        }
        for _ in 0..sweeps() {
            level.smooth(x, rhs);
        }
        let r = level.residual(x, rhs);
        let coarse = &self.levels[l + 1];
        let rc = coarse.restrict(level, &r);
        let mut e = Field::zeros(coarse.nx, coarse.ny);
        self.vcycle(l + 1, &mut e, &rc);
        e.scale(CORRECTION_DAMPING);
        x.add_interpolated(&e, &level.fixed, true);
        for _ in 0..sweeps() {
            level.smooth(x, rhs);
        }
    }

    fn jacobi_pyramid(&self, options: &SolveOptions) -> (Vec<f32>, SolveReport) {
        let r0 = self.reference_norm();
        let l = self.levels.len();
        let mut x: Option<Vec<f32>> = None;
        // Level i of the paper counts from the coarsest (0); ours from the finest.
        for depth in (0..l).rev() {
            let level = &self.levels[depth];
            let mut cur = level.start();
            if let Some(coarse) = &x {
                let coarse_level = &self.levels[depth + 1];
                let c = Field::from_full(coarse_level.nx, coarse_level.ny, coarse);
                let mut f = Field::from_full(level.nx, level.ny, &cur);
                f.add_interpolated(&c, &level.fixed, false);
                cur = f.to_full();
            }
            let paper_level = l - 1 - depth;
            for _ in 0..5 * (l - paper_level) {
                cur = level.jacobi(&cur);
            }
            x = Some(cur);
        }
        let finest = &self.levels[0];
        let mut cur = x.unwrap_or_else(|| finest.start());
        let norm = |v: &[f32]| finest.residual_norm(&Field::from_full(finest.nx, finest.ny, v), &finest.b) / r0;
        let mut history = vec![norm(&cur)];
        let max = options.max_iterations.unwrap_or(20_000);
        let mut sweeps = 0;
        while history[history.len() - 1] >= options.tolerance && sweeps < max {
            let batch = 50.min(max - sweeps);
            for _ in 0..batch {
                cur = finest.jacobi(&cur);
            }
            sweeps += batch;
            history.push(norm(&cur));
        }
        let rel = history[history.len() - 1];
        let report = SolveReport {
            solver: Solver::JacobiPyramid,
            iterations: sweeps,
            relative_residual: rel,
            converged: rel < options.tolerance,
            history,
        };
        (cur, report)
    }
}

impl Level {
    fn empty(nx: usize, ny: usize) -> Self {
        let n = nx * ny;
        Self {
            nx,
            ny,
            wl: vec![0.25; n],
            wx: vec![0.0; n],
            wy: vec![0.0; n],
            ox: vec![0; n],
            oy: vec![0; n],
            fixed: vec![false; n],
            b: vec![0.0; n],
            scale: vec![1.0; n],
        }
    }

    /// Fixed values where fixed, zero elsewhere.
    fn start(&self) -> Vec<f32> {
        (0..self.b.len()).map(|k| if self.fixed[k] { self.b[k] } else { 0.0 }).collect()
    }

    /// The coarse version, vertex-centred: coarse sample (I, J) sits on fine sample (2I, 2J) and
    /// stands for its 3 × 3 neighbourhood under full weighting (¼, ½, ¼ per axis). It is fixed when
    /// the fine sample or one of its four neighbours is (so Dirichlet data, even a one-sample-wide
    /// curve, survives every coarsening and no coarse problem is a singular pure-Neumann one), at
    /// the weighted mean of those fixed values. Otherwise it averages its neighbourhood's equation
    /// weights (upwind directions by their signed weights; what cancels goes to the Laplacian, so
    /// the row still sums to 1) and doubles the gradient steps of the right-hand side (one coarse
    /// step spans two fine ones).
    fn coarsen(&self) -> Self {
        let (cx, cy) = (self.nx.div_ceil(2), self.ny.div_ceil(2));
        let mut c = Self::empty(cx, cy);
        for jc in 0..cy {
            for ic in 0..cx {
                let k = jc * cx + ic;
                let (fi, fj) = (2 * ic, 2 * jc);
                let (mut fixed_w, mut h) = (0.0f32, 0.0f32);
                for (di, dj) in [(0i64, 0i64), (-1, 0), (1, 0), (0, -1), (0, 1)] {
                    let (i, j) = (fi as i64 + di, fj as i64 + dj);
                    if i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny {
                        let f = j as usize * self.nx + i as usize;
                        if self.fixed[f] {
                            let w = if di == 0 && dj == 0 { 4.0 } else { 1.0 };
                            fixed_w += w;
                            h += w * self.b[f];
                        }
                    }
                }
                if fixed_w > 0.0 {
                    c.fixed[k] = true;
                    c.wl[k] = 0.0;
                    c.b[k] = h / fixed_w;
                    continue;
                }
                let (mut m, mut dx, mut dy, mut b) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
                self.full_weighting(fi, fj, |f, w| {
                    if !self.fixed[f] {
                        m += w;
                        dx += w * self.wx[f] * f32::from(self.ox[f]);
                        dy += w * self.wy[f] * f32::from(self.oy[f]);
                        b += w * 2.0 * self.b[f];
                    }
                });
                let (dx, dy) = (dx / m, dy / m);
                c.b[k] = b / m;
                c.wx[k] = dx.abs();
                c.wy[k] = dy.abs();
                c.ox[k] = sign(dx);
                c.oy[k] = sign(dy);
                c.wl[k] = ((1.0 - c.wx[k] - c.wy[k]) / 4.0).max(0.0);
                // Residuals of second-order (Laplace) rows grow 4× per coarsening, first-order
                // (gradient) rows 2×.
                c.scale[k] = 16.0 * c.wl[k] + 2.0 * (c.wx[k] + c.wy[k]);
            }
        }
        c
    }

    /// Calls `f(fine index, weight)` over the 3 × 3 full-weighting neighbourhood of fine sample
    /// `(fi, fj)` (weights ¼, ½, ¼ per axis; samples off the grid skipped).
    #[inline]
    fn full_weighting(&self, fi: usize, fj: usize, mut f: impl FnMut(usize, f32)) {
        for dj in -1i64..=1 {
            let j = fj as i64 + dj;
            if j < 0 || j as usize >= self.ny {
                continue;
            }
            let wj = if dj == 0 { 0.5 } else { 0.25 };
            for di in -1i64..=1 {
                let i = fi as i64 + di;
                if i < 0 || i as usize >= self.nx {
                    continue;
                }
                let wi = if di == 0 { 0.5 } else { 0.25 };
                f(j as usize * self.nx + i as usize, wi * wj);
            }
        }
    }

    #[inline]
    fn west(i: usize) -> usize {
        if i > 0 { i - 1 } else { 1 }
    }
    #[inline]
    fn east(&self, i: usize) -> usize {
        if i + 1 < self.nx { i + 1 } else { self.nx - 2 }
    }
    #[inline]
    fn south(j: usize) -> usize {
        if j > 0 { j - 1 } else { 1 }
    }
    #[inline]
    fn north(&self, j: usize) -> usize {
        if j + 1 < self.ny { j + 1 } else { self.ny - 2 }
    }
    #[inline]
    fn step_x(&self, i: usize, o: i8) -> usize {
        match o {
            -1 => Self::west(i),
            1 => self.east(i),
            _ => i,
        }
    }
    #[inline]
    fn step_y(&self, j: usize, o: i8) -> usize {
        match o {
            -1 => Self::south(j),
            1 => self.north(j),
            _ => j,
        }
    }

    /// The right side of the update at `(i, j)`, reading neighbours through `get`.
    #[inline]
    fn update(&self, i: usize, j: usize, rhs: f32, get: impl Fn(usize, usize) -> f32) -> f32 {
        let k = j * self.nx + i;
        let lap = get(Self::west(i), j) + get(self.east(i), j) + get(i, Self::south(j)) + get(i, self.north(j));
        let mut v = self.wl[k] * lap + rhs;
        if self.wx[k] != 0.0 {
            v += self.wx[k] * get(self.step_x(i, self.ox[k]), j);
        }
        if self.wy[k] != 0.0 {
            v += self.wy[k] * get(i, self.step_y(j, self.oy[k]));
        }
        v
    }

    /// One red-black Gauss–Seidel sweep for `rhs` (fixed samples untouched).
    fn smooth(&self, x: &mut Field, rhs: &[f32]) {
        let nx = self.nx;
        for colour in 0..2 {
            let w = x.w;
            let (first, second) = x.c.split_at_mut(1);
            let (mine, other) = if colour == 0 { (&mut first[0], &second[0]) } else { (&mut second[0], &first[0]) };
            mine.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
                let get = |i: usize, jj: usize| other[jj * w + (i >> 1)];
                let start = (j + colour) & 1;
                if j == 0 || j + 1 == self.ny || nx < 3 {
                    for i in (start..nx).step_by(2) {
                        let k = j * nx + i;
                        if !self.fixed[k] {
                            row[i >> 1] = self.update(i, j, rhs[k], get);
                        }
                    }
                    return;
                }
                // Interior rows: no reflection, the vertical upwind neighbour picked from the
                // rows below, here and above by its offset (any finite value when its weight is 0).
                let rows = [&other[(j - 1) * w..j * w], &other[j * w..(j + 1) * w], &other[(j + 1) * w..(j + 2) * w]];
                let base = j * nx;
                for i in (start..nx).step_by(2) {
                    let k = base + i;
                    if self.fixed[k] {
                        continue;
                    }
                    if i == 0 || i + 1 == nx {
                        row[i >> 1] = self.update(i, j, rhs[k], get);
                        continue;
                    }
                    let h = i >> 1;
                    let mid = rows[1];
                    let lap = mid[(i - 1) >> 1] + mid[(i + 1) >> 1] + rows[0][h] + rows[2][h];
                    let bx = mid[i.wrapping_add_signed(isize::from(self.ox[k])) >> 1];
                    let by = rows[(1 + self.oy[k]) as usize][h];
                    row[h] = self.wl[k] * lap + self.wx[k] * bx + self.wy[k] * by + rhs[k];
                }
            });
        }
    }

    /// Per sample of a full row-major `x`: `f(k, x_k, U_k)` where `U_k` is the update value (the
    /// stencil applied to x plus `rhs`, or plus 0), for non-fixed samples; `fixed(k, x_k)` for
    /// fixed ones. Interior samples take a fast path without reflection.
    fn map_stencil(
        &self,
        x: &[f32],
        rhs: Option<&[f32]>,
        fixed: impl Fn(f32) -> f32 + Sync,
        f: impl Fn(f32, f32) -> f32 + Sync,
    ) -> Vec<f32> {
        let nx = self.nx;
        let mut out = vec![0.0f32; x.len()];
        out.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
            let get = |i: usize, jj: usize| x[jj * nx + i];
            let edge_row = j == 0 || j + 1 == self.ny;
            for (i, o) in row.iter_mut().enumerate() {
                let k = j * nx + i;
                if self.fixed[k] {
                    *o = fixed(x[k]);
                    continue;
                }
                let b = rhs.map_or(0.0, |r| r[k]);
                let u = if edge_row || i == 0 || i + 1 == nx {
                    self.update(i, j, b, get)
                } else {
                    let lap = x[k - 1] + x[k + 1] + x[k - nx] + x[k + nx];
                    let bx = x[k.wrapping_add_signed(isize::from(self.ox[k]))];
                    let by = x[k.wrapping_add_signed(isize::from(self.oy[k]) * nx as isize)];
                    self.wl[k] * lap + self.wx[k] * bx + self.wy[k] * by + b
                };
                *o = f(x[k], u);
            }
        });
        out
    }

    /// A·v on a full row-major array (v on fixed samples passes through).
    fn apply(&self, v: &[f32]) -> Vec<f32> {
        self.map_stencil(v, None, |x| x, |x, u| x - u)
    }

    /// b − A·x on a full row-major array (0 on fixed samples).
    fn residual_full(&self, x: &[f32]) -> Vec<f32> {
        self.map_stencil(x, Some(&self.b), |_| 0.0, |x, u| u - x)
    }

    /// One Jacobi sweep on a full row-major array.
    fn jacobi(&self, x: &[f32]) -> Vec<f32> {
        let mut out = vec![0.0f32; x.len()];
        out.par_chunks_mut(self.nx).enumerate().for_each(|(j, row)| {
            let get = |i: usize, jj: usize| x[jj * self.nx + i];
            for (i, v) in row.iter_mut().enumerate() {
                let k = j * self.nx + i;
                *v = if self.fixed[k] { x[k] } else { self.update(i, j, self.b[k], get) };
            }
        });
        out
    }

    /// The residual for `rhs`, row-major (0 on fixed samples).
    fn residual(&self, x: &Field, rhs: &[f32]) -> Vec<f32> {
        self.map_stencil(&x.to_full(), Some(rhs), |_| 0.0, |x, u| u - x)
    }

    /// ‖residual‖₂, summed per row then in row order (deterministic).
    fn residual_norm(&self, x: &Field, rhs: &[f32]) -> f64 {
        let r = self.residual(x, rhs);
        let rows: Vec<f64> =
            r.par_chunks(self.nx).map(|row| row.iter().map(|&v| f64::from(v) * f64::from(v)).sum()).collect();
        rows.iter().sum::<f64>().sqrt()
    }

    /// The fine residual `r` restricted onto this (coarse) level by full weighting, scaled per row.
    fn restrict(&self, fine: &Level, r: &[f32]) -> Vec<f32> {
        let mut out = vec![0.0f32; self.nx * self.ny];
        out.par_chunks_mut(self.nx).enumerate().for_each(|(jc, row)| {
            for (ic, v) in row.iter_mut().enumerate() {
                let k = jc * self.nx + ic;
                if self.fixed[k] {
                    continue;
                }
                let (mut s, mut m) = (0.0f32, 0.0f32);
                fine.full_weighting(2 * ic, 2 * jc, |f, w| {
                    s += w * r[f];
                    m += w;
                });
                *v = self.scale[k] * s / m;
            }
        });
        out
    }
}

/// Weight of the coarse-grid correction. The coarse rows only approximate the fine ones (second-
/// and first-order terms scale differently), and undamped corrections overshoot on slope bands
/// until V-cycles diverge; at 0.7 they converge on every constraint set we tried.
const CORRECTION_DAMPING: f32 = 0.7;

/// Red-black sweeps before and after each coarse-grid correction.
const fn sweeps() -> usize {
    2
}

/// −1, 0 or 1: the upwind step along an axis (`f32::signum` gives ±1 for zero).
fn sign(v: f32) -> i8 {
    i8::from(v > 0.0) - i8::from(v < 0.0)
}

/// Chunk length of the deterministic reductions.
const CHUNK: usize = 1 << 14;

/// ⟨a, b⟩ in f64, summed per chunk then in chunk order (the same for any thread count).
fn dot(a: &[f32], b: &[f32]) -> f64 {
    let parts: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(&u, &v)| f64::from(u) * f64::from(v)).sum())
        .collect();
    parts.iter().sum()
}

fn norm(a: &[f32]) -> f64 {
    dot(a, a).sqrt()
}

/// x += c·y.
fn add_scaled(x: &mut [f32], y: &[f32], c: f64) {
    let c = c as f32;
    x.par_chunks_mut(CHUNK).zip(y.par_chunks(CHUNK)).for_each(|(x, y)| {
        for (a, &b) in x.iter_mut().zip(y) {
            *a += c * b;
        }
    });
}

/// p = r + β·(p − ω·v).
fn axpy_update(p: &mut [f32], r: &[f32], v: &[f32], beta: f64, omega: f64) {
    let (beta, omega) = (beta as f32, omega as f32);
    p.par_chunks_mut(CHUNK).zip(r.par_chunks(CHUNK)).zip(v.par_chunks(CHUNK)).for_each(|((p, r), v)| {
        for ((a, &b), &c) in p.iter_mut().zip(r).zip(v) {
            *a = b + beta * (*a - omega * c);
        }
    });
}

/// A grid function stored by colour: `c[(i + j) % 2][j·w + i/2]`, so a sweep of one colour
/// writes one array while reading the other.
#[derive(Debug, Clone)]
struct Field {
    nx: usize,
    ny: usize,
    w: usize,
    c: [Vec<f32>; 2],
}

impl Field {
    fn zeros(nx: usize, ny: usize) -> Self {
        let w = nx.div_ceil(2);
        Self { nx, ny, w, c: [vec![0.0; w * ny], vec![0.0; w * ny]] }
    }

    fn from_full(nx: usize, ny: usize, v: &[f32]) -> Self {
        let mut f = Self::zeros(nx, ny);
        for j in 0..ny {
            for i in 0..nx {
                f.c[(i + j) & 1][j * f.w + (i >> 1)] = v[j * nx + i];
            }
        }
        f
    }

    fn scale(&mut self, s: f32) {
        for c in &mut self.c {
            c.par_chunks_mut(CHUNK).for_each(|chunk| chunk.iter_mut().for_each(|v| *v *= s));
        }
    }

    #[inline]
    fn get(&self, i: usize, j: usize) -> f32 {
        self.c[(i + j) & 1][j * self.w + (i >> 1)]
    }

    fn to_full(&self) -> Vec<f32> {
        let mut out = vec![0.0; self.nx * self.ny];
        out.par_chunks_mut(self.nx).enumerate().for_each(|(j, row)| {
            for (i, v) in row.iter_mut().enumerate() {
                *v = self.get(i, j);
            }
        });
        out
    }

    /// Adds (or, with `add` false, writes) the bilinear interpolation of the coarse field `e`
    /// (half the resolution, coarse sample I on fine sample 2I) on every non-fixed sample.
    fn add_interpolated(&mut self, e: &Field, fixed: &[bool], add: bool) {
        let (nx, w) = (self.nx, self.w);
        let coarse = e.to_full();
        let (cnx, cny) = (e.nx, e.ny);
        for colour in 0..2 {
            self.c[colour].par_chunks_mut(w).enumerate().for_each(|(j, row)| {
                // Vertex-centred: even fine indices sit on coarse samples, odd ones halfway.
                let j0 = (j / 2).min(cny - 1);
                let j1 = if j % 2 == 1 { (j0 + 1).min(cny - 1) } else { j0 };
                let (r0, r1) = (&coarse[j0 * cnx..(j0 + 1) * cnx], &coarse[j1 * cnx..(j1 + 1) * cnx]);
                for i in ((j + colour) & 1..nx).step_by(2) {
                    if fixed[j * nx + i] {
                        continue;
                    }
                    let i0 = (i / 2).min(cnx - 1);
                    let v = if i % 2 == 1 {
                        let i1 = (i0 + 1).min(cnx - 1);
                        0.25 * (r0[i0] + r0[i1] + r1[i0] + r1[i1])
                    } else {
                        0.5 * (r0[i0] + r1[i0])
                    };
                    if add {
                        row[i >> 1] += v;
                    } else {
                        row[i >> 1] = v;
                    }
                }
            });
        }
    }
}
