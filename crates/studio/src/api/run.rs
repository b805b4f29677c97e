//! Generation: previews for the views, full runs for exports, and the session's job (its
//! progress, polled or streamed, and its cancellation).

use std::convert::Infallible;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::Json;
use axum::body::Bytes;
use axum::extract::{Path, Query, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::Response;
use axum::response::sse::{Event, KeepAlive, Sse};
use futures_util::Stream;
use serde::Deserialize;
use serde_json::{Value, json};

use super::{App, Shared, parse_scene_blocking, session};
use crate::error::ApiError;
use crate::jobs::Job;
use relief::Scene;

/// `POST /api/generate`: the scene in the body as a preview, kept as a result.
pub(super) async fn generate(State(app): Shared, headers: HeaderMap, body: Bytes) -> Result<Json<Value>, ApiError> {
    let scene = parse_scene_blocking(&app, body).await?;
    let start = Instant::now();
    let session = session(&headers)?;
    let guard = app.jobs.run(session.as_deref())?;
    let held = app.memory.hold(relief::budget::estimated_bytes(&scene), "this generation").await?;
    let (worker, running) = (Arc::clone(&app), Arc::clone(&guard.job));
    // The session's editing state: its next island edit applies to what its last preview left.
    // It is locked on the blocking thread, so an abandoned request's generation keeps it until it
    // stops (between two island operations); other generators do not use it, nor wait for it.
    let island = matches!(scene.generator, relief::scene::Generator::Island(_));
    let edit = session.as_deref().filter(|_| island).map(|name| app.edits.get(name));
    let generated = tokio::task::spawn_blocking(move || {
        let _held = held;
        let mut progress = crate::jobs::JobProgress(running);
        let (root, budget) = (worker.workspace.root(), &worker.budget);
        match edit {
            Some(edit) => {
                let mut edit = edit.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
                let preview = relief::pipeline::preview_in(&mut edit, &scene, root, budget, &mut progress);
                (preview, edit.resumed())
            }
            None => (relief::pipeline::preview_with(&scene, root, budget, &mut progress), 0),
        }
    })
    .await;
    drop(guard);
    let (preview, resumed) = generated.map_err(ApiError::internal)?;
    let preview = match preview {
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
    result["resumed"] = resumed.into();
    if let Some(tree) = &preview.divide_tree {
        result["divide_tree"] = tree_json(tree);
    }
    Ok(Json(result))
}

/// An orometry scene's divide tree as the page draws it: peaks and saddles in index order (the
/// indices its tree edits take), each saddle with the two peaks it joins.
fn tree_json(tree: &relief::orometry::DivideTree) -> Value {
    let peaks: Vec<Value> = tree
        .peaks
        .iter()
        .map(|p| json!({ "position": [p.position.x, p.position.y], "elevation": p.elevation }))
        .collect();
    let saddles: Vec<Value> = tree
        .saddles
        .iter()
        .map(|s| json!({ "position": [s.position.x, s.position.y], "elevation": s.elevation, "peaks": s.peaks }))
        .collect();
    json!({ "peaks": peaks, "saddles": saddles })
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

/// The scene's outputs replaced by the one `field` set to `value`.
fn only_output(scene: &mut Scene, field: &str, value: &Value) -> Result<(), ApiError> {
    let outputs = json!({
        "heightfield": [], "contours_geojson": null, "contours_svg": null, "preview": null, "summary": null,
        field: value,
    });
    scene.outputs = serde_json::from_value(outputs).map_err(ApiError::internal)?;
    Ok(())
}

/// Generates the scene in full (drainage and contours included) under the session's job and
/// returns one output file.
pub(super) async fn export(
    State(app): Shared,
    Path(file): Path<String>,
    headers: HeaderMap,
    body: Bytes,
) -> Result<Response, ApiError> {
    let (_, field, content_type) = EXPORTS.iter().find(|(name, ..)| *name == file).ok_or_else(|| {
        let names: Vec<&str> = EXPORTS.iter().map(|(n, ..)| *n).collect();
        ApiError::not_found(format!("no export {file}: one of {}", names.join(", ")))
    })?;
    let mut scene = parse_scene_blocking(&app, body).await?;
    let value = if *field == "mesh" { json!({ "file": file }) } else { json!(file) };
    only_output(&mut scene, field, &value)?;
    let name = file.clone();
    let bytes = run_full(&app, &headers, scene, move |dir| Ok(std::fs::read(dir.join(&name)).ok())).await?;
    let bytes = bytes.ok_or_else(|| {
        let generator = "this scene's generator does not write";
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, format!("{generator} {file}"))
    })?;
    Ok(super::attachment(&file, content_type, bytes))
}

/// `POST /api/export/engine/{engine}`: generates the scene in full and returns the engine's
/// files (heightmaps or tiles, splat maps, `heightmap.import.json`) as one zip. The scene's own
/// `outputs.engines` entry for that engine sets the size, tiles and splat maps; without one, the
/// engine's nearest legal size with the default splat maps.
pub(super) async fn export_engine(
    State(app): Shared,
    Path(engine): Path<String>,
    headers: HeaderMap,
    body: Bytes,
) -> Result<Response, ApiError> {
    let found = relief::engine::Engine::ALL.into_iter().find(|e| e.name() == engine).ok_or_else(|| {
        let names: Vec<&str> = relief::engine::Engine::ALL.iter().map(|e| e.name()).collect();
        ApiError::not_found(format!("no engine {engine}: one of {}", names.join(", ")))
    })?;
    let mut scene = parse_scene_blocking(&app, body).await?;
    let output = engine_output(&scene, found);
    only_output(&mut scene, "engines", &json!([output]))?;
    let zipped =
        run_full(&app, &headers, scene, move |dir| zip_folder(&dir.join(found.name())).map_err(ApiError::internal))
            .await?;
    Ok(super::attachment(&format!("terrain-{engine}.zip"), "application/zip", zipped))
}

/// The scene's own export for `engine` in its own folder, or the defaults with splat maps.
fn engine_output(scene: &Scene, engine: relief::engine::Engine) -> relief::scene::EngineOutput {
    let own = scene.outputs.engines.iter().find(|e| e.engine == engine).cloned();
    let mut output = own.unwrap_or(relief::scene::EngineOutput {
        engine,
        dir: None,
        size: None,
        tile: None,
        splat: Some(relief::engine::SplatOptions::default()),
    });
    output.dir = Some(engine.name().into());
    output
}

/// Every file of `dir` (an engine's flat folder), by name, deflated into one zip.
fn zip_folder(dir: &std::path::Path) -> Result<Vec<u8>, Box<dyn std::error::Error + Send + Sync>> {
    use std::io::Write;
    let mut names: Vec<_> = std::fs::read_dir(dir)?.map(|e| e.map(|e| e.file_name())).collect::<Result<_, _>>()?;
    names.sort();
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for name in names {
        zip.start_file(name.to_string_lossy(), options)?;
        zip.write_all(&std::fs::read(dir.join(&name))?)?;
    }
    Ok(zip.finish()?.into_inner())
}

/// Runs `scene` in full into a temporary folder under the session's job, then `read` takes what
/// it needs from the folder.
async fn run_full<T: Send + 'static>(
    app: &Arc<App>,
    headers: &HeaderMap,
    scene: Scene,
    read: impl FnOnce(&std::path::Path) -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let session = session(headers)?;
    let guard = app.jobs.run(session.as_deref())?;
    let held = app.memory.hold(relief::budget::estimated_bytes(&scene), "this export").await?;
    let (worker, running) = (Arc::clone(app), Arc::clone(&guard.job));
    let written = tokio::task::spawn_blocking(move || -> Result<T, ApiError> {
        let _held = held;
        let dir = tempfile::tempdir().map_err(ApiError::internal)?;
        let mut progress = crate::jobs::JobProgress(running);
        match relief::pipeline::run_with(&scene, worker.workspace.root(), dir.path(), &worker.budget, &mut progress) {
            Err(relief::ReliefError::Cancelled) => Err(ApiError::new(StatusCode::CONFLICT, "cancelled")),
            Err(error) => Err(error.into()),
            Ok(_) => read(dir.path()),
        }
    })
    .await;
    drop(guard);
    written.map_err(ApiError::internal)?
}

/// `GET /api/progress`: where the session's running generation is.
pub(super) async fn progress(State(app): Shared, headers: HeaderMap) -> Result<Json<Value>, ApiError> {
    let session = session(&headers)?.ok_or_else(|| ApiError::bad_request("progress needs x-relief-session"))?;
    Ok(Json(progress_json(&app, &session)))
}

/// `{running, step, done, total}` of the session's generation, or `{running: false}`.
fn progress_json(app: &App, session: &str) -> Value {
    match app.jobs.get(session).map(|job: Arc<Job>| job.state()) {
        Some(s) => json!({ "running": true, "step": s.step, "done": s.done, "total": s.total }),
        None => json!({ "running": false }),
    }
}

/// How often the event stream looks at the session's progress.
const EVENT_PERIOD: Duration = Duration::from_millis(50);

/// The query of `/api/events` (a browser's `EventSource` cannot send headers).
#[derive(Debug, Deserialize)]
pub(super) struct EventsQuery {
    session: Option<String>,
}

/// `GET /api/events?session=ID`: the session's progress as server-sent events (`progress`, the
/// JSON of `/api/progress`), one each time it changes, for as long as the page listens or until
/// the server shuts down.
pub(super) async fn events(
    State(app): Shared,
    Query(query): Query<EventsQuery>,
) -> Result<Sse<impl Stream<Item = Result<Event, Infallible>>>, ApiError> {
    let session = query
        .session
        .filter(|s| super::session_name_ok(s))
        .ok_or_else(|| ApiError::bad_request("session: 1 to 64 letters, digits or `-`"))?;
    let stream = futures_util::stream::unfold((app, session, None), |(app, session, last)| async move {
        loop {
            if app.closing() {
                return None;
            }
            let now = progress_json(&app, &session);
            if last.as_ref() != Some(&now) {
                let event = Event::default().event("progress").data(now.to_string());
                return Some((Ok(event), (app, session, Some(now))));
            }
            tokio::time::sleep(EVENT_PERIOD).await;
        }
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::default()))
}

/// `POST /api/cancel`: stops the session's running generation.
pub(super) async fn cancel(State(app): Shared, headers: HeaderMap) -> Result<StatusCode, ApiError> {
    let session = session(&headers)?.ok_or_else(|| ApiError::bad_request("cancel needs x-relief-session"))?;
    if let Some(job) = app.jobs.get(&session) {
        job.cancel();
    }
    Ok(StatusCode::NO_CONTENT)
}
