//! Writing a generated terrain: heightfields, contours, the divide tree, the preview and the
//! summary, each atomically.

use std::path::{Path, PathBuf};

use super::Terrain;
use super::progress::{Progress, Timer};
use crate::error::SceneError;
use crate::io::Format;
use crate::scene::Outputs;
use crate::{ReliefError, ReliefError as E};

/// Width of the SVG drawing, in pixels.
const SVG_WIDTH: u32 = 1024;

/// Every heightfield output has a known extension.
pub(super) fn check_outputs(outputs: &Outputs) -> Result<(), ReliefError> {
    for (i, path) in outputs.heightfield.iter().enumerate() {
        if Format::from_extension(path).is_none() {
            return Err(E::at(
                format!("outputs.heightfield[{i}]"),
                SceneError::UnknownExtension { path: path.clone() },
            ));
        }
    }
    Ok(())
}

/// Writes the outputs of `terrain` under `out_dir` (created if needed) and returns the files
/// written, in order. Every file is written atomically. The summary, written last, includes the
/// time spent writing the others.
///
/// # Errors
/// [`ReliefError::Scene`] for an output path with an unknown extension (checked before anything is
/// written), [`ReliefError::Io`] / [`ReliefError::File`] when a file cannot be written.
pub fn write_outputs(
    terrain: &Terrain,
    outputs: &Outputs,
    out_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<Vec<PathBuf>, ReliefError> {
    check_outputs(outputs)?;
    std::fs::create_dir_all(out_dir).map_err(|source| ReliefError::File { path: out_dir.to_owned(), source })?;
    let mut timer = Timer::new(progress);
    let mut written = timer.step("write", || write_files(terrain, outputs, out_dir))?;
    if let Some(p) = &outputs.summary {
        let path = out_dir.join(p);
        let mut summary = terrain.summary.clone();
        summary.timings_ms.extend(timer.timings);
        let mut text = serde_json::to_string_pretty(&summary).map_err(|e| E::step("summary", e))?;
        text.push('\n');
        crate::io::write_atomic(&path, text.as_bytes())?;
        written.push(path);
    }
    Ok(written)
}

/// Every output but the summary, in order: heightfields, contours, divide tree, preview.
fn write_files(terrain: &Terrain, outputs: &Outputs, out_dir: &Path) -> Result<Vec<PathBuf>, ReliefError> {
    let mut written = Vec::new();
    for name in &outputs.heightfield {
        let path = out_dir.join(name);
        crate::io::write(&path, &terrain.heightfield)?;
        written.push(path);
    }
    if let Some(name) = &outputs.contours_geojson {
        let text = crate::export::contours_geojson(&terrain.contours);
        written.push(write_text(out_dir, name, &text)?);
    }
    if let Some(name) = &outputs.contours_svg {
        let text = crate::export::contours_svg(&terrain.contours, &terrain.heightfield.extent(), SVG_WIDTH);
        written.push(write_text(out_dir, name, &text)?);
    }
    if let (Some(name), Some(o)) = (&outputs.divide_tree, &terrain.summary.orometry) {
        written.push(write_text(out_dir, name, &crate::export::divide_tree_geojson(&o.tree, None))?);
    }
    if let Some(name) = &outputs.preview {
        let path = out_dir.join(name);
        let image = crate::export::preview_image(&terrain.heightfield, Some(&terrain.contours), terrain.sea_level);
        crate::io::write_rgb_png(&path, &image)?;
        written.push(path);
    }
    Ok(written)
}

/// Writes `text` to `out_dir/name` atomically and returns the path.
fn write_text(out_dir: &Path, name: &Path, text: &str) -> Result<PathBuf, ReliefError> {
    let path = out_dir.join(name);
    crate::io::write_atomic(&path, text.as_bytes())?;
    Ok(path)
}
