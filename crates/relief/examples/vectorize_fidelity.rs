//! Vectorizes real DEMs and measures what a user sees when the result is rasterized back at the
//! DEM's grid: the mean error (of the relief's half-range, twice the unit of the paper's Table 3),
//! how far samples leave the DEM's own elevation range, and how much pattern appears over ground
//! that is exactly flat in the DEM (sea, filled no-data).
//!
//! The DEMs (`fixtures/dem/`, sources in its README):
//! - `jacksboro`: SRTM ridge-and-valley terrain, 403 × 344;
//! - `salish`: ETOPO-like topography and bathymetry of the Salish Sea, 120 × 91;
//! - `salish-land`: the same with the sea set to 0, as land-only DEMs (SRTM) store it: an island
//!   coast with 44 % flat sea;
//! - `luxembourg`: SRTM elevations of Luxembourg, 95 × 90, its no-data outside the border filled
//!   with its lowest elevation.
//!
//! `cargo xtask bench` runs it; each line is one fit. `DEMS=salish,luxembourg` picks DEMs, `SEED=3`
//! the seed of the initial placement (default 0), `ITERS=350` the steps (default the library's).
//! `SIZE=1024` resamples every DEM to 1024 × 1024 and fits at that resolution, and
//! `PRIMITIVES=10000` sets the budget (instead of `DENSITY`): with both, the protocol of the
//! paper's Table 3.
//!
//! Usage: `cargo run --release -p relief --example vectorize_fidelity -- [DENSITY] [VARIANT…]`:
//! `DENSITY` primitives per 1000 DEM samples (default 10, the paper's 10 000 at 1024²);
//! variants `ours` (default), `paper` (the paper's choices as its authors' code makes them: 3DGS
//! densification by positional gradients; their Adam, one constant step size for every parameter
//! of their parametrisation with PyTorch's moment decays; their kernel's exponents, β in
//! `[2, 4]`; the plain sum with no range kept), and ours with one of those choices:
//! `positional-densify`, `uniform-steps`, `paper-exponents`, `plain-range`.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use relief::gaussian_terrain::{Densify, RasterOptions, VectorizeOptions, rasterize, vectorize};
use relief::heightfield::Heightfield;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let density: f64 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(10.0);
    let mut variants: Vec<String> = args.collect();
    if variants.is_empty() {
        variants.push("ours".into());
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/dem");
    println!("| DEM | variant | primitives | time | ℓ₁ (×10⁻³) | beyond range | flat: mean | open flat: max |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    let only = std::env::var("DEMS").ok();
    let size: Option<usize> = env_number("SIZE")?;
    let primitives: Option<usize> = env_number("PRIMITIVES")?;
    for (name, dem) in dems(&dir)? {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|d| d == name)) {
            continue;
        }
        let dem = match size {
            Some(n) => dem.resample(n, n)?,
            None => dem,
        };
        let budget = primitives.unwrap_or(((dem.samples().len() as f64) * density / 1000.0).round() as usize);
        for variant in &variants {
            let mut options = options(variant, budget)?;
            if let Some(n) = size {
                options.resolution = n;
            }
            let fit = vectorize(&dem, &options, |_| ControlFlow::Continue(()))?;
            let back = rasterize(&fit.terrain, dem.grid(), &RasterOptions::default())?;
            let m = measure(&dem, &back);
            println!(
                "| {name} | {variant} | {} | {:.1} s | {:.2} | {:.2} % | {:.3} % | {:.2} % |",
                fit.report.primitives,
                fit.report.seconds,
                fit.report.l1_normalized * 1e3,
                m.beyond,
                m.flat_mean,
                m.open_max
            );
        }
    }
    Ok(())
}

/// The four DEMs, read as a user reads them.
fn dems(dir: &Path) -> Result<Vec<(&'static str, Heightfield)>, Box<dyn std::error::Error>> {
    let read = |f: &str| -> Result<Heightfield, Box<dyn std::error::Error>> {
        Ok(relief::io::read(PathBuf::from(dir).join(f))?)
    };
    let mut luxembourg = read("luxembourg.tif")?;
    let (lo, _) = luxembourg.min_max().ok_or("luxembourg.tif has no data")?;
    luxembourg.fill_no_data(lo)?;
    Ok(vec![
        ("jacksboro", read("jacksboro.asc")?),
        ("salish", read("salish.tif")?),
        ("salish-land", read("salish-land.tif")?),
        ("luxembourg", luxembourg),
    ])
}

/// The unsigned integer in environment variable `name`, if set.
fn env_number<T: std::str::FromStr>(name: &str) -> Result<Option<T>, String> {
    match std::env::var(name) {
        Ok(s) => s.parse().map(Some).map_err(|_| format!("{name}={s}: not an unsigned integer")),
        Err(_) => Ok(None),
    }
}

fn options(variant: &str, primitives: usize) -> Result<VectorizeOptions, String> {
    let seed = env_number("SEED")?.unwrap_or(0);
    let iterations = env_number("ITERS")?.unwrap_or(VectorizeOptions::default().iterations);
    let ours = VectorizeOptions { primitives, seed, iterations, ..VectorizeOptions::default() };
    Ok(match variant {
        "ours" => ours,
        "paper" => VectorizeOptions {
            densify: Densify::PositionalGradient,
            uniform_steps: true,
            beta_range: PAPER_BETA,
            keep_range: false,
            ..ours
        },
        "plain-range" => VectorizeOptions { keep_range: false, ..ours },
        "positional-densify" => VectorizeOptions { densify: Densify::PositionalGradient, ..ours },
        "uniform-steps" => VectorizeOptions { uniform_steps: true, ..ours },
        "paper-exponents" => VectorizeOptions { beta_range: PAPER_BETA, ..ours },
        other => return Err(format!("unknown variant {other}")),
    })
}

/// The paper's kernel `exp(−(½d²)^β′)`, `β′ ∈ (1, 2)`, as our exponents.
const PAPER_BETA: [f64; 2] = [2.0, 4.0];

/// What a user sees of a fit.
struct Measures {
    /// The furthest sample beyond the DEM's range, % of the relief.
    beyond: f64,
    /// Mean |error| over samples whose 3 × 3 neighbourhood is flat in the DEM, % of the relief.
    flat_mean: f64,
    /// Largest |error| over samples whose 5 × 5 neighbourhood is flat (the open flat, away from
    /// the steps at its edges that no smooth fit follows within a sample), % of the relief.
    open_max: f64,
}

fn measure(dem: &Heightfield, back: &Heightfield) -> Measures {
    let (lo, hi) = dem.min_max().expect("a DEM with data");
    let relief = f64::from(hi - lo);
    let (nx, ny) = (dem.nx(), dem.ny());
    let flat_within = |i: usize, j: usize, r: usize| {
        let h = dem.value(i, j);
        (j.saturating_sub(r)..(j + r + 1).min(ny))
            .all(|jj| (i.saturating_sub(r)..(i + r + 1).min(nx)).all(|ii| dem.value(ii, jj) == h))
    };
    let mut beyond = 0.0f64;
    let (mut sum, mut count, mut max) = (0.0, 0usize, 0.0f64);
    for j in 0..ny {
        for i in 0..nx {
            let (h, b) = (dem.value(i, j), back.value(i, j));
            beyond = beyond.max(f64::from(b - hi)).max(f64::from(lo - b));
            let e = f64::from((b - h).abs());
            if flat_within(i, j, 1) {
                sum += e;
                count += 1;
            }
            if flat_within(i, j, 2) {
                max = max.max(e);
            }
        }
    }
    let pct = |v: f64| 100.0 * v / relief;
    Measures {
        beyond: pct(beyond),
        flat_mean: if count > 0 { pct(sum / count as f64) } else { 0.0 },
        open_max: pct(max),
    }
}
