//! The command line: clap derive types for the global flags and every subcommand, their value
//! parsers, and the resource budget the flags set.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use relief::pipeline;

/// Terrain from a few strokes of intent (nested contours, island sketches, feature curves,
/// Gaussian primitives, divide trees), and the tools to look at it: DEM contours, conversion,
/// analysis and previews.
#[derive(Debug, Parser)]
#[command(name = "relief", version, long_about = None, propagate_version = true)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
    /// Print the time of every step on stderr.
    #[arg(short, long, global = true)]
    pub(crate) verbose: bool,
    /// Print nothing but errors (no progress, no report).
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    pub(crate) quiet: bool,
    /// Replace existing output files (without it, a command refuses to write over a file).
    #[arg(short, long, global = true)]
    pub(crate) force: bool,
    /// Worker threads (default: one per core). Outputs are identical for any count.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub(crate) threads: Option<u16>,
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
    /// Most bytes of memory a generation is estimated to take, and 32 a cell of any raster read
    /// (default half this machine's memory).
    #[arg(long, global = true, value_name = "N")]
    max_bytes: Option<u64>,
    /// What a plain 8/16-bit heightmap's (or a sidecar-less .r16's) lowest and highest codes
    /// stand for, in elevation units (default 0 and 1); refused for files that store elevations.
    #[arg(long, global = true, value_parser = parse_range, allow_hyphen_values = true, value_name = "MIN,MAX")]
    z_range: Option<[f32; 2]>,
    /// Distance between samples of the heightfields read, overriding the file (`S` or `SX,SY`).
    #[arg(long, global = true, value_parser = parse_cell_size, value_name = "S")]
    cell_size: Option<[f64; 2]>,
    /// Position `X,Y` of the south-west sample of the heightfields read, overriding the file.
    #[arg(long, global = true, value_parser = parse_point, allow_hyphen_values = true, value_name = "X,Y")]
    origin: Option<[f64; 2]>,
    /// `W` or `WxH` of a .r16/.r32 file without a sidecar (default: square).
    #[arg(long, global = true, value_parser = parse_size, value_name = "WxH")]
    raw_size: Option<(usize, usize)>,
    /// Units of the heightfields' coordinates, overriding the file and its CRS: metres, degrees,
    /// feet or `us_survey_feet`.
    #[arg(long, global = true, value_parser = parse_units, value_name = "UNITS")]
    units: Option<relief::heightfield::Units>,
    /// Coordinate reference system of the heightfields read, overriding the file's: `EPSG:n`, a
    /// WKT text or a .prj file. A label only (nothing is reprojected); its units become the grid's.
    #[arg(long, global = true, value_parser = parse_crs, value_name = "CRS")]
    crs: Option<relief::heightfield::Crs>,
    /// The band (1-based) of a multi-band GeoTIFF to read.
    #[arg(long, global = true, value_name = "N")]
    band: Option<u16>,
    /// The channel of a colour image that holds the values: red, green, blue, alpha or luma (a
    /// heightmap must otherwise be gray; masks otherwise read as luma).
    #[arg(long, global = true, value_parser = parse_channel, value_name = "CHANNEL")]
    channel: Option<relief::io::Channel>,
}

impl Cli {
    /// The resource budget the flags set, defaults elsewhere.
    pub(crate) fn budget(&self) -> relief::Budget {
        let d = relief::Budget::for_this_machine();
        d.with_max_cells(self.max_cells.unwrap_or(d.max_cells))
            .with_max_bytes(self.max_bytes.unwrap_or(d.max_bytes))
            .with_max_particles(self.max_particles.unwrap_or(d.max_particles))
            .with_max_primitives(self.max_primitives.unwrap_or(d.max_primitives))
            .with_max_peaks(self.max_peaks.unwrap_or(d.max_peaks))
    }
}

impl Cli {
    /// How every heightfield a command reads is read: the budget's cell cap and the flags that
    /// say what a file does not (vertical range, cell size, origin, raw size, units, CRS, band,
    /// channel).
    pub(crate) fn read_options(&self) -> relief::io::ReadOptions {
        let budget = self.budget();
        let read = relief::io::ReadOptions::default()
            .with_limits(relief::io::Limits::default().with_max_cells(budget.max_read_cells()));
        // The same fields as a scene's `inputs` block, applied the same way.
        let flags = relief::scene::InputOptions {
            z_range: self.z_range.map(|r| r.map(f64::from)),
            cell_size: self.cell_size,
            origin: self.origin,
            raw_size: self.raw_size.map(|(w, h)| [w, h]),
            units: self.units,
            crs: self.crs.clone(),
            band: self.band,
            channel: self.channel,
        };
        flags.apply(read)
    }
}

// The variants' doc comments are the subcommands' help; the argument structs carry none, so that
// theirs cannot replace it.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Generate the built-in demo scene: an island with two ranges, a summit and a crater.
    Demo(DemoArgs),
    /// Generate the terrain a scene file describes.
    Generate(GenerateArgs),
    /// Generate a feature-curve scene (a `diffusion` generator): curves with elevation, slope and
    /// noise constraints diffused into a terrain (Hnaidi et al. 2010).
    Diffuse(DiffuseArgs),
    /// Extract contour lines from a DEM by marching squares, with their nesting: the lines GDAL's
    /// contour utility draws (its saddle rule, lines carried to the raster's outer edge and to
    /// half-way towards no-data), each running with higher ground on its left.
    Contours(ContoursArgs),
    /// Convert a heightfield between formats (chosen by extension).
    Convert(ConvertArgs),
    /// Heightmaps for a game engine or DCC tool (Unity, Unreal, Godot, Blender) at its legal size
    /// and bit depth, optionally in tiles sharing their edges, with the numbers its import dialog
    /// asks for printed and in a JSON sidecar; from a DEM or a scene (generated first).
    Export(ExportArgs),
    /// Describe a heightfield: size, extent, elevation range, no-data, and what its codes stand
    /// for (16- and 8-bit files).
    Info(InfoArgs),
    /// Render a shaded-relief preview (hillshade × hypsometric tint), optionally with contours and
    /// a scene's inputs drawn over it.
    Preview(PreviewArgs),
    /// Hydrology of a heightfield: closed basins, stream order and the terrain descriptors of the
    /// contours paper §6.5, optionally compared with a second heightfield.
    Analyze(AnalyzeArgs),
    /// Peaks, prominence, key saddles and the divide tree of a DEM (the orometry paper, akirmse's
    /// conventions), without the basins and descriptors `analyze` also computes.
    Prominence(ProminenceArgs),
    /// Vectorize a DEM into generalized Gaussian primitives (Perche et al. 2025): a JSON vector
    /// terrain that `relief rasterize` renders at any size.
    Vectorize(VectorizeArgs),
    /// Rasterize a vector terrain (JSON from `relief vectorize`) at any size, labelled with the
    /// units and CRS of the DEM it came from.
    Rasterize(RasterizeArgs),
    /// Author terrain in the browser: a local web studio over every generator, whose document is
    /// the scene JSON `relief generate` runs. Listens on 127.0.0.1 until Ctrl-C.
    Serve(ServeArgs),
    /// Print the JSON Schema of scene files.
    Schema,
    /// Print a completion script for a shell (e.g. `relief completions bash >
    /// ~/.local/share/bash-completion/completions/relief`).
    Completions(CompletionsArgs),
    /// Print the man page, in roff (e.g. `relief man > relief.1; man ./relief.1`).
    Man,
}

// `relief completions`.
#[derive(Debug, Args)]
pub(crate) struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub(crate) shell: clap_complete::Shell,
}

/// What every subcommand's help says instead of repeating the global options: their names.
fn global_options_named(globals: &[clap::Arg]) -> String {
    let names: Vec<String> = globals
        .iter()
        .map(|a| a.get_short().map_or_else(|| format!("--{}", a.get_long().unwrap_or_default()), |c| format!("-{c}")))
        .collect();
    format!("Global options ({}) go before or after the subcommand; `relief --help` describes them.", names.join(", "))
}

/// The command line as clap sees it: the derive's, with the global options described once, at
/// the end of `relief --help`, and only named in each subcommand's help.
pub(crate) fn command() -> clap::Command {
    use clap::CommandFactory as _;
    let mut cmd = Cli::command();
    let globals: Vec<clap::Arg> = cmd.get_arguments().filter(|a| a.is_global_set()).cloned().collect();
    let listing = global_options(&globals);
    let named = global_options_named(&globals);
    // A hidden global option is still parsed everywhere; it is just not listed.
    for arg in &globals {
        cmd = cmd.mut_arg(arg.get_id(), |a| a.hide(true));
    }
    let names: Vec<String> = cmd.get_subcommands().map(|s| s.get_name().to_owned()).collect();
    for name in names {
        cmd = cmd.mut_subcommand(name, |sub| sub.after_help(named.clone()));
    }
    cmd.after_help(listing)
}

/// The global options as `relief --help` lists them: flags and value names, then the help text.
fn global_options(globals: &[clap::Arg]) -> String {
    let names: Vec<String> = globals
        .iter()
        .map(|a| {
            let short = a.get_short().map_or_else(|| "    ".to_owned(), |c| format!("-{c}, "));
            let long = a.get_long().map_or_else(String::new, |l| format!("--{l}"));
            let value = match a.get_value_names() {
                Some([name, ..]) if a.get_action().takes_values() => format!(" <{name}>"),
                _ => String::new(),
            };
            format!("{short}{long}{value}")
        })
        .collect();
    let width = names.iter().map(String::len).max().unwrap_or(0);
    let mut text = String::from("Global options (before or after the subcommand):");
    for (name, arg) in names.iter().zip(globals) {
        let help = arg.get_help().map_or_else(String::new, ToString::to_string);
        let _ = write!(text, "\n  {name:width$}  {help}");
    }
    text
}

impl Cli {
    /// The parsed command line (usage errors exit the process with code 2, as clap does).
    pub(crate) fn from_env() -> Self {
        use clap::FromArgMatches as _;
        let matches = command().get_matches();
        Self::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
    }
}

// `relief demo`.
#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Output directory.
    #[arg(long, default_value = "relief-demo")]
    pub(crate) out: PathBuf,
    /// Replace the scene's seed (the demo uses 7).
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    #[command(flatten)]
    pub(crate) outputs: SceneOutputs,
}

/// What the scene commands may change in a scene's outputs.
#[derive(Debug, Args)]
pub(crate) struct SceneOutputs {
    /// Raster size `W` or `WxH`, replacing the scene's `reconstruction.resolution`.
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    pub(crate) resolution: Option<(usize, usize)>,
    /// Heightfield formats to write (comma-separated), replacing the scene's `outputs.heightfield`
    /// with `terrain.<extension>` for each.
    #[arg(long, value_enum, value_delimiter = ',', value_name = "FORMAT")]
    pub(crate) format: Vec<HeightfieldFormat>,
    /// Elevations `MIN,MAX` that the 16-bit outputs (.png, .r16) map their lowest and highest codes
    /// to: a fixed vertical scale (default: the terrain's own min and max).
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true, value_name = "MIN,MAX")]
    pub(crate) range: Option<[f32; 2]>,
}

/// A heightfield file format, as the command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum HeightfieldFormat {
    /// OpenEXR, 32-bit float.
    Exr,
    /// 16-bit grayscale PNG, quantised (the range is recorded in the file).
    Png,
    /// 8-bit grayscale PNG, quantised (convert only: scenes write 16-bit PNGs).
    Png8,
    /// Raw little-endian u16, quantised, with a JSON sidecar.
    R16,
    /// Raw little-endian f32, with a JSON sidecar.
    R32,
    /// ESRI ASCII grid.
    Asc,
    /// GeoTIFF, 32-bit float.
    Tif,
    /// SRTM tile (1201² or 3601², whole metres).
    Hgt,
}

impl HeightfieldFormat {
    /// The file extension.
    pub(crate) fn extension(self) -> &'static str {
        match self {
            Self::Exr => "exr",
            Self::Png | Self::Png8 => "png",
            Self::R16 => "r16",
            Self::R32 => "r32",
            Self::Asc => "asc",
            Self::Tif => "tif",
            Self::Hgt => "hgt",
        }
    }

    /// The format written.
    pub(crate) fn io(self) -> relief::io::Format {
        use relief::io::Format;
        match self {
            Self::Exr => Format::Exr,
            Self::Png => Format::Png16,
            Self::Png8 => Format::Png8,
            Self::R16 => Format::R16,
            Self::R32 => Format::R32,
            Self::Asc => Format::Asc,
            Self::Tif => Format::GeoTiff,
            Self::Hgt => Format::Hgt,
        }
    }
}

// `relief generate`.
#[derive(Debug, Args)]
pub(crate) struct GenerateArgs {
    /// The scene (JSON; `relief schema` prints its JSON Schema), or `-` to read it from standard
    /// input (its relative paths then resolve against the current folder).
    pub(crate) scene: PathBuf,
    /// Output directory (default: `relief-out/<scene name>`).
    #[arg(long)]
    pub(crate) out: Option<PathBuf>,
    /// Replace the scene's seed.
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    #[command(flatten)]
    pub(crate) outputs: SceneOutputs,
}

// `relief diffuse`: `generate`'s arguments, restricted to diffusion scenes.
#[derive(Debug, Args)]
pub(crate) struct DiffuseArgs {
    /// The scene (JSON; its generator must be `diffusion`), or `-` to read it from standard input.
    pub(crate) scene: PathBuf,
    /// Output directory (default: `relief-out/<scene name>`).
    #[arg(long)]
    pub(crate) out: Option<PathBuf>,
    /// Replace the scene's seed.
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    #[command(flatten)]
    pub(crate) outputs: SceneOutputs,
}

// `relief contours`.
#[derive(Debug, Args)]
pub(crate) struct ContoursArgs {
    /// The DEM.
    pub(crate) dem: PathBuf,
    /// Contour every this many units of elevation.
    #[arg(long, required_unless_present = "levels", conflicts_with = "levels")]
    pub(crate) interval: Option<f64>,
    /// This many evenly spaced levels between the lowest and highest elevation.
    #[arg(long)]
    pub(crate) levels: Option<usize>,
    /// GeoJSON output (default: `<DEM name>.contours.geojson` when no output is given).
    #[arg(long)]
    pub(crate) geojson: Option<PathBuf>,
    /// SVG output.
    #[arg(long)]
    pub(crate) svg: Option<PathBuf>,
}

// `relief convert`.
#[derive(Debug, Args)]
pub(crate) struct ConvertArgs {
    /// Input (.exr, .png, .r16, .r32, .asc, .tif, .hgt).
    pub(crate) input: PathBuf,
    /// Output; the extension picks the format.
    pub(crate) output: PathBuf,
    /// Resample to `W` or `WxH` samples over the same extent, by bilinear interpolation (exact
    /// when refining; coarsening by more than 2× aliases, and samples next to no-data become
    /// no-data).
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    pub(crate) size: Option<(usize, usize)>,
    /// The format, when the extension allows several (`png8` for an 8-bit .png); it must agree
    /// with the extension.
    #[arg(long, value_enum)]
    pub(crate) format: Option<HeightfieldFormat>,
    /// Elevations `MIN,MAX` that a 16- or 8-bit output maps its lowest and highest codes to (a
    /// fixed vertical scale; default: the field's own min and max).
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true, value_name = "MIN,MAX")]
    pub(crate) range: Option<[f32; 2]>,
    /// Write .tif and .exr uncompressed (default: a .tif is deflated with GDAL's floating-point
    /// predictor, an .exr is not compressed).
    #[arg(long, conflicts_with = "compress")]
    pub(crate) no_compress: bool,
    /// Compress an .exr too (ZIP; slower to write, about 10 % smaller for generated terrain).
    #[arg(long)]
    pub(crate) compress: bool,
    /// Sample type of a .tif: f32 (default, exact) or i16 (whole units, -32768 for no-data, as
    /// SRTM stores them; half the size).
    #[arg(long, value_enum, default_value = "f32", value_name = "TYPE")]
    pub(crate) tiff_type: TiffType,
    /// Write a .tif with its raster type "pixel is area" (GDAL's default) instead of "pixel is
    /// point"; GDAL and relief place the samples at the same coordinates either way.
    #[arg(long)]
    pub(crate) pixel_is_area: bool,
}

// `relief export`.
#[derive(Debug, Args)]
pub(crate) struct ExportArgs {
    /// A heightfield (any format `relief info` reads) or a scene file (.json), generated first.
    pub(crate) input: PathBuf,
    /// The engine or tool.
    #[arg(long = "for", value_enum, value_name = "ENGINE")]
    pub(crate) engine: EngineName,
    /// Output folder (default: `relief-out/<input name>-<engine>`).
    #[arg(short, long)]
    pub(crate) out: Option<PathBuf>,
    /// Samples per side, one of the engine's legal sizes (Unity 2ⁿ+1 from 33 to 4097; Unreal
    /// 127, 253, 505, 1009, 2017, 4033, 8129; Godot 2ⁿ+1 from 65 to 4097; Blender any, the larger
    /// side). Default: the legal size nearest the input's larger side.
    #[arg(long)]
    pub(crate) size: Option<usize>,
    /// Cut the world into tiles of this many samples per side (a legal size), neighbours sharing
    /// their edge samples, as many as keep the input's sample spacing (Unreal World Partition,
    /// Unity terrain groups).
    #[arg(long)]
    pub(crate) tile: Option<usize>,
    /// File stem of the heightmaps and the sidecar (default `heightmap`; `terrain` for glTF).
    #[arg(long)]
    pub(crate) name: Option<String>,
    /// Splat maps beside each heightmap: the weights of four layers (ground, rock, snow, water;
    /// RGBA, or one grayscale weight map per layer for Unreal) and the raw slope, elevation,
    /// convexity and flow masks (RGBA).
    #[arg(long)]
    pub(crate) splat: bool,
    /// glTF: no sample farther than this from the mesh, metres (default: 0.1 % of the relief).
    #[arg(long, value_name = "METRES")]
    pub(crate) max_error: Option<f64>,
    /// glTF: at most this many triangles (default 500 000).
    #[arg(long, value_name = "N")]
    pub(crate) triangles: Option<usize>,
    /// glTF: no hypsometric vertex colours.
    #[arg(long)]
    pub(crate) no_colours: bool,
}

/// An engine `relief export` writes for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum EngineName {
    /// Unity: 16-bit RAW, little-endian, south row first.
    Unity,
    /// Unreal Engine: 16-bit grayscale PNG.
    Unreal,
    /// Godot (`HTerrain`, `Terrain3D`): 32-bit float EXR in metres.
    Godot,
    /// Blender: 16-bit grayscale PNG for a Displace modifier.
    Blender,
    /// glTF 2.0 binary mesh (`.glb`) for any engine or viewer: metres, normals, UVs, colours.
    Gltf,
}

impl EngineName {
    /// The library's heightmap engine; `None` for a glTF mesh.
    pub(crate) fn engine(self) -> Option<relief::engine::Engine> {
        use relief::engine::Engine;
        match self {
            Self::Unity => Some(Engine::Unity),
            Self::Unreal => Some(Engine::Unreal),
            Self::Godot => Some(Engine::Godot),
            Self::Blender => Some(Engine::Blender),
            Self::Gltf => None,
        }
    }
}

/// A GeoTIFF sample type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum TiffType {
    /// 32-bit float.
    F32,
    /// 16-bit signed integer.
    I16,
}

// `relief info`.
#[derive(Debug, Args)]
pub(crate) struct InfoArgs {
    /// The heightfield.
    pub(crate) dem: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

// `relief preview`.
#[derive(Debug, Args)]
pub(crate) struct PreviewArgs {
    /// The heightfield.
    pub(crate) dem: PathBuf,
    /// Output PNG.
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Draw contours every this many units of elevation.
    #[arg(long, value_name = "INTERVAL")]
    pub(crate) contours: Option<f64>,
    /// Elevation of the sea: lower ground is drawn as water (default: the `--inputs` scene's sea
    /// level where it sets one, else 0).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) sea_level: Option<f64>,
    /// Largest image side (bigger DEMs are decimated).
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..))]
    pub(crate) max_size: Option<u32>,
    /// Draw this scene's inputs over the relief (`-` reads it from stdin): coastline white,
    /// raised regions orange, depressions blue, strokes magenta (a dot at their start), hills
    /// yellow, curves red, peaks pink, tool selections cyan.
    #[arg(long, value_name = "SCENE")]
    pub(crate) inputs: Option<PathBuf>,
}

// `relief analyze`.
#[derive(Debug, Args)]
pub(crate) struct AnalyzeArgs {
    /// The heightfield.
    pub(crate) dem: PathBuf,
    /// A second heightfield (a real DEM, say) to compare descriptors with.
    #[arg(long)]
    pub(crate) compare: Option<PathBuf>,
    /// Ground at or below this elevation is sea and drains.
    #[arg(long)]
    pub(crate) sea_level: Option<f32>,
    /// Also write the depression-filled heightfield here (format by extension).
    #[arg(long)]
    pub(crate) filled: Option<PathBuf>,
    /// Read DEM (not the compared file) as geographic (longitude/latitude degrees), e.g. an
    /// ASCII grid without a `.prj`; distances, slopes and areas are then in metres at each
    /// row's latitude.
    #[arg(long)]
    pub(crate) degrees: bool,
    /// Orometry: keep peaks at least this prominent, metres.
    #[arg(long, default_value_t = 0.0, value_name = "METRES")]
    pub(crate) min_prominence: f64,
    /// Write the peaks (highest first) as CSV here.
    #[arg(long, value_name = "FILE")]
    pub(crate) peaks: Option<PathBuf>,
    /// Write the divide tree here: GeoJSON (peaks, key saddles, ridges) or, for a `.dvt` name,
    /// akirmse/mountains' text format.
    #[arg(long, value_name = "FILE")]
    pub(crate) divide_tree: Option<PathBuf>,
    /// Write the orometric descriptor (Table 1 histograms) as JSON here.
    #[arg(long, value_name = "FILE")]
    pub(crate) descriptor: Option<PathBuf>,
    /// Classify the DEM against reference descriptors (JSON files written by --descriptor;
    /// the file name is the label): prints the nearest.
    #[arg(long, value_name = "FILE", num_args = 1..)]
    pub(crate) classify: Vec<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

// `relief prominence`.
#[derive(Debug, Args)]
pub(crate) struct ProminenceArgs {
    /// The DEM, or a divide tree in akirmse/mountains' `.dvt` format (its peaks' prominences are
    /// then those on the tree).
    pub(crate) dem: PathBuf,
    /// Keep peaks at least this prominent, metres (the divide tree is pruned to them).
    #[arg(long, default_value_t = 0.0, value_name = "METRES")]
    pub(crate) min_prominence: f64,
    /// Ground at or below this elevation is sea.
    #[arg(long)]
    pub(crate) sea_level: Option<f32>,
    /// What a land mass's highest peak is measured down to: the sea level (0 without
    /// --sea-level), as summit lists and akirmse/mountains count it (always, for a .dvt input), or
    /// its lowest outlet (where water leaves the map: the relief of a DEM that holds no sea).
    /// [default: sea-level; outlet with --depressions, whose deepest pit has no sea to count to]
    #[arg(long, value_enum)]
    pub(crate) base: Option<Base>,
    /// Anti-prominence (akirmse's -a): analyse the pits and basins instead of the summits, e.g. of
    /// bathymetry; with --sea-level, only ground below it.
    #[arg(long)]
    pub(crate) depressions: bool,
    /// Write the peaks (most prominent first for a .dvt input, else highest first) as CSV here.
    #[arg(long, value_name = "FILE")]
    pub(crate) peaks: Option<PathBuf>,
    /// The form of --peaks: relief's CSV (a header, parents, dominance, isolation), or the lines
    /// of akirmse/mountains' `prominence.txt` (`lat,lon,elevation,saddle_lat,saddle_lon,
    /// prominence`, no header, most prominent first, the top's saddle `0,0`), which its users'
    /// scripts read.
    #[arg(long, value_enum, default_value_t = PeaksFormat::Csv, value_name = "FORMAT")]
    pub(crate) peaks_format: PeaksFormat,
    /// Where a peak or saddle is said to be: its sample's centre, or the sample's north-west
    /// corner, where akirmse/mountains places it when a tile's pixels are areas whose corners lie
    /// on the whole degrees (it puts a tile's first sample on the degree itself). Applies to
    /// everything written and printed for a DEM; a .dvt input's positions are its own lattice's.
    #[arg(long, value_enum, default_value_t = Positions::Centre, value_name = "WHERE")]
    pub(crate) positions: Positions,
    /// Write the divide tree here: GeoJSON (peaks, saddles, ridges between neighbouring peaks)
    /// or, for a `.dvt` name, akirmse/mountains' text format (a geographic DEM with whole samples
    /// per degree, or a UTM one).
    #[arg(long, value_name = "FILE")]
    pub(crate) divide_tree: Option<PathBuf>,
    /// How many of the most prominent peaks to print.
    #[arg(long, default_value_t = 10)]
    pub(crate) top: usize,
    /// Print the whole analysis (peaks and saddles) as JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

/// The form of `relief prominence --peaks`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum PeaksFormat {
    /// relief's CSV.
    Csv,
    /// akirmse/mountains' `prominence.txt` lines.
    Akirmse,
}

/// Where `relief prominence` places a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Positions {
    /// The sample's centre.
    Centre,
    /// The sample's north-west corner (akirmse/mountains' tiles).
    NwCorner,
}

/// What a land mass's highest peak is measured down to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Base {
    /// The lowest outlet.
    Outlet,
    /// The sea level.
    SeaLevel,
}

// `relief vectorize`.
#[derive(Debug, Args)]
pub(crate) struct VectorizeArgs {
    /// The DEM.
    pub(crate) dem: PathBuf,
    /// Most Gaussian primitives.
    #[arg(long, default_value_t = 10_000)]
    pub(crate) primitives: usize,
    /// Output vector terrain (JSON).
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Optimisation steps.
    #[arg(long, default_value_t = 260)]
    pub(crate) iterations: usize,
    /// Samples along the longer side of the grid the fit runs on.
    #[arg(long, default_value_t = 512)]
    pub(crate) resolution: usize,
    /// Stop after this many seconds (the result then depends on the machine's speed).
    #[arg(long, value_name = "SECONDS")]
    pub(crate) time_limit: Option<f64>,
    /// Add error-map detail primitives at this Poisson spacing in DEM cells (2 restores the DEM
    /// to within f32 rounding; the JSON then carries the error map).
    #[arg(long, value_name = "CELLS")]
    pub(crate) details: Option<f64>,
    /// Fit the paper's plain sum: no floor under flat low ground (a sea stored as 0), no penalty
    /// beyond the DEM's range, no extra weight on flat ground (by default the fit keeps all three).
    #[arg(long)]
    pub(crate) plain: bool,
    /// The range of the primitives' exponent β [default: 0.6,8, peaked to flat-topped]. `2,4`
    /// is the paper's kernel: on 1024² DEMs it fits 13-25 % faster for up to 2 % more error.
    #[arg(long, value_name = "MIN,MAX", value_parser = parse_beta_range)]
    pub(crate) beta_range: Option<[f64; 2]>,
    /// Seed of the initial placement.
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u64,
    /// Fill the DEM's no-data samples before the fit: `min` at its lowest elevation (a country
    /// masked beyond its border, a sea stored as no-data: the fit's floor then holds that ground
    /// flat), or at the elevation given. Without it a DEM with no-data is refused.
    #[arg(long, value_name = "min|ELEVATION")]
    pub(crate) fill_no_data: Option<relief::scene::NoDataFill>,
}

// `relief serve`.
#[derive(Debug, Args)]
pub(crate) struct ServeArgs {
    /// The port (0 picks a free one).
    #[arg(long, default_value_t = 8737)]
    pub(crate) port: u16,
    /// The address to listen on; anything but a loopback address lets other machines in, and the
    /// studio then asks for a secret token, part of the address it prints.
    #[arg(long, default_value = "127.0.0.1")]
    pub(crate) host: std::net::IpAddr,
    /// Open the studio in the default browser.
    #[arg(long)]
    pub(crate) open: bool,
    /// The folder scenes are saved to and inputs uploaded to (created if missing).
    #[arg(long, default_value = "relief-studio")]
    pub(crate) workspace: PathBuf,
}

// `relief rasterize`.
#[derive(Debug, Args)]
pub(crate) struct RasterizeArgs {
    /// The vector terrain.
    pub(crate) terrain: PathBuf,
    /// Samples: `W` (square) or `WxH` (required unless `--like` gives the grid).
    #[arg(long, value_parser = parse_size, required_unless_present = "like")]
    pub(crate) size: Option<(usize, usize)>,
    /// Output heightfield; the extension picks the format.
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// World window `MINX,MINY,MAXX,MAXY` (default: the terrain's recorded domain, e.g. the
    /// vectorized DEM's extent, else the primitives' supports).
    #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
    pub(crate) window: Option<[f64; 4]>,
    /// Sample on this heightfield's grid (size, origin, cell size), e.g. the DEM the terrain was
    /// vectorized from, to compare the two sample by sample; instead of `--size` and `--window`.
    #[arg(long, value_name = "DEM", conflicts_with_all = ["size", "window"])]
    pub(crate) like: Option<PathBuf>,
}

/// `W` or `WxH` (each side in 2..=16384): `1024`, `2048x1024`.
fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let usage = || format!("{s:?}: give W or WxH, e.g. 1024 or 2048x1024");
    let parse = |v: &str| v.trim().parse::<usize>().map_err(|_| usage());
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

/// `MIN,MAX` with MIN < MAX, both finite.
fn parse_range(s: &str) -> Result<[f32; 2], String> {
    let usage = || format!("{s:?}: give MIN,MAX with MIN < MAX, e.g. -100,2500");
    let (a, b) = s.split_once(',').ok_or_else(usage)?;
    let parse = |v: &str| v.trim().parse::<f32>().map_err(|_| usage());
    let (min, max) = (parse(a)?, parse(b)?);
    if !(min.is_finite() && max.is_finite() && min < max) {
        return Err(usage());
    }
    Ok([min, max])
}

/// `MIN,MAX`, both numbers (the library checks the range itself).
fn parse_beta_range(s: &str) -> Result<[f64; 2], String> {
    let usage = || format!("{s:?}: give MIN,MAX, e.g. 2,4");
    let (a, b) = s.split_once(',').ok_or_else(usage)?;
    let parse = |v: &str| v.trim().parse::<f64>().map_err(|_| usage());
    Ok([parse(a)?, parse(b)?])
}

/// `S` or `SX,SY`, positive and finite.
fn parse_cell_size(s: &str) -> Result<[f64; 2], String> {
    let usage = || format!("{s:?}: give S or SX,SY (positive), e.g. 30 or 0.5,0.25");
    let parse = |v: &str| v.trim().parse::<f64>().ok().filter(|x| x.is_finite() && *x > 0.0).ok_or_else(usage);
    match s.split_once(',') {
        Some((x, y)) => Ok([parse(x)?, parse(y)?]),
        None => parse(s).map(|v| [v, v]),
    }
}

fn parse_units(s: &str) -> Result<relief::heightfield::Units, String> {
    s.parse().map_err(|e: relief::heightfield::HeightfieldError| e.to_string())
}

fn parse_channel(s: &str) -> Result<relief::io::Channel, String> {
    s.parse()
}

fn parse_crs(s: &str) -> Result<relief::heightfield::Crs, String> {
    relief::io::parse_crs(s).map_err(|e| e.kind().to_string())
}

/// `X,Y`, finite.
fn parse_point(s: &str) -> Result<[f64; 2], String> {
    let usage = || format!("{s:?}: give X,Y, e.g. 500000,4100000");
    let (x, y) = s.split_once(',').ok_or_else(usage)?;
    let parse = |v: &str| v.trim().parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(usage);
    Ok([parse(x)?, parse(y)?])
}

fn parse_window(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> =
        s.split(',').map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}"))).collect::<Result<_, _>>()?;
    match v[..] {
        [a, b, c, d] if [a, b, c, d].iter().all(|x| x.is_finite()) && c > a && d > b => Ok([a, b, c, d]),
        _ => Err("give MINX,MINY,MAXX,MAXY with MAXX > MINX and MAXY > MINY".into()),
    }
}
