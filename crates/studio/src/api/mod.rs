//! The routes: the page, and the JSON API the page drives.
//!
//! | Route | What |
//! |---|---|
//! | `GET /api/info` | version, workspace folder, template names |
//! | `GET /api/templates/{name}` | a starter scene |
//! | `POST /api/generate` | generate the scene in the body (a preview: no drainage analysis or raster contours); the result's id, size, range, step times, warnings |
//! | `GET /api/results/{id}/elevation` | its samples, f32 little-endian, north row first |
//! | `GET /api/results/{id}/download/{format}` | its heightfield as `exr`, `png` (16-bit), `tif`, `asc` or `r16`, or `r16.json` the RAW16 sidecar |
//! | `GET /api/scenes`, `GET`/`PUT /api/scenes/{name}` | saved scenes |
//! | `PUT /api/files/{name}` | upload an input (DEM, image, vector terrain); a raster over the budget gets 413 |
//! | `POST /api/files/{name}/open` | an uploaded DEM as a result (to view, analyse, download) |
//! | `GET /api/results/{id}/peaks?min_prominence=M` | its peaks and divide tree (akirmse's conventions) |
//! | `POST /api/export/{file}` | generate the scene in the body in full and return one of its outputs |
//! | `GET /api/progress`, `POST /api/cancel` | the session's running generation: its step, or stop it |
//! | `GET /api/events?session=ID` | the session's progress as server-sent events, one each time it changes |
//!
//! A page names its session in the `x-relief-session` header: a session's new generation
//! cancels the one it still runs (a newer edit supersedes an older one), which then answers 409.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use axum::Json;
use axum::Router;
use axum::extract::{DefaultBodyLimit, Path, State};
use axum::http::{HeaderMap, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use relief::Scene;
use relief::heightfield::Heightfield;
use serde_json::{Value, json};

mod files;
mod outputs;
mod run;

use crate::edits::EditSessions;
use crate::error::ApiError;
use crate::jobs::Jobs;
use crate::results::Results;
use crate::workspace::Workspace;

/// What every request shares.
#[derive(Debug)]
pub(crate) struct App {
    workspace: Workspace,
    budget: relief::Budget,
    results: Mutex<Results>,
    jobs: Jobs,
    /// The memory budget the running generations share.
    memory: crate::memory::Memory,
    /// Each session's editing state between its previews.
    pub(crate) edits: EditSessions,
    /// The server is shutting down: event streams end.
    closing: AtomicBool,
}

impl App {
    pub(crate) fn new(workspace: Workspace, config: &crate::Config) -> Self {
        Self {
            workspace,
            budget: config.budget,
            results: Mutex::new(Results::new(config.kept_results, config.kept_bytes)),
            jobs: Jobs::new(config.max_jobs),
            memory: crate::memory::Memory::new(config.budget.max_bytes, config.memory_wait),
            edits: EditSessions::default(),
            closing: AtomicBool::new(false),
        }
    }

    /// The server is shutting down: open event streams end, so that they do not hold it.
    pub(crate) fn close(&self) {
        self.closing.store(true, Ordering::Relaxed);
    }

    fn closing(&self) -> bool {
        self.closing.load(Ordering::Relaxed)
    }

    /// Keeps `hf` as a result: its id, size, range and extent as the page reads them.
    pub(crate) fn keep(&self, hf: Heightfield, sea_level: Option<f64>) -> Result<Value, ApiError> {
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

    pub(crate) fn result(&self, id: u64) -> Result<Arc<Heightfield>, ApiError> {
        let results = self.results.lock().map_err(|_| ApiError::internal("the results store is poisoned"))?;
        results.get(id).ok_or_else(|| ApiError::not_found(format!("no result {id} (only the latest are kept)")))
    }
}

/// The state every handler takes.
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
        .route("/api/generate", post(run::generate))
        .route("/api/export/{file}", post(run::export))
        .route("/api/export/engine/{engine}", post(run::export_engine))
        .route("/api/progress", get(run::progress))
        .route("/api/events", get(run::events))
        .route("/api/cancel", post(run::cancel))
        .route("/api/results/{id}/elevation", get(outputs::elevation))
        .route("/api/results/{id}/download/{format}", get(outputs::download))
        .route("/api/results/{id}/peaks", get(outputs::peaks))
        .route("/api/scenes", get(files::scenes))
        .route("/api/scenes/{name}", get(files::read_scene).put(files::write_scene))
        .route("/api/files/{name}", axum::routing::put(files::upload))
        .route("/api/files/{name}/open", post(files::open_file))
        .fallback(|| async { ApiError::not_found("no such route") })
        .layer(DefaultBodyLimit::max(max_body_bytes))
        .with_state(app)
}

/// A file to download: its content type and its name for the browser's save dialog.
pub(crate) fn attachment(file: &str, content_type: &str, bytes: Vec<u8>) -> Response {
    let disposition = format!("attachment; filename=\"{file}\"");
    ([(header::CONTENT_TYPE, content_type.to_owned()), (header::CONTENT_DISPOSITION, disposition)], bytes)
        .into_response()
}

/// `GET /api/info`: the version, the workspace and the template names.
async fn info(State(app): Shared) -> Json<Value> {
    let templates: Vec<&str> = crate::assets::templates().iter().map(|(name, _)| *name).collect();
    Json(json!({
        "version": env!("CARGO_PKG_VERSION"),
        "workspace": app.workspace.root(),
        "templates": templates,
    }))
}

/// `GET /api/templates/{name}`: a starter scene.
async fn template(Path(name): Path<String>) -> Result<Response, ApiError> {
    let (_, text) = crate::assets::templates()
        .into_iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| ApiError::not_found(format!("no template {name}")))?;
    Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response())
}

/// Runs `work` on a blocking thread, counted among the running jobs (503 when too many run) until
/// it ends, even when its client has gone (the thread cannot be stopped, so its place stays
/// taken): the async workers that answer every other request never parse, decode or analyse.
pub(crate) async fn blocking<T: Send + 'static>(
    app: &Arc<App>,
    work: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let slot = Slot { job: app.jobs.start(None)?, app: Arc::clone(app) };
    tokio::task::spawn_blocking(move || {
        let _slot = slot;
        work()
    })
    .await
    .map_err(ApiError::internal)?
}

/// A place among the running jobs held by blocking work; freed when it drops.
struct Slot {
    app: Arc<App>,
    job: Arc<crate::jobs::Job>,
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.app.jobs.end(None, &self.job);
    }
}

/// Parses a request body as a scene, on a blocking thread.
pub(crate) async fn parse_scene_blocking(app: &Arc<App>, body: axum::body::Bytes) -> Result<Scene, ApiError> {
    blocking(app, move || parse_scene(&body)).await
}

/// Parses a request body as a scene.
pub(crate) fn parse_scene(body: &[u8]) -> Result<Scene, ApiError> {
    let text = std::str::from_utf8(body).map_err(|e| ApiError::bad_request(format!("the scene is not UTF-8: {e}")))?;
    let scene = Scene::from_json(text)?;
    Workspace::check_inputs(&scene)?;
    Ok(scene)
}

/// The session a request names (`x-relief-session`), if any.
pub(crate) fn session(headers: &HeaderMap) -> Result<Option<String>, ApiError> {
    let Some(value) = headers.get("x-relief-session") else { return Ok(None) };
    let text = value.to_str().ok().filter(|t| session_name_ok(t));
    text.map(|t| Some(t.to_owned()))
        .ok_or_else(|| ApiError::bad_request("x-relief-session: 1 to 64 letters, digits or `-`"))
}

/// Whether `name` can name a session: 1 to 64 ASCII letters, digits or `-`.
pub(crate) fn session_name_ok(name: &str) -> bool {
    (1..=64).contains(&name.len()) && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-')
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocking work abandoned by its client keeps its place until it ends: its thread still
    /// runs, and the cap must count it.
    #[test]
    fn abandoned_blocking_work_holds_its_place_until_it_ends() {
        let dir = tempfile::tempdir().unwrap();
        let workspace = Workspace::open(dir.path()).unwrap();
        let app = Arc::new(App::new(workspace, &crate::Config::new(dir.path())));
        let runtime = tokio::runtime::Runtime::new().unwrap();
        let (release, wait) = std::sync::mpsc::channel::<()>();
        let (started, seen) = std::sync::mpsc::channel::<()>();
        let worker = Arc::clone(&app);
        let request = runtime.spawn(async move {
            blocking(&worker, move || {
                started.send(()).unwrap();
                wait.recv().ok();
                Ok(())
            })
            .await
        });
        seen.recv().unwrap();
        request.abort();
        assert!(runtime.block_on(request).unwrap_err().is_cancelled());
        assert_eq!(app.jobs.running(), 1, "the abandoned work still runs");
        release.send(()).unwrap();
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while app.jobs.running() != 0 {
            assert!(std::time::Instant::now() < deadline, "its place was never freed");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }
}
