//! Reference figures our benchmarks are compared with: measured by the issues on this machine
//! class, or reported by the papers (on their hardware, stated with each figure).

/// What a benchmark is compared against.
pub(crate) enum Reference {
    /// A published or previously measured time.
    Fixed {
        /// Who measured it, on what.
        label: &'static str,
        /// Seconds.
        seconds: f64,
    },
    /// Another benchmark of the same run (a foreign implementation measured side by side).
    SideBySide {
        /// What the other benchmark is.
        label: &'static str,
        /// Its criterion id.
        bench: &'static str,
    },
}

/// Table 2's Volcanic Island beside our whole generation with the paper's own solver budget.
const PAPER_BUDGET: &str =
    "paper, GPU (8800 GTS), Volcanic Island of Table 2, whole, with its solver at the same fixed budget";

/// The Fig. 26 baseline: the ratio is the slowdown the paper plots (at most 2 up to six regions).
const FIG_26: &str = "one region, same run (Fig. 26: the paper's ratio stays ≤ 2)";

/// A paragraph printed under a group's heading: what its rows measure and how to read them.
pub(crate) const GROUP_NOTES: &[(&str, &str)] = &[
    (
        "diffusion",
        "Whole generations (`generate`: rasterize, the elevation solve to the default tolerance, the noise\n\
     amplitude and roughness solves, the detail) of the 48-curve `volcanic-island-48` scene are the rows\n\
     to set against Table 2, which times whole generations of the paper's Volcanic Island, 48 curves too\n\
     (Table 1). The other rows are parts of a generation on a 4-curve scene and say so. The paper's Jacobi pyramid runs at\n\
     its own fixed budget (5·(l − i) sweeps per level) and stops far from converged. Since 2026-11-26\n\
     the multigrid's coarse-grid correction is undamped: slower per solve than the damped one timed\n\
     before (`multigrid/2048` 425 ms then), but the damped solve stopped 7 m (mean) and 31 m (worst)\n\
     from the converged solution of this scene at 2049², the undamped one 0.07 m and 1 m\n\
     (`examples/convergence.rs` with `ACCURACY=1`). The same-bytes speed-ups of 2026-11-26 (small levels\n\
     on the calling thread, banded painting, parallel hole fills, noise lattices) took rasterization\n\
     from 953 ms to 224 ms at 2048² and the whole generation with the old damped solve from 2.6 s to 1.4 s.\n\
     \n\
     Table 2's terrains, as fixture scenes with the paper's curve counts (whole `generate`, best of\n\
     5 at 512² and 1024² and of 3 at 2048², `examples/generate_timing.rs` with `WHOLE_ONLY=1`, 2 cores,\n\
     re-measured 2026-12-02 (noon) on an AMD EPYC with AVX-512, the best of two passes; this in-process\n\
     timing keeps glibc's default allocator, which hands each generation's grids back to the system, so\n\
     every run faults its memory in afresh). Each cell gives ours with\n\
     the default multigrid / ours with the paper's own solver at its fixed budget for the elevation and\n\
     the noise parameters (`\"solver\": \"jacobi_pyramid\", \"max_iterations\": 0` in the scene, which\n\
     `generate_timing` honours; the hole fills keep their multigrid) / the paper's GPU:\n\
     \n\
     | scene (curves) | 512² (ms) | 1024² (ms) | 2048² (s) |\n\
     |---|---:|---:|---:|\n\
     | `volcanic-island-48` (48) | 43 / 35 / 168 | 122 / 105 / 275 | 0.51 / 0.42 / 0.675 |\n\
     | `mountain` (59) | 65 / 65 / 187 | 227 / 195 / 270 | 0.81 / 0.65 / 0.670 |\n\
     | `lake` (45) | 65 / 43 / 185 | 187 / 144 / 261 | 0.68 / 0.64 / 0.690 |\n\
     | `canyon-step-3` (74) | 74 / 71 / 216 | 182 / 163 / 339 | 0.63 / 0.52 / 0.811 |\n\
     | `desert` (26) | 46 / 35 / 171 | 103 / 112 / 253 | 0.41 / 0.33 / 0.635 |\n\
     \n\
     Like for like (the paper's algorithm and budget on 2 CPU cores against its 2010 GPU) we are faster\n\
     on every scene at every size: 0.20–0.35× at 512², 0.38–0.72× at 1024², 0.51–0.97× at 2048² (the\n\
     mountain, where a quarter of the samples are holes and their fill covers the whole grid, 0.97×).\n\
     With the default multigrid we beat the GPU at 512² (0.26–0.35×) and 1024² (0.41–0.84×) everywhere,\n\
     and at 2048² on all but the mountain (0.64–0.98×; the mountain 1.21×). The morning's figures on\n\
     the same kind of machine (early that day, before the coarsening without copies, the noise maps'\n\
     tolerance, the painting's canvas pool and the unstored norms below), were 57 / 192 / 690 ms (`volcanic-island-48`), 89 / 295 / 1120 (`mountain`), 77 / 222 / 840\n\
     (`lake`), 94 / 250 / 770 (`canyon-step-3`) and 47 / 118 / 520 (`desert`) with the default, and 51 /\n\
     143 / 640, 69 / 220 / 940, 53 / 156 / 700, 78 / 208 / 680 and 38 / 102 / 410 with the paper's\n\
     budget. That budget stops far from the solution: at 2048²\n\
     the elevation of `volcanic-island-48` is 2.9 m off on average and 73 m at worst (of 1 500 m of\n\
     relief), that of `mountain` 23 and 363 m, where the default multigrid stops 0.012 and 3.2 m, and\n\
     0.045 and 10 m, from it. The 12-01 (evening) figures, before the coarse rows below, were 74 / 260 / 990 ms\n\
     (`volcanic-island-48`), 120 / 421 / 1640 (`mountain`), 101 / 335 / 1310 (`lake`), 111 / 304 / 1040\n\
     (`canyon-step-3`) and 66 / 163 / 690 (`desert`) with the default, and with the paper's budget the\n\
     volcanic island was 6.5 m off on average and 181 m at worst, the mountain 43 and 627 m. The first figures (2026-11-26, Intel Xeon, default solver) were\n\
     `mountain` 228 ms / 913 ms / 4.29 s, `lake` 190 / 794 ms / 3.55 s, `canyon-step-3` 162 / 553 ms /\n\
     2.30 s and `desert` 143 / 453 ms / 1.77 s. Then at 2048² the mountain spent 1.1 s filling the holes\n\
     where slope bands cross (27 % of its samples are holes, solved on windows covering 1.75× the grid)\n\
     and 2.1 s in the elevation solve (15 iterations: the V-cycle stalls on its crossing slope bands and\n\
     BiCGStab takes over), and with the paper's budget whole 2048² generations took 1.0 s\n\
     (`mountain-ridges`), 1.5 s (`volcanic-island-48`) and 2.1 s (`mountain`).\n\
     \n\
     2026-11-27: the sweeps' row kernel runs on AVX2 where the CPU has it (dispatched at run time\n\
     through `pulp`; the portable x86-64 build had only SSE2 for it), and restriction, prolongation\n\
     and the colour split run on contiguous slices, the coarsening on row-major copies of a level. Every output has the same\n\
     bits as before: the golden hashes are unchanged, unit tests compare the transfers and the\n\
     coarsening with their per-sample definitions bit for bit, and the row kernel has no fused\n\
     operation, so AVX2 runs the SSE2 build's arithmetic lane by lane. The VM ran about 40 % slower that day than on 11-26, so the rows below\n\
     compare the commit before with this one in the same session, alternated (whole 2048² `generate`,\n\
     best of 3, `generate_timing` with `WHOLE_ONLY=1`); the tables above and below keep the 11-26 figures:\n\
     \n\
     | scene (curves) | before | after | after / before |\n\
     |---|---:|---:|---:|\n\
     | `volcanic-island-48` (48) | 3.77 s | 2.74 s | 0.73 |\n\
     | `mountain` (59) | 6.23 s | 4.85 s | 0.78 |\n\
     | `lake` (45) | 5.01 s | 3.96 s | 0.79 |\n\
     | `canyon-step-3` (74) | 3.49 s | 3.19 s | 0.91 |\n\
     | `desert` (26) | 2.59 s | 2.16 s | 0.83 |\n\
     | `mountain-ridges` (9) | 2.73 s | 1.98 s | 0.72 |\n\
     \n\
     By phase (`mountain`, best of 5 each): the elevation solve went from 2.75–2.83 s to 2.16–2.23 s, the\n\
     amplitude and roughness solves from 0.67–0.71 s to 0.52–0.58 s. What is left is mostly the number\n\
     of cycles, not their cost: a V-cycle cuts a plain Laplace residual (the noise amplitude) by only\n\
     0.3–0.45, where textbook multigrid on Poisson's equation reaches about 0.1, most likely because a\n\
     coarse sample is fixed when any of its five fine samples is, so the coarse correction is zero on a\n\
     ring of fine samples that are free. Fixing only the coarse samples whose own fine sample is fixed\n\
     diverged (the coarse problems lose thin curves), and one sweep before and after (V(1,1)) instead\n\
     of two needed twice the cycles. Below 0.6 s needs both fewer cycles and cheaper painting and hole\n\
     fills (0.25–0.47 s and 0.5–1.1 s of the 2048² generations).\n\
     \n\
     2026-11-27, later session, the same bits again (golden hashes unchanged; a hash of the maps and all\n\
     three solutions unchanged). Parts of a 2048² generation of `mountain-ridges` timed in one process,\n\
     best of 5, the commit before and this one alternated twice (a throwaway copy of\n\
     `examples/generate_timing.rs` timing each part):\n\
     \n\
     | part | before | after |\n\
     |---|---:|---:|\n\
     | elevation set-up (hierarchy) | 91–104 ms | 62–72 ms |\n\
     | amplitude hierarchy | 95–97 ms | 56–61 ms |\n\
     | roughness hierarchy (`laplace_like`) | 62–65 ms | 39–43 ms |\n\
     | detail noise (`relief -v diffuse`, best of 3) | 165–178 ms | 94–103 ms |\n\
     \n\
     The coarsening summed each coarse sample's 3 × 3 neighbourhood twice (once for the weights, once for\n\
     the right-hand side) and built its row-major copy of a level through a merged intermediate; both are\n\
     one pass now. The noise does per row what depends on the row (each octave's lattice rows, offset and\n\
     fade). BiCGStab now keeps its seven vectors for the whole solve; in a fresh process that changed\n\
     nothing measurable (`mountain` solve 1.16–1.18 s against 1.20–1.32 s), and the reason is the VM:\n\
     the first touch of fresh memory costs about 3.5 µs per 4 KiB page here (0.9 ms per MiB), so\n\
     BiCGStab's first iteration on `mountain-ridges` took 185 ms and its second 60 ms, the same work. A\n\
     single `relief diffuse` run touches about 0.5 GB for the first time, which is why its diffusion step\n\
     varies from 0.76 s to 1.7 s between identical runs on this machine. `mimalloc` as the CLI's\n\
     allocator cut the in-process parts by about 30 % (it keeps freed memory mapped) but left single\n\
     runs within that spread, so it was not adopted; neither was `GLIBC_TUNABLES` (about 20 % in\n\
     process). Also measured and not adopted: four sweeps per half V-cycle instead of two (`mountain`\n\
     solve 1.23 → 1.06 s and `lake` 1.12 → 0.84 s, `mountain-ridges` unchanged, different bits). On\n\
     `mountain-ridges` the first V-cycle after full multigrid already stalls (the residual falls by less\n\
     than 15 %) and BiCGStab finishes in 2 iterations. Whole generations in one process\n\
     (`generate_timing` with `WHOLE_ONLY=1`, best of 3, the commit before and this one alternated twice):\n\
     `mountain-ridges` 1.36–1.47 s → 1.05–1.11 s, `volcanic-island-48` 1.89–2.12 s → 1.88–1.98 s\n\
     (within its spread).\n\
     \n\
     2026-11-28: the noise amplitude and roughness are diffused at half resolution from 256 samples a\n\
     side and interpolated back, painted samples exact (`src/parameters.rs`): in a single `relief\n\
     diffuse` of `mountain-ridges` at 2048² their two solves took 250–290 ms and take 85 ms. They stay\n\
     within 0.4 % of their range of the full solve on average, one sample off by a third of it beside a\n\
     calm crack crossing a rough ridge (the coarse grid places that edge a sample off); the fixture\n\
     terrains at 2048² moved by under 1 m at the 99.9th percentile, 19 m at most (one sample of\n\
     `mountain`, 2.2 km of relief), and the golden hashes and gallery were re-made. Painting reuses one\n\
     canvas per worker (same bits). Whole 2048² generations in one process (`generate_timing` with\n\
     `WHOLE_ONLY=1`, best of 3, the commit before and this one alternated twice, AMD EPYC):\n\
     `mountain-ridges` 914–991 → 766–780 ms, `volcanic-island-48` 1.46–1.54 → 1.27–1.37 s, `mountain`\n\
     2.53–2.59 → 2.22 s, `lake` 2.09–2.12 → 1.82–1.88 s, `canyon-step-3` 1.44–1.45 → 1.26 s, `desert`\n\
     0.98–1.00 → 0.77–0.79 s. Issue #26's 0.6 s is not reached: on `mountain-ridges` the elevation\n\
     solve (full multigrid 70–80 ms, then V-cycles of 20–27 ms each at 2048², one kept and five more\n\
     inside BiCGStab), the painting and the detail noise are what is left.\n\
     \n\
     Later on 2026-11-28: the elevation's cycles are W-shaped below the finest level (each coarse level\n\
     corrects with two cycles of the level below; Laplace problems keep V-cycles, which W made 20–40 %\n\
     slower), and a cycle hands over to BiCGStab when it takes off less than 30 % (15 % before). At\n\
     2048² the elevation solves reach the same tolerance in fewer iterations (`mountain` 15 → 8,\n\
     `lake` 13 → 6, `volcanic-island-48` 6 → 4, `canyon-step-3` 5 → 3, `mountain-ridges` 3 → 1) and\n\
     much closer to the converged solution (mean distance `mountain-ridges` 1.65 → 0.08 m, `desert`\n\
     0.40 → 0.02 m, `canyon-step-3` 0.42 → 0.01 m; worst `volcanic-island-48` 26.9 → 7.8 m). Whole\n\
     2048² generations, the same protocol: `mountain-ridges` 758–808 → 720–738 ms,\n\
     `volcanic-island-48` 1.26–1.36 → 1.23 s, `mountain` 2.20 → 1.92–1.99 s, `lake` 1.80–1.84 →\n\
     1.54–1.57 s, `canyon-step-3` 1.22–1.27 → 1.13–1.15 s; `desert` 0.72–0.79 → 0.80–0.83 s is the\n\
     one slower (its V-cycles had converged in two plain cycles, to 0.40 m of the solution). A single\n\
     `relief -v diffuse` of `mountain-ridges` at 2048², diffusion step, alternated over four rounds:\n\
     1.07–1.24 s at the start of the day, 0.86–0.99 s now.\n\
     The criterion rows below were re-measured after these changes and a set-up that builds the finest\n\
     level row-major once (same bits; `mountain-ridges` set-up 75–90 → 67–77 ms), on the AMD EPYC:\n\
     `generate/2048` 1.24 s (2.61 s on 11-26, Intel), `generate/512` 119 ms against the paper's 168 ms,\n\
     `multigrid/4096` 1.27 s (4.68 s).\n\
     \n\
     Later still on 2026-11-28: a cycle that stalls hands BiCGStab its step as the first search direction\n\
     (the same vector as preconditioning the start's residual: one cycle fewer), BiCGStab keeps six\n\
     grids instead of nine with fused vector updates (fresh grids page-fault on first touch), the detail\n\
     noise runs octave by octave along a row with one lattice lookup per run of samples in a cell,\n\
     `floor` and the weight quantization no longer call libm (same bits), and the CLI tells glibc to keep\n\
     freed grids for reuse (`mallopt`: 223 k → 77 k page faults in a 2048² `diffuse`). `relief -v\n\
     diffuse` at 2048², diffusion step, three runs each of the session's first commit (ef071ff) and its\n\
     last, alternated: `mountain-ridges` 886–1155 → 522–596 ms (under issue #26's 0.6 s),\n\
     `volcanic-island-48` 1.25–1.30 → 0.96–1.09 s, `mountain` 1.98–2.16 → 1.67–1.69 s, `lake` 1.61–1.79\n\
     → 1.31–1.33 s, `desert` 832–941 → 578–623 ms, `canyon-step-3` 1.22–1.43 → 0.99–1.06 s. The criterion\n\
     rows below (in process, glibc's default allocator) were re-measured: `multigrid/2048` 272 → 140 ms,\n\
     `generate/2048` 1.24 → 1.06 s, `generate/512` 119 → 107 ms. The terrains moved by 1.5 cm at most\n\
     (1024²).\n\
     \n\
     2026-12-01: hole windows that share samples are solved as one, their bounding box, when that box\n\
     has no more samples than they have in all (`raster::merge_overlapping`). On `mountain` the 76\n\
     windows covered 7.35 M samples, 2.7 times their union, and become one window (the whole 4.19 M-sample\n\
     grid); `volcanic-island-48`'s 149 windows (2.74 M samples) become 2 boxes of 2.03 M, `lake`'s 4.67 M\n\
     become 7 boxes of 2.81 M; on `canyon-step-3` at 2048² the box would be larger, so its windows stay. The fills\n\
     also come closer to the paper's diffusion over the whole map: the smooth terrain (no noise) against\n\
     one hole diffusion over the whole grid differed by 15.9 m mean and 1 725 m worst on `mountain` (a\n\
     gash beside the summit, visible in the gallery before this change), 7.3 / 575 m on `lake` and 0.50 /\n\
     294 m on `volcanic-island-48`; merged, 0 / 0 m, 0.13 / 15 m and 0.018 / 5.4 m. Rasterization (painting\n\
     and holes) at 2048², best of 6 alternated twice (Intel Xeon): `mountain` 704–726 → 601–611 ms,\n\
     `volcanic-island-48` 358–361 → 274–282 ms, `lake` 490–509 → 384–386 ms. Whole 2048² generations\n\
     (`generate_timing` with `WHOLE_ONLY=1`, best of 3, the commit before and this one alternated twice,\n\
     AMD EPYC): `volcanic-island-48` 1.03–1.12 → 0.97–1.01 s, `mountain` 1.72–1.96 → 1.63–1.71 s (its\n\
     elevation solve 8 → 7 iterations), `lake` 1.56–1.67 → 1.53–1.61 s, `mountain-ridges` unchanged\n\
     (0.64–0.74 s both). The criterion rows below were re-measured the same day (AMD EPYC):\n\
     `generate/512` 107 → 91 ms, `generate/1024` 362 → 301 ms, `generate/2048` 1.06 → 1.08 s (within\n\
     this VM's spread between sessions; still 1.6× the paper's 675 ms).\n\
     \n\
     2026-12-01 (evening), the same bits again (golden hashes unchanged): the elevation band's elevation\n\
     and noise are painted in one pass, the scanline rounding no longer calls libm\n\
     (`heightfield::rounding`), and the hole fills read and write their windows row by row in parallel.\n\
     Rasterization alone of `volcanic-island-48` at 2048², best of 5, alternated three times: 324–336 →\n\
     291–324 ms. Tried and not adopted: hole fills at half resolution (the volcanic island's fill 190 →\n\
     120 ms, but the smooth terrain moved by up to 76 m there and 79 m on `mountain`); hole fills to a\n\
     relative residual of 3e-3 or 1e-2 instead of 1e-3 (`mountain`'s rasterization 674 → 602 or 538 ms,\n\
     its terrain 14 or 41 m off at worst); the noise parameters and the detail computed alongside the\n\
     elevation solve (the same bytes, within 3 %: both already use both cores); transparent huge pages\n\
     for the grids (glibc's `hugetlb=1` tunable: page faults in a 2048² `relief diffuse` fell from 110 k\n\
     to 35 k, but the kernel's time rose from 0.33 to 0.7–0.8 s and the diffusion step from 0.94–1.0 to\n\
     1.3–1.4 s); and, in a serial prototype, 2–6 Gauss–Seidel passes after each coarse correction over\n\
     the free fine samples whose interpolation reads a fixed coarse sample (the ring the correction\n\
     cannot reach): the full multigrid's start improved (3.3e-3 → 2.5e-3 of the initial residual on the\n\
     volcanic island) and `mountain` took 5 iterations instead of 7, but each cycle still cut the\n\
     residual by only about half, so the stall is not the ring's alone. That day's criterion rows (AMD\n\
     EPYC, in a slow phase of this VM: `generate/2048` 1.16 s against 1.08 s earlier that day) included\n\
     `generate_paper_budget`, the whole volcanic-island generation with the paper's fixed budget, to set\n\
     against Table 2: 47, 183 and 684 ms against the GPU's 168, 275 and 675 ms.\n\
     \n\
     2026-12-02: coarse rows at their own spacing. A free coarse row averaged its fine neighbourhood's\n\
     weights and kept their mix of Laplacian ((1 − a)/4 on each neighbour) and upwind first difference\n\
     (a). On twice the spacing the same equation's second difference shrinks 4× and its first difference\n\
     2×, so the coarse row must weight its upwind part 2a/(1 + a) and take 4/(1 + a) times the fine\n\
     mean right-hand side (`coarse_row` in `solver.rs`; the residual's restriction already grew each row\n\
     by 4 − 2a, which is 4/(1 + a) for such a row). The finest slope rows are half gradient (a = ½), so\n\
     every coarse level under-weighted the slopes and the cycles stalled on slope bands. The weights are\n\
     now stored in units of 2⁻¹⁵ rather than 2⁻¹⁶, since coarse upwind weights grow towards 1. At 2048²\n\
     the elevation solves went from 4 to 3 iterations (`volcanic-island-48`), 7 to 4 (`mountain`), 7 to\n\
     4 (`lake`), 3 to 2 (`canyon-step-3`) and 2 to 2 (`desert`), all of them now plain W-cycles cutting\n\
     the residual 0.27–0.48× each, where `BiCGStab` had taken over after a first cycle of about 0.5×;\n\
     the full multigrid's start is 1.8e-3 of the initial residual on the volcanic island (2.6e-3\n\
     before). Whole 2048² generations, best of 3, the commit before and this one alternated twice in a\n\
     slow phase of this VM: `volcanic-island-48` 1.11–1.19 → 0.81–0.89 s, `mountain` 2.01–2.09 →\n\
     1.38–1.56 s, `lake` 1.71–1.74 → 1.16–1.23 s, `canyon-step-3` 1.20–1.22 → 0.99–1.12 s, `desert`\n\
     0.72–0.73 → 0.63–0.64 s. The paper's Jacobi pyramid solves the same coarse problems, so its fine\n\
     levels now start closer (the errors above). Tried with the new rows: V-cycles below the top (γ = 1)\n\
     solved faster (130–229 against 187–334 ms) but stopped up to 1.4 m (mean) and 47 m (worst) from\n\
     the converged solution (`desert`, where W-cycles stop 0.02 and 1.1 m); one sweep before and after\n\
     each correction instead of two took 2–9 iterations and longer; three took 1–3 iterations in about\n\
     the same time. A 2048² generation of the volcanic island now spends (in process, best of 3,\n\
     0.74 s): 0.30 s painting and filling holes, 0.15 s building the elevation hierarchy and its full\n\
     multigrid start, 0.11 s in three cycles, 0.11 s on the amplitude and roughness, 0.06 s on the\n\
     detail. The criterion rows below are this change's run (AMD EPYC): `generate` 78, 222 and 805 ms at\n\
     512², 1024² and 2048² (85, 305 ms and 1.16 s before; the GPU's 168, 275 and 675 ms),\n\
     `generate_paper_budget` 53, 160 and 624 ms, and the 4-curve scene's elevation solve alone\n\
     (`multigrid`) 16, 39, 113 and 485 ms from 512² to 4096² (24, 73, 164 ms and 1.05 s).\n\
     \n\
     Later the same day the elevation's W-cycle stops at the fourth level (`W_LEVELS` in `solver.rs`):\n\
     levels 1 to 3 run two cycles on the level below, deeper ones one. A W-cycle visits level l\n\
     2^(l − 1) times, so at 2048² (ten levels) the coarsest ran its 60 sweeps 256 times per cycle, and\n\
     the small levels' per-visit costs outweighed their arithmetic. Every Table 2 scene took the same\n\
     iterations at 512², 1024² and 2048² and stopped as close to the converged solution (means within\n\
     0.03 m; the same worst cases but `desert` at 1024², 2.32 against 1.97 m); the volcanic island's\n\
     elevation solve at 2048² took 215–242 against 254–259 ms (best of 10, alternated twice), its whole\n\
     generation 733–899 against 821–923 ms (best of 3, alternated three times, a noisy phase of this VM).\n\
     Running the W from the first two coarse levels only left `desert` at 2048² 0.13 m (mean) and 3.3 m\n\
     (worst) from the converged solution, against 0.02 and 1.1 m. The criterion rows were not re-run.\n\
     \n\
     On 2026-12-02 (morning) the set-up, the hole fills and the noise maps got faster, on a slower VM\n\
     than the day before (an AMD EPYC with AVX2 only, where the volcanic island's 2048² generation at the\n\
     evening's commit took 1.3–1.5 s against 0.69–0.9 s on the AVX-512 machine): Table 2 and the\n\
     criterion rows below were not re-measured, and the figures here are this machine's, each build\n\
     alternated with the evening's commit (best of N). The coarsening adds each coarse row's sums term\n\
     by term over the whole row, straight from the colour-split storage, in the same order as before (no\n\
     row-major copy of any level; the loops vectorize): the volcanic island's elevation set-up 108–127 →\n\
     90–96 ms, the same bits. Laplace levels (the hole fills' and the noise maps') are coarsened from\n\
     their fixed samples alone, and `laplace_like` shares the weights instead of copying them: a 2048²\n\
     Laplace set-up 92–101 → 37–38 ms, `mountain`'s hole fills (three solves over the whole grid) best\n\
     790 → 653 ms. The painting scans each triangle by rows or by columns, whichever crosses it fewer\n\
     times (5.65 M → 4.07 M lines for 2.1 M samples on the volcanic island, 15.0 M → 12.7 M for 4.9 M on\n\
     `mountain`; the same bits, the time saved within noise). The noise amplitude and roughness are\n\
     solved to a relative residual of 10⁻³ (`NOISE_TOLERANCE`, as the hole fills), not the elevation's\n\
     10⁻⁴: one cycle after their starts instead of six, the volcanic island's two solves 184–216 → 82–99 ms; the\n\
     terrains of `volcanic-island-48`, `mountain`, `lake` and `desert` moved by 3.3, 3.9, 2.5 and\n\
     0.15 cm on average and 0.42, 1.26, 0.68 and 0.19 m at most. Whole 2048² generations, best of 3,\n\
     alternated five (three) times: `volcanic-island-48` 1.31–1.44 → 1.19–1.37 s (medians 1.40 → 1.27),\n\
     `mountain` 2.11–2.30 → 1.92–2.07 s, `lake` 1.75–1.83 → 1.64–1.82 s, `canyon-step-3` 1.54–1.68 →\n\
     1.42–1.48 s, `desert` 0.95–1.10 → 0.80–0.90 s: 6–15 % faster. Tried and dropped: the hole fill's\n\
     three solves one after the other rather than side by side (a first generation's page faults in the\n\
     hole fills 98 k → 62 k on `mountain`, but its rasterization 1.10–1.20 → 1.25–1.27 s). A first\n\
     generation of the volcanic island in a fresh process takes 166 k page faults, 100 k of them in the\n\
     rasterization: 25 k for the maps, 33 k for the 16 painting canvases rayon's split jobs make, 40 k\n\
     in the hole fills.\n\
     \n\
     On 2026-12-02 (later, the same AVX2 VM) the painting's memory and the solver's norms, with the same\n\
     bits. Painting keeps one canvas per worker thread (`CanvasPool`): `for_each_init` had made one per\n\
     job rayon split the 32 bands into, 16–20 a generation, each faulted in afresh; the canvas keeps its\n\
     sums and counts in separate arrays, the noise's two sums sharing one count (65 → 49 bytes a\n\
     sample), and a sample painted once is not divided. The reference norm and each cycle's residual\n\
     norm are summed chunk by chunk from scratch rows (`Level::residual_sq`) instead of from a stored\n\
     residual (the volcanic island's elevation start and its three cycles about 15 ms sooner each).\n\
     Laplace problems fill their finest level in one pass (`Level::filled`). A first 2048² rasterization\n\
     of the volcanic island in a fresh process: 100 k → 71 k page faults; `desert`'s (painting only)\n\
     341–368 → 228–273 ms. Whole first generations in a fresh process without the CLI's allocator\n\
     settings (four alternated runs): `volcanic-island-48` 1.44–1.56 → 1.31–1.40 s, `mountain` 1.96–2.22\n\
     → 1.82–2.02 s. With the CLI's settings, which already reused freed canvases, `relief -v diffuse` at\n\
     2048² (diffusion step, alternated): `volcanic-island-48` 1.15–1.25 → 1.08–1.18 s (medians 1.18 →\n\
     1.16), `mountain` 1.72–1.96 → 1.67–1.92 s (within noise). Tried and dropped: stations a cell\n\
     apart instead of half a cell (painting 25–30 % faster, but the terrain 2–4× further from a\n\
     quarter-cell painting: 99.9th percentile 0.6–1.8 m against 0.2–0.5 m, and 74 m against 18 m at\n\
     worst below the lake's cliff); more full-multigrid cycles on the coarse levels of the Laplace\n\
     problems (the start stays at 9.5–9.6 × 10⁻³ of the initial residual: the error left is the finest\n\
     level's) and W-cycles for them (the same iterations, the volcanic island's hole fills 277 →\n\
     322 ms). Faulting memory in ahead with `MADV_POPULATE_WRITE` costs 2.2 µs a page on this VM\n\
     against 3 µs for a first touch, too little to be worth an allocator hook. A first generation\n\
     still takes 90 k page faults with the CLI's settings (63 k of them in the rasterization: the maps\n\
     and the hole fills' three solves, side by side).\n\
     \n\
     On 2026-12-02 (noon), on an AMD EPYC with AVX-512 again. `relief` now gives every thread one malloc\n\
     arena (`M_ARENA_MAX` 1, beside its other `mallopt` settings): with an arena per thread, a grid\n\
     freed on one rayon worker could not serve the next allocation made on another, and a first 2048²\n\
     `relief diffuse` of `volcanic-island-48` took 105 k page faults, now 74 k (`mountain` 125 k →\n\
     80–93 k); the diffusion stage's time moved within this VM's noise (484–549 → 471–507 ms, three\n\
     alternated rounds). The solver's finest start serves both the reference norm and the full\n\
     multigrid's last level, and the iterate kept before each cycle lives in one buffer (the same bits).\n\
     The criterion rows below were re-run the same hour: `generate/2048` 480 ms, 0.71× the paper's GPU.\n\
     Whole first generations in the CLI, `relief -v diffuse SCENE --resolution 2048` (its diffusion\n\
     stage, ten runs in two passes, the VM's speed drifting by a quarter between them), against Table\n\
     2's GPU: `volcanic-island-48` 463–649 ms (median 566; 0.84× the GPU's 675), `mountain` 741–992\n\
     (817; 1.22× its 670), `lake` 589–811 (655; 0.95× its 690), `canyon-step-3` 548–767 (623; 0.77×\n\
     its 811), `desert` 332–412 (371; 0.58× its 635), and the issue's `mountain-ridges` 315–455 (407).\n\
     Under the issue's 0.6 s: `mountain-ridges`, `desert` and the volcanic island in most runs; not\n\
     `mountain` (its whole-grid hole fill and five cycles) nor, by a few per cent, `lake` and\n\
     `canyon-step-3`. On the AVX2-only EPYC of the morning the same generations took about twice as\n\
     long. Measured and not pursued: a W-cycle from the first coarse level took 7–12 ms against 1–2 ms\n\
     for that level's own sweeps, but running its levels serially or with a higher parallel threshold\n\
     changed nothing measurable (short rows, not thread hand-offs, make the cost); more smoothing on the\n\
     finest level (V(2,3), V(3,3), V(2,4)) cut the hole fills' cycles (the normals' 2 → 1, the step's 1\n\
     → 0) without making the fills faster. Of `mountain`'s painting (about 160 ms warm), 48 ms are the\n\
     samples' own work, 88 ms the scanlines and triangles around them (1.36 M triangles, 9.0 M lines,\n\
     60 % of them empty, for 4.1 M samples) and 21 ms the canvases and maps: what is left there is the\n\
     scan's overhead, not the painting. Setting each triangle's edges up once for all its lines (their\n\
     ranges of y, runs and rises; the same bits) changed nothing measurable: each line's division and\n\
     its branch on an empty span remain.",
    ),
    (
        "gaussian_terrain",
        "Rasterizer rows re-measured 2026-11-26 after the row loops went through `pulp` (AVX2) with\n\
     whole-vector spans and fused polynomials; the previous rasterizer on the same machine, same\n\
     session: 62.5 ms (10k), 102.7 ms (30k), 131.7 ms (60k) at 1024². The 60k row is still 1.3× the\n\
     issue #25 target of 50 ms. Query rows: batched continuous queries at the 1024² sample positions\n\
     (`TerrainQuery::elevations`, hierarchy built once outside the timing); they test about twice the\n\
     supports each point lies in, so they run at a third of the rasterizer's speed per sample.\n\
     \n\
     Queries re-measured 2026-11-27 after each cell's points went into groups of 16 neighbours that\n\
     skip the supports they cannot reach (a conservative box test in each support's own frame; the\n\
     former test, the support ellipse grown by the cell's half-diagonal, missed slivers of elongated\n\
     supports by up to 0.8 % of their amplitude). This VM ran about 1.5× slower than on 11-26, so the\n\
     rows below are left as they were. Two criterion runs today: rasterize/1024/60k 96.4 and 88.3 ms,\n\
     query/samples 216.4 and 238.3 ms, query/elevations 237.6 and 250.0 ms, build 40.7 and 47.7 ms:\n\
     2.2–2.8× the rasterizer per sample. Interleaved in one process (rasterizer, new query, former\n\
     query on the same 1024² samples, best of 10, three runs): the new query takes 0.78–0.85 of the\n\
     former's time. `elevations` now skips the gradients (unless a detail layer follows the slope):\n\
     on this terrain that gains little (2.2–2.3× the rasterizer against 2.1–2.5× for `samples`, same\n\
     runs), but with a noise detail layer (100 000 falloffs of σ 20, the one in `tests/query.rs`)\n\
     added, `elevations` took 1.34 s against the rasterizer's 0.42 s, and `samples` 24.1 s: a detail\n\
     layer's gradient is a central difference, which walked the hierarchy four more times per point.\n\
     It now reuses the cell's falloffs (culled with the step added): 5.8 s, still four more sums of\n\
     every falloff over the point, in f64. What is left is the kernel itself (gradient terms, and a logarithm and a power\n\
     for every β ≠ 2, on every lane of a group a support may reach) against the rasterizer's\n\
     value-only spans cut to the samples inside each support.\n\
     \n\
     Rasterizer re-measured 2026-11-27 (evening) after its set-up (each primitive's inverse axes,\n\
     support and rows) went parallel; the table rows below are the 11-26 run's and are left as they\n\
     were. One criterion run each, the same session, before → after: 1024²/10k 34.5 → 33.4 ms,\n\
     1024²/30k 59.3 → 53.3 ms, 1024²/60k 57.6 → 55.1 ms, 4096²/60k 612 → 621 ms (one run each: within\n\
     this VM's noise). Alternated in one process, best of 10, three rounds, 1024²/60k: 55–58 ms before,\n\
     51–54 ms after, the same output bits (hashed). Tried and dropped, measured the same way: copying\n\
     each band's primitives next to each other (1024²/60k 50–51 ms, but 1024²/10k 32 → 41 ms),\n\
     whole-vector chunks in the row loop (2 ms slower at 60k), bands of 8 rows (67–75 ms) or 32 (no\n\
     change). Lanes counted on the 1024²/60k terrain: the rasterizer evaluates 22.3 M lanes over\n\
     1.22 M row spans (81 % of them inside a support); the batched query 36 M lanes (53 %) behind\n\
     4.78 M f64 box tests. Groups of 8 points, each support tried with the kernel's own inside test\n\
     after a box test of 8 supports at once, cut that to 25 M lanes (76 %) but took 229–252 ms\n\
     against 214–222 ms single-threaded: the cost is per (group, support) pair, not per wasted lane.\n\
     Storing the supports in the hierarchy's leaf order did not help either.\n\
     \n\
     Queries re-measured 2026-11-28 after they went the rasterizer's way: the points sorted into\n\
     strips (a grid row, or a quarter of a typical support width of y for scattered points), bands of\n\
     16 strips in parallel, each support added to the stretch of each strip its ellipse covers, the\n\
     Gaussians stored by the y of their centres. Criterion, the same session (the table rows below are\n\
     the 11-26 run's and are left as they were): rasterize/1024/60k 56.5 ms, query/elevations 71.7 ms\n\
     (1.27×), query/samples 88.8 ms (1.57×), build 24.0 ms. Alternated in one process against the\n\
     former query (best of 8, three rounds, 1024² grid in row order): elevations 123–125 ms → 68 ms\n\
     (2.0–2.5× → 1.29–1.34× the rasterizer's 51–53 ms), samples 135–146 → 95–99 ms; 1M scattered\n\
     points in random order 122–143 → 130–135 ms (the sort into strips is a counting sort by slabs,\n\
     then small sorts); 100 000 single queries 3.5 → 4.1 µs each (a batch of one allocates its strip).\n\
     Every support's arithmetic is unchanged, but the summation order (by centre y, not index)\n\
     changes f32 roundings: the golden `gaussian-atlas` skeleton's elevations were re-blessed. What\n\
     is left against the rasterizer: about 11 ms building the strips (sorting check, cutting, each\n\
     point's corner and coordinates) and the stretches' own work (the x range of an ellipse over a\n\
     strip, two square roots, where the rasterizer's row needs one; the cut at each anchor square;\n\
     loading each point's coordinates where the rasterizer steps them).\n\
     \n\
     Since 2026-11-28 `cargo xtask bench` regenerates the rows of every group from the medians on disk\n\
     and carries the others over (marked †), so the rows below are this group's last criterion run\n\
     (2026-11-28, on this VM's current CPU, an AMD EPYC; the 11-22 rows of other groups ran on an Intel\n\
     Xeon): rasterize/1024/60k 55.5 ms, query/elevations 68.1 ms (1.23×), query/samples 84.1 ms\n\
     (1.51×), build 23.2 ms. Tried and dropped, alternated in one process against the committed query\n\
     (best of 8, three rounds): exact stretches on grid rows (one load and compare at each end instead\n\
     of a neighbour that may come along: 7 % fewer lanes, but 2.5–3 ms slower, the loads sitting on\n\
     the stretch's critical path), and a parallel first pass over the points (filter and order check:\n\
     no gain, the 4 MB index vector's first touch dominates). Time per part of `elevations` on this\n\
     CPU: 10–11 ms building the strips (3 ms checking and indexing, 2 ms cutting, 5 ms filling them),\n\
     53 ms in the bands' kernels (the rasterizer's whole run is 51–55 ms), 2 ms writing the results.\n\
     A point alone (a single query, or a band of one point) now sends every candidate support\n\
     straight to the kernel, whose inside test decides, instead of finding an x range and a stretch\n\
     per support: 100 000 single queries on this terrain 3.95–4.0 → 2.5 µs each (alternated, three\n\
     rounds; the 11-27 query took 3.5 µs), the same bits.\n\
     \n\
     Since 2026-11-28 (afternoon) `pulp`'s `x86-v4` feature (AVX-512 on stable Rust) is on, and a span\n\
     or stretch is widened to whole vectors of the dispatched register's width (16 f32 with AVX-512, 8\n\
     with AVX2) rather than always to 8. The output bits are unchanged (golden hashes unchanged; the\n\
     vector-against-scalar test now runs the AVX-512 build on this CPU). Best of 10 in one process on\n\
     the 1024²/60k terrain: rasterization 51.0–51.7 → 42.3–45.0 ms (45.8–46.3 ms with AVX-512 but\n\
     8-wide spans); batched elevations 65.7–68.3 → 63.0 ms (65.7–67.1 ms with 8-wide stretches). The\n\
     rows below are the criterion run after it: the rasterizer under the issue #25 target of 50 ms,\n\
     and the query further from the rasterizer (1.42×) because the rasterizer gained more. A profile\n\
     of `elevations` puts 58 % of its time in the vector loops, 23 % in each stretch's scalar work\n\
     (x range, ranks, anchor cuts, the support's local frame) and 12 % in building the strips and\n\
     writing the results. The diffusion solver's sweeps, dispatched the same way, did not change\n\
     (`mountain-ridges` at 2048², best of 3: 874–894 against 886–939 ms).\n\
     \n\
     On 2026-11-29 the strips lost their serial passes. The check that a batch's points are within\n\
     the anchor lattice and in order of y runs in parallel, and when they are (a grid in row order)\n\
     no index vector is made; strips are cut only where y changes, the changes found in parallel; a\n\
     strip finds where its anchor squares change by a search instead of placing every point; and a\n\
     batch in the order given writes its results strip by strip in parallel. Timed inside\n\
     `elevations` on the 1024²/60k grid: building the strips 18–25 → 8–9 ms (ordering 6 → 2 ms,\n\
     cutting 5 → 1.5 ms, filling 11 → 5 ms), writing the\n\
     results 3.6 ms → a parallel collect; the bands' kernels are unchanged at 44 ms. Best of 8 in one\n\
     process, alternated with the former build (four rounds): elevations 65–75 → 54–58 ms\n\
     (1.60–1.72× → 1.31–1.44× the rasterizer's 39–45 ms in the same runs), samples 104–117 →\n\
     95–103 ms; 1M scattered points (best of 20: 113–121 against 112–124 ms) and single queries\n\
     (1.5 µs) unchanged; every output bit the same (hashed). The query rows and the 1024²/60k\n\
     rasterizer rows below are that day's criterion run, on an Intel Xeon VM (the 11-28 rows ran on an\n\
     AMD EPYC): elevations 1.27× the rasterizer. What is\n\
     left is in the kernels' stretches: the x range of a support over a strip (two square roots\n\
     where the rasterizer's row needs one), ranks, anchor cuts, a load per point where the\n\
     rasterizer steps its coordinates, and an inside test on every lane.\n\
     \n\
     On 2026-12-02 (on an AMD EPYC with AVX-512) a grid row's stretch became exact without a search:\n\
     the strip measures how far each point's place `(x − x₀)·n/(x_last − x₀)` lies from its index\n\
     (its drift, 0 to rounding on a grid row), and a support's x range maps to the indices within the\n\
     drift of its ends, so no neighbour comes along at each end (lanes 29.2 → 28.2 M, stretches\n\
     1.30 M against the rasterizer's 1.22 M spans, the rest being anchor cuts; the 11-28 attempt,\n\
     which loaded each end's x, had been slower). A point's anchor run is found by a scan among a\n\
     strip's few runs instead of a bisection (5 % of the kernel's profile had gone to its branches),\n\
     strips are filled column by column instead of point by point, and each band of a batch in row\n\
     order writes its own stretch of the output as it ends instead of a collect over all strips.\n\
     The same bits (golden hashes and a hash of 1M scattered points unchanged). Interleaved in one\n\
     process with the rasterizer on the 1024²/60k terrain (21 rounds, the median of the per-round\n\
     ratios, three runs alternated with the former build): elevations 1.23–1.29× → 1.14–1.21× the\n\
     rasterizer (best elevations 63–68 → 51–62 ms); single queries and 1M scattered points\n\
     unchanged. Criterion in a slow phase of this VM the same hour: rasterize/1024/60k 61–67 ms,\n\
     query/elevations 70–79 ms (1.10–1.30×); the rows below are left from 11-29. Tried and dropped,\n\
     measured the same way: bands of 32 strips (no change); on one thread, AVX2 (8-lane) dispatch for\n\
     the query alone (1.30–1.41× against 1.21–1.27×), stretches widened to 8 lanes within the\n\
     AVX-512 loop (slower: LLVM's remainder loop) and coarser anchor squares (64 typical widths:\n\
     within noise); and a branch-free count in place of the bisection that picks a support's strips\n\
     within a band (no measurable change). Then a stretch that passes into the next anchor square went in one pass\n\
     instead of two, the lanes past the square's edge taking that square's brackets (the same bits:\n\
     each point still computes from its own square's corner): per-round ratio medians 1.12–1.19× →\n\
     1.09–1.13×, CPU time 1.15–1.21× → 1.13× the rasterizer's (three runs alternated). What is left:\n\
     the hierarchy walk and the sort of each band's candidates (about 4 % of the CPU time), the\n\
     strips' set-up (3 %), and a stretch's scalar work (the x range of an ellipse over a strip, two\n\
     square roots where the rasterizer's row needs one).\n\
     \n\
     On 2026-12-03 (an Intel Xeon VM with AVX-512, about twice as slow as the 11-29 one and noisy:\n\
     the rasterizer's best of 21 ranged 70–160 ms over the session) a band wide enough (a quarter of\n\
     the Gaussians' x extent: a grid's, a scattered batch's) takes its candidates without the\n\
     hierarchy. The Gaussians are stored by the y of their centres, so with each one's running\n\
     highest top (over those before it) and lowest bottom (over those after it) two bisections bound\n\
     the ones that may meet the band, and an exact box test keeps them, already in the order every\n\
     point sums them; a 1024² grid's bands of 16 rows scan 3.5–6 k Gaussians and keep about 2 k\n\
     (the walk returned each leaf's up to 8 supports whole, to be sorted). A narrow band (a single\n\
     query) still walks the hierarchy and now drops the leaf-mates its box misses, and a stretch with\n\
     no next anchor square compares each lane once (its split is past every lane). The same bits: a\n\
     hash of the 1024² grid's elevations and of 1M scattered points unchanged, golden hashes\n\
     unchanged. Interleaved with the rasterizer on the 1024²/60k terrain (21 rounds, CPU time now\n\
     summed over every thread, where the 12-02 figures counted the calling thread only; four runs\n\
     alternated with the former build): elevations 1.18–1.22× → 1.16–1.17× the rasterizer's CPU\n\
     time, per-round wall-time ratio medians 1.12–1.18× → 1.10–1.16×. Tried and dropped, measured\n\
     the same way: one square root for a row's x range (the widest over the slack-thick band and the\n\
     centre line's extremes, a superset the inside test trims; 1.16–1.18× against 1.12–1.15×), both\n\
     roots in one vector (LLVM kept two scalar roots), and other hierarchies for single queries\n\
     (obvhs's medium and slow builds, leaves of 2, 4 or 8: 7.1–9.7 µs each, no gain). Single queries\n\
     take 7–10 µs on this VM for the 11-29 build, the 12-02 build and this one alike, so the 11-29\n\
     note's 1.5 µs does not reproduce here (this VM's rasterizer is 2× slower than that day's, its\n\
     single queries 5–6×); 1M scattered points 217–540 ms for either build. Where the CPU time goes now:\n\
     the query's band kernels take 80 % of its time (vector lanes 56 %, a stretch's scalar work\n\
     25 %), the rasterizer's 87 % of its own (vector 56 %, scalar 31 %), so the kernels are within\n\
     about 6 % of each other; what is left is the query's per-point bookkeeping outside them\n\
     (building strips, 4 %: index, f64 and f32 coordinate vectors and the drift; the bands' f32 sums\n\
     turned into f64 results), about 10 % of the rasterizer's time.\n\
     \n\
     Later on 2026-12-03, the same VM: a batch's bookkeeping outside the kernels trimmed, the same\n\
     bits (both hashes, golden test). Strips of points in the order given and by x (a grid's rows)\n\
     keep no list of indices; a scan for changes of y, the order check and a strip's drift test each\n\
     block of points without a branch per point; each support's reach box is stored packed for the\n\
     window scans (about 2 % of the CPU time had gone to reading them from the supports); each band\n\
     writes its strips' results row by row. Interleaved with the rasterizer (21 rounds, three runs\n\
     alternated with the former build): the query's CPU time per 1024² batch 216–233 ms → 197–208 ms,\n\
     but the rasterizer, whose code did not change, took 189–206 → 172–185 ms in the new build (code\n\
     placement), so the ratio stayed at 1.13–1.17×. Profile of the query now: band kernels 86 %, the\n\
     rest 14 % (strips 3 %, candidate scans 1.3 %, the order and change scans about 2 %, results\n\
     0.5 %). What separates the two is now mostly inside the kernels: the query's takes about 14 %\n\
     more time than the rasterizer's (two square roots per stretch and a point's coordinates loaded\n\
     rather than stepped).\n\
     \n\
     Afternoon of 2026-12-03, the same VM: two changes to the query's band kernel and one to the\n\
     rasterizer's, the same bits (both query hashes, a hash of the 1024² raster, golden test). Lanes\n\
     outside a stretch or a support now add +0 instead of keeping the old sum (no sum is ever −0, the\n\
     one value +0 would change), so each lane takes one add and a plain store: 1.15–1.17× → 1.08–1.14×\n\
     the rasterizer's CPU time (six rounds alternated with the former build). Then each support's\n\
     stretches over a band's strips are found first and the kernel run over each after: a kernel's\n\
     first load (a point's coordinate) waits on its stretch's square roots and roundings, which had\n\
     each sat behind the previous kernel loop's exit branch; back to back they overlap: 0.99–1.06×,\n\
     and a profile put the query's band kernels 7 % below the rasterizer's. The rasterizer has the\n\
     same shape (a primitive's row spans, each behind the previous row's loop), so it got the same\n\
     change (spans of a primitive's rows first), and the ratio is back to 1.09–1.14×: against the\n\
     morning's build (eight rounds) the rasterizer's CPU time per 1024²/60k 168–189 → 155–181 ms, the\n\
     query's 196–219 → 170–202 ms. Criterion in quick mode the same hour (this VM's slow phase, so\n\
     the rows below are left as they were): rasterize/1024/60k 78.7 ms, query/elevations 88.6 ms\n\
     (1.13×), query/samples 131.7 ms, build 64.0 ms; before the rasterizer's change 96.6 and 98.5 ms\n\
     (1.02×). Tried and dropped: loops without the per-lane choice of the next square's brackets for\n\
     stretches in one square (no change), bands of 8 strips (1.18–1.22× against 1.15–1.20×) or 32\n\
     (no change), touching each stretch's first point before the kernels (1.07–1.10× against\n\
     1.03–1.06×), and the stretches in a vector per band instead of a stack array (1.09–1.19× against\n\
     0.98–1.05×, likely code placement). The query's band kernels are now 84 % of its CPU time; the\n\
     rest, 16 %, is the per-point work the rasterizer does not have (strips, the order check, results).\n\
     \n\
     Late afternoon of 2026-12-03, the same VM: three changes to the query's bookkeeping, the same bits\n\
     (both query hashes, golden test). Each band builds its own strips just before it sums them (all\n\
     strips had been built first, 12 MB for a 1024² grid, and the kernels read them back from memory);\n\
     a batch in y order writes each band's stretch of the output even when a strip sorted its points by\n\
     x. In sorted input each run of one y ends where a search by doubling steps and a bisection finds\n\
     it (a grid row: about 20 looks instead of 1024; the scan of every point had been 2–3 % of the\n\
     query's CPU time). The order check tests each chunk of points against a bound in their own units\n\
     before it divides (its pass 3.6 → 2.4 % of the CPU time). Against the session's first build (eight\n\
     rounds alternated): the query's CPU time per 1024² batch 1.11–1.14× → 1.05–1.09× the rasterizer's.\n\
     The query's bookkeeping outside its band kernels now costs about what the rasterizer's does; its\n\
     kernels' function takes about 7 % more than the rasterizer's (per stretch: the strips a support\n\
     reaches, the run a stretch starts in, the next square's brackets). Criterion in quick mode went\n\
     from 0.94× to 1.19× between runs in the same hour, so the rows below are left as they were. Tried\n\
     and dropped: the change search fused into the order check (no change); a stretch stored for every\n\
     strip, empty ones skipped in the kernel loop, in place of the compacted list (1.11–1.17× against\n\
     1.04–1.08×); a stretch's run found by a branch-free count in place of the scan (1.13–1.16× against\n\
     1.04–1.10×).\n\
     \n\
     Evening of 2026-12-03, the same VM: a harness that holds two variants in one binary behind a switch\n\
     and alternates them with the rasterizer repetition by repetition (31 each, CPU time summed over\n\
     threads) resolves about 1 % (two identical variants: 0.993–1.020 over nine runs), where separate\n\
     builds alternated by round vary by ±5 %. Counted on the 1024² grid of 60k Gaussians, the query's\n\
     kernels do exactly the rasterizer's work: 1.222 M stretches against 1.222 M spans, 1.707 M vectors\n\
     against 1.705 M, 18.04 M lanes inside against 18.01 M, 132 k candidates against 132 k band members;\n\
     what it costs more is set-up per stretch. Kept: the elevations' kernel is compiled with and without\n\
     the per-lane choice of the next square's brackets, and a stretch in one square takes the second\n\
     (0.979–0.997× the query's CPU time over four runs; in separate builds over ten rounds the median\n\
     ratio to the rasterizer went 1.043 → 1.033; the same split had shown no change in other code\n\
     before). The gradients' kernel showed none (0.994–1.023×) and keeps one loop. Tried and dropped,\n\
     each in that harness: a support's x range, stretch and roundings over all of a band's strips at once\n\
     in f64 vectors, with no search for the strips it reaches (0.994–1.010×: the profile's set-up hot\n\
     spots moved into the kernel's first loads); a stretch's run by a branch-free count (1.088–1.120×:\n\
     the scan's branch is predicted, the count is a dependency the kernel waits on); at least two vectors\n\
     per stretch so the loop's trip count is predictable (1.087–1.109×); two one-vector stretches of\n\
     adjacent rows summed in one pass (1.040–1.066×, and the binary's other path 1.20× the rasterizer);\n\
     the elevations' output allocated zeroed rather than filled in parallel (0.982–1.013×); the\n\
     single-query path dispatched as its own `pulp` operation, so that the bands' function is smaller\n\
     (1.019–1.033×); loops aligned to 64 bytes (`-C llvm-args=-align-loops=64`: no change). The query's\n\
     CPU time per 1024² batch in these binaries: 1.01–1.05× the rasterizer's in most, 0.98–1.12× over\n\
     all but the pairs' one.\n\
     \n\
     On 2026-12-04 (an AMD EPYC VM with AVX-512) the rows below are a criterion run again, the first for\n\
     this group since 11-29, with no query or rasterizer code changed since 12-03: rasterize/1024/60k\n\
     45.9 ms, under the issue's 50 ms, query/elevations 49.0 ms (1.07×), samples 47.8 ms, build 27.6 ms.\n\
     Six runs of the pair alone in the hour before: rasterizer 51.9–57.5 ms, query 49.9–56.4 ms,\n\
     0.87–1.05× run by run. The example `query_vs_raster` (`cargo run --release -p\n\
     relief-gaussian-terrain --example query_vs_raster`) alternates one rasterization and one batch of\n\
     the same 1024² samples call by call and times them as a user sees them (wall time, both threads):\n\
     over fourteen runs of 31 rounds the median per-round ratio was 0.950–0.999 (medians 44.9–58.1 ms for\n\
     the query, 46.3–62.1 ms for the rasterizer). On this VM batched queries are as fast per sample as\n\
     rasterization, 0–5 % faster; on 12-03's Intel VM the CPU-time harness above gave 1.01–1.05×.",
    ),
    (
        "engine_export",
        "`glb` rows time a whole mesh export: greedy-insertion decimation to the error bound (a fraction of\n\
     the relief), normals, colours and the GLB bytes. On the 1025² fBm terrain (539 m of relief) 0.1 %\n\
     (0.54 m) keeps 445 133 triangles (21 % of the grid's two per sample), 1 % (5.4 m) 27 580 (1.3 %);\n\
     Jacksboro (403 × 344, 840 m) at 1 % keeps 69 985 (25 %: a rough 3″ DEM). Counts from\n\
     `cargo run --release -p relief-engine-export --example mesh_sizes -- fbm:1025 0.539 5.39`.\n\
     The Khronos glTF validator (npm `gltf-validator`) reports no error or warning on these files.\n\
     `splat` is the four masks (slope, elevation, convexity, D8 flow on the filled terrain) and the\n\
     layer weights; `prepare` resamples a 1025² terrain to Unity's 4 × 4 tiles of 257.",
    ),
];

/// Paragraphs printed under a section's heading and intro when the section is generated (a
/// section carried over from the previous report keeps its own): measurements made by hand
/// beside the section's runs, and what to read from them. Keyed by the heading's text.
pub(crate) const SECTION_NOTES: &[(&str, &str)] = &[
    (
        "gaussian-terrain, vectorize",
        "The same protocol on a real DEM (`relief vectorize` of Jacksboro resampled to 1024², `--resolution \
         1024 --primitives 10000`), re-measured 2026-12-01 after the backward pass read whole 16-lane vectors \
         in place (it copied 8 samples at a time into stack arrays): 32.1 s, 9453 primitives, ℓ₁ 4.29e-3 \
         (42.4 s before, the same ℓ₁; 48.2 s before the kernels used AVX-512; 65.6 s before the loss kept its \
         buffers between steps: glibc's allocator handed them back to the system every step and faulted them \
         in again, a quarter of the CPU time). The time saved buys steps: `--iterations 350` reached ℓ₁ \
         3.39e-3 with 9979 primitives in 56.6 s. Then the initialisation placed 90 % of the budget (80 % \
         before) and the per-parameter step sizes grew by a quarter (tuned on this DEM, checked on the four \
         of the fidelity tables below, where ℓ₁ fell 2–10 % but on Luxembourg, within 1.5 % there): 200 \
         steps 30.2 s, 9992 primitives, ℓ₁ 3.84e-3; 350 steps 53.4 s, 9995 primitives, ℓ₁ 3.31e-3, inside \
         the 60 s target (the fBm rows above: 3.17e-3 → 2.93e-3). With all flat ground weighing 32 in the \
         last fifth of the steps (below; this DEM has a reservoir), 200 steps 32.7 s, 9991 primitives, ℓ₁ \
         3.87e-3; 350 steps 56.7 s, 9995 primitives, ℓ₁ 3.33e-3. With the loss's sample-wise passes in \
         parallel (its errors, SSIM windows, products and sums had run on one thread; the same bytes), 200 \
         steps alternated with the former build 32.5–32.7 → 29.2–31.1 s, 350 steps 55.7 s (the fBm rows \
         above, re-run with it: 10.4, 11.3 and 32.8 s against 11.9, 11.6 and 33.8 s). Measured on the way, at 200 steps: a 95 % \
         share alone 3.87e-3, with the larger steps 3.74e-3, but on budgets of a few hundred the levels' grids \
         round their counts up to the whole budget and densification had no room left (it could exceed \
         it: the initialisation is now cut to the budget, keeping its most voluminous primitives); step \
         sizes 2× and 3× alone 3.95e-3 and 4.00e-3 (with the 95 % share, 1.5× 3.70e-3 and 2× 3.58e-3); \
         decaying the step size to 0.3 of itself rather than 0.1, 4.14e-3; densifying every 25 steps, or by \
         10 % of the budget a round, 4.17e-3 and 4.14e-3. Table 3 gives 2.24e-3 at 6k and 2.21e-3 at 11k \
         primitives on the paper's own DEM: our ℓ₁ at this budget is 1.5–1.7× the paper's (1.3× on the fBm \
         DEM). Tried and dropped (the same DEM and protocol): a fit that starts on a 512² \
         grid and ends on the 1024² one (its primitives scaled over, Adam restarted) reached 3.56e-3 in \
         39.1 s (300 + 150 steps), better than 1024² alone for that time, but 3.49e-3 in 56.3 s (400 + 200), \
         no better than 350 steps at 1024²; half the step size on the fine grid, 3.66e-3. Before the \
         backward pass ran as a pulp operation it called the software `fmaf` (its fast transcendentals' \
         `mul_add`s ran outside pulp's FMA context): the same 1024² fit took about 4 × longer, the 512² rows \
         61.7 and 68.4 s.",
    ),
    (
        "gaussian-terrain, vectorize",
        "How Table 3 reads (noticed 2026-12-03). Its columns add up to its ℓ (at 11k primitives 2.21 + 1.31 \
         + 7.64 = 11.16 against 11.1, at 6k 12.79 against 12.8, at 20k 10.14 against 10.1; only the 3k row \
         is off, by 0.16), and the paper defines ℓ as α₁ℓ₁ + α₂ℓ_LPIPS + (1 − α₁ − α₂)ℓ_SSIM with α₁ = 0.5 \
         and α₂ = 0.25 (§4). If its ℓ is that loss, each column is a weighted term and the ℓ₁ column is \
         α₁·ℓ₁: a mean error of 4.48e-3 at 6k and 4.42e-3 at 11k, against which ours at 10k (3.33e-3 on \
         Jacksboro in 350 steps, 56.7 s; 2.93e-3 on the fBm DEM) is 0.75× and 0.66×. If the columns are the \
         raw terms and ℓ only their plain sum, the ratios above hold (1.5× and 1.3×). The paper does not \
         say which, and its DEM is not ours, so these notes keep the stricter reading: under it, the \
         issue's target is not met yet (the authors' code, read on 12-04, settles it otherwise: see \
         \"Table 3's unit\" below). \
         Fitting ℓ₁ alone does not lower it: at 40 primitives per 1000 samples and 200 steps (the fidelity \
         table's protocol), Jacksboro's ℓ₁ went from 8.77e-3 with the paper's weights (0.5, 0.25, 0.25) to \
         10.52e-3 with ℓ₁ alone, 8.93e-3 with (0.75, 0.25 on the gradient term, no SSIM) and 9.67e-3 with \
         (0.75, no gradient term, 0.25 SSIM); Salish's from 36.94e-3 to 39.33e-3, 38.69e-3 and 36.46e-3.",
    ),
    (
        "gaussian-terrain, vectorize",
        "Adam's second moment (2026-12-03, night). Our per-parameter steps had kept PyTorch's β₂ = 0.999, \
         whose mean squared gradient remembers the large gradients of the first steps for hundreds of steps: \
         every parameter's step shrinks as the fit settles, on top of the learning rate's decay to a tenth. \
         With β₂ = 0.95 (a memory of about 20 steps) the steps keep their size until the schedule lowers it, \
         and larger step sizes then pay; the defaults are now β₂ = 0.95 and 1.5× the former step sizes (the \
         paper's Adam, `uniform_steps`, keeps 0.999). On Jacksboro at 1024² with 10 000 primitives: 200 steps \
         48.2 s, 9980 primitives, ℓ₁ 3.45e-3 (3.87e-3 before); 350 steps 76.2 s, 9998 primitives, ℓ₁ 2.99e-3 \
         (3.33e-3 before). The VM was in a slow phase this hour: the former build took 80.7 and 93.1 s for \
         the same 350 steps, 56.7 s on 12-01; a step's work is the same. The fBm rows above: 3.08, 3.35 and \
         2.93e-3 → 2.85, 3.26 and 2.80e-3. Against Table 3 at 11k, under the stricter reading ours is now \
         1.35× the paper's on Jacksboro (1.27× on fBm at 200 steps), under the weighted one 0.68×. Measured \
         on the way (the same DEM, 350 steps): β₂ 0.95 alone 3.14e-3; with the steps 1.25×, 1.5×, 2× and 3×: \
         3.05, 3.00, 2.97 and 3.31e-3; with 2× and a decay to 0.05 rather than 0.1, 2.95e-3; β₂ 0.95 with a \
         decay to 0.15, 3.19e-3. 2× fitted closest at the DEM's own resolution (the fidelity tables' \
         Jacksboro 7.46e-3 against 7.73e-3 at 40 per 1000) but worse where the fit runs on a grid coarser \
         than the DEM (the default `--resolution 512` of a 1024² DEM, 200 steps: fBm 3.35 → 3.56e-3, \
         Luxembourg resampled to 1024² 5.11 → 5.50e-3), where 1.5× stays within 3 % of the former fit or \
         better (fBm 3.26e-3, the row above; Jacksboro 4.79 → 4.50e-3, Salish-land 3.49 → 3.40e-3, Luxembourg \
         5.26e-3). At the fidelity protocol (40 per 1000; Jacksboro, Salish and Luxembourg), β₂ from 0.8 to \
         0.97 all beat 0.999 by 2–7 % with the former steps (0.95 by 2–7 % over seeds 0–2); β₁ 0.8 helped \
         with β₂ 0.999 (Jacksboro 8.43e-3 against 8.77e-3) but not with 0.9 (8.30e-3 against 8.28e-3), β₁ \
         0.95 was worse (9.61e-3). Over seeds 0–35 at the paper's density, Luxembourg's mean ℓ₁ went from \
         76.9 to 70.5 × 10⁻³ with no open-flat error above 1 % of the relief (one of 0.55 %, seed 17; 0.16 % \
         at most before), and Salish-land's open sea stays under 0.3 %.",
    ),
    (
        "gaussian-terrain, vectorize",
        "Shorter tails while placing (2026-12-04). A fit's first four fifths place primitives (densification) \
         and its last fifth settles them; the placing steps now cut each support at 10⁻² of its amplitude \
         (3.03 σ for β = 2) rather than at the render's 10⁻³ (3.72 σ), two thirds of the samples, and the \
         settling fifth fits the tails at 10⁻³ (a fit at 10⁻² throughout had left a 50 % larger ℓ₁ at render; \
         a fit with a time budget or a target loss, which may stop at any step, keeps 10⁻³ throughout). The \
         default budget went from 200 to 260 steps, about what 200 cost before. On Jacksboro at 1024² with 10 \
         000 primitives, on this day's VM (an AMD EPYC with AVX2 only, in a slow phase: the former build took \
         80.8 s for 350 steps, ℓ₁ 2.99e-3): 350 steps 58.8 and 64.4 s (two runs), ℓ₁ 2.98e-3; 420 steps 72.0 \
         s, 2.83e-3; 450 steps 73.6 s, 2.86e-3; the default 260 steps 50.4 s, 3.20e-3; 200 steps 39.9 s, \
         3.47e-3. The fBm rows above (200 steps): 2.85, 3.26 and 2.80e-3 → 2.95, 3.28 and 2.81e-3 for the \
         same steps in 15.2, 13.9 and 40.3 s; at 260 steps on the 1024² grid, 2.63e-3 in 45.5 s. Against \
         Table 3 at 11k under the stricter reading: 1.35× on Jacksboro in 58.8–64.4 s (1.28× in 72 s), 1.19× on \
         fBm in 45.5 s. On the small real DEMs of the fidelity tables, the same 200 steps fit up to 6 % worse \
         (Luxembourg at the paper's density 69.06 → 73.20 × 10⁻³; Salish-land 0.6 % better) in 20–35 % less \
         time, and 270 steps 1–6 % better than 200 before; the tables below are at the new default of 260 \
         steps. Over seeds 0–35 at the paper's density (260 steps), Luxembourg's mean ℓ₁ went from 70.5 to \
         67.1 × 10⁻³ and its largest open-flat error from 0.55 to 0.23 % of the relief; Salish-land's open \
         sea at 0.03 % at most. Measured on the way (Jacksboro 1024², 350 steps): 3·10⁻² while placing, \
         3.01e-3 in 45.0 s but no closer for the same time (470 steps: 2.88e-3 in 61.4 s); 10⁻² until the \
         last tenth, 3.00e-3; 3·10⁻² until the last tenth, 3.32e-3; 10⁻¹, 8.16e-3. Tried and dropped: a \
         least-squares solve of the amplitudes after the fit (the shapes fixed, conjugate gradients on the \
         normal equations): on ℓ₂ it moved ℓ₁ by −0.5 to +2.6 % on Jacksboro, Salish and Luxembourg at 40 per \
         1000 (and raised Luxembourg 2 % of the relief beyond its range), reweighted towards ℓ₁ (four rounds \
         of ten iterations) −0.6 to −1.6 %: the amplitudes Adam leaves are close to their optimum, the error \
         is in the shapes and places; and, on AVX2, the backward pass's 16 partial sums in two passes of 8 \
         (half the accumulator registers live, the same bits): 5–13 % slower. The criterion row \
         `gaussian_terrain/vectorize/256/2k-20-steps` (an fBm DEM at 256², 2 000 primitives, 20 steps of \
         which 16 place) does not move: the bench binaries before and after, alternated four times on this \
         VM, took 504–568 ms and 506–569 ms (its row above is of an earlier VM). The saving does not show at \
         that size, where a support is a few samples wide: on Jacksboro at 256² with 2 000 primitives, \
         `relief vectorize` takes 0.11 s for 1 step, 0.38 s for 20 and 1.42 s for 100.",
    ),
    (
        "gaussian-terrain, vectorize",
        "Table 3's unit, read from the authors' code (2026-12-04; their public repository \
         Arches-Team/vector-based_terrain_modelling, `optimisation/`). Their optimisation reads the DEM as a \
         16-bit PNG divided by its largest value, so its elevations span [0, 1] (at most), and fits PyTorch's \
         `L1Loss` of the rasterized image against that; the [−1, 1] of §4 is the primitives' domain (their \
         positions are clipped to it). So Table 3's ℓ₁ is a mean error as a fraction of the whole relief, \
         half the figures in these notes, which divide by the half-range (and if their PNG does not span all \
         of [0, 1], their error relative to the relief is only larger). Their loop also logs each term \
         multiplied by its weight and ℓ as the sum (`losses.py`, `optimise_utils.py`), which is why Table 3's \
         columns add up to its ℓ; the code's weights are 0.4, 0.2 and 0.2 (the paper's 0.5, 0.25 and 0.25 \
         scaled by 0.8, the same balance), so its ℓ₁ column would be 0.4·ℓ₁, a raw mean error of 5.53e-3 of \
         the relief at 11k primitives. `VectorizeReport::l1_of_relief` gives our error in that unit and \
         `relief vectorize` prints it. At 1024² with 10 000 primitives and the default 260 steps, on this session's \
         VM (an AMD EPYC with AVX-512): Jacksboro 30.2 s, 9995 primitives, 1.60e-3 of the \
         relief (350 steps: 42.4 s, 1.49e-3); Salish-land 28.3 s, 9531 primitives, 1.36e-3; Luxembourg (its \
         no-data filled at its lowest elevation) 31.7 s, 9520 primitives, 0.82e-3; the fBm DEM at 260 steps \
         1.32e-3 (45.5 s on 12-04's slower morning). Against Table 3's 2.21e-3 at 11k read as a raw ℓ₁ that \
         is 0.72× on Jacksboro (0.37–0.62× on the others), against the 5.53e-3 it stands for if weighted \
         0.29×: the issue's target (at or below Table 3 for the same budget at 1024², in at most 60 s on 2 \
         cores) is met under either reading. The \"stricter reading\" above compared a half-range figure with \
         a whole-relief one. One caveat stays: our real DEMs are resampled up to 1024² (Jacksboro from 403 × \
         344), smoother than a native 1024² DEM such as the paper's; the fBm DEM, generated at 1024² with \
         detail down to the sample, fits to 1.32e-3.",
    ),
    (
        "gaussian-terrain, vectorize",
        "The issue's own protocol on a real coast (`relief vectorize` of `fixtures/dem/salish-land.tif` \
         resampled to 1024² with `relief convert --size 1024`, `--resolution 1024 --primitives 10000`, then \
         `relief rasterize --size 1024`), re-measured 2026-11-28 after the floor's flat ground got the flat \
         weight in the last fifth of the fit: 45.3 s (the VM loaded by other work; 43.2 s before), 8369 \
         primitives, mean error 0.17 % of the relief (the issue measured 0.5 % and 56.6 s on its island \
         DEM); the lowest sample is exactly the sea's 0 and the highest 0.69 % below the DEM's top; over the \
         open sea (357 020 samples whose 5 × 5 neighbourhood, cut at the grid's edge, is sea) the mean error \
         is 4 × 10⁻⁶ % and the largest 0.21 % of the relief (0.32 % before), against the lacy −4.6 % the \
         issue found. Again on 2026-12-01 with the faster backward pass, the 90 % initial share and the \
         larger steps: 29.8 s, 9046 primitives, mean error 0.16 %, the lowest sample 0, the highest 0.34 % \
         below the top, over the open sea a mean of 2 × 10⁻⁸ % and a largest error of 0.003 %. With all \
         flat ground weighing 32 in the last fifth: 30.4 s, 9044 primitives, mean error 0.16 %, the highest \
         sample 0.34 % below the top, the open sea exact (mean and largest error 0 to the display's \
         0.001 %).",
    ),
    (
        "Real DEMs: fidelity, and our choices against the paper's",
        "What wins: ours. Per-parameter steps are the largest gain. The paper's Adam as its authors' code runs it \
         (`uniform_steps`, since 2026-12-04, later: one constant step size, 10⁻², for every parameter of their \
         parametrisation, tanh positions across the domain's [−1, 1] and heights in [0, 1], so that a centre moves \
         up to 0.5 % of the grid's width per step, with PyTorch's β₂ = 0.999) leaves ℓ₁ 1.07–1.27× ours at the \
         paper's density, 1.11–1.65× at 4× it, and 1.9–5.1× at the paper's protocol below; at 1000 steps \
         rather than 260 (the authors run up to 1001), 1.04–1.18× at the paper's density. The former rows took \
         that step size in our raw units (a centre moving a hundredth of a sample per step) and read 1.29–1.78×: \
         they overstated the gap on these small DEMs. The paper's kernel exponents (β′ ∈ (1, 2) in \
         exp(−(½d²)^β′), which is ours with β = 2β′ in [2, 4]: `paper-exponents`, the option `beta_range`) \
         cost 0.5–7.8 % in ℓ₁ on these DEMs, whose rough ground takes peaked (β < 2) and flat-topped (β > 4) \
         shapes; at 1024² they come within 2 % of ours (Jacksboro 1 % lower) and fit 13–25 % faster, their \
         supports being narrower: a choice left to the user, not the default. Error-driven densification beats positional gradients by up to 6.6 % in ℓ₁ (the two tie on Luxembourg at both densities, and come within 1.2 % on Salish and Salish-land at the paper's). Keeping the range lowers ℓ₁ by 2–23 % where the sea or the filled no-data is flat (but on Salish-land at 40 per 1000, where the plain sum's ℓ₁ is 3.4 % lower by rising 17.2 % of the relief beyond the range), removes the rises and dips beyond the DEM's range there (up to 22.2 % of the relief with the plain sum) and the ripples over the flat (open-flat error 0.00 % against 0.85–10.7 %); on ground that is flat above the minimum (Jacksboro's \
         reservoir, the Salish shores) its extra weight on flat samples cuts the error there 2.5–3.2× (flat mean 0.06–0.20 % against 0.20–0.58 %, open-flat max 0.08–0.33 % against 0.35–1.32 %), for at most 4.4 % more ℓ₁ (the Salish topobathy at 40 per 1000). These tables are of 2026-12-04, at the new default of 260 steps, the placing steps' tails cut at 10⁻² (see the vectorize section): ours fell 1–6 % in ℓ₁ from the 12-03 tables (200 steps, Adam's second moment forgetting in about 20 steps and 1.5× the step sizes, which had lowered ours 4–12 % from the 12-01 tables and kept the paper's rows' bytes), the paper's rows, which take the same steps, 3–12 %; their times were that day's VM, an AMD EPYC with AVX2 only. \
         Re-run later on 12-04 (the same VM family, with AVX-512, so the times moved): every row but the \
         `paper` and `uniform-steps` ones (now with the authors' step sizes, and the paper's with their \
         exponents) has the same bytes. \
         The paper's protocol (Table 3: 1024², 10 000 primitives), each DEM resampled to 1024² and fitted \
         there in 260 steps (`SIZE=1024 PRIMITIVES=10000`; ℓ₁ ×10⁻³ of the half-range as in the tables, \
         Table 3's unit being half; this VM): Jacksboro ours 3.20 in 33.4 s, `paper` 12.53, `uniform-steps` \
         9.62, `paper-exponents` 3.17 in 26.1 s; Salish-land 2.73 in 25.5 s, 6.42, 5.25, 2.76 in 22.2 s; \
         Luxembourg 1.61 in 31.8 s, 10.92, 8.13, 1.64 in 23.7 s (the paper's rows 28–36 s). At 1000 steps, \
         Jacksboro: ours 2.54, `paper` 10.57, `uniform-steps` 10.86 (at 260 steps 9.62: a constant step \
         of that size no longer settles). Within our pipeline (our initialisation, loss and rasterizer) the \
         authors' optimizer therefore stays 2.4–6.8× above ours at their own protocol, and above their \
         Table 3 (2.21 × 10⁻³ of the relief, 4.42 in these units), which their own pipeline reaches; what \
         differs there (their random initialisation, LPIPS, 1001 steps keeping the best) is not ours to \
         reproduce without their network weights. The floor's own flat ground gets that weight too in the last fifth of the \
         steps, once densification is over (since 2026-11-28): before, the land's primitives left bumps \
         over Luxembourg's filled border at the paper's density (1.55 % of the relief with seed 0, \
         2.3–22.8 % with seeds 1–5), after it 0.26 % (0.00–0.31 %), for 0.2–1.2 % more ℓ₁; the open sea of \
         the Salish coast went from 0.06 % (0.41–0.79 %) to 0.00 % (0.00–0.40 %). Weighting it from the \
         first step cut the bump too but cost 19 % of ℓ₁. The bump was not gone: over seeds 0–11 at the \
         paper's density (`SEED=k`), Luxembourg's border kept one above 1 % of the relief in 1 fit of 12 \
         with the 11-28 defaults (6.2 %, seed 7) and in 3 of 12 with the 12-01 ones (26.3 %, 12.5 % and \
         1.2 %; seeds 4, 5 and 10), whose ℓ₁ there is 3.4 % lower on average (76.0 against 78.6 × 10⁻³); \
         with the 90 % share alone, 2 of 12 (20.9 % and 1.1 %). Salish-land's open sea stays under 0.6 % \
         in all of them. Dropping, after the fit, every primitive whose removal alone lowers the ℓ₁ over \
         its support did not remove those bumps (their primitives also cover land; another seed's rose to \
         3.3 %) and was left out. The bumps are land primitives, often flat-topped (β near 8) and thin, \
         that follow the border and reach over it, half hidden by negative ones below the floor. Since \
         2026-12-01 all flat ground weighs 32 in the last fifth of the steps (4 before that fifth). Over \
         seeds 0–35 at the paper's density, the last fifth's weight against Luxembourg's bumps above 1 % of \
         the relief and its mean ℓ₁ (× 10⁻³): 4, 9 of 36 (up to 26.3 %), 75.4; 8, 5 (9.4 %), 75.9; 12, 4 \
         (9.9 %), 76.4; 16, 3 (10.9 %), 76.8; 32, 1 (2.8 %, seed 31), 77.4; 64, none in seeds 0–11 but 6 % \
         more ℓ₁. With 32 the other DEMs' ℓ₁ moved by −0.1 to +0.5 % at the paper's density and by at most \
         1.2 % at 4× (Salish), their flat ground's mean error fell up to 2.3× (Jacksboro 0.31 → 0.14 %). \
         Tried and dropped: pushing the sum back up where it falls below the floor (so that negative \
         primitives cannot hide there), 33–36 bumps in 36 and 11–28 % more ℓ₁ (the floor is what lets a \
         small fit follow a coast); a light weight on the floor's flat ground from the first step (0.05 or \
         0.25 of the flat weight, 16 in the last fifth), 5 and 1 bumps of 36 for 2.4 and 6.7 % more ℓ₁; a \
         weight growing with the error there, 17–43 % more ℓ₁. \
         Seed 31's bump was not the flat weight's: it appeared after the fit, when the pruning (§4) \
         dropped a thin negative primitive along the border (23:1, beyond the elongation limit t_e of 20) \
         that had cancelled land primitives there. Since 2026-12-01 (later) the fit holds every primitive \
         within t_e, its area kept, so the pruning no longer removes a primitive the others lean on: over \
         seeds 0–35 the largest open-flat error is 0.16 % of the relief (seed 24), none above 0.5 %, and \
         the mean ℓ₁ 76.9 against 77.4 × 10⁻³. No primitive of the other fits at the paper's density \
         reached the limit (the same bytes, as for the 1024² Jacksboro protocol); at 4× Salish-land and \
         Luxembourg moved (ℓ₁ 54.23 → 54.07 and 41.05 → 40.42). \
         What is left: at the paper's density these \
         DEMs, far rougher per sample than a 1024² one, stay at ℓ₁ 2.2–8.4 × 10⁻².",
    ),
    (
        "studio",
        "Island edits resume from the island the page's last preview left (`relief::pipeline::preview_in`\n\
         with the session's `EditSession`). The same 100-edit history through `POST /api/generate` (release\n\
         `relief serve`, 2026-11-27, medians of 20 appended edits): replayed from scratch, as before, 227 ms\n\
         on the server (224 ms of it the island step); resumed, 4.3 ms (0.1 ms of island step for a hill\n\
         edit, plus copying the kept island). Before resuming, the first line's server time was 24.8 ms. The\n\
         contour line moved from 271 ms to 505 ms between runs on this noisy VM with no change to that path.",
    ),
];

/// `(criterion id, reference)`; a benchmark may have several references.
pub(crate) const REFERENCES: &[(&str, Reference)] = &[
    (
        "poisson/rect/100000",
        Reference::Fixed { label: "plain grid Bridson, same machine class (issue #2)", seconds: 0.37 },
    ),
    (
        "poisson/rect/100000",
        Reference::Fixed { label: "`fast_poisson` crate, same machine class (issue #2)", seconds: 1.6 },
    ),
    (
        "poisson/rect/1000000",
        Reference::Fixed { label: "plain grid Bridson, same machine class (issue #2)", seconds: 4.0 },
    ),
    (
        "poisson/rect/1000000",
        Reference::Fixed { label: "`fast_poisson` crate, same machine class (issue #2)", seconds: 65.0 },
    ),
    (
        "tin/build/10000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/10000",
        },
    ),
    (
        "tin/build/100000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/100000",
        },
    ),
    (
        "tin/build/1000000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/1000000",
        },
    ),
    (
        "tin/spade_bulk_load/100000",
        Reference::Fixed { label: "spade `bulk_load`, issue #2's measurement", seconds: 0.090 },
    ),
    (
        "tin/spade_bulk_load/1000000",
        Reference::Fixed { label: "spade `bulk_load`, issue #2's measurement", seconds: 0.7 },
    ),
    (
        "tin/rasterize_100k_to_2048",
        Reference::SideBySide { label: "our serial rasterizer, same run", bench: "tin/rasterize_serial_100k_to_2048" },
    ),
    // Contours paper, Table 1 (Ryzen 5 5600X) and the authors' code on this machine class.
    ("eden/growth/10000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.086 }),
    ("eden/growth/10000", Reference::Fixed { label: "authors' code, this machine class", seconds: 0.180 }),
    ("eden/growth/20000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.297 }),
    ("eden/growth/50000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 1.880 }),
    ("eden/growth/50000", Reference::Fixed { label: "authors' code, this machine class", seconds: 3.5 }),
    ("eden/growth/100000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 5.827 }),
    ("eden/growth/100000", Reference::Fixed { label: "authors' code, this machine class", seconds: 6.9 }),
    ("eden/growth/500000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 91.79 }),
    ("eden/graph/100000", Reference::Fixed { label: "authors' code, this machine class", seconds: 1.9 }),
    (
        "relief_contours/multilevel/3",
        Reference::SideBySide {
            label: "one pass at the same node count, same run",
            bench: "relief_contours/multilevel/1",
        },
    ),
    ("eden/regions/2", Reference::SideBySide { label: FIG_26, bench: "eden/regions/1" }),
    ("eden/regions/4", Reference::SideBySide { label: FIG_26, bench: "eden/regions/1" }),
    ("eden/regions/16", Reference::SideBySide { label: FIG_26, bench: "eden/regions/1" }),
    ("eden/regions/64", Reference::SideBySide { label: FIG_26, bench: "eden/regions/1" }),
    ("relief_table1/growth/10000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.086 }),
    ("relief_table1/growth/10000", Reference::Fixed { label: "authors' code, this machine class", seconds: 0.180 }),
    ("relief_table1/growth/20000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.297 }),
    ("relief_table1/growth/50000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 1.880 }),
    ("relief_table1/growth/50000", Reference::Fixed { label: "authors' code, this machine class", seconds: 3.5 }),
    ("relief_table1/growth/100000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 5.827 }),
    ("relief_table1/growth/100000", Reference::Fixed { label: "authors' code, this machine class", seconds: 6.9 }),
    ("relief_table1/growth/500000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 91.79 }),
    ("relief_table1/graph/100000", Reference::Fixed { label: "authors' code, this machine class", seconds: 1.9 }),
    ("contours/extract_10_levels/100000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.071 }),
    ("contours/extract_20_levels/100000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.142 }),
    ("contours/extract_30_levels/100000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.212 }),
    (
        "contours/extract_30_levels/100000",
        Reference::Fixed { label: "authors' code, this machine class", seconds: 0.340 },
    ),
    ("contours/extract_10_levels/500000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.386 }),
    ("contours/extract_20_levels/500000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.766 }),
    ("contours/extract_30_levels/500000", Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 1.140 }),
    (
        "relief_table1/extract_10_levels/100000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.071 },
    ),
    (
        "relief_table1/extract_20_levels/100000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.142 },
    ),
    (
        "relief_table1/extract_30_levels/100000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.212 },
    ),
    (
        "relief_table1/extract_30_levels/100000",
        Reference::Fixed { label: "authors' code, this machine class", seconds: 0.340 },
    ),
    (
        "relief_table1/extract_10_levels/500000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.386 },
    ),
    (
        "relief_table1/extract_20_levels/500000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 0.766 },
    ),
    (
        "relief_table1/extract_30_levels/500000",
        Reference::Fixed { label: "paper, Table 1 (Ryzen 5 5600X)", seconds: 1.140 },
    ),
    (
        "contours/pipeline_30_levels/1000000",
        Reference::Fixed { label: "target (issue #3): 1M particles end to end", seconds: 4.0 },
    ),
    ("contours/reconstruct_interpolated_2048", Reference::Fixed { label: "target (issue #3)", seconds: 1.0 }),
    (
        "relief_demo/generate_and_write",
        Reference::Fixed { label: "target (issue #5): `relief demo` in release", seconds: 5.0 },
    ),
    ("relief_preview/shade_4096", Reference::Fixed { label: "target (issue #5)", seconds: 1.0 }),
    (
        "diffusion/generate/512",
        Reference::Fixed {
            label: "paper, GPU (8800 GTS), Volcanic Island of Table 2 (48 curves, as ours), whole",
            seconds: 0.168,
        },
    ),
    (
        "diffusion/generate/1024",
        Reference::Fixed {
            label: "paper, GPU (8800 GTS), Volcanic Island of Table 2 (48 curves, as ours), whole",
            seconds: 0.275,
        },
    ),
    (
        "diffusion/generate/2048",
        Reference::Fixed {
            label: "paper, GPU (8800 GTS), Volcanic Island of Table 2 (48 curves, as ours), whole",
            seconds: 0.675,
        },
    ),
    (
        "diffusion/generate/2048",
        Reference::Fixed { label: "paper, GPU (8800 GTS), fastest of Table 2 (Hills), whole", seconds: 0.611 },
    ),
    ("diffusion/generate/2048", Reference::Fixed { label: "target (issue #26), whole", seconds: 0.6 }),
    ("diffusion/generate_paper_budget/512", Reference::Fixed { label: PAPER_BUDGET, seconds: 0.168 }),
    ("diffusion/generate_paper_budget/1024", Reference::Fixed { label: PAPER_BUDGET, seconds: 0.275 }),
    ("diffusion/generate_paper_budget/2048", Reference::Fixed { label: PAPER_BUDGET, seconds: 0.675 }),
    (
        "diffusion/multigrid/512",
        Reference::SideBySide {
            label: "the paper's Jacobi pyramid at its fixed budget (not converged), our code; solve only",
            bench: "diffusion/jacobi_pyramid/512",
        },
    ),
    (
        "diffusion/multigrid/1024",
        Reference::SideBySide {
            label: "the paper's Jacobi pyramid at its fixed budget (not converged), our code; solve only",
            bench: "diffusion/jacobi_pyramid/1024",
        },
    ),
    (
        "diffusion/multigrid/2048",
        Reference::SideBySide {
            label: "the paper's Jacobi pyramid at its fixed budget (not converged), our code; solve only",
            bench: "diffusion/jacobi_pyramid/2048",
        },
    ),
    ("diffusion/multigrid/2048", Reference::Fixed { label: "target (issue #7), solve only", seconds: 0.5 }),
    (
        "hydrology/flood_and_accumulation/4096",
        Reference::Fixed { label: "target (issue #6): fill + D8 accumulation", seconds: 3.0 },
    ),
    (
        "hydrology/priority_flood/1024",
        Reference::SideBySide {
            label: "textbook Priority-Flood+ε (Barnes 2014, Alg. 3), same run",
            bench: "hydrology/textbook_priority_flood/1024",
        },
    ),
    (
        "hydrology/priority_flood/2048",
        Reference::SideBySide {
            label: "textbook Priority-Flood+ε (Barnes 2014, Alg. 3), same run",
            bench: "hydrology/textbook_priority_flood/2048",
        },
    ),
    (
        "hydrology/priority_flood/4096",
        Reference::SideBySide {
            label: "textbook Priority-Flood+ε (Barnes 2014, Alg. 3), same run",
            bench: "hydrology/textbook_priority_flood/4096",
        },
    ),
    (
        "warp/points_100k_50_segments",
        Reference::Fixed { label: "interactive budget: one frame at 30 fps", seconds: 0.033 },
    ),
    ("island/silhouette_update/32", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.007 }),
    ("island/hills_updated_50/32", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.001 }),
    ("island/perturbations_1000/32", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.001 }),
    ("island/silhouette_update/64", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.03 }),
    ("island/hills_updated_50/64", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.002 }),
    ("island/perturbations_1000/64", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.002 }),
    ("island/silhouette_update/128", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.13 }),
    ("island/hills_updated_50/128", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.002 }),
    ("island/perturbations_1000/128", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.002 }),
    ("island/silhouette_update/256", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.58 }),
    ("island/hills_updated_50/256", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.003 }),
    ("island/perturbations_1000/256", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.003 }),
    ("island/silhouette_update/512", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 1.94 }),
    ("island/hills_updated_50/512", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.005 }),
    ("island/perturbations_1000/512", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.007 }),
    ("island/silhouette_update/1024", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 8.13 }),
    ("island/hills_updated_50/1024", Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.047 }),
    (
        "island/perturbations_1000/1024",
        Reference::Fixed { label: "paper, Pentium D 2.8 GHz (Table 4)", seconds: 0.036 },
    ),
    ("island/silhouette_update/1024", Reference::Fixed { label: "target (issue #10)", seconds: 0.05 }),
    // Perche et al. 2025, Table 1 and §6.1: rasterization on an RTX 3090 (10k primitives 15 ms,
    // 32k 17 ms, 62k 21 ms at 1024²; 388 ms at 4096²), and issue #8's targets on this CPU.
    ("gaussian_terrain/rasterize/1024/10k", Reference::Fixed { label: "paper, RTX 3090 (Table 1)", seconds: 0.015 }),
    (
        "gaussian_terrain/rasterize/1024/30k",
        Reference::Fixed { label: "paper, RTX 3090 (Table 1, 32k)", seconds: 0.017 },
    ),
    (
        "gaussian_terrain/rasterize/1024/60k",
        Reference::Fixed { label: "paper, RTX 3090 (Table 1, 62k)", seconds: 0.021 },
    ),
    ("gaussian_terrain/rasterize/1024/60k", Reference::Fixed { label: "target (issue #8)", seconds: 0.25 }),
    ("gaussian_terrain/rasterize/4096/60k", Reference::Fixed { label: "paper, RTX 3090 (§6.1)", seconds: 0.388 }),
    ("gaussian_terrain/rasterize/1024/60k", Reference::Fixed { label: "target (issue #25)", seconds: 0.05 }),
    ("gaussian_terrain/rasterize/4096/60k", Reference::Fixed { label: "target (issue #8)", seconds: 4.0 }),
    // Issue 25: batched continuous queries at least as fast per sample as rasterizing them.
    (
        "gaussian_terrain/query/elevations/1024/60k",
        Reference::SideBySide {
            label: "rasterizing the same 1024² samples, same run (target ≤ 1×)",
            bench: "gaussian_terrain/rasterize/1024/60k",
        },
    ),
    ("orometry/analyze/3601", Reference::Fixed { label: "target (issue #9)", seconds: 3.0 }),
    (
        "orometry/synthesize/3000",
        Reference::Fixed { label: "paper, Core i7 4 GHz, Python + C++ (§7, fastest case)", seconds: 60.0 },
    ),
    ("orometry/synthesize/3000", Reference::Fixed { label: "target (issue #9)", seconds: 30.0 }),
];
