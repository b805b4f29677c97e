//! Resource budgets: caps on what a scene may make the pipeline allocate (raster cells, growth
//! particles, Gaussian primitives, divide-tree peaks), checked before the work that would
//! allocate it. Scene files are untrusted input; the budget belongs to whoever runs them (the
//! CLI's `--max-cells`, `--max-particles`, `--max-primitives` and `--max-peaks`).

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
}

impl Default for Budget {
    fn default() -> Self {
        Self { max_cells: 1 << 28, max_particles: 50_000_000, max_primitives: 1 << 22, max_peaks: 200_000 }
    }
}

impl Budget {
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
