//! The studio's API as the page uses it: requests through the router, no socket.

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use http_body_util::BodyExt;
use relief_studio::{Config, router};
use serde_json::Value;
use tower::ServiceExt;

struct Studio {
    router: Router,
    dir: tempfile::TempDir,
}

impl Studio {
    fn new() -> Self {
        Self::with(|c| c)
    }

    fn with(configure: impl FnOnce(Config) -> Config) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let router = router(&configure(Config::new(dir.path().join("ws")))).unwrap();
        Self { router, dir }
    }

    /// Sends `method path` with `body`; the status and the body's bytes.
    fn send(&self, method: &str, path: &str, body: impl Into<Body>) -> (StatusCode, Vec<u8>) {
        self.send_as(None, method, path, body)
    }

    /// [`Studio::send`] for a session.
    fn send_as(&self, session: Option<&str>, method: &str, path: &str, body: impl Into<Body>) -> (StatusCode, Vec<u8>) {
        self.send_with(&[("x-relief-session", session.unwrap_or_default())], method, path, body)
    }

    /// Starts generating `scene` as session `busy` on a runtime of its own and returns once
    /// the studio reports it running: the runtime and the request's task.
    fn start_busy(
        &self,
        scene: &Value,
    ) -> (tokio::runtime::Runtime, tokio::task::JoinHandle<Result<axum::response::Response, std::convert::Infallible>>)
    {
        let runtime = tokio::runtime::Runtime::new().unwrap();
        let request = Request::post("/api/generate")
            .header("content-type", "application/json")
            .header("x-relief-session", "busy")
            .body(Body::from(scene.to_string()));
        let task = runtime.spawn(self.router.clone().oneshot(request.unwrap()));
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        let running = || {
            let (_, body) = self.send_as(Some("busy"), "GET", "/api/progress", Body::empty());
            serde_json::from_slice::<Value>(&body).unwrap()["running"] == true
        };
        while !running() {
            assert!(!task.is_finished() && std::time::Instant::now() < deadline, "never seen running");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        (runtime, task)
    }

    /// [`Studio::send`] with headers (an empty value leaves the header out).
    fn send_with(
        &self,
        headers: &[(&str, &str)],
        method: &str,
        path: &str,
        body: impl Into<Body>,
    ) -> (StatusCode, Vec<u8>) {
        let (status, _, body) = self.exchange(headers, method, path, body);
        (status, body)
    }

    /// [`Studio::send_with`], with the response's headers.
    fn exchange(
        &self,
        headers: &[(&str, &str)],
        method: &str,
        path: &str,
        body: impl Into<Body>,
    ) -> (StatusCode, axum::http::HeaderMap, Vec<u8>) {
        let mut request = Request::builder().method(method).uri(path);
        // The page declares every body JSON (uploads aside), as the studio requires.
        let upload = method == "PUT" && path.starts_with("/api/files/");
        let typed = headers.iter().any(|(name, _)| name.eq_ignore_ascii_case("content-type"));
        if matches!(method, "POST" | "PUT") && !upload && !typed {
            request = request.header("content-type", "application/json");
        }
        for (name, value) in headers.iter().filter(|(_, v)| !v.is_empty()) {
            request = request.header(*name, *value);
        }
        let request = request.body(body.into()).unwrap();
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        runtime.block_on(async {
            let response = self.router.clone().oneshot(request).await.unwrap();
            let (status, headers) = (response.status(), response.headers().clone());
            (status, headers, response.into_body().collect().await.unwrap().to_bytes().to_vec())
        })
    }

    fn json(&self, method: &str, path: &str, body: impl Into<Body>) -> (StatusCode, Value) {
        let (status, bytes) = self.send(method, path, body);
        (status, serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&bytes))))
    }

    fn template(&self, name: &str) -> Value {
        let (status, scene) = self.json("GET", &format!("/api/templates/{name}"), Body::empty());
        assert_eq!(status, StatusCode::OK);
        scene
    }
}

/// A small island scene: the template at 128² with one hill.
fn island_scene(studio: &Studio) -> Value {
    let mut scene = studio.template("island");
    scene["reconstruction"]["resolution"] = serde_json::json!([128, 128]);
    scene["generator"]["island"]["operations"] =
        serde_json::json!([{ "add_hill": { "center": [2000, 2000], "radii": [800, 600], "height": 500 } }]);
    scene
}

#[test]
fn the_page_and_its_scripts_are_served() {
    let studio = Studio::new();
    for (path, needle) in [
        ("/", "<canvas"),
        ("/studio.js", "fetch("),
        ("/view3d.js", "export function"),
        ("/shapes.js", "export function"),
        ("/studio.css", "{"),
    ] {
        let (status, body) = studio.send("GET", path, Body::empty());
        assert_eq!(status, StatusCode::OK, "{path}");
        assert!(String::from_utf8(body).unwrap().contains(needle), "{path}");
    }
    let (status, info) = studio.json("GET", "/api/info", Body::empty());
    assert_eq!(status, StatusCode::OK);
    assert_eq!(info["templates"], serde_json::json!(["demo", "island", "contours", "curves"]));
    let (status, error) = studio.json("GET", "/api/nothing", Body::empty());
    assert_eq!((status, error["error"].as_str()), (StatusCode::NOT_FOUND, Some("no such route")));
}

#[test]
fn every_template_generates() {
    let studio = Studio::new();
    for name in ["demo", "island", "contours", "curves"] {
        let mut scene = studio.template(name);
        scene["reconstruction"]["resolution"] = serde_json::json!([96, 96]);
        let (status, result) = studio.json("POST", "/api/generate", scene.to_string());
        assert_eq!(status, StatusCode::OK, "{name}: {result}");
        assert!(result["max"].as_f64().unwrap() > result["min"].as_f64().unwrap() + 100.0, "{name}: {result}");
    }
}

#[test]
fn requests_addressed_to_another_host_are_refused() {
    let studio = Studio::new();
    for host in ["localhost:8737", "127.0.0.1:8737", "[::1]:8737", "[::ffff:127.0.0.1]:8737"] {
        let (status, _) = studio.send_with(&[("host", host)], "GET", "/api/info", Body::empty());
        assert_eq!(status, StatusCode::OK, "{host}");
    }
    // A page whose domain was rebound to 127.0.0.1 sends its own name.
    for (method, path) in [("GET", "/"), ("GET", "/api/scenes"), ("POST", "/api/generate")] {
        let (status, body) = studio.send_with(&[("host", "evil.example:8737")], method, path, "{}");
        assert_eq!(status, StatusCode::FORBIDDEN, "{method} {path}");
        assert!(String::from_utf8_lossy(&body).contains("localhost only"));
    }
    // Served to other machines (`relief serve --host 0.0.0.0`), any host passes.
    let mut open = Config::new(tempfile::tempdir().unwrap().path().join("ws"));
    open.loopback_only = false;
    let open = Studio { router: router(&open).unwrap(), dir: tempfile::tempdir().unwrap() };
    let (status, _) = open.send_with(&[("host", "terrain.lan:8737")], "GET", "/api/info", Body::empty());
    assert_eq!(status, StatusCode::OK);
}

#[test]
fn another_sites_page_changes_nothing() {
    let studio = Studio::new();
    let scene = island_scene(&studio).to_string();
    // What any page may send without asking: a text/plain POST, stamped with its origin.
    let evil = [("host", "127.0.0.1:8737"), ("origin", "http://evil.example"), ("content-type", "text/plain")];
    for (method, path) in [
        ("POST", "/api/generate"),
        ("POST", "/api/export/heightfield.exr"),
        ("PUT", "/api/scenes/planted.json"),
        ("PUT", "/api/files/planted.json"),
        ("POST", "/api/cancel"),
    ] {
        let (status, body) = studio.send_with(&evil, method, path, scene.clone());
        assert_eq!(status, StatusCode::FORBIDDEN, "{method} {path}");
        assert!(String::from_utf8_lossy(&body).contains("cross-site"), "{}", String::from_utf8_lossy(&body));
    }
    // The browser's own word for it (Sec-Fetch-Site) is enough, even on a GET of the API.
    let site = [("sec-fetch-site", "cross-site")];
    assert_eq!(studio.send_with(&site, "GET", "/api/scenes", Body::empty()).0, StatusCode::FORBIDDEN);
    let (_, listed) = studio.json("GET", "/api/scenes", Body::empty());
    assert_eq!(listed["scenes"], serde_json::json!([]), "nothing was saved");
    assert!(!studio.dir.path().join("ws/planted.json").exists());
    assert_eq!(studio.send("GET", "/api/results/1/elevation", Body::empty()).0, StatusCode::NOT_FOUND);
    // The studio's own page passes, and must declare its JSON.
    let own = [("host", "127.0.0.1:8737"), ("origin", "http://127.0.0.1:8737"), ("sec-fetch-site", "same-origin")];
    let plain: Vec<_> = own.iter().copied().chain([("content-type", "text/plain")]).collect();
    let (status, _) = studio.send_with(&plain, "POST", "/api/generate", scene.clone());
    assert_eq!(status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    let (status, headers, _) = studio.exchange(&own, "POST", "/api/generate", scene);
    assert_eq!(status, StatusCode::OK);
    // No page may frame the studio: every answer says so, refusals included.
    assert_eq!(headers["x-frame-options"], "DENY");
    assert_eq!(headers["content-security-policy"], "frame-ancestors 'none'");
    let (_, headers, _) = studio.exchange(&evil, "POST", "/api/generate", "{}");
    assert_eq!(headers["x-frame-options"], "DENY");
}

#[test]
fn a_studio_with_a_token_answers_its_holders_only() {
    let studio = Studio::with(|mut c| {
        c.token = Some("s3cret".into());
        c
    });
    let host = ("host", "127.0.0.1:8737");
    for headers in
        [vec![host], vec![host, ("authorization", "Bearer wrong")], vec![host, ("cookie", "relief_token_8737=x")]]
    {
        let (status, body) = studio.send_with(&headers, "GET", "/api/info", Body::empty());
        assert_eq!(status, StatusCode::UNAUTHORIZED, "{headers:?}");
        assert!(String::from_utf8_lossy(&body).contains("token"));
    }
    assert_eq!(studio.send_with(&[host], "GET", "/?token=wrong", Body::empty()).0, StatusCode::UNAUTHORIZED);
    // The printed address sets the cookie and leaves the address bar without the secret.
    let (status, headers, _) = studio.exchange(&[host], "GET", "/?token=s3cret", Body::empty());
    assert_eq!(status, StatusCode::SEE_OTHER);
    assert_eq!(headers["location"], "/");
    let cookie = headers["set-cookie"].to_str().unwrap();
    assert!(cookie.starts_with("relief_token_8737=s3cret;") && cookie.contains("HttpOnly"), "{cookie}");
    assert!(cookie.contains("SameSite=Strict"), "{cookie}");
    for credential in [("cookie", "other=1; relief_token_8737=s3cret"), ("authorization", "Bearer s3cret")] {
        let (status, _) = studio.send_with(&[host, credential], "GET", "/api/info", Body::empty());
        assert_eq!(status, StatusCode::OK, "{credential:?}");
    }
    // Another port's cookie is another studio's.
    let (status, _) =
        studio.send_with(&[("host", "127.0.0.1:9000"), ("cookie", "relief_token_8737=s3cret")], "GET", "/", "");
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

#[test]
fn generating_a_scene_returns_its_heightfield_north_up() {
    let studio = Studio::new();
    let mut scene = island_scene(&studio);
    // The hill in the north half: the elevation's first rows hold it.
    scene["generator"]["island"]["operations"][0]["add_hill"]["center"] = serde_json::json!([2000, 3000]);
    let (status, result) = studio.json("POST", "/api/generate", scene.to_string());
    assert_eq!(status, StatusCode::OK, "{result}");
    let (w, h) = (result["width"].as_u64().unwrap() as usize, result["height"].as_u64().unwrap() as usize);
    assert_eq!((w, h), (128, 128));
    let max = result["max"].as_f64().unwrap();
    assert!(max > 300.0, "{result}");
    let (status, bytes) = studio.send("GET", &format!("/api/results/{}/elevation", result["id"]), Body::empty());
    assert_eq!(status, StatusCode::OK);
    assert_eq!(bytes.len(), w * h * 4);
    let z: Vec<f32> = bytes.chunks(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect();
    let top = z.iter().copied().fold(f32::MIN, f32::max);
    assert_eq!(f64::from(top), max);
    let row_of_top = z.iter().position(|&v| v == top).unwrap() / w;
    // y = 3000 of 0…4000 is a quarter of the way down from the north edge.
    assert!((row_of_top as f64 - 0.25 * h as f64).abs() < 0.06 * h as f64, "top at row {row_of_top}");
}

/// A session's island edits apply to the island its last preview left: the result says how many
/// operations it took from there, and the samples are a fresh replay's.
#[test]
fn a_sessions_next_island_edit_resumes_from_its_last_preview() {
    let studio = Studio::new();
    let mut scene = island_scene(&studio);
    let elevation =
        |result: &Value| studio.send("GET", &format!("/api/results/{}/elevation", result["id"]), Body::empty()).1;
    let generate = |session: Option<&str>, scene: &Value| {
        let (status, bytes) = studio.send_as(session, "POST", "/api/generate", scene.to_string());
        assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&bytes));
        serde_json::from_slice::<Value>(&bytes).unwrap()
    };
    assert_eq!(generate(Some("e"), &scene)["resumed"], 0);
    let hill = serde_json::json!({ "add_hill": { "center": [2600, 1600], "radii": [300, 300], "height": 200 } });
    scene["generator"]["island"]["operations"].as_array_mut().unwrap().push(hill);
    let resumed = generate(Some("e"), &scene);
    assert_eq!(resumed["resumed"], 1, "{resumed}");
    // Another session, and a request without one, replay the history.
    assert_eq!(generate(Some("other"), &scene)["resumed"], 0);
    let replayed = generate(None, &scene);
    assert_eq!(replayed["resumed"], 0);
    assert_eq!(elevation(&resumed), elevation(&replayed));
    // A scene of another kind resumes nothing.
    assert_eq!(generate(Some("e"), &studio.template("curves"))["resumed"], 0);
}

#[test]
fn downloads_read_back_as_the_generated_heightfield() {
    let studio = Studio::new();
    let (_, result) = studio.json("POST", "/api/generate", island_scene(&studio).to_string());
    let id = &result["id"];
    for format in ["exr", "tif", "png", "asc", "r16"] {
        let (status, bytes) = studio.send("GET", &format!("/api/results/{id}/download/{format}"), Body::empty());
        assert_eq!(status, StatusCode::OK, "{format}");
        assert!(bytes.len() > 1000, "{format}: {} bytes", bytes.len());
        if format == "exr" {
            let path = studio.dir.path().join("back.exr");
            std::fs::write(&path, &bytes).unwrap();
            let back = relief::io::read(&path).unwrap();
            assert_eq!((back.nx(), back.ny()), (128, 128));
            assert_eq!(f64::from(back.min_max().unwrap().1), result["max"].as_f64().unwrap());
        }
    }
    // A RAW16's sidecar: the elevations its lowest and highest codes stand for.
    let (status, sidecar) = studio.json("GET", &format!("/api/results/{id}/download/r16.json"), Body::empty());
    assert_eq!(status, StatusCode::OK, "{sidecar}");
    assert_eq!(sidecar["max"].as_f64(), result["max"].as_f64(), "{sidecar}");
    assert_eq!(sidecar["min"].as_f64(), result["min"].as_f64(), "{sidecar}");
    let (status, error) = studio.json("GET", &format!("/api/results/{id}/download/bmp"), Body::empty());
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error["error"].as_str().unwrap().contains("exr, png, tif, asc, r16, r16.json"), "{error}");
    let (status, _) = studio.json("GET", "/api/results/999/elevation", Body::empty());
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[test]
fn every_output_is_exported_from_a_full_run() {
    let studio = Studio::new();
    let scene = island_scene(&studio).to_string();
    let (status, bytes) = studio.send("POST", "/api/export/contours.geojson", scene.clone());
    assert_eq!(status, StatusCode::OK);
    let geojson: Value = serde_json::from_slice(&bytes).unwrap();
    let features = geojson["features"].as_array().unwrap();
    assert!(features.len() >= 10 && features.iter().all(|f| f["properties"]["elevation"].is_number()));
    let (_, svg) = studio.send("POST", "/api/export/contours.svg", scene.clone());
    assert!(svg.starts_with(b"<svg"));
    let (_, glb) = studio.send("POST", "/api/export/terrain.glb", scene.clone());
    assert_eq!(&glb[..4], b"glTF");
    let (_, png) = studio.send("POST", "/api/export/preview.png", scene.clone());
    assert_eq!(&png[1..4], b"PNG");
    // The summary of a full run: the drainage analysis a preview skips.
    let (status, summary) = studio.json("POST", "/api/export/summary.json", scene.clone());
    assert_eq!(status, StatusCode::OK);
    assert!(summary["drainage"]["closed_basins"].is_number(), "{summary}");
    // A gaussian output of an island scene, an unknown export.
    let (status, error) = studio.json("POST", "/api/export/skeleton.geojson", scene.clone());
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error["error"].as_str().unwrap().contains("does not write skeleton.geojson"), "{error}");
    let (status, _) = studio.send("POST", "/api/export/passwd", scene);
    assert_eq!(status, StatusCode::NOT_FOUND);
}

/// The names and bytes of every file in a zip.
fn unzip(bytes: Vec<u8>) -> Vec<(String, Vec<u8>)> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    (0..zip.len())
        .map(|k| {
            let mut file = zip.by_index(k).unwrap();
            let mut bytes = Vec::new();
            std::io::Read::read_to_end(&mut file, &mut bytes).unwrap();
            (file.name().unwrap().into_owned(), bytes)
        })
        .collect()
}

#[test]
fn an_engine_export_is_one_zip_of_its_files() {
    let studio = Studio::new();
    let mut scene = island_scene(&studio);
    // Without an engine output in the scene: the nearest legal size, with splat maps.
    let (status, bytes) = studio.send("POST", "/api/export/engine/unity", scene.to_string());
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&bytes));
    let files = unzip(bytes);
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["heightmap.import.json", "heightmap.raw", "heightmap_masks.png", "heightmap_splat.png"]);
    let sidecar: Value = serde_json::from_slice(&files[0].1).unwrap();
    let n = sidecar["settings"]["samples"][0].as_u64().unwrap();
    assert!(n.is_power_of_two() || (n - 1).is_power_of_two(), "{sidecar}");
    assert_eq!(files[1].1.len() as u64, 2 * n * n, "a 16-bit RAW of {n}² samples");
    // The scene's own entry sets the size and tiles, without splat maps: 256² samples are at
    // least 2 × 2 Unreal tiles of 127.
    scene["reconstruction"]["resolution"] = serde_json::json!([256, 256]);
    scene["outputs"]["engines"] = serde_json::json!([{ "for": "unreal", "tile": 127 }]);
    let (status, bytes) = studio.send("POST", "/api/export/engine/unreal", scene.to_string());
    assert_eq!(status, StatusCode::OK);
    let files = unzip(bytes);
    let tiles = files.iter().filter(|(n, _)| n.starts_with("heightmap_x")).count();
    assert!(tiles >= 4, "{:?}", files.iter().map(|(n, _)| n).collect::<Vec<_>>());
    assert_eq!(files.len(), tiles + 1, "the tiles and the sidecar");
    assert!(files.iter().filter(|(n, _)| n.starts_with("heightmap_x")).all(|(_, b)| &b[1..4] == b"PNG"));
    // An engine it does not know.
    let (status, error) = studio.json("POST", "/api/export/engine/cryengine", scene.to_string());
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error["error"].as_str().unwrap().contains("unity, unreal, godot, blender"), "{error}");
}

#[test]
fn a_bad_scene_gets_a_4xx_naming_its_json_path() {
    let studio = Studio::new();
    let mut scene = island_scene(&studio);
    scene["generator"]["island"]["operations"][0]["add_hill"]["radii"] = serde_json::json!([-5, 600]);
    let (status, error) = studio.json("POST", "/api/generate", scene.to_string());
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{error}");
    assert!(error["path"].as_str().unwrap().starts_with("generator.island.operations[0]"), "{error}");
    let (status, error) = studio.json("POST", "/api/generate", "{\"version\": 1, \"generator\": {\"nope\": {}}}");
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{error}");
    assert!(error["error"].as_str().unwrap().contains("nope"), "{error}");
    let (status, _) = studio.json("POST", "/api/generate", vec![0xff, 0xfe]);
    assert_eq!(status, StatusCode::BAD_REQUEST);
}

#[test]
fn scenes_run_under_the_budget_and_bodies_are_capped() {
    let studio = Studio::with(|c| c.with_budget(relief::Budget::default().with_max_cells(100 * 100)));
    let (status, error) = studio.json("POST", "/api/generate", island_scene(&studio).to_string());
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{error}");
    assert!(error["error"].as_str().unwrap().contains("budget"), "{error}");
    assert_eq!(error["path"], "reconstruction.resolution", "{error}");
    // A raster upload over the budget is refused as it arrives and not kept, by its header alone
    // (a PNG cut after its header announces as many), and a raw file by its length; one within
    // it and a file that does not decode (left to the scene that reads it) are kept.
    let (big, raw) = (image_bytes(101, |_, _| 7), vec![0; 101 * 101 * 2]);
    for (name, bytes) in [("big.png", &big[..]), ("cut.png", &big[..33]), ("raw.r16", &raw[..])] {
        let (status, error) = studio.json("PUT", &format!("/api/files/{name}"), bytes.to_vec());
        assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{name}: {error}");
        assert!(error["error"].as_str().unwrap().contains("10201 cells"), "{error}");
        assert!(!studio.dir.path().join("ws").join(name).exists());
    }
    for (name, bytes) in [
        ("fits.png", image_bytes(100, |_, _| 7)),
        ("raw.r16", vec![0; 100 * 100 * 2]),
        ("junk.png", b"not a PNG".to_vec()),
    ] {
        let (status, _) = studio.send("PUT", &format!("/api/files/{name}"), bytes);
        assert_eq!(status, StatusCode::NO_CONTENT, "{name}");
    }
    let mut config = Config::new(tempfile::tempdir().unwrap().path().join("ws"));
    config.max_body_bytes = 1000;
    let small = Studio { router: router(&config).unwrap(), dir: tempfile::tempdir().unwrap() };
    let (status, _) = small.send("POST", "/api/generate", vec![b' '; 2000]);
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
}

#[test]
fn scenes_save_and_load_inside_the_workspace_only() {
    let studio = Studio::new();
    let scene = island_scene(&studio);
    let (status, _) = studio.send("PUT", "/api/scenes/my-island.json", scene.to_string());
    assert_eq!(status, StatusCode::NO_CONTENT);
    // Only scenes are listed, not the inputs beside them.
    let (status, _) = studio.send("PUT", "/api/files/dem.asc", "ncols 2\nnrows 2\n");
    assert_eq!(status, StatusCode::NO_CONTENT);
    let (_, list) = studio.json("GET", "/api/scenes", Body::empty());
    assert_eq!(list["scenes"], serde_json::json!(["my-island.json"]));
    let (status, back) = studio.json("GET", "/api/scenes/my-island.json", Body::empty());
    assert_eq!(status, StatusCode::OK);
    let parsed = |v: &Value| relief::Scene::from_json(&v.to_string()).unwrap();
    assert_eq!(parsed(&back), parsed(&scene));
    // No temporary file is left beside them.
    let files: Vec<_> = std::fs::read_dir(studio.dir.path().join("ws")).unwrap().collect();
    assert_eq!(files.len(), 2);
    // Names that climb out, hide or are not scenes; a scene that is not valid is not saved.
    for name in ["..%2Fescape.json", ".hidden.json", "a%20b.json", "notes.txt"] {
        let (status, _) = studio.send("PUT", &format!("/api/scenes/{name}"), scene.to_string());
        assert_eq!(status, StatusCode::BAD_REQUEST, "{name}");
    }
    assert!(!studio.dir.path().join("escape.json").exists());
    let (status, _) = studio.send("PUT", "/api/scenes/broken.json", "{\"version\": 1}");
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    let (status, _) = studio.send("GET", "/api/scenes/missing.json", Body::empty());
    assert_eq!(status, StatusCode::NOT_FOUND);
    // Nor through an upload: a scene uploaded must be valid, any .json must be JSON, and a saved
    // scene is not replaced by something else.
    let (status, body) = studio.json("PUT", "/api/files/bad.json", r#"{"version": 1, "generator": {"nope": {}}}"#);
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
    assert!(body["path"].as_str().is_some_and(|p| p.starts_with("generator")), "{body}");
    let (status, _) = studio.send("PUT", "/api/files/text.json", "not json");
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    let lines = r#"{"type": "FeatureCollection", "features": []}"#;
    let (status, _) = studio.send("PUT", "/api/files/my-island.json", lines);
    assert_eq!(status, StatusCode::CONFLICT);
    assert_eq!(parsed(&studio.json("GET", "/api/scenes/my-island.json", Body::empty()).1), parsed(&scene));
    assert_eq!(studio.send("PUT", "/api/files/lines.geojson", lines).0, StatusCode::NO_CONTENT);
    assert_eq!(studio.send("PUT", "/api/files/other.json", scene.to_string()).0, StatusCode::NO_CONTENT);
    for name in ["bad.json", "text.json"] {
        assert!(!studio.dir.path().join("ws").join(name).exists(), "{name}");
    }
}

#[test]
fn a_scene_reads_inputs_from_the_workspace_and_nowhere_else() {
    let studio = Studio::new();
    let mut scene = island_scene(&studio);
    // A paint-program mask uploaded, then traced as the coastline.
    let mut mask = image_bytes(64, |x, y| u8::from((f64::from(x) - 32.0).hypot(f64::from(y) - 32.0) < 20.0) * 255);
    let (status, _) = studio.send("PUT", "/api/files/mask.png", std::mem::take(&mut mask));
    assert_eq!(status, StatusCode::NO_CONTENT);
    scene["generator"]["island"]["coastline_image"] = serde_json::json!({ "path": "mask.png" });
    let (status, result) = studio.json("POST", "/api/generate", scene.to_string());
    assert_eq!(status, StatusCode::OK, "{result}");
    for escape in ["../mask.png", "/etc/hostname"] {
        scene["generator"]["island"]["coastline_image"]["path"] = escape.into();
        let (status, error) = studio.json("POST", "/api/generate", scene.to_string());
        assert_eq!(status, StatusCode::FORBIDDEN, "{escape}: {error}");
        assert!(error["error"].as_str().unwrap().contains("inside its workspace"), "{error}");
    }
    let (status, _) = studio.send("PUT", "/api/files/run.sh", "echo");
    assert_eq!(status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
}

#[test]
fn a_newer_generation_of_a_session_supersedes_the_running_one() {
    let studio = Studio::new();
    // A slow scene: the contour template grown from 600 000 particles (about a second here,
    // its growth alone hundreds of times longer than the quick scene's whole run).
    let mut slow = studio.template("contours");
    slow["generator"]["contours"]["particles"] = 600_000.into();
    let quick = island_scene(&studio).to_string();
    let progress = |session| {
        let (_, bytes) = studio.send_as(Some(session), "GET", "/api/progress", Body::empty());
        serde_json::from_slice::<Value>(&bytes).unwrap()
    };
    // Stopped by a newer generation of its session, then by the page's cancel button.
    for interrupt in ["generate", "cancel"] {
        assert_eq!(progress("s1")["running"], false);
        std::thread::scope(|scope| {
            let running = scope.spawn(|| studio.send_as(Some("s1"), "POST", "/api/generate", slow.to_string()));
            // Wait until it is growing.
            let start = std::time::Instant::now();
            loop {
                let state = progress("s1");
                if state["running"] == true && matches!(state["step"].as_str(), Some("graph" | "growth")) {
                    break;
                }
                assert!(start.elapsed().as_secs() < 60 && !running.is_finished(), "never saw it grow: {state}");
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            // Another session's edit does not touch it; this session's does.
            let (status, _) = studio.send_as(Some("s2"), "POST", "/api/generate", quick.clone());
            assert_eq!(status, StatusCode::OK);
            assert_eq!(progress("s1")["running"], true);
            let (status, _) = match interrupt {
                "generate" => studio.send_as(Some("s1"), "POST", "/api/generate", quick.clone()),
                _ => studio.send_as(Some("s1"), "POST", "/api/cancel", Body::empty()),
            };
            assert!(status.is_success(), "{interrupt}: {status}");
            let (status, body) = running.join().unwrap();
            assert_eq!(status, StatusCode::CONFLICT, "{interrupt}: {}", String::from_utf8_lossy(&body));
        });
    }
    assert_eq!(progress("s1")["running"], false);
    let (status, _) = studio.send_as(Some("bad/name"), "GET", "/api/progress", Body::empty());
    assert_eq!(status, StatusCode::BAD_REQUEST);
}

#[test]
fn an_uploaded_dem_is_vectorized_and_synthesized_from() {
    let studio = Studio::new();
    let dem = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/dem/jacksboro.asc")).unwrap();
    let (status, _) = studio.send("PUT", "/api/files/jacksboro.asc", dem);
    assert_eq!(status, StatusCode::NO_CONTENT);
    // As the page's "Vectorize it" and "Synthesize from it" buttons write them, smaller.
    let vector = serde_json::json!({
        "version": 1,
        "generator": { "gaussian": { "source": { "kind": "dem", "path": "jacksboro.asc", "primitives": 100,
                                                  "iterations": 10, "resolution": 64 }, "operations": [] } },
        "reconstruction": { "resolution": [64, 64] }
    });
    let orometry = serde_json::json!({
        "version": 1,
        "domain": { "min": [0, 0], "max": [20000, 20000] },
        "generator": { "orometry": { "source": { "kind": "dem", "path": "jacksboro.asc", "min_prominence": 100 } } },
        "reconstruction": { "resolution": [64, 64] }
    });
    for scene in [vector, orometry] {
        let (status, result) = studio.json("POST", "/api/generate", scene.to_string());
        assert_eq!(status, StatusCode::OK, "{result}");
        // Jacksboro spans 236 … 1076 m: both keep most of that relief.
        let relief = result["max"].as_f64().unwrap() - result["min"].as_f64().unwrap();
        assert!(relief > 400.0, "{result}");
        // The orometry scene sends its divide tree: a tree joins n peaks with n − 1 saddles.
        if scene["generator"].get("orometry").is_some() {
            let tree = &result["divide_tree"];
            let peaks = tree["peaks"].as_array().unwrap().len();
            assert!(peaks >= 3, "{tree}");
            assert_eq!(tree["saddles"].as_array().unwrap().len() + 1, peaks);
        } else {
            assert!(result.get("divide_tree").is_none());
        }
    }
}

#[test]
fn an_uploaded_dem_opens_with_its_peaks_and_divide_tree() {
    let studio = Studio::new();
    let dem = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/dem/jacksboro.asc")).unwrap();
    studio.send("PUT", "/api/files/jacksboro.asc", dem);
    let (status, result) = studio.json("POST", "/api/files/jacksboro.asc/open", Body::empty());
    assert_eq!(status, StatusCode::OK, "{result}");
    assert_eq!((result["min"].as_f64(), result["max"].as_f64()), (Some(236.0), Some(1076.0)));
    let (status, tree) =
        studio.json("GET", &format!("/api/results/{}/peaks?min_prominence=100", result["id"]), Body::empty());
    assert_eq!(status, StatusCode::OK, "{tree}");
    let (peaks, saddles) = (tree["peaks"].as_array().unwrap(), tree["saddles"].as_array().unwrap());
    assert!(peaks.len() >= 5, "{} peaks", peaks.len());
    assert!(peaks.iter().all(|p| p["prominence"].as_f64().unwrap() >= 100.0));
    assert!(peaks.iter().any(|p| p["elevation"].as_f64() == Some(1076.0)), "the summit is a peak");
    // A divide tree: one key saddle fewer than peaks, each below the two peaks it joins, with
    // its ridge line.
    assert_eq!(saddles.len() + 1, peaks.len());
    for saddle in saddles {
        let z = saddle["elevation"].as_f64().unwrap();
        for k in saddle["peaks"].as_array().unwrap() {
            assert!(peaks[k.as_u64().unwrap() as usize]["elevation"].as_f64().unwrap() > z, "{saddle}");
        }
        assert!(saddle["ridge"].as_array().unwrap().len() >= 2, "{saddle}");
    }
    let (status, _) = studio.json("POST", "/api/files/nothing.asc/open", Body::empty());
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _) =
        studio.send("GET", &format!("/api/results/{}/peaks?min_prominence=-1", result["id"]), Body::empty());
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
}

/// A page that aborts its request (a newer edit, a closed tab) drops the handler: its generation
/// is cancelled and its place freed, not left running.
#[test]
fn an_abandoned_request_frees_its_generation() {
    let studio = Studio::new();
    let mut slow = studio.template("contours");
    slow["generator"]["contours"]["particles"] = 600_000.into();
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let request = Request::post("/api/generate")
            .header("content-type", "application/json")
            .header("x-relief-session", "gone")
            .body(Body::from(slow.to_string()));
        let task = tokio::spawn(studio.router.clone().oneshot(request.unwrap()));
        let progress = || async {
            let request = Request::get("/api/progress").header("x-relief-session", "gone").body(Body::empty()).unwrap();
            let body = studio.router.clone().oneshot(request).await.unwrap().into_body().collect().await.unwrap();
            serde_json::from_slice::<Value>(&body.to_bytes()).unwrap()
        };
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        while progress().await["running"] != true {
            assert!(!task.is_finished(), "it ended before it was seen running");
            assert!(std::time::Instant::now() < deadline, "never seen running");
            tokio::time::sleep(std::time::Duration::from_millis(5)).await;
        }
        task.abort();
        assert!(task.await.unwrap_err().is_cancelled());
        assert_eq!(progress().await["running"], false, "the abandoned job is gone");
    });
}

/// Parsing, uploads, downloads and generations share one cap on running jobs: while the only
/// place runs a generation, an upload, a download and another session's scene get 503, and all
/// are served once it ends.
#[test]
fn heavy_requests_share_the_job_cap() {
    let studio = Studio::with(|mut c| {
        c.max_jobs = 1;
        c
    });
    let small = studio.template("island");
    let (status, result) = studio.json("POST", "/api/generate", small.to_string());
    assert_eq!(status, StatusCode::OK, "{result}");
    let download = format!("/api/results/{}/download/exr", result["id"]);
    let mut slow = studio.template("contours");
    slow["generator"]["contours"]["particles"] = 600_000.into();
    let (runtime, task) = studio.start_busy(&slow);
    let refused = [
        studio.send("PUT", "/api/files/m.png", image_bytes(8, |_, _| 1)).0,
        studio.send("GET", &download, Body::empty()).0,
        studio.json("POST", "/api/generate", small.to_string()).0,
    ];
    assert_eq!(refused, [StatusCode::SERVICE_UNAVAILABLE; 3]);
    task.abort();
    let _ = runtime.block_on(task);
    assert_eq!(studio.send("PUT", "/api/files/m.png", image_bytes(8, |_, _| 1)).0, StatusCode::NO_CONTENT);
    assert_eq!(studio.send("GET", &download, Body::empty()).0, StatusCode::OK);
}

/// Two generations that each fit the memory budget but not together: the second waits for its
/// share, then gets 503 naming the memory; once the first ends, it runs.
#[test]
fn concurrent_generations_share_one_memory_budget() {
    let mut slow = Studio::new().template("contours");
    slow["generator"]["contours"]["particles"] = 600_000.into();
    let estimate = relief::budget::estimated_bytes(&relief::Scene::from_json(&slow.to_string()).unwrap());
    let studio = Studio::with(|mut c| {
        c.budget = c.budget.with_max_bytes(estimate * 3 / 2);
        c.memory_wait = std::time::Duration::from_millis(200);
        c
    });
    let (runtime, task) = studio.start_busy(&slow);
    let (status, body) = studio.send_as(Some("other"), "POST", "/api/generate", Body::from(slow.to_string()));
    let error: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{error}");
    assert!(error["error"].as_str().unwrap().contains("MiB of memory"), "{error}");
    // A smaller scene fits beside it.
    let mut small = slow.clone();
    small["reconstruction"]["resolution"] = serde_json::json!([64, 64]);
    small["generator"]["contours"]["particles"] = Value::Null;
    let (status, _) = studio.send_as(Some("other"), "POST", "/api/generate", Body::from(small.to_string()));
    assert_eq!(status, StatusCode::OK);
    // Once the first has ended, the second runs.
    let first = runtime.block_on(task).unwrap().unwrap();
    assert_eq!(first.status(), StatusCode::OK);
    let (status, _) = studio.send_as(Some("other"), "POST", "/api/generate", Body::from(slow.to_string()));
    assert_eq!(status, StatusCode::OK);
}

/// The page's event stream: a DEM's vectorization reports each fitting iteration as it runs,
/// the cancel button stops it mid-fit, and the stream then says nothing runs.
#[test]
fn progress_streams_as_server_sent_events_down_to_the_fits_iterations() {
    let studio = Studio::new();
    let dem = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/dem/jacksboro.asc")).unwrap();
    studio.send("PUT", "/api/files/jacksboro.asc", dem);
    let slow = serde_json::json!({
        "version": 1,
        "generator": { "gaussian": { "source": { "kind": "dem", "path": "jacksboro.asc", "primitives": 400,
                                                  "iterations": 100_000, "resolution": 96 }, "operations": [] } },
        "reconstruction": { "resolution": [64, 64] }
    });
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let events = Request::get("/api/events?session=ev").body(Body::empty()).unwrap();
        let response = studio.router.clone().oneshot(events).await.unwrap();
        assert_eq!(response.headers()["content-type"], "text/event-stream");
        let mut body = response.into_body();
        let mut next_event = async || -> Value {
            let mut text = String::new();
            loop {
                if let Some(end) = text.find("\n\n") {
                    let data = text[..end].lines().find_map(|l| l.strip_prefix("data: ")).map(str::to_owned);
                    text.drain(..end + 2);
                    if let Some(data) = data {
                        return serde_json::from_str(&data).unwrap();
                    }
                    continue;
                }
                let frame = body.frame().await.expect("the stream ended").unwrap();
                text.push_str(std::str::from_utf8(&frame.into_data().unwrap()).unwrap());
            }
        };
        assert_eq!(next_event().await, serde_json::json!({ "running": false }));
        let request = Request::post("/api/generate")
            .header("content-type", "application/json")
            .header("x-relief-session", "ev")
            .body(Body::from(slow.to_string()))
            .unwrap();
        let running = tokio::spawn(studio.router.clone().oneshot(request));
        // The fit's iterations, counted against its budget, rising.
        let mut seen = Vec::new();
        while seen.len() < 3 {
            let event = next_event().await;
            if event["step"] == "source" && event["done"].as_u64().unwrap() > 0 {
                assert_eq!(event["total"], 100_000, "{event}");
                seen.push(event["done"].as_u64().unwrap());
            }
        }
        assert!(seen.is_sorted() && seen[0] < seen[2], "{seen:?}");
        let cancel = Request::post("/api/cancel")
            .header("content-type", "application/json")
            .header("x-relief-session", "ev")
            .body(Body::empty())
            .unwrap();
        assert!(studio.router.clone().oneshot(cancel).await.unwrap().status().is_success());
        let response = tokio::time::timeout(std::time::Duration::from_secs(30), running).await;
        assert_eq!(
            response.expect("the fit went on after the cancel").unwrap().unwrap().status(),
            StatusCode::CONFLICT
        );
        while next_event().await["running"] != false {}
    });
    for query in ["?session=bad/name", ""] {
        let (status, error) = studio.json("GET", &format!("/api/events{query}"), Body::empty());
        assert_eq!(status, StatusCode::BAD_REQUEST);
        assert!(error["error"].as_str().unwrap().starts_with("session"), "{error}");
    }
}

/// A page left open holds a progress stream; stopping the server (Ctrl-C in `relief serve`)
/// ends it instead of waiting for the tab to close.
#[test]
fn shutting_down_ends_the_open_event_streams() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let dir = tempfile::tempdir().unwrap();
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let address = listener.local_addr().unwrap();
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let config = Config::new(dir.path().join("ws"));
        let server = tokio::spawn(relief_studio::serve_until(listener, config, async {
            stopped.await.ok();
        }));
        let mut page = tokio::net::TcpStream::connect(address).await.unwrap();
        page.write_all(b"GET /api/events?session=open HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n").await.unwrap();
        let mut received = Vec::new();
        while !String::from_utf8_lossy(&received).contains("event: progress") {
            let mut buffer = [0; 4096];
            let n = page.read(&mut buffer).await.unwrap();
            assert!(n > 0, "the stream closed before its first event");
            received.extend_from_slice(&buffer[..n]);
        }
        stop.send(()).unwrap();
        let ended = tokio::time::timeout(std::time::Duration::from_secs(10), server).await;
        ended.expect("the open event stream held the shutdown").unwrap().unwrap();
    });
}

/// Connections that send nothing, or stay idle after their request, are closed after the header
/// timeout: more of them than the studio takes at once delay a real request by about that long
/// instead of locking it out.
#[test]
fn idle_connections_cannot_lock_the_studio_out() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let dir = tempfile::tempdir().unwrap();
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let address = listener.local_addr().unwrap();
        let mut config = Config::new(dir.path().join("ws"));
        config.max_connections = 4;
        config.header_timeout = std::time::Duration::from_millis(300);
        let server = tokio::spawn(relief_studio::serve_until(listener, config, std::future::pending()));
        // Ten silent connections, and one kept alive after its answer.
        let mut idle = Vec::new();
        for _ in 0..10 {
            idle.push(tokio::net::TcpStream::connect(address).await.unwrap());
        }
        let ask = async || {
            let mut client = tokio::net::TcpStream::connect(address).await.unwrap();
            client.write_all(b"GET /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n").await.unwrap();
            let mut buffer = [0; 4096];
            let n = client.read(&mut buffer).await.unwrap();
            (client, String::from_utf8_lossy(&buffer[..n]).into_owned())
        };
        let answered = tokio::time::timeout(std::time::Duration::from_secs(20), ask()).await;
        let (mut kept, answer) = answered.expect("idle connections locked the studio out");
        assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
        // The kept-alive connection and the silent ones are closed by the server (EOF).
        for stream in idle.iter_mut().chain([&mut kept]) {
            let mut buffer = [0; 64];
            let read = tokio::time::timeout(std::time::Duration::from_secs(20), stream.read(&mut buffer)).await;
            assert!(matches!(read, Ok(Ok(0) | Err(_))), "an idle connection stayed open: {read:?}");
        }
        server.abort();
    });
}

/// A gray PNG of `size`² pixels.
fn image_bytes(size: u32, pixel: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, size, size);
    encoder.set_color(png::ColorType::Grayscale);
    let mut writer = encoder.write_header().unwrap();
    let data: Vec<u8> = (0..size * size).map(|k| pixel(k % size, k / size)).collect();
    writer.write_image_data(&data).unwrap();
    drop(writer);
    bytes
}
