//! `relief`: terrain from a few strokes of intent, on the command line.
//!
//! `relief demo` generates the built-in scene; `relief generate SCENE.json` any scene file;
//! `contours`, `convert`, `info` and `preview` work on existing DEMs. Argument parsing is clap
//! (derive), progress is indicatif spinners on stderr (hidden when stderr is not a terminal or with
//! `--quiet`), errors are anyhow chains printed on one line. Exit codes: 0 success, 1 failure,
//! 2 usage error.
#![forbid(unsafe_code)]

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result, bail};
use clap::{Args, Parser, Subcommand};
use glam::DVec2;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use relief::contours::{ContourSet, evenly_spaced_levels, extract_dem, interval_levels};
use relief::gaussian_terrain::{VectorTerrain, VectorizeOptions};
use relief::heightfield::{Extent, GridSpec, Heightfield, Units};
use relief::io::Format;
use relief::pipeline::{self, MAX_LEVELS};
use relief::{Progress, Scene};

/// Terrain from a few strokes of intent: iso-contour generation, DEM contours, conversion and
/// previews.
#[derive(Debug, Parser)]
#[command(name = "relief", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print the time of every step on stderr.
    #[arg(short, long, global = true)]
    verbose: bool,
    /// Print nothing but errors (no progress, no report).
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Worker threads (default: one per core). Outputs are identical for any count.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=1024))]
    threads: Option<u16>,
    /// Most raster cells a scene may ask for or a command may read (grids, working grids, input
    /// DEMs and images; default 2^28).
    #[arg(long, global = true, value_name = "N")]
    max_cells: Option<u64>,
    /// Most growth particles a contour scene may ask for (default 50 million).
    #[arg(long, global = true, value_name = "N")]
    max_particles: Option<u64>,
    /// Most Gaussian primitives a scene may list, load or fit (default 2^22).
    #[arg(long, global = true, value_name = "N")]
    max_primitives: Option<u64>,
    /// Most divide-tree peaks an orometry scene may ask for (default 200 000).
    #[arg(long, global = true, value_name = "N")]
    max_peaks: Option<u64>,
}

impl Cli {
    /// The resource budget the flags set, defaults elsewhere.
    fn budget(&self) -> relief::Budget {
        let d = relief::Budget::default();
        d.with_max_cells(self.max_cells.unwrap_or(d.max_cells))
            .with_max_particles(self.max_particles.unwrap_or(d.max_particles))
            .with_max_primitives(self.max_primitives.unwrap_or(d.max_primitives))
            .with_max_peaks(self.max_peaks.unwrap_or(d.max_peaks))
    }
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Generate the built-in demo scene: an island with two ranges, a summit and a crater.
    Demo {
        /// Output directory.
        #[arg(long, default_value = "relief-demo")]
        out: PathBuf,
    },
    /// Generate the terrain a scene file describes.
    Generate {
        /// The scene (JSON; see docs/scene.schema.json).
        scene: PathBuf,
        /// Output directory (default: relief-out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Replace the scene's seed.
        #[arg(long)]
        seed: Option<u64>,
    },
    /// Generate a feature-curve scene (a `diffusion` generator): curves with elevation, slope and
    /// noise constraints diffused into a terrain (Hnaidi et al. 2010).
    Diffuse {
        /// The scene (JSON; its generator must be `diffusion`).
        scene: PathBuf,
        /// Output directory (default: relief-out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Replace the scene's seed.
        #[arg(long)]
        seed: Option<u64>,
    },
    /// Extract contour lines from a DEM (as GDAL's contour utility does).
    Contours(ContoursArgs),
    /// Convert a heightfield between formats (chosen by extension).
    Convert {
        /// Input (.exr, .png, .r16, .r32, .asc, .tif, .hgt).
        input: PathBuf,
        /// Output; the extension picks the format.
        output: PathBuf,
    },
    /// Describe a heightfield: size, extent, elevation range, no-data.
    Info {
        /// The heightfield.
        dem: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Render a shaded-relief preview (hillshade × hypsometric tint), optionally with contours.
    Preview {
        /// The heightfield.
        dem: PathBuf,
        /// Output PNG.
        #[arg(short, long)]
        output: PathBuf,
        /// Draw contours every this many units of elevation.
        #[arg(long, value_name = "INTERVAL")]
        contours: Option<f64>,
        /// Elevation of the sea: lower ground is drawn as water.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        sea_level: f64,
        /// Largest image side (bigger DEMs are decimated).
        #[arg(long)]
        max_size: Option<usize>,
    },
    /// Hydrology of a heightfield: closed basins, stream order and the terrain descriptors of the
    /// contours paper §6.5, optionally compared with a second heightfield.
    Analyze {
        /// The heightfield.
        dem: PathBuf,
        /// A second heightfield (a real DEM, say) to compare descriptors with.
        #[arg(long)]
        compare: Option<PathBuf>,
        /// Ground at or below this elevation is sea and drains.
        #[arg(long)]
        sea_level: Option<f32>,
        /// Also write the depression-filled heightfield here (format by extension).
        #[arg(long)]
        filled: Option<PathBuf>,
        /// Read DEM (not the compared file) as geographic (longitude/latitude degrees), e.g. an
        /// ASCII grid without a `.prj`; distances, slopes and areas are then in metres at each
        /// row's latitude.
        #[arg(long)]
        degrees: bool,
        /// Orometry: keep peaks at least this prominent, metres.
        #[arg(long, default_value_t = 0.0, value_name = "METRES")]
        min_prominence: f64,
        /// Write the peaks (highest first) as CSV here.
        #[arg(long, value_name = "FILE")]
        peaks: Option<PathBuf>,
        /// Write the divide tree (peaks, key saddles, ridges) as GeoJSON here.
        #[arg(long, value_name = "FILE")]
        divide_tree: Option<PathBuf>,
        /// Write the orometric descriptor (Table 1 histograms) as JSON here.
        #[arg(long, value_name = "FILE")]
        descriptor: Option<PathBuf>,
        /// Classify the DEM against reference descriptors (JSON files written by --descriptor;
        /// the file name is the label): prints the nearest.
        #[arg(long, value_name = "FILE", num_args = 1..)]
        classify: Vec<PathBuf>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Vectorize a DEM into generalized Gaussian primitives (Perche et al. 2025): a JSON vector
    /// terrain that `relief rasterize` renders at any size.
    Vectorize {
        /// The DEM.
        dem: PathBuf,
        /// Most Gaussian primitives.
        #[arg(long, default_value_t = 10_000)]
        primitives: usize,
        /// Output vector terrain (JSON).
        #[arg(short, long)]
        output: PathBuf,
        /// Optimisation steps.
        #[arg(long, default_value_t = 200)]
        iterations: usize,
        /// Samples along the longer side of the grid the fit runs on.
        #[arg(long, default_value_t = 512)]
        resolution: usize,
        /// Stop after this many seconds (the result then depends on the machine's speed).
        #[arg(long, value_name = "SECONDS")]
        time_limit: Option<f64>,
        /// Add error-map detail primitives at this Poisson spacing in DEM cells (2 restores the DEM
        /// to within f32 rounding; the JSON then carries the error map).
        #[arg(long, value_name = "CELLS")]
        details: Option<f64>,
        /// Seed of the initial placement.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Rasterize a vector terrain (JSON from `relief vectorize`) at any size.
    Rasterize {
        /// The vector terrain.
        terrain: PathBuf,
        /// Samples: `W` (square) or `WxH`.
        #[arg(long, value_parser = parse_size)]
        size: (usize, usize),
        /// Output heightfield; the extension picks the format.
        #[arg(short, long)]
        output: PathBuf,
        /// World window `MINX,MINY,MAXX,MAXY` (default: the terrain's recorded domain, e.g. the
        /// vectorized DEM's extent, else the primitives' supports).
        #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
        window: Option<[f64; 4]>,
    },
    /// Print the JSON Schema of scene files.
    Schema,
}

fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let parse = |v: &str| v.trim().parse::<usize>().map_err(|e| format!("{v:?}: {e}"));
    let (w, h) = if let Some((w, h)) = s.split_once(['x', 'X']) {
        (parse(w)?, parse(h)?)
    } else {
        let n = parse(s)?;
        (n, n)
    };
    if w < 2 || h < 2 || w > pipeline::MAX_RESOLUTION || h > pipeline::MAX_RESOLUTION {
        return Err(format!("{w} x {h}: each side must be in 2..={}", pipeline::MAX_RESOLUTION));
    }
    Ok((w, h))
}

fn parse_window(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> =
        s.split(',').map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}"))).collect::<Result<_, _>>()?;
    match v[..] {
        [a, b, c, d] if [a, b, c, d].iter().all(|x| x.is_finite()) && c > a && d > b => Ok([a, b, c, d]),
        _ => Err("give MINX,MINY,MAXX,MAXY with MAXX > MINX and MAXY > MINY".into()),
    }
}

#[derive(Debug, Args)]
struct ContoursArgs {
    /// The DEM.
    dem: PathBuf,
    /// Contour every this many units of elevation.
    #[arg(long, required_unless_present = "levels", conflicts_with = "levels")]
    interval: Option<f64>,
    /// This many evenly spaced levels between the lowest and highest elevation.
    #[arg(long)]
    levels: Option<usize>,
    /// GeoJSON output (default: <DEM name>.contours.geojson when no output is given).
    #[arg(long)]
    geojson: Option<PathBuf>,
    /// SVG output.
    #[arg(long)]
    svg: Option<PathBuf>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

#[allow(clippy::too_many_lines)] // one arm per subcommand
fn run(cli: &Cli) -> Result<()> {
    if let Some(n) = cli.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n.into()).build_global().context("starting the thread pool")?;
    }
    let mut ui = Ui::new(cli.verbose, cli.quiet, cli.budget());
    match &cli.command {
        Command::Demo { out } => {
            let scene = Scene::demo();
            run_scene(&scene, Path::new("."), out, &mut ui)?;
            ui.say(format_args!("open {} to see it", out.join("preview.png").display()));
            Ok(())
        }
        Command::Generate { scene: path, out, seed } | Command::Diffuse { scene: path, out, seed } => {
            let mut scene = pipeline::load_scene(path)?;
            if matches!(cli.command, Command::Diffuse { .. })
                && !matches!(scene.generator, relief::scene::Generator::Diffusion(_))
            {
                bail!(
                    "{}: `relief diffuse` runs diffusion scenes; this one is generated by `relief generate`",
                    path.display()
                );
            }
            if let Some(seed) = seed {
                scene.seed = *seed;
            }
            let base = path.parent().unwrap_or(Path::new("."));
            let out = out
                .clone()
                .unwrap_or_else(|| Path::new("relief-out").join(path.file_stem().unwrap_or(path.as_os_str())));
            run_scene(&scene, base, &out, &mut ui)
        }
        Command::Contours(args) => contours(args, &mut ui),
        Command::Convert { input, output } => {
            let format = Format::from_extension(output)
                .with_context(|| format!("{}: unknown output extension", output.display()))?;
            let dem = ui.read(input)?;
            ui.step("write", || relief::io::write(output, &dem))?;
            ui.say(format_args!(
                "{} ({} x {}) -> {} ({format:?})",
                input.display(),
                dem.nx(),
                dem.ny(),
                output.display()
            ));
            Ok(())
        }
        Command::Info { dem: path, json } => {
            let dem = ui.read(path)?;
            println!("{}", if *json { info_json(path, &dem) } else { info_text(path, &dem) });
            Ok(())
        }
        Command::Analyze {
            dem: path,
            compare,
            sea_level,
            filled,
            degrees,
            min_prominence,
            peaks,
            divide_tree,
            descriptor,
            classify,
            json,
        } => {
            let read = ui.read;
            let read = if *degrees { read.with_units(Units::Degrees) } else { read };
            let orometry = OrometryOutputs {
                min_prominence: *min_prominence,
                peaks: peaks.as_deref(),
                divide_tree: divide_tree.as_deref(),
                descriptor: descriptor.as_deref(),
                classify,
            };
            analyze(&mut ui, &read, path, compare.as_deref(), *sea_level, filled.as_deref(), &orometry, *json)
        }
        Command::Preview { dem: path, output, contours, sea_level, max_size } => {
            let dem = ui.read(path)?;
            let dem = match max_size {
                Some(m) if dem.nx().max(dem.ny()) > *m => {
                    let stride = dem.nx().max(dem.ny()).div_ceil(*m);
                    dem.resample(dem.nx().div_ceil(stride).max(2), dem.ny().div_ceil(stride).max(2))?
                }
                _ => dem,
            };
            let set = match contours {
                Some(interval) => Some(ui.step("contours", || dem_contours(&dem, Some(*interval), None))?),
                None => None,
            };
            let image = ui.step("shade", || relief::export::preview_image(&dem, set.as_ref(), Some(*sea_level)));
            ui.step("write", || relief::io::write_rgb_png(output, &image))?;
            ui.say(format_args!("wrote {} ({} x {})", output.display(), image.width, image.height));
            Ok(())
        }
        Command::Schema => {
            println!("{}", Scene::json_schema());
            Ok(())
        }
        Command::Vectorize { dem, primitives, output, iterations, resolution, time_limit, details, seed } => {
            let time_budget = match time_limit {
                Some(t) if t.is_finite() && *t >= 0.0 => Some(Duration::from_secs_f64(*t)),
                Some(t) => bail!("--time-limit {t}: give a number of seconds ≥ 0"),
                None => None,
            };
            let options = VectorizeOptions {
                primitives: *primitives,
                iterations: *iterations,
                resolution: *resolution,
                time_budget,
                detail_spacing: *details,
                seed: *seed,
                ..VectorizeOptions::default()
            };
            vectorize(&mut ui, dem, output, &options)
        }
        Command::Rasterize { terrain, size, output, window } => rasterize(&mut ui, terrain, *size, output, *window),
    }
}

fn vectorize(ui: &mut Ui, dem: &Path, output: &Path, options: &VectorizeOptions) -> Result<()> {
    ui.budget.primitives(options.primitives as u64, "--primitives")?;
    let side = options.resolution as u64;
    ui.budget.cells(side.saturating_mul(side), "--resolution")?;
    let heightfield = ui.read(dem)?;
    let target = if ui.draw { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
    let bar = ProgressBar::with_draw_target(Some(options.iterations as u64), target);
    bar.set_style(
        ProgressStyle::with_template("vectorize {bar:30} {pos}/{len} {msg} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let fit = relief::gaussian_terrain::vectorize(&heightfield, options, |p| {
        bar.set_position(p.iteration as u64);
        bar.set_message(format!("{} primitives, loss {:.2e}", p.primitives, p.loss.total));
        std::ops::ControlFlow::Continue(())
    })
    .with_context(|| format!("vectorizing {}", dem.display()))?;
    bar.finish_and_clear();
    let json = serde_json::to_string(&fit.terrain).context("encoding the vector terrain")?;
    ui.step("write", || relief::io::write_atomic(output, json.as_bytes()))?;
    let r = &fit.report;
    ui.say(format_args!(
        "{} primitives after {} steps ({}) in {:.1} s: mean error {:.3} ({:.2e} of the relief's half-range){}",
        r.primitives,
        r.iterations,
        r.stopped_by,
        r.seconds,
        r.l1,
        r.l1_normalized,
        if options.detail_spacing.is_some() {
            format!(", {:.2e} with details", r.l1_with_details)
        } else {
            String::new()
        }
    ));
    ui.say(format_args!("  {}", output.display()));
    Ok(())
}

fn rasterize(
    ui: &mut Ui,
    path: &Path,
    (nx, ny): (usize, usize),
    output: &Path,
    window: Option<[f64; 4]>,
) -> Result<()> {
    Format::from_extension(output).with_context(|| format!("{}: unknown output extension", output.display()))?;
    ui.budget.cells((nx as u64).saturating_mul(ny as u64), "--size")?;
    let text = relief::budget::read_json_text(path).with_context(|| format!("reading {}", path.display()))?;
    let terrain: VectorTerrain =
        serde_json::from_str(&text).with_context(|| format!("{}: not a vector terrain", path.display()))?;
    terrain.validate().with_context(|| path.display().to_string())?;
    ui.budget.primitives(terrain.len() as u64, &path.display().to_string())?;
    let extent = match window {
        Some([a, b, c, d]) => Extent::new(DVec2::new(a, b), DVec2::new(c, d)),
        None => relief::vector::default_extent(&terrain),
    };
    let grid = GridSpec::from_extent(nx, ny, extent)?;
    let heightfield = ui.step("rasterize", || {
        relief::gaussian_terrain::rasterize(&terrain, &grid, &relief::gaussian_terrain::RasterOptions::default())
    })?;
    ui.step("write", || relief::io::write(output, &heightfield))?;
    ui.say(format_args!("{} primitives -> {} ({nx} x {ny})", terrain.len(), output.display()));
    Ok(())
}

fn run_scene(scene: &Scene, base: &Path, out: &Path, ui: &mut Ui) -> Result<()> {
    let start = Instant::now();
    let budget = ui.budget;
    let (terrain, written) = pipeline::run_with(scene, base, out, &budget, ui)?;
    let s = &terrain.summary;
    let source = match (&s.graph, &s.diffusion) {
        (Some(g), _) => format!("{} nodes, ", g.nodes),
        (None, Some(d)) => format!(
            "{} solve: {} iterations to a {:.1e} residual, ",
            match d.solver {
                relief::diffusion::Solver::Multigrid => "multigrid",
                relief::diffusion::Solver::JacobiPyramid => "Jacobi pyramid",
            },
            d.iterations,
            d.relative_residual
        ),
        (None, None) => String::new(),
    };
    let fit =
        s.histogram_match.as_ref().map_or_else(String::new, |h| format!(" (histogram match: KS {:.4})", h.raster));
    ui.say(format_args!(
        "{source}{} contours on {} levels, {} x {} heightfield in {:.2} s{fit}",
        s.contours.contours,
        s.contours.levels,
        s.heightfield.nx,
        s.heightfield.ny,
        start.elapsed().as_secs_f64(),
    ));
    for path in &written {
        ui.say(format_args!("  {}", path.display()));
    }
    if let Some(d) = s.diffusion.as_ref().filter(|d| !d.converged && !ui.quiet) {
        eprintln!(
            "warning: the diffusion stopped at a relative residual of {:.2e}, above the tolerance",
            d.relative_residual
        );
    }
    let Some(fit) = &s.histogram_match else { return Ok(()) };
    if fit.nodes > HISTOGRAM_WARNING && !ui.quiet {
        eprintln!(
            "warning: elevations deviate from the histogram (KS {:.3}): explicit region heights give each \
             level a fixed share of the histogram, which differs here from its share of the area; adjust the \
             weights or drop a height",
            fit.nodes
        );
    }
    Ok(())
}

/// Node heights match the histogram to 1/(2N) unless explicit heights force a different split.
const HISTOGRAM_WARNING: f64 = 0.02;

fn contours(args: &ContoursArgs, ui: &mut Ui) -> Result<()> {
    let dem = ui.read(&args.dem)?;
    let set = ui.step("contours", || dem_contours(&dem, args.interval, args.levels))?;
    let geojson = match (&args.geojson, &args.svg) {
        (None, None) => Some(PathBuf::from(format!(
            "{}.contours.geojson",
            args.dem.file_stem().unwrap_or(args.dem.as_os_str()).to_string_lossy()
        ))),
        (g, _) => g.clone(),
    };
    ui.step("write", || -> Result<()> {
        if let Some(path) = &geojson {
            relief::io::write_atomic(path, relief::export::contours_geojson(&set).as_bytes())?;
        }
        if let Some(path) = &args.svg {
            relief::io::write_atomic(path, relief::export::contours_svg(&set, &dem.extent(), 1024).as_bytes())?;
        }
        Ok(())
    })?;
    ui.say(format_args!("{} contours on {} levels, {} vertices", set.len(), set.levels().len(), set.vertex_count()));
    for path in geojson.iter().chain(&args.svg) {
        ui.say(format_args!("  {}", path.display()));
    }
    Ok(())
}

/// Contours of `dem` every `interval` (multiples of it, like `gdal_contour -i`) or at `count`
/// evenly spaced levels.
fn dem_contours(dem: &Heightfield, interval: Option<f64>, count: Option<usize>) -> Result<ContourSet> {
    let Some((lo, hi)) = dem.min_max() else { bail!("the DEM has no valid sample") };
    let (lo, hi) = (f64::from(lo), f64::from(hi));
    let levels = match (interval, count) {
        (Some(m), _) => interval_levels(lo, hi, m, 0.0, MAX_LEVELS)?,
        (None, Some(k)) if k > MAX_LEVELS => bail!("{k} levels, more than {MAX_LEVELS}"),
        (None, Some(k)) if lo < hi => evenly_spaced_levels(lo, hi, k)?,
        (None, Some(_)) => Vec::new(),
        (None, None) => bail!("give --interval or --levels"),
    };
    Ok(extract_dem(dem, &levels)?)
}

fn info_text(path: &Path, dem: &Heightfield) -> String {
    let grid = dem.grid();
    let (e, c) = (grid.extent(), grid.cell_size());
    let unit = match grid.units() {
        Units::Metres => "m",
        Units::Degrees => "°",
    };
    let stats = dem.statistics();
    let range = stats.map_or_else(
        || "no valid sample".to_owned(),
        |s| format!("{} .. {} (mean {:.3}, std dev {:.3})", s.min, s.max, s.mean, s.std_dev),
    );
    format!(
        "{}\n  size       {} x {} ({} samples)\n  extent     x {} .. {}, y {} .. {} ({unit})\n  cell size  {} x {} {unit}\n  elevation  {range}\n  no-data    {}",
        path.display(),
        dem.nx(),
        dem.ny(),
        grid.len(),
        e.min.x,
        e.max.x,
        e.min.y,
        e.max.y,
        c.x,
        c.y,
        dem.no_data_count()
    )
}

/// The orometry part of `relief analyze`.
struct OrometryOutputs<'a> {
    min_prominence: f64,
    peaks: Option<&'a Path>,
    divide_tree: Option<&'a Path>,
    descriptor: Option<&'a Path>,
    classify: &'a [PathBuf],
}

/// The analysis, the descriptor, and the nearest reference (label, mean EMD).
type OrometryResult = (relief::orometry::Orometry, relief::orometry::Descriptor, Option<(String, f64)>);

/// Orometry of `dem`: the analysis, its files, and the nearest reference descriptor.
fn analyze_orometry(
    ui: &mut Ui,
    dem: &Heightfield,
    sea_level: Option<f32>,
    out: &OrometryOutputs<'_>,
) -> anyhow::Result<OrometryResult> {
    use relief::orometry::{AnalysisOptions, Descriptor, DivideTree, classify};
    let options = AnalysisOptions { sea_level, min_prominence: out.min_prominence };
    let (oro, descriptor) = ui.step("orometry", || Descriptor::of(dem, &options))?;
    let geographic = dem.grid().units() == Units::Degrees;
    if let Some(p) = out.peaks {
        ui.step("write", || relief::io::write_atomic(p, relief::export::peaks_csv(&oro, geographic).as_bytes()))?;
    }
    if let Some(p) = out.divide_tree {
        let tree = DivideTree::from_orometry(&oro);
        let text = relief::export::divide_tree_geojson(&tree, Some(&oro));
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if let Some(p) = out.descriptor {
        let text = serde_json::to_string_pretty(&descriptor)?;
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    let mut references = Vec::with_capacity(out.classify.len());
    for p in out.classify {
        let text = relief::budget::read_json_text(p).with_context(|| format!("reading {}", p.display()))?;
        let d: Descriptor =
            serde_json::from_str(&text).with_context(|| format!("{} is not a descriptor", p.display()))?;
        d.validate().with_context(|| format!("{}", p.display()))?;
        let label = p.file_stem().map_or_else(|| p.display().to_string(), |s| s.to_string_lossy().into_owned());
        references.push((label, d));
    }
    let nearest = classify(&descriptor, references.iter().map(|r| &r.1))?.map(|(k, d)| (references[k].0.clone(), d));
    Ok((oro, descriptor, nearest))
}

/// `relief analyze`: closed basins, descriptors, orometry, an optional comparison and filled output.
#[allow(clippy::too_many_arguments)] // one per command-line option group
fn analyze(
    ui: &mut Ui,
    read: &relief::io::ReadOptions,
    path: &Path,
    compare: Option<&Path>,
    sea_level: Option<f32>,
    filled: Option<&Path>,
    orometry: &OrometryOutputs<'_>,
    json: bool,
) -> anyhow::Result<()> {
    use relief::hydrology::{DescriptorOptions, Descriptors, Outlets, depressions};
    let dem = ui.step("read", || relief::io::read_with(path, read))?;
    let (oro, oro_descriptor, nearest) = analyze_orometry(ui, &dem, sea_level, orometry)?;
    let outlets = sea_level.map_or_else(Outlets::new, |s| Outlets::new().with_sea_level(s));
    let options = DescriptorOptions { outlets, ..DescriptorOptions::default() };
    let closed = ui.step("depressions", || depressions(&dem, outlets))?;
    let descriptors = ui.step("descriptors", || Descriptors::of(&dem, &options))?;
    let other = match compare {
        Some(p) => {
            let dem = ui.read(p)?;
            Some(ui.step("descriptors", || Descriptors::of(&dem, &options))?)
        }
        None => None,
    };
    if let Some(out) = filled {
        let dem = ui.step("fill", || relief::hydrology::fill(&dem, outlets))?;
        ui.step("write", || relief::io::write(out, &dem))?;
    }
    let deepest = closed.basins.iter().max_by(|a, b| a.depth().total_cmp(&b.depth()));
    let volume: f64 = closed.basins.iter().map(|b| b.volume_m3).sum();
    let distance = other.as_ref().map(|o| descriptors.distance(o));
    if json {
        let value = serde_json::json!({
            "path": path,
            "closed_basins": closed.basins.len(),
            "closed_volume_m3": volume,
            "basins": closed.basins,
            "descriptors": descriptors,
            "compared_with": compare,
            "distance": distance,
            "orometry": {
                "peaks": oro.peaks.len(),
                "min_prominence": orometry.min_prominence,
                "highest": oro.peaks.first(),
                "descriptor": oro_descriptor,
                "nearest": nearest.as_ref().map(|(label, d)| serde_json::json!({ "label": label, "mean_emd": d })),
            },
        });
        println!("{}", serde_json::to_string_pretty(&value)?);
        return Ok(());
    }
    let median = |h: &relief::hydrology::Histogram| {
        let (mut lo, mut hi) = (h.lo, h.hi);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if h.cdf(mid) < 0.5 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    };
    println!("{}", path.display());
    println!(
        "  closed basins   {}{}",
        closed.basins.len(),
        deepest.map_or_else(String::new, |b| format!(
            " (holding {volume:.4e} m³; deepest {:.3} at ({}, {}), spills at {:.3})",
            b.depth(),
            b.pit.0,
            b.pit.1,
            b.fill_level
        ))
    );
    println!("  max Strahler    {} (streams from {:.4e} m²)", descriptors.max_strahler, descriptors.stream_area_m2);
    println!("  median slope    {:.2}°", median(&descriptors.slope_deg));
    println!("  median log10 A  {:.3} (drainage area in m², Freeman MFD)", median(&descriptors.log10_drainage_area));
    println!("  peaks           {} (prominence ≥ {} m)", oro.peaks.len(), orometry.min_prominence);
    let mut by_prominence: Vec<&relief::orometry::Peak> = oro.peaks.iter().collect();
    by_prominence.sort_by(|a, b| b.prominence.total_cmp(&a.prominence));
    for p in by_prominence.iter().take(5) {
        println!(
            "    {:>9.1} m  prominence {:>8.1} m  at ({}, {}){}",
            p.elevation,
            p.prominence,
            p.position[0],
            p.position[1],
            if p.edge_effect { "  (edge effect)" } else { "" }
        );
    }
    if let Some((label, d)) = &nearest {
        println!("  nearest type    {label} (mean EMD {d:.4})");
    }
    if let (Some(d), Some(p)) = (distance, compare) {
        println!("compared with {} (earth mover's distances)", p.display());
        println!("  elevation       {:.3}", d.elevation);
        println!("  slope           {:.3}°", d.slope_deg);
        println!("  log10 area      {:.3}", d.log10_drainage_area);
        println!("  Strahler        {:+}", d.strahler);
    }
    Ok(())
}

fn info_json(path: &Path, dem: &Heightfield) -> String {
    let grid = dem.grid();
    let (e, c) = (grid.extent(), grid.cell_size());
    let stats = dem.statistics();
    let value = serde_json::json!({
        "path": path,
        "nx": dem.nx(),
        "ny": dem.ny(),
        "extent": { "min": [e.min.x, e.min.y], "max": [e.max.x, e.max.y] },
        "cell_size": [c.x, c.y],
        "units": match grid.units() { Units::Metres => "metres", Units::Degrees => "degrees" },
        "min": stats.map(|s| s.min),
        "max": stats.map(|s| s.max),
        "mean": stats.map(|s| s.mean),
        "no_data": dem.no_data_count(),
    });
    serde_json::to_string_pretty(&value).unwrap_or_default()
}

/// Spinners on stderr, step timings with `-v`, reports on stdout unless `-q`.
struct Ui {
    /// What every command reads under: the budget's cell cap.
    read: relief::io::ReadOptions,
    /// The budget scenes run under.
    budget: relief::Budget,
    verbose: bool,
    quiet: bool,
    bar: Option<ProgressBar>,
    draw: bool,
}

impl Ui {
    fn new(verbose: bool, quiet: bool, budget: relief::Budget) -> Self {
        let read = relief::io::ReadOptions::default()
            .with_limits(relief::io::Limits::default().with_max_cells(budget.max_cells));
        Self { read, budget, verbose, quiet, bar: None, draw: !quiet && std::io::stderr().is_terminal() }
    }

    /// Reads a heightfield under the cell budget, as a timed step.
    fn read(&mut self, path: &Path) -> Result<Heightfield, relief::io::IoError> {
        let read = self.read;
        self.step("read", || relief::io::read_with(path, &read))
    }

    fn say(&self, message: std::fmt::Arguments<'_>) {
        if !self.quiet {
            println!("{message}");
        }
    }

    /// Runs `f` as a step with a spinner.
    fn step<T>(&mut self, name: &'static str, f: impl FnOnce() -> T) -> T {
        self.start(name);
        let start = Instant::now();
        let out = f();
        self.finish(name, start.elapsed());
        out
    }
}

impl Progress for Ui {
    fn start(&mut self, step: &'static str) {
        let target = if self.draw { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        let bar = ProgressBar::with_draw_target(None, target);
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(step);
        bar.enable_steady_tick(Duration::from_millis(100));
        self.bar = Some(bar);
    }

    fn finish(&mut self, step: &'static str, elapsed: Duration) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        if self.verbose {
            eprintln!("{step:>15} {:>9.1} ms", elapsed.as_secs_f64() * 1e3);
        }
    }
}
