//! What runs on every generator's heightfield: the scene's post-processes (erosion, filling) and
//! the drainage summary. The sea (when the generator has one) and the map border are the base
//! level water drains to.

use super::progress::Tick;
use super::summary::DrainageSummary;
use crate::heightfield::Heightfield;
use crate::hydrology::{self, D8, HydrologyError, Outlets, StreamPower};
use crate::scene::PostProcess;
use crate::{ReliefError, ReliefError as E};

/// Where water leaves: the border, and the sea below `sea_level` when there is one.
pub(super) fn outlets(sea_level: Option<f64>) -> Outlets {
    match sea_level {
        Some(sea) => Outlets::new().with_sea_level(sea as f32),
        None => Outlets::new(),
    }
}

/// The units of work of the post-processes, as [`post_process`] ticks them: one per erosion
/// iteration, one per fill.
pub(super) fn post_work(post: &[PostProcess]) -> u64 {
    let units = |step: &PostProcess| match step {
        PostProcess::StreamPower(law) => law.iterations as u64,
        PostProcess::Thermal(thermal) => thermal.iterations as u64,
        PostProcess::Fill {} | PostProcess::Details { .. } => 1,
    };
    post.iter().map(units).sum()
}

/// Runs the scene's post-processes in order, ticking each unit of [`post_work`]; a `details`
/// step adds the raster's changes to `vector` (a gaussian scene's terrain).
pub(super) fn post_process(
    mut hf: Heightfield,
    post: &[PostProcess],
    sea_level: Option<f64>,
    mut vector: Option<&mut crate::gaussian_terrain::VectorTerrain>,
    seed: u64,
    tick: &mut Tick<'_>,
) -> Result<Heightfield, ReliefError> {
    let outlets = outlets(sea_level);
    for (k, step) in post.iter().enumerate() {
        tick.check()?;
        let fail = |kind: &str, e: HydrologyError| match e {
            HydrologyError::InvalidParameter { .. } | HydrologyError::LengthMismatch { .. } => {
                E::located(&format!("post[{k}].{kind}"), e)
            }
            e => E::step("post-process", e),
        };
        match step {
            PostProcess::StreamPower(law) => {
                let law = StreamPower { outlets, ..law.clone() };
                law.run(&mut hf, |_| tick.tick()).map_err(|e| fail("stream_power", e))?;
            }
            PostProcess::Thermal(thermal) => thermal.run(&mut hf, |_| tick.tick()).map_err(|e| fail("thermal", e))?,
            PostProcess::Fill {} => {
                hf = hydrology::fill(&hf, outlets).map_err(|e| fail("fill", e))?;
                tick.tick();
            }
            PostProcess::Details { spacing } => {
                let at = format!("post[{k}].details");
                let Some(terrain) = vector.as_deref_mut() else {
                    let rule = "only a gaussian scene has a vector terrain to add details to";
                    return Err(E::at(at, crate::SceneError::OutOfRange { value: "details".into(), rule }));
                };
                terrain.add_error_details(&hf, *spacing, seed).map_err(|e| E::at(at, e))?;
                tick.tick();
            }
        }
    }
    Ok(hf)
}

/// Closed basins and stream order of `hf`.
pub(super) fn drainage(hf: &Heightfield, sea_level: Option<f64>) -> Result<DrainageSummary, ReliefError> {
    let fail = |e: HydrologyError| E::step("drainage", e);
    let closed = hydrology::depressions(hf, outlets(sea_level)).map_err(fail)?;
    let artefacts = hydrology::measure_artefacts_with_basins(hf, sea_level, &closed.basins);
    let routed = D8::new(&closed.filled).map_err(fail)?;
    let sea = sea_level.map_or(f32::NEG_INFINITY, |s| s as f32);
    let land_area: f64 =
        (0..hf.ny()).map(|j| hf.row(j).iter().filter(|&&v| v > sea).count() as f64 * hf.grid().cell_area_m2(j)).sum();
    let streams = routed.streams(0.005 * land_area).map_err(fail)?;
    let max_strahler = routed.strahler(&streams).map_err(fail)?.into_iter().max().unwrap_or(0);
    Ok(DrainageSummary {
        closed_basins: closed.basins.len(),
        closed_volume: closed.basins.iter().map(|b| b.volume_m3).sum(),
        max_strahler,
        artefacts,
    })
}
