//! Resource budgets: caps on what a scene may make the pipeline allocate (raster cells, growth
//! particles, Gaussian primitives, divide-tree peaks, and the memory a generation is estimated to
//! take), checked before the work that would allocate it. Scene files are untrusted input; the
//! budget belongs to whoever runs them (the CLI's `--max-cells`, `--max-particles`,
//! `--max-primitives`, `--max-peaks` and `--max-bytes`).
//!
//! The memory estimate is the output grid's cells times what one cell costs the scene's
//! generator at its peak ([`bytes_per_cell`], measured), and 32 bytes per cell of every raster
//! read (a colour image decodes to 16 bytes a pixel beside the decoder's own buffer). The
//! library's default leaves memory unbounded; [`Budget::for_this_machine`], which the CLI and the
//! studio start from, caps it at half the machine's memory.

use std::path::Path;

use crate::ReliefError;
use crate::scene::{GaussianSource, Generator, Scene};

/// Caps on what generating one scene may allocate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct Budget {
    /// Most cells of any raster: the output grid, a working grid, and every DEM or image a scene
    /// reads (checked against the file's header before decoding). Default 2^28 (16384², 1 GiB of
    /// f32 samples).
    pub max_cells: u64,
    /// Most growth particles (nodes inside Ω), asked for directly or through a Poisson radius.
    /// Default 50 million.
    pub max_particles: u64,
    /// Most Gaussian primitives, listed, loaded, fitted or added by the editing tools. Default 2^22.
    pub max_primitives: u64,
    /// Most peaks of a generated divide tree. Default 200 000.
    pub max_peaks: u64,
    /// Most bytes of memory a generation is estimated to take (see the module's documentation),
    /// and 32 bytes a cell of any raster read. Default unbounded; half the machine's memory from
    /// [`Budget::for_this_machine`].
    pub max_bytes: u64,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            max_cells: 1 << 28,
            max_particles: 50_000_000,
            max_primitives: 1 << 22,
            max_peaks: 200_000,
            max_bytes: u64::MAX,
        }
    }
}

/// Bytes a raster read may take per cell while it is decoded (a colour image: 16 bytes a pixel
/// of RGBA f32 beside the decoder's buffer).
pub const READ_BYTES_PER_CELL: u64 = 32;

/// What one output cell costs `generator` at the peak of a whole run (generation, drainage,
/// contours, outputs), bytes. Measured as the slope of the peak resident memory between 1024²
/// and 2048² runs of the gallery scenes (`/usr/bin/time -f %M`, 2026-12-07): contours 53
/// (mesa), 61 (volcanic island) and 71 (a label image), island 62 (craggy island), feature
/// curves 79 (mountain), Gaussian 54 (massif), orometry 47 (Jacksboro); a tenth or more added.
pub fn bytes_per_cell(generator: &Generator) -> u64 {
    match generator {
        Generator::Contours(_) => 80,
        Generator::Diffusion(_) => 96,
        Generator::Island(_) => 72,
        Generator::Gaussian(_) => 64,
        Generator::Orometry(_) => 56,
    }
}

/// The memory generating `scene` is estimated to take at its peak, bytes: its output cells times
/// [`bytes_per_cell`] (what [`Budget::check`] holds against [`Budget::max_bytes`]).
pub fn estimated_bytes(scene: &Scene) -> u64 {
    let [nx, ny] = scene.reconstruction.resolution;
    cells(nx, ny).saturating_mul(bytes_per_cell(&scene.generator))
}

/// The machine's physical memory, bytes, where the system says (Linux's `/proc/meminfo`).
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

impl Budget {
    /// The default budget with [`Budget::max_bytes`] at half the machine's physical memory
    /// (unbounded where it cannot be told): what the CLI and the studio run under unless told.
    pub fn for_this_machine() -> Self {
        Self::default().with_max_bytes(physical_memory().map_or(u64::MAX, |bytes| bytes / 2))
    }

    /// The same budget with at most `bytes` of estimated memory.
    #[must_use]
    pub fn with_max_bytes(mut self, bytes: u64) -> Self {
        self.max_bytes = bytes;
        self
    }

    /// The most cells a raster read may have: [`Budget::max_cells`], and no more than
    /// [`Budget::max_bytes`] allows at [`READ_BYTES_PER_CELL`].
    pub fn max_read_cells(&self) -> u64 {
        self.max_cells.min(self.max_bytes / READ_BYTES_PER_CELL)
    }

    /// Checks `requested` bytes of estimated memory against the cap; `at` names what asked.
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] when over the cap.
    pub fn bytes(&self, requested: u64, at: &str) -> Result<(), ReliefError> {
        over(requested, self.max_bytes, "bytes", at)
    }

    /// The same budget with at most `cells` raster cells.
    #[must_use]
    pub fn with_max_cells(mut self, cells: u64) -> Self {
        self.max_cells = cells;
        self
    }

    /// The same budget with at most `particles` growth particles.
    #[must_use]
    pub fn with_max_particles(mut self, particles: u64) -> Self {
        self.max_particles = particles;
        self
    }

    /// The same budget with at most `primitives` Gaussian primitives.
    #[must_use]
    pub fn with_max_primitives(mut self, primitives: u64) -> Self {
        self.max_primitives = primitives;
        self
    }

    /// The same budget with at most `peaks` divide-tree peaks.
    #[must_use]
    pub fn with_max_peaks(mut self, peaks: u64) -> Self {
        self.max_peaks = peaks;
        self
    }

    /// Checks what the scene asks for in so many words: its raster size, particle count,
    /// primitive count, working-grid size and peak count. What depends on input files (their
    /// sizes, a radius's particle count, a loaded terrain's primitives, primitives a paste or
    /// stamp adds, a peak count from a descriptor's density) is checked when known: before the
    /// work, or for a stamp (which at most doubles the terrain) right after it.
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] naming the JSON path of the first value over its cap.
    pub fn check(&self, scene: &Scene) -> Result<(), ReliefError> {
        let [nx, ny] = scene.reconstruction.resolution;
        self.cells(cells(nx, ny), "reconstruction.resolution")?;
        self.bytes(estimated_bytes(scene), "reconstruction.resolution")?;
        match &scene.generator {
            Generator::Contours(g) => {
                if let Some(n) = g.particles {
                    self.particles(n as u64, "generator.contours.particles")?;
                }
            }
            Generator::Gaussian(g) => match &g.source {
                GaussianSource::Primitives(terrain) => {
                    self.primitives(terrain.len() as u64, "generator.gaussian.source.primitives")?;
                }
                GaussianSource::Dem { primitives, resolution, .. } => {
                    self.primitives(*primitives as u64, "generator.gaussian.source.primitives")?;
                    self.cells(cells(*resolution, *resolution), "generator.gaussian.source.resolution")?;
                }
                GaussianSource::Terrain { .. } => {}
            },
            Generator::Orometry(g) => {
                if let Some(n) = g.tree.peaks {
                    self.peaks(n as u64, "generator.orometry.tree.peaks")?;
                }
            }
            Generator::Diffusion(_) | Generator::Island(_) => {}
        }
        Ok(())
    }

    /// Checks `requested` raster cells against the cap; `at` names what asked (a JSON path or a flag).
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] when over the cap.
    pub fn cells(&self, requested: u64, at: &str) -> Result<(), ReliefError> {
        over(requested, self.max_cells, "cells", at)
    }

    /// Checks `requested` growth particles against the cap; `at` names what asked (a JSON path or a flag).
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] when over the cap.
    pub fn particles(&self, requested: u64, at: &str) -> Result<(), ReliefError> {
        over(requested, self.max_particles, "particles", at)
    }

    /// Checks `requested` Gaussian primitives against the cap; `at` names what asked (a JSON path or a flag).
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] when over the cap.
    pub fn primitives(&self, requested: u64, at: &str) -> Result<(), ReliefError> {
        over(requested, self.max_primitives, "primitives", at)
    }

    /// Checks `requested` divide-tree peaks against the cap; `at` names what asked (a JSON path or a flag).
    ///
    /// # Errors
    /// [`ReliefError::OverBudget`] when over the cap.
    pub fn peaks(&self, requested: u64, at: &str) -> Result<(), ReliefError> {
        over(requested, self.max_peaks, "peaks", at)
    }
}

fn cells(nx: usize, ny: usize) -> u64 {
    (nx as u64).saturating_mul(ny as u64)
}

fn over(requested: u64, limit: u64, what: &'static str, at: &str) -> Result<(), ReliefError> {
    if requested > limit {
        return Err(ReliefError::OverBudget { path: at.to_owned(), what, requested, limit });
    }
    Ok(())
}

/// Largest JSON input read (scene, vector terrain, atlas, descriptor, divide tree): 1 GiB, room for
/// [`Budget::max_primitives`]' default of 2^22 listed primitives several times over.
pub const MAX_JSON_BYTES: u64 = 1 << 30;

/// The text of a JSON input file: regular files only (a path to `/dev/zero` or a FIFO fails at
/// once rather than reading forever) and at most [`MAX_JSON_BYTES`], checked from its size first.
///
/// # Errors
/// The operating system's error, or `InvalidInput` naming the reason.
pub fn read_json_text(path: &Path) -> std::io::Result<String> {
    use std::io::{Error, ErrorKind};
    let bytes = crate::io::read_capped(path, MAX_JSON_BYTES).map_err(|e| match e {
        crate::io::CapError::Io(e) => e,
        crate::io::CapError::TooLarge { bytes, .. } => Error::new(
            ErrorKind::InvalidInput,
            format!("{bytes} bytes is more than the {MAX_JSON_BYTES}-byte limit on JSON inputs"),
        ),
        other => Error::new(ErrorKind::InvalidInput, other.to_string()),
    })?;
    String::from_utf8(bytes).map_err(|e| Error::new(ErrorKind::InvalidData, e))
}
