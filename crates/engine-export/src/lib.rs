//! Heightmaps for game engines and DCC tools: a `relief` heightfield as Unity, Unreal, Godot or
//! Blender import it, at the engine's legal size and bit depth, tiled with shared edges for worlds
//! larger than one engine tile, with the numbers its import dialog asks for so the terrain keeps
//! its true dimensions in metres; splat maps for texturing; glTF 2.0 meshes.
//!
//! This is no paper's algorithm but the step after all of them (World Machine and Gaea users
//! expect it). [`prepare`] resamples the heightfield (bilinear, over its own extent) to the
//! engine's size and cuts the tiles, and computes the [`ImportSettings`]; [`export`] writes the
//! tiles and a JSON sidecar (`NAME.import.json`) atomically. Per engine ([`Engine`]):
//!
//! - **Unity**: square 16-bit little-endian RAW of 2ⁿ + 1 samples, south row first (Unity's
//!   `Import Raw…` with *Flip Vertically* off); the terrain size (X, Y, Z) = (width, height range,
//!   depth) in metres, its position Y the lowest elevation. Tiles `NAME_X_Z.raw` for the Terrain
//!   Toolbox's batch import.
//! - **Unreal**: square 16-bit grayscale PNG at a recommended landscape size; scale X/Y in
//!   centimetres per sample, Z in percent (code 32768 sits at the actor's Z, one code is
//!   Z/128 cm), location Z so code 0 is the lowest elevation. Tiles `NAME_x{X}_y{Y}.png` for World
//!   Partition's tiled import.
//! - **Godot**: square 32-bit float `OpenEXR` of 2ⁿ + 1 samples in metres (`HTerrain`, `Terrain3D`):
//!   no height scale to type, only the map's horizontal scale.
//! - **Blender**: a 16-bit PNG at the heightfield's own size for a Displace modifier (strength =
//!   height range, midlevel 0) on a grid of as many vertices, scaled to the terrain's metres.
//!
//! With [`ExportOptions::splat`], every heightmap gets splat maps at its size ([`masks`]):
//! four layers' weights summing to 255 (ground, rock, snow, water from slope, elevation and D8
//! flow on the depression-filled terrain; RGBA, or one grayscale weight map per layer for
//! Unreal) and the raw masks (slope, elevation, convexity, flow). [`TerrainMesh`] writes any
//! heightfield or TIN as a glTF 2.0 binary (`.glb`): positions in metres, normals, UVs,
//! optional hypsometric vertex colours.
//!
//! Meshes are decimated by greedy insertion ([`relief_tin::approximate`], Garland & Heckbert
//! 1995) rather than by a general mesh simplifier such as meshoptimizer: on a heightfield it
//! guarantees a vertical error bound in metres (the number a terrain user asks for), never
//! builds the full-resolution mesh (two triangles per sample), yields a Delaunay mesh without
//! slivers, and needs no C++ toolchain. The glTF document and its binary container come from
//! the `gltf` crate (`gltf-json`), which the tests also load the files back with.
//!
//! Heights are quantised over the whole world's range (every tile the same scale), so tiles meet
//! without steps: neighbouring tiles share their edge samples, bit for bit. No-data samples
//! become the lowest elevation (engines have no holes in heightmaps); [`Prepared::filled_no_data`]
//! counts them. Geographic (degree) grids are measured in metres at their middle row.
//!
//! ```
//! use glam::DVec2;
//! use relief_engine_export::{Engine, ExportOptions, prepare};
//! use relief_heightfield::{GridSpec, Heightfield};
//!
//! // A 3 km × 2 km ramp, 100 m to 400 m high, sampled every 10 m.
//! let grid = GridSpec::new(301, 201, DVec2::ZERO, DVec2::splat(10.0))?;
//! let dem = Heightfield::from_fn(grid, |p| (100.0 + p.x / 10.0) as f32)?;
//! let unity = prepare(&dem, Engine::Unity, &ExportOptions::default())?;
//! // One square terrain of 257 × 257 samples (2⁸ + 1 is nearest 301), 3000 × 300 × 2000 m.
//! assert_eq!(unity.settings.samples, [257, 257]);
//! assert_eq!(unity.settings.tile_size_m, [3000.0, 2000.0]);
//! assert_eq!(unity.settings.height_range_m, 300.0);
//! println!("{}", unity.settings.summary());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]

mod engine;
mod error;
mod mesh;
mod splat;

use std::path::{Path, PathBuf};

use relief_heightfield::{GridSpec, Heightfield};
use relief_heightfield_io::{Format, WriteOptions};
use serde::Serialize;

pub use engine::Engine;
use engine::HeightmapFile;
pub use error::EngineError;
pub use mesh::{MAX_MESH_TRIANGLES, MeshOptions, TerrainMesh};
pub use splat::{Masks, SplatOptions, masks};

/// What to export besides the engine.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// Samples per side of the heightmap (of each tile when tiling); must be one of the engine's
    /// [`Engine::legal_sizes`]. Default: the legal size nearest the heightfield's larger side (its
    /// own size for Blender), or the size that keeps the heightfield's resolution when tiling.
    pub size: Option<usize>,
    /// Cut the world into tiles of this many samples per side, neighbours sharing their edge
    /// samples (Unreal World Partition, Unity terrain groups); as many tiles along each axis as
    /// keep the heightfield's finer ground spacing on both axes (within 10 %). `None`: one
    /// heightmap.
    pub tile: Option<usize>,
    /// File stem of the heightmaps and sidecar (default `heightmap`).
    pub name: String,
    /// Splat maps beside each heightmap, at its size: the four layers' weights and the raw masks
    /// ([`masks`], [`Masks::splat`], [`Masks::packed`]). `None`: heightmaps only.
    pub splat: Option<SplatOptions>,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self { size: None, tile: None, name: "heightmap".to_owned(), splat: None }
    }
}

/// At most this many tiles along each axis.
pub const MAX_TILES_PER_AXIS: usize = 64;
/// At most this many samples over all tiles (a 16k × 16k world).
pub const MAX_WORLD_SAMPLES: usize = 1 << 28;

/// The numbers an engine's import dialog asks for, and where each tile goes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImportSettings {
    /// The engine.
    pub engine: Engine,
    /// Samples of each heightmap, `[x, y]` (square for every engine but Blender).
    pub samples: [usize; 2],
    /// Tiles along x and y.
    pub tiles: [usize; 2],
    /// One tile's size on the ground, `[x (east), y (north)]` in metres.
    pub tile_size_m: [f64; 2],
    /// The whole world's size on the ground, metres.
    pub world_size_m: [f64; 2],
    /// Lowest elevation, metres: what code 0 (or the EXR's value) stands for.
    pub min_m: f64,
    /// Highest elevation, metres.
    pub max_m: f64,
    /// What the full code range (0 … 65535) spans, metres: the height range, or 1 m for flat
    /// ground.
    pub height_range_m: f64,
    /// The engine's own fields.
    pub dialog: Dialog,
}

/// The engine's import dialog, field by field.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dialog {
    /// `Terrain > Import Raw…`, then the terrain's settings and transform.
    Unity {
        /// Depth (bits).
        depth: u8,
        /// Byte order ("Windows": little-endian).
        byte_order: &'static str,
        /// Flip Vertically.
        flip_vertically: bool,
        /// Terrain Size X (width), Y (height range), Z (length), metres.
        terrain_size: [f64; 3],
        /// The terrain's position Y, metres (the lowest elevation).
        position_y: f64,
    },
    /// `Landscape > Import from File` (or World Partition's tiled import).
    Unreal {
        /// Scale X and Y (centimetres per sample) and Z (percent).
        scale: [f64; 3],
        /// Location Z, centimetres.
        location_z: f64,
    },
    /// `HTerrain`'s or `Terrain3D`'s importer: heights are metres already.
    Godot {
        /// The terrain node's scale: metres per sample along x, 1 (heights as written), along z.
        scale: [f64; 3],
    },
    /// A Grid mesh with a Displace modifier using the PNG (colour space Non-Color, UV coordinates).
    Blender {
        /// The grid's X and Y subdivisions (faces: samples − 1).
        subdivisions: [usize; 2],
        /// The grid's dimensions X and Y, metres.
        dimensions: [f64; 2],
        /// The modifier's strength, metres (the height range).
        strength: f64,
        /// The modifier's midlevel.
        midlevel: f64,
        /// The object's location Z, metres (the lowest elevation).
        location_z: f64,
    },
}

impl ImportSettings {
    /// One line giving the numbers to type into the engine's import dialog.
    pub fn summary(&self) -> String {
        let [w, h] = self.samples;
        let tiles = if self.tiles == [1, 1] {
            String::new()
        } else {
            format!("{} × {} tiles, each ", self.tiles[0], self.tiles[1])
        };
        let r = |v: f64| (v * 1000.0).round() / 1000.0;
        match &self.dialog {
            Dialog::Unity { terrain_size: [x, y, z], position_y, .. } => format!(
                "unity: {tiles}Import Raw: Depth Bit 16, Width {w}, Height {h}, Byte Order Windows, Flip Vertically off; \
                 Terrain Size X {} Y {} Z {} m; position Y {} m",
                r(*x),
                r(*y),
                r(*z),
                r(*position_y)
            ),
            Dialog::Unreal { scale: [x, y, z], location_z } => format!(
                "unreal: {tiles}{w} × {h} PNG; Scale X {} Y {} Z {}; Location Z {} cm",
                r(*x),
                r(*y),
                r(*z),
                r(*location_z)
            ),
            Dialog::Godot { scale: [x, y, z] } => {
                format!("godot: {tiles}{w} × {h} EXR in metres; node scale X {} Y {} Z {}", r(*x), r(*y), r(*z))
            }
            Dialog::Blender { subdivisions: [sx, sy], dimensions: [dx, dy], strength, midlevel, location_z } => {
                format!(
                    "blender: {tiles}Grid with X Subdivisions {sx}, Y Subdivisions {sy}, Dimensions X {} Y {} m; Displace \
                 (UV, Non-Color) Strength {} Midlevel {midlevel}; Location Z {} m",
                    r(*dx),
                    r(*dy),
                    r(*strength),
                    r(*location_z)
                )
            }
        }
    }
}

/// One tile of a prepared export.
#[derive(Debug, Clone)]
pub struct Tile {
    /// Column, from the west.
    pub column: usize,
    /// Row, from the north.
    pub row: usize,
    /// Its west and south edges from the world's south-west corner, metres.
    pub offset_m: [f64; 2],
    /// Its heights, as written (no-data filled).
    pub heights: Heightfield,
    /// Its texturing masks, when splat maps were asked for.
    pub masks: Option<Masks>,
}

/// An export ready to write: the settings and every tile's heights.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The import dialog's numbers.
    pub settings: ImportSettings,
    /// The tiles, row by row from the north-west.
    pub tiles: Vec<Tile>,
    /// No-data samples of the heightfield, written as the lowest elevation.
    pub filled_no_data: usize,
}

/// The files an [`export`] wrote.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The import dialog's numbers.
    pub settings: ImportSettings,
    /// Each tile's heightmap, in [`Prepared::tiles`] order.
    pub files: Vec<PathBuf>,
    /// Each tile's splat maps (weights, then raw masks), in tile order; empty without
    /// [`ExportOptions::splat`].
    pub splat_files: Vec<Vec<PathBuf>>,
    /// The JSON sidecar: the settings and each tile's file and offset.
    pub sidecar: PathBuf,
    /// No-data samples written as the lowest elevation.
    pub filled_no_data: usize,
}

/// Resamples `hf` for `engine` and cuts its tiles, without writing anything.
///
/// # Errors
/// [`EngineError::IllegalSize`] for a size or tile size the engine does not take,
/// [`EngineError::NoData`] for a heightfield without a valid sample, [`EngineError::TooLarge`]
/// beyond [`MAX_TILES_PER_AXIS`] or [`MAX_WORLD_SAMPLES`].
pub fn prepare(hf: &Heightfield, engine: Engine, options: &ExportOptions) -> Result<Prepared, EngineError> {
    let (min, max) = hf.min_max().ok_or(EngineError::NoData)?;
    let filled_no_data = hf.no_data_count();
    let mut filled = hf.clone();
    filled.fill_no_data(min)?;
    let (samples, tiles) = layout(hf, engine, options)?;
    let world = [tiles[0] * (samples[0] - 1) + 1, tiles[1] * (samples[1] - 1) + 1];
    let world_hf = if world == [hf.nx(), hf.ny()] { filled } else { filled.resample(world[0], world[1])? };
    let size_m = ground_size(hf.grid());
    let tile_size_m = [size_m[0] / tiles[0] as f64, size_m[1] / tiles[1] as f64];
    let world_masks = options.splat.as_ref().map(|o| masks(&world_hf, o)).transpose()?;
    let (min, max) = (f64::from(min), f64::from(max));
    let height_range_m = if max > min { max - min } else { 1.0 };
    let mut cut = Vec::with_capacity(tiles[0] * tiles[1]);
    for row in 0..tiles[1] {
        for column in 0..tiles[0] {
            // Rows of the grid run south to north; tile rows north to south.
            let j0 = (tiles[1] - 1 - row) * (samples[1] - 1);
            let i0 = column * (samples[0] - 1);
            let offset_m = [column as f64 * tile_size_m[0], (tiles[1] - 1 - row) as f64 * tile_size_m[1]];
            let masks = world_masks.as_ref().map(|m| m.crop(i0, j0, samples));
            cut.push(Tile { column, row, offset_m, heights: crop(&world_hf, i0, j0, samples)?, masks });
        }
    }
    let settings = ImportSettings {
        engine,
        samples,
        tiles,
        tile_size_m,
        world_size_m: size_m,
        min_m: min,
        max_m: max,
        height_range_m,
        dialog: dialog(engine, samples, tile_size_m, min, height_range_m),
    };
    Ok(Prepared { settings, tiles: cut, filled_no_data })
}

/// [`prepare`]s `hf` for `engine` and writes its tiles and sidecar into `dir` (created if needed),
/// each file atomically: [`Prepared::write`].
///
/// # Errors
/// As [`prepare`] and [`Prepared::write`].
pub fn export(hf: &Heightfield, engine: Engine, options: &ExportOptions, dir: &Path) -> Result<Exported, EngineError> {
    prepare(hf, engine, options)?.write(&options.name, dir)
}

impl Prepared {
    /// The file names [`Prepared::write`] gives the tiles, in tile order: `NAME.EXT` for one,
    /// the engine's tiled-import names for several.
    pub fn file_names(&self, name: &str) -> Vec<String> {
        let extension = self.settings.engine.extension();
        (0..self.tiles.len()).map(|k| format!("{name}{}.{extension}", self.tile_suffix(k))).collect()
    }

    /// Tile `k`'s suffix in the engine's tiled-import naming; none for a single heightmap.
    fn tile_suffix(&self, k: usize) -> String {
        match self.tiles.get(k) {
            Some(t) if self.tiles.len() > 1 => {
                self.settings.engine.tile_suffix(t.column, t.row, self.settings.tiles[1])
            }
            _ => String::new(),
        }
    }

    /// The splat files [`Prepared::write`] gives tile `k`, the tile suffix last as tiled imports
    /// expect: `NAME_splat.png` (RGBA: ground, rock, snow, water) for every engine but Unreal,
    /// which imports one 8-bit grayscale weight map per layer (`NAME_ground.png`,
    /// `NAME_rock_x0_y1.png`, …), then `NAME_masks.png` (RGBA: slope, elevation, convexity,
    /// flow). Empty without masks.
    pub fn splat_names(&self, name: &str, k: usize) -> Vec<String> {
        if self.tiles.get(k).is_none_or(|t| t.masks.is_none()) {
            return Vec::new();
        }
        let suffix = self.tile_suffix(k);
        let kinds: &[&str] = if self.settings.engine == Engine::Unreal { &SPLAT_LAYERS } else { &["splat"] };
        kinds.iter().chain(&["masks"]).map(|kind| format!("{name}_{kind}{suffix}.png")).collect()
    }

    /// The sidecar's file name: `NAME.import.json`.
    pub fn sidecar_name(name: &str) -> String {
        format!("{name}.import.json")
    }

    /// Writes the tiles (named by [`Prepared::file_names`]) and the JSON sidecar (the settings,
    /// the summary line, each tile's file and offset) into `dir`, created if needed, each file
    /// atomically.
    ///
    /// # Errors
    /// [`EngineError::CreateDir`] or [`EngineError::Io`] when a folder or file cannot be written.
    pub fn write(self, name: &str, dir: &Path) -> Result<Exported, EngineError> {
        std::fs::create_dir_all(dir).map_err(|source| EngineError::CreateDir { path: dir.to_owned(), source })?;
        let mut files = Vec::with_capacity(self.tiles.len());
        let mut entries = Vec::with_capacity(self.tiles.len());
        let mut splat_files = Vec::new();
        for (k, (tile, file)) in self.tiles.iter().zip(self.file_names(name)).enumerate() {
            let path = dir.join(&file);
            write_tile(&path, self.settings.engine, &tile.heights, &self.settings)?;
            let splats = self.splat_names(name, k);
            if let Some(m) = &tile.masks {
                splat_files.push(write_splats(m, self.settings.engine, dir, &splats)?);
            }
            entries.push(serde_json::json!({
                "file": file,
                "splat": splats,
                "column": tile.column,
                "row_from_north": tile.row,
                "offset_m": tile.offset_m,
            }));
            files.push(path);
        }
        let sidecar = dir.join(Self::sidecar_name(name));
        let json = serde_json::json!({
            "settings": self.settings,
            "summary": self.settings.summary(),
            "splat_layers": if splat_files.is_empty() { None } else { Some(SPLAT_LAYERS) },
            "tiles": entries,
            "filled_no_data": self.filled_no_data,
        });
        let text = serde_json::to_string_pretty(&json).unwrap_or_default() + "\n";
        relief_heightfield_io::write_atomic(&sidecar, text.as_bytes())?;
        Ok(Exported { settings: self.settings, files, splat_files, sidecar, filled_no_data: self.filled_no_data })
    }
}

/// Samples per tile and tiles per axis.
fn layout(hf: &Heightfield, engine: Engine, options: &ExportOptions) -> Result<([usize; 2], [usize; 2]), EngineError> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let Some(tile) = options.tile else {
        let size = match options.size {
            Some(s) => engine.check_size(s)?,
            None => engine.nearest_size(nx.max(ny)),
        };
        let samples = if engine.square() {
            [size, size]
        } else if options.size.is_none() && nx.max(ny) <= size {
            [nx, ny]
        } else {
            // Blender: the larger side at `size`, the other in proportion.
            let scale = (size - 1) as f64 / (nx.max(ny) - 1).max(1) as f64;
            let other = |n: usize| ((n - 1) as f64 * scale).round() as usize + 1;
            if nx >= ny { [size, other(ny).max(2)] } else { [other(nx).max(2), size] }
        };
        return Ok((samples, [1, 1]));
    };
    let tile = engine.check_size(tile)?;
    if let Some(size) = options.size
        && size != tile
    {
        return Err(EngineError::IllegalSize { engine, size, legal: format!("{tile} (the tile size) when tiling") });
    }
    // The input's finer ground spacing along both axes (not coarser than 10 % beyond it), so
    // the tiles' samples are as near square as whole tiles allow.
    let size_m = ground_size(hf.grid());
    let spacing = (size_m[0] / (nx.max(2) - 1) as f64).min(size_m[1] / (ny.max(2) - 1) as f64);
    let count = |metres: f64| {
        let k = (metres / (spacing * (tile - 1) as f64) / 1.1).ceil();
        if k.is_finite() && k >= 1.0 { (k as usize).min(MAX_TILES_PER_AXIS + 1) } else { 1 }
    };
    let tiles = [count(size_m[0]), count(size_m[1])];
    if tiles[0].max(tiles[1]) > MAX_TILES_PER_AXIS {
        return Err(EngineError::TooLarge {
            what: format!("{} × {} tiles of {tile} samples", tiles[0], tiles[1]),
            max: MAX_TILES_PER_AXIS,
        });
    }
    let world = (tiles[0] * (tile - 1) + 1) * (tiles[1] * (tile - 1) + 1);
    if world > MAX_WORLD_SAMPLES {
        return Err(EngineError::TooLarge { what: format!("{world} samples over all tiles"), max: MAX_WORLD_SAMPLES });
    }
    Ok(([tile, tile], tiles))
}

/// The grid's extent on the ground, metres (degrees measured at the middle row).
fn ground_size(grid: &GridSpec) -> [f64; 2] {
    let span = grid.cell_size() * glam::DVec2::new((grid.nx() - 1) as f64, (grid.ny() - 1) as f64);
    let metres = span * grid.metres_per_unit(grid.ny() / 2);
    [metres.x, metres.y]
}

/// The splat layers in channel order (R, G, B, A).
pub const SPLAT_LAYERS: [&str; 4] = ["ground", "rock", "snow", "water"];

/// Writes a tile's splat maps under `names` ([`Prepared::splat_names`]), north row first.
fn write_splats(m: &Masks, engine: Engine, dir: &Path, names: &[String]) -> Result<Vec<PathBuf>, EngineError> {
    let north_first = |px: Vec<[u8; 4]>| -> Vec<[u8; 4]> { px.chunks(m.nx).rev().flatten().copied().collect() };
    let weights = north_first(m.splat());
    let mut images: Vec<(Vec<u8>, image::ExtendedColorType)> = if engine == Engine::Unreal {
        (0..4).map(|c| (weights.iter().map(|p| p[c]).collect(), image::ExtendedColorType::L8)).collect()
    } else {
        vec![(weights.into_iter().flatten().collect(), image::ExtendedColorType::Rgba8)]
    };
    images.push((north_first(m.packed()).into_iter().flatten().collect(), image::ExtendedColorType::Rgba8));
    let mut paths = Vec::with_capacity(names.len());
    for ((bytes, colour), name) in images.into_iter().zip(names) {
        let path = dir.join(name);
        let mut png = Vec::new();
        let encoder = image::codecs::png::PngEncoder::new(&mut png);
        image::ImageEncoder::write_image(encoder, &bytes, m.nx as u32, m.ny as u32, colour)
            .map_err(|e| EngineError::Encode { path: path.clone(), reason: e.to_string() })?;
        relief_heightfield_io::write_atomic(&path, &png)?;
        paths.push(path);
    }
    Ok(paths)
}

/// `samples` of `hf` from column `i0`, row `j0`.
fn crop(hf: &Heightfield, i0: usize, j0: usize, [w, h]: [usize; 2]) -> Result<Heightfield, EngineError> {
    let grid = hf.grid();
    let tile = GridSpec::new(w, h, grid.position(i0, j0), grid.cell_size())?.with_units(grid.units())?;
    Ok(Heightfield::from_fn_indexed(tile, |i, j| hf.value(i0 + i, j0 + j))?.with_crs(hf.crs().cloned()))
}

fn dialog(engine: Engine, [w, h]: [usize; 2], [sx, sy]: [f64; 2], min: f64, range: f64) -> Dialog {
    let (cx, cy) = (sx / (w - 1) as f64, sy / (h - 1) as f64);
    match engine {
        Engine::Unity => Dialog::Unity {
            depth: 16,
            byte_order: "Windows",
            flip_vertically: false,
            terrain_size: [sx, range, sy],
            position_y: min,
        },
        // Height in cm = (code − 32768) · Z / 128: the code range spans 65535 · Z / 128 cm.
        Engine::Unreal => {
            let z = range * 100.0 * 128.0 / 65535.0;
            Dialog::Unreal { scale: [cx * 100.0, cy * 100.0, z], location_z: 100.0 * min + 32768.0 * z / 128.0 }
        }
        Engine::Godot => Dialog::Godot { scale: [cx, 1.0, cy] },
        Engine::Blender => Dialog::Blender {
            subdivisions: [w - 1, h - 1],
            dimensions: [sx, sy],
            strength: range,
            midlevel: 0.0,
            location_z: min,
        },
    }
}

/// The 16-bit code of each sample over `[min, min + range]`, north row first.
fn codes(hf: &Heightfield, min: f64, range: f64) -> impl Iterator<Item = u16> + '_ {
    (0..hf.ny()).rev().flat_map(move |j| {
        hf.row(j).iter().map(move |&v| ((f64::from(v) - min) / range * 65535.0).round().clamp(0.0, 65535.0) as u16)
    })
}

fn write_tile(path: &Path, engine: Engine, tile: &Heightfield, s: &ImportSettings) -> Result<(), EngineError> {
    match engine.file() {
        HeightmapFile::Raw16SouthFirst => {
            // Unity reads the first row as the terrain's back edge (z = 0, south).
            let north_first: Vec<u16> = codes(tile, s.min_m, s.height_range_m).collect();
            let bytes: Vec<u8> =
                north_first.chunks(tile.nx()).rev().flat_map(|row| row.iter().flat_map(|c| c.to_le_bytes())).collect();
            relief_heightfield_io::write_atomic(path, &bytes)?;
        }
        HeightmapFile::Png16 => {
            let (lo, hi) = (s.min_m as f32, (s.min_m + s.height_range_m) as f32);
            let options = WriteOptions::default().with_format(Format::Png16).with_range(lo, hi);
            relief_heightfield_io::write_with(path, tile, &options)?;
        }
        HeightmapFile::Exr => {
            relief_heightfield_io::write_with(path, tile, &WriteOptions::default().with_format(Format::Exr))?;
        }
    }
    Ok(())
}
