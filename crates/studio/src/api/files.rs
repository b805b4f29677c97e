//! Saved scenes and uploaded inputs in the workspace.

use std::time::Instant;

use axum::Json;
use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::{Value, json};

use super::{Shared, parse_scene};
use crate::error::ApiError;

/// `GET /api/scenes`: the saved scenes' names.
pub(super) async fn scenes(State(app): Shared) -> Result<Json<Value>, ApiError> {
    Ok(Json(json!({ "scenes": app.workspace.scenes()? })))
}

/// `GET /api/scenes/{name}`: a saved scene's text.
pub(super) async fn read_scene(State(app): Shared, Path(name): Path<String>) -> Result<Response, ApiError> {
    let text = app.workspace.read_scene(&name)?;
    Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response())
}

/// Saves a scene after checking it parses: a saved scene always loads.
pub(super) async fn write_scene(
    State(app): Shared,
    Path(name): Path<String>,
    body: Bytes,
) -> Result<StatusCode, ApiError> {
    let scene = super::parse_scene_blocking(&app, body).await?;
    app.workspace.write_scene(&name, &scene.to_json())?;
    Ok(StatusCode::NO_CONTENT)
}

/// Reads an uploaded DEM under the budget's cell cap and keeps it as a result.
pub(super) async fn open_file(State(app): Shared, Path(name): Path<String>) -> Result<Json<Value>, ApiError> {
    crate::workspace::check_name(&name)?;
    let path = app.workspace.root().join(&name);
    if !path.is_file() {
        return Err(ApiError::not_found(format!("no file {name}: upload it first")));
    }
    let options = read_options(app.budget.max_read_cells());
    let start = Instant::now();
    let read =
        move || relief::io::read_with(&path, &options).map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e));
    let hf = super::blocking(&app, read).await?;
    let mut result = app.keep(hf, None)?;
    result["ms"] = (start.elapsed().as_secs_f64() * 1e3).into();
    result["timings"] = json!([]);
    result["warnings"] = json!([]);
    Ok(Json(result))
}

/// `PUT /api/files/{name}`: saves an uploaded input, atomically, unless it is a raster whose
/// header announces more cells than the budget allows (413): the upload is refused then, not
/// the first scene that reads it.
pub(super) async fn upload(State(app): Shared, Path(name): Path<String>, body: Bytes) -> Result<StatusCode, ApiError> {
    crate::workspace::check_name(&name)?;
    let worker = std::sync::Arc::clone(&app);
    super::blocking(&app, move || {
        check_json_upload(&worker, &name, &body)?;
        raster_fits(&name, &body, worker.budget.max_read_cells())?;
        worker.workspace.write_input(&name, &body)
    })
    .await?;
    Ok(StatusCode::NO_CONTENT)
}

/// A `.json`/`.geojson` upload must be JSON; one that is a scene (an object with a `generator`)
/// must be a valid one (422 at its JSON path), and an upload may not replace a saved scene with
/// anything else (409): the scene list offers every `.json`, and each must load.
fn check_json_upload(app: &super::App, name: &str, body: &[u8]) -> Result<(), ApiError> {
    let extension = std::path::Path::new(name).extension().and_then(|e| e.to_str()).unwrap_or_default();
    if !(extension.eq_ignore_ascii_case("json") || extension.eq_ignore_ascii_case("geojson")) {
        return Ok(());
    }
    let value: Value = serde_json::from_slice(body)
        .map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, format!("{name} is not JSON: {e}")))?;
    if value.get("generator").is_some() {
        parse_scene(body)?;
        return Ok(());
    }
    let existing = std::fs::read_to_string(app.workspace.root().join(name)).ok();
    if existing.is_some_and(|text| relief::Scene::from_json(&text).is_ok()) {
        let error =
            format!("{name} is a saved scene: save scenes with PUT /api/scenes/{name}, or upload under another name");
        return Err(ApiError::new(StatusCode::CONFLICT, error));
    }
    Ok(())
}

/// Refuses a raster upload (by its extension) whose header announces more than `max_cells`
/// cells (the budget's cells, and no more than its memory allows a read). Only the header is read ([`relief::io::announced_cells`]): a small compressed image can
/// announce gigabytes of pixels. Other problems are left to the scene that reads the file: a
/// colour label image, say, is not a DEM but is a fine upload, and a raw file (no header) is
/// counted by its length.
fn raster_fits(name: &str, bytes: &[u8], max_cells: u64) -> Result<(), ApiError> {
    use relief::io::Format;
    let Some(format) = Format::from_extension(std::path::Path::new(name)) else { return Ok(()) };
    match relief::io::announced_cells(bytes, format, name, &relief::io::ReadOptions::default()) {
        Ok(cells) if cells > max_cells => {
            let error = format!("{name} announces {cells} cells, more than the studio's budget of {max_cells}");
            Err(ApiError::new(StatusCode::PAYLOAD_TOO_LARGE, error))
        }
        _ => Ok(()),
    }
}

/// How the studio reads an uploaded raster: under the budget's cell cap.
fn read_options(max_cells: u64) -> relief::io::ReadOptions {
    relief::io::ReadOptions::default().with_limits(relief::io::Limits::default().with_max_cells(max_cells))
}
