//! What every generator reads the same way: files relative to the scene, under the budget, and
//! the raster grid a scene asks for.

use std::path::{Path, PathBuf};

use glam::DVec2;

use crate::budget::{Budget, read_json_text};
use crate::error::SceneError;
use crate::heightfield::{Extent, GridSpec, Heightfield};
use crate::io::{IoError, Limits, ReadOptions};
use crate::poisson_sampling::Rect;
use crate::{ReliefError, Scene};

/// Largest raster side a scene may ask for.
pub const MAX_RESOLUTION: usize = 16_384;

/// Where a scene's relative paths resolve, and the budget its inputs are read under.
pub(crate) struct Env<'a> {
    pub(crate) dir: &'a Path,
    pub(crate) budget: Budget,
    /// The scene's read options for what the files do not say.
    pub(crate) inputs: &'a crate::scene::InputOptions,
}

impl Env<'_> {
    /// `path` resolved against the scene's directory.
    pub(crate) fn join(&self, path: &Path) -> PathBuf {
        self.dir.join(path)
    }

    fn options(&self) -> ReadOptions {
        self.inputs
            .apply(ReadOptions::default().with_limits(Limits::default().with_max_cells(self.budget.max_read_cells())))
    }

    /// Reads a heightfield, refusing one over the cell budget before decoding it.
    pub(crate) fn read(&self, path: &Path) -> Result<Heightfield, IoError> {
        crate::io::read_with(self.join(path), &self.options())
    }

    /// Reads an image as gray levels (see [`crate::io::read_gray_image`]) under the cell budget.
    pub(crate) fn read_gray(&self, path: &Path) -> Result<Heightfield, IoError> {
        crate::io::read_gray_image(self.join(path), &self.options())
    }

    /// Reads an image's colours (see [`crate::io::read_color_image`]) under the cell budget.
    pub(crate) fn read_color(&self, path: &Path) -> Result<crate::io::ColorImage, IoError> {
        crate::io::read_color_image(self.join(path), &self.options())
    }

    /// Reads a JSON input of the scene (a vector terrain, atlas or descriptor, which validate
    /// themselves as they deserialize); errors name the scene value `at` and the file.
    pub(crate) fn read_json<T: serde::de::DeserializeOwned>(&self, path: &Path, at: &str) -> Result<T, ReliefError> {
        let file = self.join(path);
        let fail = |source: Box<dyn std::error::Error + Send + Sync>| {
            ReliefError::at(at, SceneError::JsonFile { file: file.clone(), source })
        };
        let text = read_json_text(&file).map_err(|e| fail(e.into()))?;
        serde_json::from_str(&text).map_err(|e| fail(e.into()))
    }

    /// Reads a map and stretches it over `extent` (its own georeferencing is ignored: maps are
    /// usually images); errors name the scene value `at`.
    pub(crate) fn control_map(&self, path: &Path, extent: Extent, at: &str) -> Result<Heightfield, ReliefError> {
        let map = self.read(path).map_err(|e| ReliefError::at(at, e))?;
        let grid = GridSpec::from_extent(map.nx(), map.ny(), extent).map_err(|e| ReliefError::at(at, e))?;
        Heightfield::from_samples(grid, map.into_samples()).map_err(|e| ReliefError::at(at, e))
    }
}

/// The raster of `extent` at the scene's resolution, checked.
pub(crate) fn raster_grid(scene: &Scene, extent: Extent) -> Result<GridSpec, ReliefError> {
    let [nx, ny] = scene.reconstruction.resolution;
    if !(2..=MAX_RESOLUTION).contains(&nx) || !(2..=MAX_RESOLUTION).contains(&ny) {
        return Err(ReliefError::at(
            "reconstruction.resolution",
            SceneError::Resolution { nx, ny, max: MAX_RESOLUTION },
        ));
    }
    GridSpec::from_extent(nx, ny, extent).map_err(|e| ReliefError::at("domain", e))
}

/// `bounds` grown by 5 % of their larger side, then widened to the resolution's aspect ratio so
/// cells are square: the default domain of drawn inputs.
pub(crate) fn default_domain(bounds: Rect, [nx, ny]: [usize; 2]) -> Extent {
    let size = bounds.size();
    let grown = bounds.grow(0.05 * size.max_element());
    let (centre, mut half) = (0.5 * (grown.min + grown.max), 0.5 * grown.size());
    let aspect = (nx.max(2) - 1) as f64 / (ny.max(2) - 1) as f64;
    if half.x / half.y < aspect {
        half.x = half.y * aspect;
    } else {
        half.y = half.x / aspect;
    }
    Extent::new(centre - half, centre + half)
}

/// The bounding rectangle of `points` (at least 1 × 1).
pub(crate) fn bounds(points: impl Iterator<Item = DVec2>) -> Rect {
    let (lo, hi) = points.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
    Rect::new(lo, hi.max(lo + DVec2::ONE))
}
