//! Vector terrains: `vectorize` fits generalized Gaussian primitives to a DEM (Perche et al. 2025),
//! `rasterize` renders such a terrain at any size.

use std::time::Duration;

use anyhow::{Context as _, Result, bail};
use glam::DVec2;
use relief::gaussian_terrain::{VectorTerrain, VectorizeOptions};
use relief::heightfield::{Extent, GridSpec, Heightfield};

use crate::cli::{RasterizeArgs, VectorizeArgs};
use crate::ui::Ui;
use crate::writes::Written;

/// `relief vectorize`: the fit, with a progress bar over its steps, written as JSON.
pub(crate) fn vectorize(args: &VectorizeArgs, ui: &mut Ui) -> Result<()> {
    ui.writes().reads(&args.dem).writes(&args.output, Written::Json)?.check()?;
    let options = vectorize_options(args)?;
    ui.budget().primitives(options.primitives as u64, "--primitives")?;
    let side = options.resolution as u64;
    ui.budget().cells(side.saturating_mul(side), "--resolution")?;
    let mut heightfield = ui.read(&args.dem)?;
    fill_no_data(&mut heightfield, args, ui)?;
    let bar = ui.bar(options.iterations as u64, "vectorize {bar:30} {pos}/{len} {msg} {elapsed}");
    let fit = relief::gaussian_terrain::vectorize(&heightfield, &options, |p| {
        bar.set_position(p.iteration as u64);
        bar.set_message(format!("{} primitives, loss {:.2e}", p.primitives, p.loss.total));
        std::ops::ControlFlow::Continue(())
    })
    .with_context(|| format!("vectorizing {}", args.dem.display()))?;
    bar.finish_and_clear();
    let json = serde_json::to_string(&fit.terrain).context("encoding the vector terrain")?;
    ui.step("write", || relief::io::write_atomic(&args.output, json.as_bytes()))?;
    let r = &fit.report;
    ui.say(format_args!(
        "{} primitives after {} steps ({}) in {:.1} s: mean error {:.3} ({:.2e} of the relief, Table 3's unit; \
         {:.2e} of its half-range){}",
        r.primitives,
        r.iterations,
        r.stopped_by,
        r.seconds,
        r.l1,
        r.l1_of_relief(),
        r.l1_normalized,
        if options.detail_spacing.is_some() {
            format!(", {:.2e} with details", r.l1_with_details)
        } else {
            String::new()
        }
    ));
    ui.say(format_args!("  {}", args.output.display()));
    Ok(())
}

/// Fills the DEM's no-data samples as `--fill-no-data` says, and says how many; without the
/// flag, a DEM with no-data is refused with the flag's name (the library's error names a
/// function a command-line user cannot call).
fn fill_no_data(dem: &mut Heightfield, args: &VectorizeArgs, ui: &Ui) -> Result<()> {
    let count = dem.no_data_count();
    if count == 0 {
        return Ok(());
    }
    let Some(fill) = args.fill_no_data else {
        bail!(
            "{}: {count} no-data samples; pass --fill-no-data min to fill them at the lowest elevation \
             (a masked border or sea then stays flat) or --fill-no-data ELEVATION",
            args.dem.display()
        );
    };
    let value = fill.fill(dem).map_err(|e| anyhow::anyhow!("--fill-no-data: {e}"))?;
    ui.say(format_args!("{}: {count} no-data samples filled at {value}", args.dem.display()));
    Ok(())
}

/// The fit's options from the flags; `--time-limit` must be a number of seconds ≥ 0.
fn vectorize_options(args: &VectorizeArgs) -> Result<VectorizeOptions> {
    let time_budget = match args.time_limit {
        Some(t) if t.is_finite() && t >= 0.0 => Some(Duration::from_secs_f64(t)),
        Some(t) => bail!("--time-limit {t}: give a number of seconds ≥ 0"),
        None => None,
    };
    Ok(VectorizeOptions {
        primitives: args.primitives,
        iterations: args.iterations,
        resolution: args.resolution,
        time_budget,
        detail_spacing: args.details,
        keep_range: !args.plain,
        beta_range: args.beta_range.unwrap_or(VectorizeOptions::default().beta_range),
        seed: args.seed,
        ..VectorizeOptions::default()
    })
}

/// `relief rasterize`: the terrain sampled on a `--size` grid over `--window` (default: its
/// recorded domain), or on the grid of the `--like` heightfield, in its recorded units and CRS,
/// checked against the budget before anything is allocated.
pub(crate) fn rasterize(args: &RasterizeArgs, ui: &mut Ui) -> Result<()> {
    let (path, output) = (&args.terrain, &args.output);
    let inputs = std::iter::once(path).chain(&args.like).cloned();
    ui.writes().reads_all(inputs).writes(output, Written::Heightfield)?.check()?;
    let like = args.like.as_ref().map(|p| ui.read(p).map(|dem| (p, *dem.grid()))).transpose()?;
    let (nx, ny) = like.map_or(args.size.unwrap_or_default(), |(_, g)| (g.nx(), g.ny()));
    let what = if like.is_some() { "--like" } else { "--size" };
    ui.budget().cells((nx as u64).saturating_mul(ny as u64), what)?;
    let text = relief::budget::read_json_text(path).with_context(|| format!("reading {}", path.display()))?;
    let mut terrain: VectorTerrain =
        serde_json::from_str(&text).with_context(|| format!("{}: not a vector terrain", path.display()))?;
    terrain.validate().with_context(|| path.display().to_string())?;
    // The global `--crs` and `--units` relabel the terrain's frame as they would a file's.
    let read = ui.read_options();
    if let Some(crs) = read.crs {
        terrain.units = crs.units().or(terrain.units);
        terrain.crs = Some(crs);
    }
    terrain.units = read.units.or(terrain.units);
    ui.budget().primitives(terrain.len() as u64, &path.display().to_string())?;
    let grid = match like {
        Some((dem, grid)) if grid.units() != terrain.units() => anyhow::bail!(
            "{} is in {}, the terrain {} in {}: give --size and --window in the terrain's units",
            dem.display(),
            grid.units().name(),
            path.display(),
            terrain.units().name()
        ),
        Some((_, grid)) => grid,
        None => {
            let extent = match args.window {
                Some([a, b, c, d]) => Extent::new(DVec2::new(a, b), DVec2::new(c, d)),
                None => terrain.extent(),
            };
            GridSpec::from_extent(nx, ny, extent)?
        }
    };
    // Labelled like the DEM it was vectorized from: its units and CRS.
    let grid = grid.with_units(terrain.units())?;
    let heightfield = ui.step("rasterize", || {
        relief::gaussian_terrain::rasterize(&terrain, &grid, &relief::gaussian_terrain::RasterOptions::default())
    })?;
    let heightfield = heightfield.with_crs(terrain.crs.clone());
    ui.step("write", || relief::io::write(output, &heightfield))?;
    ui.say(format_args!("{} primitives -> {} ({nx} x {ny})", terrain.len(), output.display()));
    Ok(())
}
