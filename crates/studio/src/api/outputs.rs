//! A result's samples for the views, its heightfield as a file, and its peaks.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::{Value, json};

use super::Shared;
use crate::error::ApiError;
use relief::heightfield::Heightfield;

/// The samples as little-endian f32, the northern row first (no-data as NaN).
fn north_up_bytes(hf: &Heightfield) -> Vec<u8> {
    let nx = hf.nx();
    let rows: Vec<&[f32]> = hf.samples().chunks(nx).collect();
    let south_first = hf.grid().cell_size().y > 0.0;
    let ordered: Box<dyn Iterator<Item = &&[f32]>> =
        if south_first { Box::new(rows.iter().rev()) } else { Box::new(rows.iter()) };
    ordered.flat_map(|row| row.iter()).flat_map(|v| v.to_le_bytes()).collect()
}

/// `GET /api/results/{id}/elevation`: the samples for the views.
pub(super) async fn elevation(State(app): Shared, Path(id): Path<u64>) -> Result<Response, ApiError> {
    let hf = app.result(id)?;
    let bytes = super::blocking(&app, move || Ok(north_up_bytes(&hf))).await?;
    Ok(([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response())
}

/// The download formats: `(name in the route, file written, file sent, content type)`. A RAW16
/// file holds codes only: its sidecar (`r16.json`) says what elevations they stand for.
const DOWNLOADS: [(&str, &str, &str, &str); 6] = [
    ("exr", "terrain.exr", "terrain.exr", "image/x-exr"),
    ("png", "terrain.png", "terrain.png", "image/png"),
    ("tif", "terrain.tif", "terrain.tif", "image/tiff"),
    ("asc", "terrain.asc", "terrain.asc", "text/plain"),
    ("r16", "terrain.r16", "terrain.r16", "application/octet-stream"),
    ("r16.json", "terrain.r16", "terrain.r16.json", "application/json"),
];

/// `GET /api/results/{id}/download/{format}`: the heightfield as a file (or a RAW16's sidecar).
pub(super) async fn download(
    State(app): Shared,
    Path((id, format)): Path<(u64, String)>,
) -> Result<Response, ApiError> {
    let (_, written, sent, content_type) = DOWNLOADS.iter().find(|(name, ..)| *name == format).ok_or_else(|| {
        let names: Vec<&str> = DOWNLOADS.iter().map(|(n, ..)| *n).collect();
        ApiError::not_found(format!("no format {format}: one of {}", names.join(", ")))
    })?;
    let hf = app.result(id)?;
    let bytes = super::blocking(&app, move || {
        let dir = tempfile::tempdir().map_err(ApiError::internal)?;
        relief::io::write(dir.path().join(written), &hf).map_err(ApiError::internal)?;
        std::fs::read(dir.path().join(sent)).map_err(ApiError::internal)
    })
    .await?;
    Ok(super::attachment(sent, content_type, bytes))
}

/// What the peak search takes per cell of the result, bytes: as an orometry generation's
/// (`relief::budget::bytes_per_cell`), whose analysis it is.
const PEAKS_BYTES_PER_CELL: u64 = 56;

/// `?min_prominence=M` (default: 5 % of the result's relief).
#[derive(Debug, serde::Deserialize)]
pub(super) struct PeaksQuery {
    min_prominence: Option<f64>,
}

/// The result's peaks at least `min_prominence` prominent and the key saddles joining them,
/// each with its ridge line.
pub(super) async fn peaks(
    State(app): Shared,
    Path(id): Path<u64>,
    axum::extract::Query(query): axum::extract::Query<PeaksQuery>,
) -> Result<Json<Value>, ApiError> {
    let hf = app.result(id)?;
    let held = app.memory.hold(hf.samples().len() as u64 * PEAKS_BYTES_PER_CELL, "this peak search").await?;
    let (orometry, min_prominence) = super::blocking(&app, move || {
        let _held = held;
        let (lo, hi) = hf.min_max().unwrap_or((0.0, 0.0));
        let min_prominence = query.min_prominence.unwrap_or(0.05 * f64::from(hi - lo));
        let options = relief::orometry::AnalysisOptions { min_prominence, ridge_lines: true, ..Default::default() };
        let analysed = relief::orometry::analyze(&hf, &options);
        analysed.map(|o| (o, min_prominence)).map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e))
    })
    .await?;
    let peaks: Vec<Value> = orometry
        .peaks
        .iter()
        .map(|p| json!({ "position": p.position, "elevation": p.elevation, "prominence": p.prominence }))
        .collect();
    let saddles: Vec<Value> = orometry
        .saddles
        .iter()
        .map(|s| json!({ "position": s.position, "elevation": s.elevation, "peaks": s.peaks, "ridge": s.ridge }))
        .collect();
    Ok(Json(json!({ "min_prominence": min_prominence, "peaks": peaks, "saddles": saddles })))
}
