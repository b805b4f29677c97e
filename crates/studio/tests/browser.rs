//! The studio in a real headless browser, used as a user uses it: Chromium driven through
//! `chromedriver` (the W3C `WebDriver` protocol) with real pointer gestures on the map.
//!
//! Needs `chromium` and `chromedriver` on the PATH (Debian: `apt-get install chromium
//! chromium-driver`). Without them the test says so and passes, unless `RELIEF_E2E` is set, as
//! `.ci/run` sets it after installing them.

use std::net::TcpListener;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use fantoccini::actions::{InputSource, MOUSE_BUTTON_LEFT, MouseActions, PointerAction};
use fantoccini::elements::Element;
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{Value, json};

/// `name` on the PATH.
fn on_path(name: &str) -> Option<PathBuf> {
    std::env::split_paths(&std::env::var_os("PATH")?).map(|dir| dir.join(name)).find(|p| p.is_file())
}

/// A chromedriver process, killed on drop.
struct Driver(Child);

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

async fn connect(driver: &std::path::Path) -> (Driver, Client) {
    let port = free_port();
    let child = Command::new(driver)
        .arg(format!("--port={port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starting chromedriver");
    let driver = Driver(child);
    let options = json!({
        "args": ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1900,1000",
                 "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
    });
    let mut capabilities = serde_json::Map::new();
    capabilities.insert("goog:chromeOptions".into(), options);
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let connector = hyper_util::client::legacy::connect::HttpConnector::new();
        match ClientBuilder::new(connector)
            .capabilities(capabilities.clone())
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
        {
            Ok(client) => return (driver, client),
            Err(e) if Instant::now() > deadline => panic!("chromedriver did not start: {e}"),
            Err(_) => tokio::time::sleep(Duration::from_millis(200)).await,
        }
    }
}

async fn js(client: &Client, script: &str) -> Value {
    client.execute(script, vec![]).await.unwrap_or_else(|e| panic!("{script}: {e}"))
}

/// Waits for a result newer than `after`; its id. Fails on an error shown by the page.
async fn next_result(client: &Client, after: u64) -> u64 {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let state = js(
            client,
            "return [document.body.dataset.state, Number(document.body.dataset.resultId || 0), \
             document.getElementById('message').textContent]",
        )
        .await;
        let id = state[1].as_u64().unwrap();
        match state[0].as_str() {
            Some("idle") if id > after => return id,
            Some("error") => panic!("the page shows an error: {}", state[2]),
            _ if Instant::now() > deadline => panic!("no result after {after}: {state}"),
            _ => tokio::time::sleep(Duration::from_millis(100)).await,
        }
    }
}

/// Presses at the first point (pixels from the map's centre), moves through the others, and
/// releases at the last.
async fn drag(client: &Client, map: &Element, points: &[(f64, f64)]) {
    let step = Some(Duration::from_millis(30));
    let (x, y) = points[0];
    let mut mouse = MouseActions::new("mouse".into())
        .then(PointerAction::MoveToElement { element: map.clone(), duration: None, x, y })
        .then(PointerAction::Down { button: MOUSE_BUTTON_LEFT });
    for &(x, y) in &points[1..] {
        mouse = mouse.then(PointerAction::MoveToElement { element: map.clone(), duration: step, x, y });
    }
    client.perform_actions(mouse.then(PointerAction::Up { button: MOUSE_BUTTON_LEFT })).await.unwrap();
}

async fn choose_tool(client: &Client, tool: &str) {
    client.find(Locator::Css(&format!("input[name=tool][value={tool}]"))).await.unwrap().click().await.unwrap();
}

async fn new_scene(client: &Client, template: &str, after: u64) -> u64 {
    client.find(Locator::Id("template")).await.unwrap().select_by_value(template).await.unwrap();
    client.find(Locator::Id("new")).await.unwrap().click().await.unwrap();
    next_result(client, after).await
}

async fn doc(client: &Client) -> Value {
    js(client, "return window.studio.doc").await
}

async fn result_field(client: &Client, field: &str) -> Value {
    js(client, &format!("return window.studio.result.{field}")).await
}

#[test]
fn a_user_draws_an_island_undoes_saves_and_reloads_it() {
    let Some(driver) = browser() else { return };
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let workspace = tempfile::tempdir().unwrap();
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let url = format!("http://{}/", listener.local_addr().unwrap());
        tokio::spawn(relief_studio::serve(listener, relief_studio::Config::new(workspace.path())));
        let (_driver, client) = connect(&driver).await;
        client.goto(&url).await.unwrap();
        scenario(&client, workspace.path()).await;
        client.close().await.unwrap();
    });
}

/// The browser and its driver, or `None` (the test skips) when they are not installed.
fn browser() -> Option<PathBuf> {
    let driver = on_path("chromedriver").filter(|_| on_path("chromium").is_some());
    if driver.is_none() {
        assert!(std::env::var_os("RELIEF_E2E").is_none(), "RELIEF_E2E is set but chromium or chromedriver is missing");
        eprintln!("skipped: chromium and chromedriver are not on the PATH (apt-get install chromium chromium-driver)");
    }
    driver
}

/// A page on another site, open in the user's browser beside the studio, tries what any page
/// may: a `text/plain` POST (no preflight), a JSON POST (preflighted), a form posted into a
/// frame, and framing the studio. None of it generates: the studio's first result is its own
/// page's demo.
#[test]
fn a_page_on_another_site_cannot_use_the_studio() {
    let Some(driver) = browser() else { return };
    let runtime = tokio::runtime::Runtime::new().unwrap();
    runtime.block_on(async {
        let workspace = tempfile::tempdir().unwrap();
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let studio = format!("http://{}", listener.local_addr().unwrap());
        tokio::spawn(relief_studio::serve(listener, relief_studio::Config::new(workspace.path())));
        let scene = include_str!("../web/templates/island.json");
        let page = format!(
            "<!doctype html><body><form id=f method=post enctype=text/plain target=sink \
             action='{studio}/api/generate'><input name='{{\"a\":1}}' value=''></form>\
             <iframe name=sink></iframe><iframe id=framed src='{studio}/'></iframe><script>\
             const scene = {scene};\n\
             const text = fetch('{studio}/api/generate', {{ method: 'POST', mode: 'no-cors', \
               headers: {{ 'content-type': 'text/plain' }}, body: JSON.stringify(scene) }}).then(() => 'sent', e => String(e));\n\
             const json = fetch('{studio}/api/generate', {{ method: 'POST', \
               headers: {{ 'content-type': 'application/json' }}, body: JSON.stringify(scene) }}).then(r => r.status, e => 'blocked');\n\
             document.getElementById('f').submit();\n\
             window.attack = Promise.all([text, json]);</script></body>"
        );
        let evil = axum::Router::new().route("/", axum::routing::get(move || async move { axum::response::Html(page) }));
        let evil_listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let evil_port = evil_listener.local_addr().unwrap().port();
        tokio::spawn(async move { axum::serve(evil_listener, evil).await });
        let (_driver, client) = connect(&driver).await;
        // `localhost` is another site than `127.0.0.1`, as a web page's domain would be.
        client.goto(&format!("http://localhost:{evil_port}/")).await.unwrap();
        let outcome = client
            .execute_async("window.attack.then(arguments[arguments.length - 1])", vec![])
            .await
            .unwrap();
        assert_eq!(outcome[1], "blocked", "a preflighted JSON POST got through: {outcome}");
        // The form's answer lands (refused) in its frame; the framed studio shows nothing.
        tokio::time::sleep(Duration::from_millis(500)).await;
        client.goto(&format!("{studio}/")).await.unwrap();
        assert_eq!(next_result(&client, 0).await, 1, "another site's page generated a scene");
        client.close().await.unwrap();
    });
}

async fn scenario(client: &Client, workspace: &std::path::Path) {
    let id = demo_and_3d(client).await;
    screenshot(client, "studio-demo").await;
    let id = island_gestures(client, workspace, id).await;
    let map = client.find(Locator::Id("map")).await.unwrap();
    let id = contour_gestures(client, &map, id).await;
    let id = curve_and_upload_gestures(client, &map, workspace, id).await;
    if std::env::var_os("RELIEF_STUDIO_LATENCY").is_some() {
        latency(client, &map, id).await;
    }
}

/// With `RELIEF_SCREENSHOTS=DIR`, saves the page as `DIR/name.png`.
async fn screenshot(client: &Client, name: &str) {
    if let Some(dir) = std::env::var_os("RELIEF_SCREENSHOTS") {
        let png = client.screenshot().await.unwrap();
        std::fs::write(std::path::Path::new(&dir).join(format!("{name}.png")), png).unwrap();
    }
}

/// With `RELIEF_STUDIO_LATENCY` set, prints the page's end-to-end times (edit → map and 3D view
/// redrawn) of island hill moves at 512² and of contour regrowths from 50 000 nodes at 512².
async fn latency(client: &Client, map: &Element, mut id: u64) {
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let timings = |client: &Client, from: usize| {
        let client = client.clone();
        async move {
            let all = js(&client, "return window.studio.timings").await;
            let all = all.as_array().unwrap()[from..].to_vec();
            let get = |key: &str| all.iter().map(|t| t[key].as_f64().unwrap()).collect::<Vec<f64>>();
            (get("server_ms"), get("total_ms"))
        }
    };
    id = new_scene(client, "island", id).await;
    choose_tool(client, "hill").await;
    drag(client, map, &[(0.0, 0.0), (60.0, 0.0)]).await;
    id = next_result(client, id).await;
    choose_tool(client, "move-hill").await;
    let from = js(client, "return window.studio.timings.length").await.as_u64().unwrap() as usize;
    id = move_hill_20_times(client, map, id).await;
    let (server, total) = timings(client, from).await;
    eprintln!(
        "island 512², move a hill: server {:.1} ms, end to end {:.1} ms (medians of 20)",
        median(server),
        median(total)
    );
    // A long session: 20 coast strokes and 80 hill edits before the hill is moved again. Each
    // edit applies to the island the last one left (the page's editing session on the server).
    let history = "window.studio.editDoc(d => { const ops = d.generator.island.operations; \
        for (let k = 0; k < 20; k++) { const a = 2 * Math.PI * k / 20; \
          ops.push({ stroke: { points: [[1640, a + 0.16], [1800, a + 0.12], [1800, a + 0.04], [1640, a]] \
            .map(([r, t]) => [2000 + r * Math.cos(t), 2000 + r * Math.sin(t)]) } }); } \
        for (let k = 0; k < 80; k++) ops.push({ add_hill: { center: [1200 + 20 * k, 1200 + 15 * (k % 40)], \
          radii: [200, 160], height: 80 } }); })";
    js(client, history).await;
    id = next_result(client, id).await;
    let from = js(client, "return window.studio.timings.length").await.as_u64().unwrap() as usize;
    id = move_hill_20_times(client, map, id).await;
    let (server, total) = timings(client, from).await;
    eprintln!(
        "island 512² after 100 edits (20 coast strokes, 80 hills), move a hill: server {:.1} ms, end to end {:.1} ms \
         (medians of 20)",
        median(server),
        median(total)
    );
    id = new_scene(client, "contours", id).await;
    let from = js(client, "return window.studio.timings.length").await.as_u64().unwrap() as usize;
    for k in 0..5 {
        let script = format!(
            "window.studio.editDoc(d => {{ d.generator.contours.particles = 50000; \
             d.generator.contours.regions[1].height = {}; }})",
            600 + 50 * k
        );
        js(client, &script).await;
        id = next_result(client, id).await;
    }
    let (server, total) = timings(client, from).await;
    eprintln!(
        "contours 512², regrow 50 000 nodes: server {:.0} ms, end to end {:.0} ms (medians of 5)",
        median(server),
        median(total)
    );
}

/// Drags the hill at the map's centre 20 times (the move-hill tool chosen); the last result's id.
async fn move_hill_20_times(client: &Client, map: &Element, mut id: u64) -> u64 {
    for k in 0..20 {
        let x = f64::from(k % 5) * 10.0;
        drag(client, map, &[(x, 0.0), (x + 10.0, 5.0)]).await;
        id = next_result(client, id).await;
    }
    id
}

/// The demo generates on load and shows in 3D; its result's id.
async fn demo_and_3d(client: &Client) -> u64 {
    // The demo scene generates on load, and the 3D view shows it: not one flat colour.
    let id = next_result(client, 0).await;
    let colours = colours_3d(client).await;
    assert!(colours.as_u64().unwrap() > 100, "the 3D view is blank: {colours} colours");
    id
}

/// How many colours the 3D view shows: a blank or flat view has a handful.
async fn colours_3d(client: &Client) -> Value {
    js(
        client,
        "const c = document.getElementById('view3d'); const gl = c.getContext('webgl'); \
         const px = new Uint8Array(4 * c.width * c.height); \
         gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, px); \
         const seen = new Set(); for (let k = 0; k < px.length; k += 4) seen.add(px[k] << 16 | px[k + 1] << 8 | px[k + 2]); \
         return seen.size",
    )
    .await
}

/// Hill, stroke, undo and crater on a new island, then save and reload; the last result's id.
async fn island_gestures(client: &Client, workspace: &std::path::Path, mut id: u64) -> u64 {
    // A new island: the start circle, 150 m high, over a 4 km square shown 640 px wide.
    id = new_scene(client, "island", id).await;
    let map = client.find(Locator::Id("map")).await.unwrap();
    assert_eq!(result_field(client, "max").await.as_f64(), Some(150.0));

    // A hill dragged out to 80 px (500 m) north-east of the centre.
    choose_tool(client, "hill").await;
    drag(client, &map, &[(60.0, -40.0), (100.0, -40.0), (140.0, -40.0)]).await;
    id = next_result(client, id).await;
    let hill = &doc(client).await["generator"]["island"]["operations"][0]["add_hill"];
    let (centre, radius) = (&hill["center"], hill["radii"][0].as_f64().unwrap());
    assert!((centre[0].as_f64().unwrap() - 2375.0).abs() < 20.0, "{hill}");
    assert!((centre[1].as_f64().unwrap() - 2250.0).abs() < 20.0, "{hill}");
    assert!((radius - 500.0).abs() < 20.0, "{hill}");
    let max = result_field(client, "max").await.as_f64().unwrap();
    assert!(max > 500.0, "the hill raised the island to {max} m");
    // The heightfield read back by the page has that maximum, north-east of the centre.
    let peak = js(
        client,
        "const r = window.studio.result; let k = 0; \
         for (let i = 1; i < r.z.length; i++) if (r.z[i] > r.z[k]) k = i; \
         return [r.z[k], k % r.width, Math.floor(k / r.width)]",
    )
    .await;
    assert_eq!(peak[0].as_f64().unwrap(), max);
    assert!(peak[1].as_u64().unwrap() > 256 && peak[2].as_u64().unwrap() < 256, "peak at {peak}");

    // A stroke out across the eastern coast and back supplements the land there.
    let land = "return window.studio.result.z.filter(v => v > window.studio.result.sea_level).length";
    let area = |count: Value| count.as_f64().unwrap();
    let before = area(js(client, land).await);
    choose_tool(client, "stroke").await;
    let bump: Vec<(f64, f64)> =
        (0..=12).map(|k| (230.0 + 100.0 * (f64::from(k) * 0.26).sin(), -60.0 + 10.0 * f64::from(k))).collect();
    drag(client, &map, &bump).await;
    id = next_result(client, id).await;
    assert!(
        doc(client).await["generator"]["island"]["operations"][1]["stroke"]["points"].as_array().unwrap().len() >= 5
    );
    let stroked = area(js(client, land).await);
    assert!(stroked > before * 1.01, "the stroke added land: {before} → {stroked} samples");

    // Undo takes the stroke back: the same island as before it.
    client.find(Locator::Id("undo")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(doc(client).await["generator"]["island"]["operations"].as_array().unwrap().len(), 1);
    assert_eq!(area(js(client, land).await), before);

    // A stroke out in the sea is refused; the page undoes it and says so, and the next gestures
    // work on the island as it was.
    choose_tool(client, "stroke").await;
    let at_sea: Vec<(f64, f64)> = (0..=8).map(|k| (-300.0 + 10.0 * f64::from(k), 290.0)).collect();
    drag(client, &map, &at_sea).await;
    wait_for(client, "document.body.dataset.state === 'refused'").await;
    let message = js(client, "return document.getElementById('message').textContent").await;
    assert!(message.as_str().unwrap().contains("refused and undone"), "{message}");
    assert_eq!(doc(client).await["generator"]["island"]["operations"].as_array().unwrap().len(), 1);

    // A crater in the hill: a hollow (negative hill) dragged at its centre.
    choose_tool(client, "hollow").await;
    drag(client, &map, &[(60.0, -40.0), (75.0, -40.0), (90.0, -40.0)]).await;
    id = next_result(client, id).await;
    let crater = &doc(client).await["generator"]["island"]["operations"][1]["add_hill"];
    assert!(crater["height"].as_f64().unwrap() < 0.0, "{crater}");
    screenshot(client, "studio-island").await;

    // Reloading the page keeps the unsaved island (and says so).
    let unsaved = doc(client).await;
    client.refresh().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(doc(client).await, unsaved);
    let message = js(client, "return document.getElementById('message').textContent").await;
    assert!(message.as_str().unwrap().contains("restored"), "{message}");

    save_and_reload(client, workspace, id).await
}

/// Saves the scene, starts something else, and loads it back; the last result's id.
async fn save_and_reload(client: &Client, workspace: &std::path::Path, mut id: u64) -> u64 {
    let name = client.find(Locator::Id("name")).await.unwrap();
    name.clear().await.unwrap();
    name.send_keys("e2e-island.json").await.unwrap();
    client.find(Locator::Id("save")).await.unwrap().click().await.unwrap();
    let saved = doc(client).await;
    wait_for(client, "document.getElementById('status').textContent.startsWith('saved')").await;
    // Export the contours of a full run.
    client.find(Locator::Id("export")).await.unwrap().select_by_value("contours.geojson").await.unwrap();
    client.find(Locator::Id("export-button")).await.unwrap().click().await.unwrap();
    wait_for(client, "document.getElementById('status').textContent === 'exported contours.geojson'").await;
    // A game engine's files, as one zip: the page hands the browser what the server sent.
    js(
        client,
        "window.blobs = []; const made = URL.createObjectURL; \
         URL.createObjectURL = (b) => { window.blobs.push(b.type); return made(b); }; return null",
    )
    .await;
    client.find(Locator::Id("export")).await.unwrap().select_by_value("engine/godot").await.unwrap();
    client.find(Locator::Id("export-button")).await.unwrap().click().await.unwrap();
    wait_for(client, "document.getElementById('status').textContent === 'exported engine/godot'").await;
    assert_eq!(js(client, "return window.blobs").await, json!(["application/zip"]));
    let scene = |v: &Value| relief::Scene::from_json(&v.to_string()).unwrap();
    let on_disk = relief::pipeline::load_scene(workspace.join("e2e-island.json")).unwrap();
    assert_eq!(on_disk, scene(&saved));
    id = new_scene(client, "contours", id).await;
    client.find(Locator::Id("load")).await.unwrap().select_by_value("e2e-island.json").await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(scene(&doc(client).await), on_disk);
    id
}

/// Draws a region and a warp on the contour template; the last result's id.
async fn contour_gestures(client: &Client, map: &Element, mut id: u64) -> u64 {
    // The contour template has one range at 600 m. A summit region drawn corner by corner
    // inside it at 900 m; a second range at 600 m in the east, with a crater in it.
    id = new_scene(client, "contours", id).await;
    let corners = [(-60.0, -30.0), (0.0, -35.0), (10.0, 0.0), (-55.0, 5.0)];
    id = draw_region(client, map, "region", "900", &corners, id).await;
    let regions = doc(client).await["generator"]["contours"]["regions"].clone();
    assert_eq!(regions.as_array().unwrap().len(), 3, "{regions}");
    assert_eq!(regions[2]["height"].as_f64(), Some(900.0));
    assert!(regions[2]["polygon"]["exterior"].as_array().unwrap().len() >= 4);
    // The region is the 900 m contour: the terrain passes through its corners at 900 m.
    for z in at_corners(client, 2).await {
        assert!((z - 900.0).abs() < 40.0, "a corner at {z} m, the region's height is 900 m");
    }
    assert!(result_field(client, "max").await.as_f64().unwrap() > 900.0);
    let range = [(110.0, 25.0), (180.0, 30.0), (185.0, 90.0), (115.0, 95.0)];
    id = draw_region(client, map, "region", "600", &range, id).await;
    for z in at_corners(client, 3).await {
        assert!((z - 600.0).abs() < 40.0, "a corner of the second range at {z} m");
    }
    let crater = [(135.0, 48.0), (160.0, 48.0), (160.0, 72.0), (135.0, 72.0)];
    id = draw_region(client, map, "depression", "600", &crater, id).await;
    assert_eq!(doc(client).await["generator"]["contours"]["regions"][4]["depression"], true);
    // The crater's floor lies below its rim.
    let floor = js(
        client,
        "const r = window.studio.result, e = r.extent; \
         const c = window.studio.doc.generator.contours.regions[4].polygon.exterior; \
         const cx = c.reduce((s, p) => s + p[0], 0) / c.length, cy = c.reduce((s, p) => s + p[1], 0) / c.length; \
         const i = Math.round((cx - e.min[0]) / (e.max[0] - e.min[0]) * (r.width - 1)); \
         const j = Math.round((e.max[1] - cy) / (e.max[1] - e.min[1]) * (r.height - 1)); \
         return r.z[j * r.width + i]",
    )
    .await
    .as_f64()
    .unwrap();
    let rim = at_corners(client, 4).await;
    assert!(rim.iter().all(|&z| z > floor + 20.0), "the crater's floor {floor} m, its rim {rim:?}");
    id = reedit_regions(client, map, id).await;
    downloads(client).await;

    // A warp stroke dragged across the range becomes an edit, and generates.
    choose_tool(client, "warp").await;
    drag(client, map, &[(-120.0, 60.0), (-60.0, 40.0), (0.0, 20.0), (40.0, 10.0)]).await;
    id = next_result(client, id).await;
    assert!(doc(client).await["edits"][0]["warp"]["stroke"].as_array().unwrap().len() >= 3);
    screenshot(client, "studio-contours").await;

    // A painted growth map: the stroke's file is uploaded and becomes the probability map.
    let before =
        js(client, "return Array.from(window.studio.result.z.slice(0, 512 * 512).filter((_, k) => k % 997 === 0))")
            .await;
    choose_tool(client, "paint").await;
    drag(client, map, &[(-150.0, 100.0), (-100.0, 120.0), (-50.0, 130.0), (0.0, 120.0)]).await;
    id = next_result(client, id).await;
    let path = doc(client).await["generator"]["contours"]["probability"]["image"]["path"].as_str().unwrap().to_owned();
    assert!(path.starts_with("growth-") && path.ends_with("-1.png"), "{path}");
    let after =
        js(client, "return Array.from(window.studio.result.z.slice(0, 512 * 512).filter((_, k) => k % 997 === 0))")
            .await;
    assert_ne!(before, after, "the painted map changed the growth");

    // Deleting the 900 m contour (the height setting) flattens its inside to a low dome.
    let inside = "const r = window.studio.result, e = r.extent, [x, y] = window.studio.doc.edits[0].warp.stroke[0]; \
                  const c = window.studio.doc.generator.contours.regions[2].polygon.exterior; \
                  const cx = c.reduce((s, p) => s + p[0], 0) / c.length, cy = c.reduce((s, p) => s + p[1], 0) / c.length; \
                  const i = Math.round((cx - e.min[0]) / (e.max[0] - e.min[0]) * (r.width - 1)); \
                  const j = Math.round((e.max[1] - cy) / (e.max[1] - e.min[1]) * (r.height - 1)); \
                  return [r.z[j * r.width + i], cx, cy]";
    let before = js(client, inside).await;
    assert!(before[0].as_f64().unwrap() > 900.0, "{before}");
    choose_tool(client, "delete").await;
    let height = client.find(Locator::Id("height")).await.unwrap();
    height.clear().await.unwrap();
    height.send_keys("900").await.unwrap();
    drag(client, map, &[(-25.0, -15.0)]).await;
    id = next_result(client, id).await;
    assert_eq!(doc(client).await["edits"][1]["delete"]["height"].as_f64(), Some(900.0));
    let after = js(client, inside).await;
    assert!(after[0].as_f64().unwrap() < before[0].as_f64().unwrap() - 100.0, "{before} → {after}");

    // A slope curve dragged along the range's south side steepens the ground there.
    let sample = "return Array.from(window.studio.result.z.filter((_, k) => k % 389 === 0))";
    let unsloped = js(client, sample).await;
    let radius = client.find(Locator::Id("warp-radius")).await.unwrap();
    radius.clear().await.unwrap();
    radius.send_keys("400").await.unwrap();
    choose_tool(client, "slope").await;
    drag(client, map, &[(-100.0, 80.0), (-50.0, 85.0), (0.0, 80.0), (50.0, 70.0)]).await;
    id = next_result(client, id).await;
    let slope = doc(client).await["edits"][2]["slope"].clone();
    assert!(slope["curve"].as_array().unwrap().len() >= 2 && slope["radius"] == 400.0, "{slope}");
    assert_ne!(js(client, sample).await, unsloped, "the slope curve changed nothing");
    radius.clear().await.unwrap();
    radius.send_keys("800").await.unwrap();

    move_and_copy_relief(client, map, id).await
}

/// The Download link: OpenEXR, and RAW16 with its sidecar.
async fn downloads(client: &Client) {
    // The Download link fetches the heightfield as OpenEXR, 512² f32 samples.
    let exr = js(
        client,
        "return fetch(document.getElementById('download').href).then(r => r.arrayBuffer()) \
         .then(b => [b.byteLength, Array.from(new Uint8Array(b, 0, 4))])",
    )
    .await;
    assert_eq!(exr[1], json!([0x76, 0x2f, 0x31, 0x01]), "{exr}");
    assert!(exr[0].as_u64().unwrap() > 512 * 512, "{exr}");
    // RAW16 comes with its sidecar: the elevations its codes stand for.
    client.find(Locator::Id("format")).await.unwrap().select_by_value("r16").await.unwrap();
    wait_for(client, "!document.getElementById('download-sidecar').hidden").await;
    let sidecar = js(
        client,
        "return fetch(document.getElementById('download-sidecar').href).then(r => r.json()) \
         .then(s => [s.max, window.studio.result.max])",
    )
    .await;
    assert_eq!(sidecar[0], sidecar[1], "{sidecar}");
    client.find(Locator::Id("format")).await.unwrap().select_by_value("exr").await.unwrap();
    wait_for(client, "document.getElementById('download-sidecar').hidden").await;
}

/// Move relief and Copy relief dragged from the summit: each takes the contour of the height
/// setting, as Delete does; the last result's id.
async fn move_and_copy_relief(client: &Client, map: &Element, mut id: u64) -> u64 {
    let height = client.find(Locator::Id("height")).await.unwrap();
    height.clear().await.unwrap();
    height.send_keys("600").await.unwrap();
    for (k, tool) in [(3, "cut"), (4, "paste")] {
        choose_tool(client, tool).await;
        drag(client, map, &[(-25.0, -15.0), (-15.0, -15.0), (-5.0, -15.0)]).await;
        id = next_result(client, id).await;
        let edit = doc(client).await["edits"][k][tool].clone();
        assert_eq!(edit["height"].as_f64(), Some(600.0), "{tool}: {edit}");
    }
    height.clear().await.unwrap();
    height.send_keys("900").await.unwrap();
    id
}

/// Clicks a region's corners with `tool` (`region` or `depression`) at height `h`, double-clicks
/// its last corner; the result's id.
async fn draw_region(client: &Client, map: &Element, tool: &str, h: &str, corners: &[(f64, f64)], id: u64) -> u64 {
    choose_tool(client, tool).await;
    let height = client.find(Locator::Id("height")).await.unwrap();
    height.clear().await.unwrap();
    height.send_keys(h).await.unwrap();
    let (last, others) = corners.split_last().unwrap();
    for &(x, y) in others {
        drag(client, map, &[(x, y)]).await;
    }
    let mut close = MouseActions::new("mouse".into()).then(PointerAction::MoveToElement {
        element: map.clone(),
        duration: None,
        x: last.0,
        y: last.1,
    });
    for _ in 0..2 {
        close = close
            .then(PointerAction::Down { button: MOUSE_BUTTON_LEFT })
            .then(PointerAction::Up { button: MOUSE_BUTTON_LEFT });
    }
    client.perform_actions(close).await.unwrap();
    next_result(client, id).await
}

/// The summit region drawn earlier (region 2, 900 m) gets a new height, then its own back, and a
/// moved corner; the crater (region 4) is removed; the last result's id.
async fn reedit_regions(client: &Client, map: &Element, mut id: u64) -> u64 {
    let height = client.find(Locator::Id("height")).await.unwrap();
    choose_tool(client, "region-height").await;
    for h in ["1000", "900"] {
        height.clear().await.unwrap();
        height.send_keys(h).await.unwrap();
        drag(client, map, &[(-25.0, -15.0)]).await;
        id = next_result(client, id).await;
        let h: f64 = h.parse().unwrap();
        assert_eq!(doc(client).await["generator"]["contours"]["regions"][2]["height"].as_f64(), Some(h));
        for z in at_corners(client, 2).await {
            assert!((z - h).abs() < 40.0, "a corner at {z} m, the region's height is now {h} m");
        }
    }
    // The corner at (10, 0) px dragged 20 px east: the 900 m contour follows it.
    choose_tool(client, "move-corner").await;
    let before = doc(client).await["generator"]["contours"]["regions"][2]["polygon"]["exterior"][2].clone();
    drag(client, map, &[(10.0, 0.0), (20.0, 0.0), (30.0, 0.0)]).await;
    id = next_result(client, id).await;
    let after = doc(client).await["generator"]["contours"]["regions"][2]["polygon"]["exterior"][2].clone();
    let moved = after[0].as_f64().unwrap() - before[0].as_f64().unwrap();
    assert!(
        moved > 0.0 && (after[1].as_f64().unwrap() - before[1].as_f64().unwrap()).abs() < moved / 4.0,
        "{before} → {after}"
    );
    for z in at_corners(client, 2).await {
        assert!((z - 900.0).abs() < 40.0, "a corner at {z} m after the move");
    }
    // Clicking inside the crater removes it (the innermost region there), not the range.
    choose_tool(client, "remove-region").await;
    drag(client, map, &[(147.0, 60.0)]).await;
    id = next_result(client, id).await;
    let regions = doc(client).await["generator"]["contours"]["regions"].clone();
    assert_eq!(regions.as_array().unwrap().len(), 4, "{regions}");
    assert!(regions.as_array().unwrap().iter().all(|r| r["depression"] != true), "{regions}");
    id
}

/// The ridge drawn on the curve template: its middle point dragged 60 px south carries the crest
/// there; then the ridge is removed and the crest goes; the last result's id.
async fn reedit_ridge(client: &Client, map: &Element, mut id: u64) -> u64 {
    let z_at = |dy: f64| {
        format!(
            "const r = window.studio.result; const j = Math.round((320 + {dy}) / 640 * (r.height - 1)); \
             return r.z[j * r.width + Math.round((r.width - 1) / 2)]"
        )
    };
    choose_tool(client, "move-feature").await;
    drag(client, map, &[(0.0, -220.0), (0.0, -200.0), (0.0, -180.0), (0.0, -160.0)]).await;
    id = next_result(client, id).await;
    let ridge = &doc(client).await["generator"]["diffusion"]["presets"][1]["ridge"];
    let ys: Vec<f64> = ridge["points"].as_array().unwrap().iter().map(|p| p[1].as_f64().unwrap()).collect();
    assert_eq!(ys.iter().filter(|&&y| y != ys[0]).count(), 1, "one point moved: {ridge}");
    let (old, new) = (js(client, &z_at(-220.0)).await, js(client, &z_at(-160.0)).await);
    assert!((new.as_f64().unwrap() - 900.0).abs() < 90.0, "the moved crest is at {new} m");
    assert!(old.as_f64().unwrap() < new.as_f64().unwrap() - 50.0, "the old crest {old} m, the moved one {new} m");
    choose_tool(client, "remove-feature").await;
    drag(client, map, &[(-150.0, -220.0)]).await;
    id = next_result(client, id).await;
    let presets = doc(client).await["generator"]["diffusion"]["presets"].clone();
    assert_eq!(presets.as_array().unwrap().len(), 1, "{presets}");
    let gone = js(client, &z_at(-160.0)).await;
    assert!(gone.as_f64().unwrap() < new.as_f64().unwrap() - 150.0, "the crest at {new} m, {gone} m once removed");
    id
}

/// The elevations at the corners of the scene's region `k`.
async fn at_corners(client: &Client, k: usize) -> Vec<f64> {
    let script = format!(
        "const r = window.studio.result, e = r.extent; \
         return window.studio.doc.generator.contours.regions[{k}].polygon.exterior.map(([x, y]) => {{ \
           const i = Math.round((x - e.min[0]) / (e.max[0] - e.min[0]) * (r.width - 1)); \
           const j = Math.round((e.max[1] - y) / (e.max[1] - e.min[1]) * (r.height - 1)); \
           return r.z[j * r.width + i]; }})"
    );
    js(client, &script).await.as_array().unwrap().iter().map(|z| z.as_f64().unwrap()).collect()
}

/// The map shows an opened DEM, not the scene: a gesture changes nothing and says why.
async fn gesture_on_the_opened_dem(client: &Client, map: &Element) {
    let scene = doc(client).await;
    choose_tool(client, "smooth").await;
    drag(client, map, &[(10.0, 10.0)]).await;
    wait_for(client, "document.getElementById('message').textContent.includes('opened DEM')").await;
    assert_eq!(doc(client).await, scene, "a gesture on the opened DEM edited the hidden scene");
}

/// A ridge dragged on the feature-curve template; a mask uploaded and traced as an island's
/// coast; the last result's id.
async fn curve_and_upload_gestures(client: &Client, map: &Element, workspace: &std::path::Path, mut id: u64) -> u64 {
    // The curve template: 8 km shown 640 px wide. A ridge dragged west to east across the
    // north, its crest at the height setting (900 m) halfway.
    id = new_scene(client, "curves", id).await;
    choose_tool(client, "ridge").await;
    let course: Vec<(f64, f64)> = (0..=20).map(|k| (-200.0 + 20.0 * f64::from(k), -220.0)).collect();
    drag(client, map, &course).await;
    id = next_result(client, id).await;
    let ridge = &doc(client).await["generator"]["diffusion"]["presets"][1]["ridge"];
    assert_eq!(ridge["peak_h"].as_f64(), Some(900.0), "{ridge}");
    assert!(ridge["points"].as_array().unwrap().len() >= 5, "{ridge}");
    // Halfway along (the map's middle column, 220 px north of the centre): the crest height.
    let crest = js(
        client,
        "const r = window.studio.result; const j = Math.round((320 - 220) / 640 * (r.height - 1)); \
         return r.z[j * r.width + Math.round((r.width - 1) / 2)]",
    )
    .await;
    assert!((crest.as_f64().unwrap() - 900.0).abs() < 90.0, "the crest is at {crest} m");
    id = reedit_ridge(client, map, id).await;
    id = bezier_gestures(client, map, id).await;
    screenshot(client, "studio-curves").await;

    // A paint-program mask uploaded through the page, then traced as a new island's coast: a
    // square of land over the map's western half.
    let mask = workspace.join("upload-source.png");
    write_mask(&mask);
    id = new_scene(client, "island", id).await;
    let land = "return window.studio.result.z.filter(v => v > window.studio.result.sea_level).length";
    let circle = js(client, land).await.as_f64().unwrap();
    client.find(Locator::Id("upload")).await.unwrap().send_keys(mask.to_str().unwrap()).await.unwrap();
    wait_for(client, "!document.getElementById('trace').disabled").await;
    client.find(Locator::Id("trace")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(doc(client).await["generator"]["island"]["coastline_image"]["path"], "upload-source.png");
    assert!(workspace.join("upload-source.png").is_file());
    let traced = js(client, land).await.as_f64().unwrap();
    // The circle covers π·0.4² ≈ 50 % of the map, the mask's square 36 %.
    assert!(traced < 0.85 * circle, "{circle} → {traced} land samples");
    let west = js(
        client,
        "const r = window.studio.result; let w = 0, e = 0; \
         r.z.forEach((v, k) => { if (v > r.sea_level) { if (k % r.width < r.width / 2) w++; else e++; } }); return [w, e]",
    )
    .await;
    assert!(west[0].as_f64().unwrap() > 3.0 * west[1].as_f64().unwrap(), "land west/east: {west}");

    // The same mask as a label image: a new contour scene whose land is its white square.
    client.find(Locator::Id("labels")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(doc(client).await["generator"]["contours"]["label_image"]["path"], "upload-source.png");
    let west = js(
        client,
        "const r = window.studio.result; let w = 0, e = 0; \
         r.z.forEach((v, k) => { if (v > 1) { if (k % r.width < r.width / 2) w++; else e++; } }); return [w, e]",
    )
    .await;
    // The square spans x = 500 … 6500 of 0 … 10 000: three times as much land west of the middle.
    let ratio = west[0].as_f64().unwrap() / west[1].as_f64().unwrap();
    assert!((2.0..4.5).contains(&ratio), "labelled land west/east: {west}");

    // A real DEM uploaded and opened as it is, with its peaks and divide tree drawn.
    let dem = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/dem/jacksboro.asc");
    client
        .find(Locator::Id("upload"))
        .await
        .unwrap()
        .send_keys(dem.canonicalize().unwrap().to_str().unwrap())
        .await
        .unwrap();
    wait_for(client, "document.getElementById('status').textContent === 'uploaded jacksboro.asc'").await;
    client.find(Locator::Id("open-dem")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(result_field(client, "max").await.as_f64(), Some(1076.0));
    // A geographic DEM (degrees) in metres in 3D: not blank.
    let colours = colours_3d(client).await;
    assert!(colours.as_u64().unwrap() > 100, "the DEM's 3D view is blank: {colours} colours");
    let prominence = client.find(Locator::Id("min-prominence")).await.unwrap();
    prominence.send_keys("100").await.unwrap();
    client.find(Locator::Id("show-peaks")).await.unwrap().click().await.unwrap();
    wait_for(client, "Number(document.body.dataset.peaks || 0) >= 5").await;
    screenshot(client, "studio-peaks").await;
    gesture_on_the_opened_dem(client, map).await;

    // A terrain synthesized from its divide tree; one tree peak raised to 1500 m by a click.
    client.find(Locator::Id("show-peaks")).await.unwrap().click().await.unwrap();
    client.find(Locator::Id("synthesize")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    let before = result_field(client, "max").await.as_f64().unwrap();
    assert!(before < 1400.0, "{before}");
    let offset = js(
        client,
        "const r = window.studio.result, e = r.extent, p = r.divide_tree.peaks[0].position; \
         const s = 640 / Math.max(e.max[0] - e.min[0], e.max[1] - e.min[1]); \
         return [(p[0] - e.min[0]) * s - 320, (e.max[1] - p[1]) * s - 320]",
    )
    .await;
    let at = (offset[0].as_f64().unwrap(), offset[1].as_f64().unwrap());
    choose_tool(client, "peak-height").await;
    let height = client.find(Locator::Id("height")).await.unwrap();
    height.clear().await.unwrap();
    height.send_keys("1500").await.unwrap();
    drag(client, map, &[at]).await;
    id = next_result(client, id).await;
    let edit = &doc(client).await["generator"]["orometry"]["edits"][0];
    assert_eq!(
        (edit["op"].as_str(), edit["peak"].as_u64(), edit["elevation"].as_f64()),
        (Some("move_peak"), Some(0), Some(1500.0))
    );
    let raised = result_field(client, "max").await.as_f64().unwrap();
    assert!(raised > 1400.0, "the tree's peak 0 at 1500 m: the terrain's top at {raised} m");
    id = tree_gestures(client, map, at, id).await;
    screenshot(client, "studio-orometry").await;
    vector_gestures(client, map, id).await
}

/// On the curve template (12.5 m per pixel, the map's centre at 4 km, 4 km): a free Bézier curve
/// drawn west to east with its slopes steeper on the left, a lower constraint placed at its
/// middle, and its end anchor dragged north.
async fn bezier_gestures(client: &Client, map: &Element, mut id: u64) -> u64 {
    js(
        client,
        "document.getElementById('height').value = 700; document.getElementById('c-theta').value = 30; \
         document.getElementById('c-phi').value = 5; document.getElementById('warp-radius').value = 800; \
         for (const c of ['c-elevation', 'c-slope', 'c-noise']) document.getElementById(c).checked = true",
    )
    .await;
    choose_tool(client, "bezier").await;
    let course: Vec<(f64, f64)> = (0..=20).map(|k| (-200.0 + 20.0 * f64::from(k), 220.0)).collect();
    drag(client, map, &course).await;
    id = next_result(client, id).await;
    let curve = doc(client).await["generator"]["diffusion"]["curves"][0].clone();
    let points = curve["points"].as_array().unwrap();
    assert!(points.len() >= 4 && (points.len() - 1) % 3 == 0, "a cubic Bézier spline: {curve}");
    assert_eq!((points[0][0].as_f64(), points[0][1].as_f64()), (Some(1500.0), Some(1250.0)), "{curve}");
    let ends = &curve["constraints"];
    assert_eq!((ends[0]["u"].as_f64(), ends[1]["u"].as_f64()), (Some(0.0), Some(1.0)), "{curve}");
    assert_eq!(ends[0]["elevation"]["h"].as_f64(), Some(700.0), "{curve}");
    assert_eq!((ends[0]["slope"]["theta"].as_f64(), ends[0]["slope"]["phi"].as_f64()), (Some(30.0), Some(5.0)));
    let on = z_at_px(client, 0.0, 220.0).await;
    assert!((on - 700.0).abs() < 40.0, "the curve's middle at {on} m");
    // θ = 30° on the left (north of a west-to-east curve), φ = 5° on the right, 250 m out.
    let (north, south) = (z_at_px(client, 0.0, 200.0).await, z_at_px(client, 0.0, 240.0).await);
    assert!(north < on - 60.0 && south - north > 50.0, "250 m north {north} m, on {on} m, 250 m south {south} m");

    // A click on the curve's middle, the height at 300 m: a third constraint there.
    js(client, "document.getElementById('height').value = 300").await;
    choose_tool(client, "constrain").await;
    drag(client, map, &[(0.0, 220.0)]).await;
    id = next_result(client, id).await;
    let constraints = doc(client).await["generator"]["diffusion"]["curves"][0]["constraints"].clone();
    let middle = &constraints[1];
    assert_eq!(constraints.as_array().unwrap().len(), 3, "{constraints}");
    assert!((middle["u"].as_f64().unwrap() - 0.5).abs() < 0.02, "{constraints}");
    assert_eq!(middle["elevation"]["h"].as_f64(), Some(300.0), "{constraints}");
    let lowered = z_at_px(client, 0.0, 220.0).await;
    assert!((lowered - 300.0).abs() < 40.0, "the constrained middle at {lowered} m");

    // The end anchor dragged 40 px (500 m) north takes its handle along.
    choose_tool(client, "move-control").await;
    drag(client, map, &[(200.0, 220.0), (200.0, 200.0), (200.0, 180.0)]).await;
    id = next_result(client, id).await;
    let moved = doc(client).await["generator"]["diffusion"]["curves"][0]["points"].clone();
    let n = moved.as_array().unwrap().len();
    let shift = |k: usize| {
        let (a, b) = (&points[k], &moved[k]);
        (b[0].as_f64().unwrap() - a[0].as_f64().unwrap(), b[1].as_f64().unwrap() - a[1].as_f64().unwrap())
    };
    assert_eq!((shift(n - 1), shift(n - 2), shift(0)), ((0.0, 500.0), (0.0, 500.0), (0.0, 0.0)), "{moved}");
    let end = z_at_px(client, 200.0, 180.0).await;
    assert!((end - 700.0).abs() < 40.0, "the moved end at {end} m");
    id
}

/// The current result's elevation at a pixel offset from the map's centre (a square extent).
async fn z_at_px(client: &Client, dx: f64, dy: f64) -> f64 {
    let script = format!(
        "const r = window.studio.result; const i = Math.round((320 + {dx}) / 640 * (r.width - 1)); \
         const j = Math.round((320 + {dy}) / 640 * (r.height - 1)); return r.z[j * r.width + i]"
    );
    js(client, &script).await.as_f64().unwrap()
}

/// On a synthesized terrain whose tree peak 0 is at `at` (pixels from the map's centre): a new
/// peak dragged out from it, then the new saddle dragged south.
async fn tree_gestures(client: &Client, map: &Element, at: (f64, f64), mut id: u64) -> u64 {
    let count = |what: &'static str| async move {
        js(client, &format!("return window.studio.result.divide_tree.{what}.length")).await.as_u64().unwrap()
    };
    let (peaks, saddles) = (count("peaks").await, count("saddles").await);
    js(client, "document.getElementById('height').value = 1200").await;
    choose_tool(client, "insert-peak").await;
    let dx = if at.0 > 0.0 { -60.0 } else { 60.0 };
    drag(client, map, &[at, (at.0 + dx / 2.0, at.1), (at.0 + dx, at.1)]).await;
    id = next_result(client, id).await;
    let inserted = doc(client).await["generator"]["orometry"]["edits"][1].clone();
    assert_eq!(
        (inserted["op"].as_str(), inserted["connect_to"].as_u64()),
        (Some("insert_peak"), Some(0)),
        "{inserted}"
    );
    assert_eq!(inserted["elevation"].as_f64(), Some(1200.0), "{inserted}");
    assert!(inserted["saddle_elevation"].as_f64().unwrap() < 1200.0, "{inserted}");
    assert_eq!((count("peaks").await, count("saddles").await), (peaks + 1, saddles + 1));

    // The new saddle, found in the generated tree at the position the edit gave it, dragged 30 px
    // south: the tree's saddle follows.
    let script = format!(
        "const r = window.studio.result, e = r.extent, s = 640 / Math.max(e.max[0] - e.min[0], e.max[1] - e.min[1]);          const k = r.divide_tree.saddles.findIndex(q => Math.hypot(q.position[0] - {x}, q.position[1] - {y}) < 1e-6 * s);          const p = r.divide_tree.saddles[k].position; return [k, (p[0] - e.min[0]) * s - 320, (e.max[1] - p[1]) * s - 320, s]",
        x = inserted["saddle"][0],
        y = inserted["saddle"][1],
    );
    let found = js(client, &script).await;
    let k = found[0].as_i64().unwrap();
    assert!(k >= 0, "the inserted saddle is not in the tree: {found}");
    let (sx, sy, scale) = (found[1].as_f64().unwrap(), found[2].as_f64().unwrap(), found[3].as_f64().unwrap());
    choose_tool(client, "move-saddle").await;
    drag(client, map, &[(sx, sy), (sx, sy + 15.0), (sx, sy + 30.0)]).await;
    id = next_result(client, id).await;
    let moved = doc(client).await["generator"]["orometry"]["edits"][2].clone();
    assert_eq!((moved["op"].as_str(), moved["saddle"].as_i64()), (Some("move_saddle"), Some(k)), "{moved}");
    let now = js(client, &format!("return window.studio.result.divide_tree.saddles[{k}].position")).await;
    let south = (inserted["saddle"][1].as_f64().unwrap() - now[1].as_f64().unwrap()) * scale;
    assert!((south - 30.0).abs() < 1.5, "the saddle moved {south} px south: {now}");
    id
}

/// The uploaded DEM vectorized; a landform copied and pasted elsewhere, a crest node dragged.
async fn vector_gestures(client: &Client, map: &Element, mut id: u64) -> u64 {
    // The status line, as the server's progress stream updates it during the fit.
    js(
        client,
        "window.statuses = []; new MutationObserver(() => window.statuses.push(document.getElementById('status') \
         .textContent)).observe(document.getElementById('status'), { childList: true, characterData: true, subtree: true })",
    )
    .await;
    client.find(Locator::Id("vectorize")).await.unwrap().click().await.unwrap();
    id = next_result(client, id).await;
    assert_eq!(doc(client).await["generator"]["gaussian"]["source"]["path"], "jacksboro.asc");
    let fitting = js(client, "return window.statuses.filter(s => /^generating: source \\d+\\/40…$/.test(s))").await;
    assert!(!fitting.as_array().unwrap().is_empty(), "the fit's iterations never showed: {fitting}");
    // Vectorized in degrees, shown in metres: not a needle in an empty 3D view.
    let colours = colours_3d(client).await;
    assert!(colours.as_u64().unwrap() > 100, "the vectorized DEM's 3D view is blank: {colours} colours");
    // Jacksboro is in degrees: a radius of 0.03° (about 3 km).
    let radius = client.find(Locator::Id("warp-radius")).await.unwrap();
    radius.clear().await.unwrap();
    radius.send_keys("0.03").await.unwrap();
    choose_tool(client, "copy-landform").await;
    drag(client, map, &[(0.0, 0.0)]).await;
    id = next_result(client, id).await;
    // The sample under a point of the map, `(x, y)` pixels from its centre.
    let at = |x: f64, y: f64| {
        format!(
            "const r = window.studio.result, e = r.extent, [wx, wy] = window.studio.canvasToWorld(320 + {x}, 320 + {y}); \
             const i = Math.round((wx - e.min[0]) / (e.max[0] - e.min[0]) * (r.width - 1)); \
             const j = Math.round((e.max[1] - wy) / (e.max[1] - e.min[1]) * (r.height - 1)); \
             return r.z[j * r.width + i]"
        )
    };
    // The ground at the paste point and around it (±20 px): how much one sample changes depends
    // on how much the copied landform resembles the ground it lands on, so the test asks for the
    // largest change near the paste point.
    let offsets: Vec<(f64, f64)> = (-2..=2)
        .flat_map(|a| (-2..=2).map(move |b| (150.0 + 10.0 * f64::from(a), 60.0 + 10.0 * f64::from(b))))
        .collect();
    let mut before = Vec::new();
    for &(x, y) in &offsets {
        before.push(js(client, &at(x, y)).await.as_f64().unwrap());
    }
    choose_tool(client, "paste-landform").await;
    drag(client, map, &[(150.0, 60.0)]).await;
    id = next_result(client, id).await;
    let ops = doc(client).await["generator"]["gaussian"]["operations"].clone();
    assert_eq!((ops[0]["op"].as_str(), ops[0]["name"].as_str()), (Some("copy"), Some("landform-1")), "{ops}");
    assert_eq!((ops[1]["op"].as_str(), ops[1]["landform"].as_str()), (Some("paste"), Some("landform-1")), "{ops}");
    let mut change = 0.0f64;
    for (&(x, y), b) in offsets.iter().zip(&before) {
        change = change.max((js(client, &at(x, y)).await.as_f64().unwrap() - b).abs());
    }
    assert!(change > 5.0, "the pasted landform left the ground near the paste point within {change} m");
    // The crest skeleton appears with the crest tool; a node dragged 20 px east.
    choose_tool(client, "move-crest").await;
    wait_for(client, "Number(document.body.dataset.skeleton || 0) > 0").await;
    let node = js(
        client,
        "const n = window.studio.skeleton[Math.floor(window.studio.skeleton.length / 2)]; \
         const [x, y] = window.studio.worldToCanvas(n.position); return [n.id, x - 320, y - 320]",
    )
    .await;
    let (x, y) = (node[1].as_f64().unwrap(), node[2].as_f64().unwrap());
    drag(client, map, &[(x, y), (x + 10.0, y), (x + 20.0, y)]).await;
    id = next_result(client, id).await;
    let moved = &doc(client).await["generator"]["gaussian"]["operations"][2];
    assert_eq!((moved["op"].as_str(), moved["node"].as_u64()), (Some("move_crest"), node[0].as_u64()), "{moved}");
    assert!(moved["by"][0].as_f64().unwrap() > 0.0, "{moved}");
    wait_for(client, "Number(document.body.dataset.skeleton || 0) > 0").await;
    screenshot(client, "studio-vector").await;
    id
}

/// A 200² gray PNG: white land over x in 10–130 and y in 40–160, black sea elsewhere.
fn write_mask(path: &std::path::Path) {
    let file = std::fs::File::create(path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 200, 200);
    encoder.set_color(png::ColorType::Grayscale);
    let data: Vec<u8> = (0..200 * 200)
        .map(|k| if (10..130).contains(&(k % 200)) && (40..160).contains(&(k / 200)) { 255 } else { 0 })
        .collect();
    encoder.write_header().unwrap().write_image_data(&data).unwrap();
}

async fn wait_for(client: &Client, condition: &str) {
    let deadline = Instant::now() + Duration::from_secs(20);
    while js(client, &format!("return {condition}")).await != json!(true) {
        assert!(Instant::now() < deadline, "waiting for {condition}");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}
