//! A contour scene's label image: read in colour, placed, cleaned into a label map, and the
//! warning for the patches cleaning merged.

use super::contours::GENERATOR;
use super::inputs::Env;
use crate::eden_growth::{LabelLevel, LabelMap, MaskCleaning, MaskOptions, Sampling, hex};
use crate::error::SceneError;
use crate::heightfield::GridSpec;
use crate::scene::LabelImage;
use crate::{ReliefError, ReliefError as E};

/// A label image read, placed, cleaned (edge blends snapped, specks merged) and turned into a
/// label map.
pub(super) fn label_map(label: &LabelImage, env: &Env<'_>, sampling: Sampling) -> Result<LabelMap, ReliefError> {
    let at = format!("{GENERATOR}.label_image");
    let levels = match &label.levels {
        None => None,
        Some(rows) => Some(
            rows.iter()
                .enumerate()
                .map(|(k, row)| {
                    let color = row.value.rgb().map_err(|reason| {
                        E::at(
                            format!("{at}.levels[{k}].value"),
                            SceneError::OutOfRange { value: reason, rule: "a colour" },
                        )
                    })?;
                    Ok(LabelLevel { color, height: row.height, depression: row.depression })
                })
                .collect::<Result<Vec<_>, ReliefError>>()?,
        ),
    };
    let image = env.read_color(&label.path).map_err(|e| E::at(format!("{at}.path"), e))?;
    let grid = GridSpec::from_extent(image.grid.nx(), image.grid.ny(), label.extent)
        .map_err(|e| E::at(format!("{at}.extent"), e))?;
    let place = if label.levels.is_some() { format!("{at}.levels") } else { format!("{at}.path") };
    let labels =
        LabelMap::from_mask(grid, &image.pixels, &MaskOptions { levels, sampling }).map_err(|e| E::at(place, e))?;
    Ok(labels.with_depressions(label.depressions))
}

/// The warning for patches of a label image merged into their surroundings.
pub(super) fn merge_warning(cleaning: &MaskCleaning) -> Option<String> {
    let first = cleaning.merged.first()?;
    Some(format!(
        "label image: {} patch{} smaller than the sampling holds ({} pixels) merged into the level around {}, e.g. {} \
         pixel{} of {} at ({:.0}, {:.0}) into {}; summary.json lists them",
        cleaning.merged_count,
        if cleaning.merged_count == 1 { "" } else { "es" },
        cleaning.min_patch_pixels,
        if cleaning.merged_count == 1 { "it" } else { "them" },
        first.pixels,
        if first.pixels == 1 { "" } else { "s" },
        hex(first.color),
        first.at.x,
        first.at.y,
        hex(first.into)
    ))
}
