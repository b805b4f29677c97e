//! The routes: the page, and the JSON API the page drives.
//!
//! | Route | What |
//! |---|---|
//! | `GET /api/info` | version, workspace folder, template names |
//! | `GET /api/templates/{name}` | a starter scene |
//! | `POST /api/generate` | generate the scene in the body (a preview: no drainage analysis or raster contours); the result's id, size, range, step times, warnings |
//! | `GET /api/results/{id}/elevation` | its samples, f32 little-endian, north row first |
//! | `GET /api/results/{id}/download/{format}` | its heightfield as `exr`, `png` (16-bit), `tif`, `asc` or `r16` |
//! | `GET /api/scenes`, `GET`/`PUT /api/scenes/{name}` | saved scenes |
//! | `PUT /api/files/{name}` | upload an input (DEM, image, vector terrain) |
//! | `POST /api/files/{name}/open` | an uploaded DEM as a result (to view, analyse, download) |
//! | `GET /api/results/{id}/peaks?min_prominence=M` | its peaks and divide tree (akirmse's conventions) |
//! | `POST /api/export/{file}` | generate the scene in the body in full and return one of its outputs |
//! | `GET /api/progress`, `POST /api/cancel` | the session's running generation: its step, or stop it |
//!
//! A page names its session in the `x-relief-session` header: a session's new generation
//! cancels the one it still runs (a newer edit supersedes an older one), which then answers 409.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use axum::Json;
use axum::Router;
use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Path, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use relief::Scene;
use relief::heightfield::Heightfield;
use serde_json::{Value, json};

use crate::error::ApiError;
use crate::jobs::{Job, Jobs};
use crate::results::Results;
use crate::workspace::Workspace;

/// What every request shares.
#[derive(Debug)]
pub(crate) struct App {
    workspace: Workspace,
    budget: relief::Budget,
    results: Mutex<Results>,
    jobs: Jobs,
}

impl App {
    pub(crate) fn new(workspace: Workspace, config: &crate::Config) -> Self {
        Self {
            workspace,
            budget: config.budget,
            results: Mutex::new(Results::new(config.kept_results)),
            jobs: Jobs::default(),
        }
    }

    /// Keeps `hf` as a result: its id, size, range and extent as the page reads them.
    fn keep(&self, hf: Heightfield, sea_level: Option<f64>) -> Result<Value, ApiError> {
        let (min, max) = hf.min_max().unwrap_or((0.0, 0.0));
        let extent = hf.extent();
        let (width, height) = (hf.nx(), hf.ny());
        let metres = hf.grid().metres_per_unit(height / 2);
        let mut results = self.results.lock().map_err(|_| ApiError::internal("the results store is poisoned"))?;
        let id = results.insert(hf);
        Ok(json!({
            "id": id,
            "width": width,
            "height": height,
            "min": min,
            "max": max,
            "extent": { "min": [extent.min.x, extent.min.y], "max": [extent.max.x, extent.max.y] },
            "sea_level": sea_level,
            "metres_per_unit": [metres.x, metres.y],
        }))
    }

    fn result(&self, id: u64) -> Result<Arc<Heightfield>, ApiError> {
        let results = self.results.lock().map_err(|_| ApiError::internal("the results store is poisoned"))?;
        results.get(id).ok_or_else(|| ApiError::not_found(format!("no result {id} (only the latest are kept)")))
    }
}

type Shared = State<Arc<App>>;

/// Every route, with bodies capped at `max_body_bytes`.
pub(crate) fn routes(app: Arc<App>, max_body_bytes: usize) -> Router {
    let mut router = Router::new();
    for (route, content_type, body) in crate::assets::FILES {
        router = router.route(route, get(move || async move { ([(header::CONTENT_TYPE, content_type)], body) }));
    }
    router
        .route("/api/info", get(info))
        .route("/api/templates/{name}", get(template))
        .route("/api/generate", post(generate))
        .route("/api/results/{id}/elevation", get(elevation))
        .route("/api/results/{id}/download/{format}", get(download))
        .route("/api/scenes", get(scenes))
        .route("/api/scenes/{name}", get(read_scene).put(write_scene))
        .route("/api/files/{name}", axum::routing::put(upload))
        .route("/api/files/{name}/open", post(open_file))
        .route("/api/results/{id}/peaks", get(peaks))
        .route("/api/export/{file}", post(export))
        .route("/api/progress", get(progress))
        .route("/api/cancel", post(cancel))
        .fallback(|| async { ApiError::not_found("no such route") })
        .layer(DefaultBodyLimit::max(max_body_bytes))
        .with_state(app)
}

async fn info(State(app): Shared) -> Json<Value> {
    let templates: Vec<&str> = crate::assets::templates().iter().map(|(name, _)| *name).collect();
    Json(json!({
        "version": env!("CARGO_PKG_VERSION"),
        "workspace": app.workspace.root(),
        "templates": templates,
    }))
}

async fn template(Path(name): Path<String>) -> Result<Response, ApiError> {
    let (_, text) = crate::assets::templates()
        .into_iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| ApiError::not_found(format!("no template {name}")))?;
    Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response())
}

/// Parses a request body as a scene.
fn parse_scene(body: &[u8]) -> Result<Scene, ApiError> {
    let text = std::str::from_utf8(body).map_err(|e| ApiError::bad_request(format!("the scene is not UTF-8: {e}")))?;
    let scene = Scene::from_json(text)?;
    Workspace::check_inputs(&scene)?;
    Ok(scene)
}

/// The session a request names (`x-relief-session`), if any.
fn session(headers: &HeaderMap) -> Result<Option<String>, ApiError> {
    let Some(value) = headers.get("x-relief-session") else { return Ok(None) };
    let text = value
        .to_str()
        .ok()
        .filter(|t| (1..=64).contains(&t.len()) && t.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-'));
    text.map(|t| Some(t.to_owned()))
        .ok_or_else(|| ApiError::bad_request("x-relief-session: 1 to 64 letters, digits or `-`"))
}

async fn generate(State(app): Shared, headers: HeaderMap, body: Bytes) -> Result<Json<Value>, ApiError> {
    let scene = parse_scene(&body)?;
    let start = Instant::now();
    let session = session(&headers)?;
    let job = app.jobs.start(session.as_deref())?;
    let (worker, running) = (Arc::clone(&app), Arc::clone(&job));
    let generated = tokio::task::spawn_blocking(move || {
        let mut progress = crate::jobs::JobProgress(running);
        relief::pipeline::preview_with(&scene, worker.workspace.root(), &worker.budget, &mut progress)
    })
    .await;
    app.jobs.end(session.as_deref(), &job);
    let preview = match generated.map_err(ApiError::internal)? {
        Err(relief::ReliefError::Cancelled) => {
            return Err(ApiError::new(StatusCode::CONFLICT, "cancelled: a newer generation superseded it"));
        }
        other => other?,
    };
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let timings = serde_json::to_value(&preview.timings).map_err(ApiError::internal)?;
    let mut result = app.keep(preview.heightfield, preview.sea_level)?;
    result["ms"] = ms.into();
    result["timings"] = timings;
    result["warnings"] = json!(preview.warnings);
    Ok(Json(result))
}

/// The samples as little-endian f32, the northern row first (no-data as NaN).
fn north_up_bytes(hf: &Heightfield) -> Vec<u8> {
    let nx = hf.nx();
    let rows: Vec<&[f32]> = hf.samples().chunks(nx).collect();
    let south_first = hf.grid().cell_size().y > 0.0;
    let ordered: Box<dyn Iterator<Item = &&[f32]>> =
        if south_first { Box::new(rows.iter().rev()) } else { Box::new(rows.iter()) };
    ordered.flat_map(|row| row.iter()).flat_map(|v| v.to_le_bytes()).collect()
}

async fn elevation(State(app): Shared, Path(id): Path<u64>) -> Result<Response, ApiError> {
    let hf = app.result(id)?;
    let bytes = tokio::task::spawn_blocking(move || north_up_bytes(&hf)).await.map_err(ApiError::internal)?;
    Ok(([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response())
}

/// The download formats: `(name in the route, extension, content type)`.
const DOWNLOADS: [(&str, &str, &str); 5] = [
    ("exr", "exr", "image/x-exr"),
    ("png", "png", "image/png"),
    ("tif", "tif", "image/tiff"),
    ("asc", "asc", "text/plain"),
    ("r16", "r16", "application/octet-stream"),
];

async fn download(State(app): Shared, Path((id, format)): Path<(u64, String)>) -> Result<Response, ApiError> {
    let (_, extension, content_type) = DOWNLOADS.iter().find(|(name, ..)| *name == format).ok_or_else(|| {
        let names: Vec<&str> = DOWNLOADS.iter().map(|(n, ..)| *n).collect();
        ApiError::not_found(format!("no format {format}: one of {}", names.join(", ")))
    })?;
    let hf = app.result(id)?;
    let file = format!("terrain.{extension}");
    let name = file.clone();
    let bytes = tokio::task::spawn_blocking(move || -> Result<Vec<u8>, ApiError> {
        let dir = tempfile::tempdir().map_err(ApiError::internal)?;
        let path = dir.path().join(&name);
        relief::io::write(&path, &hf).map_err(ApiError::internal)?;
        std::fs::read(&path).map_err(ApiError::internal)
    })
    .await
    .map_err(ApiError::internal)??;
    let disposition = format!("attachment; filename=\"{file}\"");
    Ok(([(header::CONTENT_TYPE, (*content_type).to_owned()), (header::CONTENT_DISPOSITION, disposition)], bytes)
        .into_response())
}

async fn scenes(State(app): Shared) -> Result<Json<Value>, ApiError> {
    Ok(Json(json!({ "scenes": app.workspace.scenes()? })))
}

async fn read_scene(State(app): Shared, Path(name): Path<String>) -> Result<Response, ApiError> {
    let text = app.workspace.read_scene(&name)?;
    Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response())
}

/// Saves a scene after checking it parses: a saved scene always loads.
async fn write_scene(State(app): Shared, Path(name): Path<String>, body: Bytes) -> Result<StatusCode, ApiError> {
    let scene = parse_scene(&body)?;
    app.workspace.write_scene(&name, &scene.to_json())?;
    Ok(StatusCode::NO_CONTENT)
}

/// The outputs `/api/export/{file}` writes: `(file, the scene's outputs field, content type)`.
const EXPORTS: [(&str, &str, &str); 8] = [
    ("contours.geojson", "contours_geojson", "application/geo+json"),
    ("contours.svg", "contours_svg", "image/svg+xml"),
    ("preview.png", "preview", "image/png"),
    ("summary.json", "summary", "application/json"),
    ("divide-tree.geojson", "divide_tree", "application/geo+json"),
    ("vector-terrain.json", "vector_terrain", "application/json"),
    ("skeleton.geojson", "skeleton", "application/geo+json"),
    ("terrain.glb", "mesh", "model/gltf-binary"),
];

/// The scene's outputs replaced by `file` alone.
fn only_output(scene: &mut Scene, field: &str, file: &str) -> Result<(), ApiError> {
    let value = if field == "mesh" { json!({ "file": file }) } else { json!(file) };
    let outputs = json!({
        "heightfield": [], "contours_geojson": null, "contours_svg": null, "preview": null, "summary": null,
        field: value,
    });
    scene.outputs = serde_json::from_value(outputs).map_err(ApiError::internal)?;
    Ok(())
}

/// Generates the scene in full (drainage and contours included) under the session's job and
/// returns one output file.
async fn export(
    State(app): Shared,
    Path(file): Path<String>,
    headers: HeaderMap,
    body: Bytes,
) -> Result<Response, ApiError> {
    let (_, field, content_type) = EXPORTS.iter().find(|(name, ..)| *name == file).ok_or_else(|| {
        let names: Vec<&str> = EXPORTS.iter().map(|(n, ..)| *n).collect();
        ApiError::not_found(format!("no export {file}: one of {}", names.join(", ")))
    })?;
    let mut scene = parse_scene(&body)?;
    only_output(&mut scene, field, &file)?;
    let session = session(&headers)?;
    let job = app.jobs.start(session.as_deref())?;
    let (worker, running, name) = (Arc::clone(&app), Arc::clone(&job), file.clone());
    let written = tokio::task::spawn_blocking(move || -> Result<Option<Vec<u8>>, ApiError> {
        let dir = tempfile::tempdir().map_err(ApiError::internal)?;
        let mut progress = crate::jobs::JobProgress(running);
        match relief::pipeline::run_with(&scene, worker.workspace.root(), dir.path(), &worker.budget, &mut progress) {
            Err(relief::ReliefError::Cancelled) => Err(ApiError::new(StatusCode::CONFLICT, "cancelled")),
            Err(error) => Err(error.into()),
            Ok(_) => Ok(std::fs::read(dir.path().join(&name)).ok()),
        }
    })
    .await;
    app.jobs.end(session.as_deref(), &job);
    let bytes = written.map_err(ApiError::internal)??.ok_or_else(|| {
        let generator = "this scene's generator does not write";
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, format!("{generator} {file}"))
    })?;
    let disposition = format!("attachment; filename=\"{file}\"");
    Ok(([(header::CONTENT_TYPE, (*content_type).to_owned()), (header::CONTENT_DISPOSITION, disposition)], bytes)
        .into_response())
}

async fn progress(State(app): Shared, headers: HeaderMap) -> Result<Json<Value>, ApiError> {
    let session = session(&headers)?.ok_or_else(|| ApiError::bad_request("progress needs x-relief-session"))?;
    let state = app.jobs.get(&session).map(|job: Arc<Job>| job.state());
    Ok(Json(match state {
        Some(s) => json!({ "running": true, "step": s.step, "done": s.done, "total": s.total }),
        None => json!({ "running": false }),
    }))
}

async fn cancel(State(app): Shared, headers: HeaderMap) -> Result<StatusCode, ApiError> {
    let session = session(&headers)?.ok_or_else(|| ApiError::bad_request("cancel needs x-relief-session"))?;
    if let Some(job) = app.jobs.get(&session) {
        job.cancel();
    }
    Ok(StatusCode::NO_CONTENT)
}

/// Reads an uploaded DEM under the budget's cell cap and keeps it as a result.
async fn open_file(State(app): Shared, Path(name): Path<String>) -> Result<Json<Value>, ApiError> {
    crate::workspace::check_name(&name)?;
    let path = app.workspace.root().join(&name);
    if !path.is_file() {
        return Err(ApiError::not_found(format!("no file {name}: upload it first")));
    }
    let limits = relief::io::Limits::default().with_max_cells(app.budget.max_cells);
    let options = relief::io::ReadOptions::default().with_limits(limits);
    let start = Instant::now();
    let read = tokio::task::spawn_blocking(move || relief::io::read_with(&path, &options)).await;
    let hf = read.map_err(ApiError::internal)?.map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e))?;
    let mut result = app.keep(hf, None)?;
    result["ms"] = (start.elapsed().as_secs_f64() * 1e3).into();
    result["timings"] = json!([]);
    result["warnings"] = json!([]);
    Ok(Json(result))
}

/// `?min_prominence=M` (default: 5 % of the result's relief).
#[derive(Debug, serde::Deserialize)]
struct PeaksQuery {
    min_prominence: Option<f64>,
}

/// The result's peaks at least `min_prominence` prominent and the key saddles joining them,
/// each with its ridge line.
async fn peaks(
    State(app): Shared,
    Path(id): Path<u64>,
    axum::extract::Query(query): axum::extract::Query<PeaksQuery>,
) -> Result<Json<Value>, ApiError> {
    let hf = app.result(id)?;
    let analysed = tokio::task::spawn_blocking(move || {
        let (lo, hi) = hf.min_max().unwrap_or((0.0, 0.0));
        let min_prominence = query.min_prominence.unwrap_or(0.05 * f64::from(hi - lo));
        let options = relief::orometry::AnalysisOptions { min_prominence, ridge_lines: true, ..Default::default() };
        relief::orometry::analyze(&hf, &options).map(|o| (o, min_prominence))
    })
    .await
    .map_err(ApiError::internal)?;
    let (orometry, min_prominence) = analysed.map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e))?;
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

async fn upload(State(app): Shared, Path(name): Path<String>, body: Bytes) -> Result<StatusCode, ApiError> {
    app.workspace.write_input(&name, &body)?;
    Ok(StatusCode::NO_CONTENT)
}
