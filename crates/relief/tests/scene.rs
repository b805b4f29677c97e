//! Scene files: every fixture and the demo parse and round-trip, the checked-in JSON Schema is the
//! one the types generate, and every kind of bad value fails with an error naming its JSON path.

use std::path::{Path, PathBuf};

use relief::pipeline::{generate, load_scene, run};
use relief::{ReliefError, Scene};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn fixtures() -> Vec<PathBuf> {
    let dir = root().join("fixtures/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn there_are_at_least_five_fixture_scenes_and_each_parses_and_round_trips() {
    let files = fixtures();
    assert!(files.len() >= 5, "{files:?}");
    for path in files.iter().chain([&root().join("crates/relief/scenes/demo.json")]) {
        let scene = load_scene(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(Scene::from_json(&scene.to_json()).unwrap(), scene, "{}", path.display());
        assert!(scene.description.is_some(), "{}: say what the scene shows", path.display());
    }
    assert_eq!(Scene::demo(), load_scene(root().join("crates/relief/scenes/demo.json")).unwrap());
}

/// Every file name in a fixture scene outside its outputs is a file the scene says it reads, and
/// each exists: the CLI and the studio check these paths before a run.
#[test]
fn fixture_scenes_list_every_file_they_read() {
    fn file_names<'a>(value: &'a serde_json::Value, found: &mut Vec<&'a str>) {
        match value {
            serde_json::Value::String(s)
                if Path::new(s).extension().is_some_and(|e| e.len() <= 7 && !s.contains(' ')) =>
            {
                found.push(s);
            }
            serde_json::Value::Array(items) => items.iter().for_each(|v| file_names(v, found)),
            serde_json::Value::Object(map) => {
                map.iter()
                    .filter(|(k, _)| !matches!(k.as_str(), "outputs" | "description"))
                    .for_each(|(_, v)| file_names(v, found));
            }
            _ => {}
        }
    }
    let mut checked = 0;
    for path in fixtures() {
        let scene = load_scene(&path).unwrap();
        let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let mut named = Vec::new();
        file_names(&json, &mut named);
        let listed = scene.input_files();
        for name in named {
            assert!(listed.contains(&Path::new(name)), "{}: {name} is read but not listed", path.display());
            checked += 1;
        }
        for file in listed {
            assert!(path.parent().unwrap().join(file).is_file(), "{}: {} is missing", path.display(), file.display());
        }
    }
    assert!(checked >= 10, "{checked} file names");
}

/// `docs/scene.schema.json` is generated from the types; regenerate it with
/// `RELIEF_BLESS=1 cargo test -p relief --test scene` (or `relief schema > docs/scene.schema.json`).
#[test]
fn checked_in_schema_matches_the_types() {
    let path = root().join("docs/scene.schema.json");
    let expected = format!("{}\n", Scene::json_schema());
    if std::env::var_os("RELIEF_BLESS").is_some() {
        std::fs::write(&path, &expected).unwrap();
    }
    let found = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        found == expected,
        "docs/scene.schema.json is stale: run `RELIEF_BLESS=1 cargo test -p relief --test scene`"
    );
    // It really is a schema of the format: the fields a reader needs are there.
    let schema: serde_json::Value = serde_json::from_str(&found).unwrap();
    for key in ["version", "seed", "generator", "edits", "reconstruction", "outputs", "domain"] {
        assert!(schema["properties"].get(key).is_some(), "{key} missing from the schema");
    }
}

/// A small valid scene as a JSON value, to break in one place per test.
fn base() -> serde_json::Value {
    serde_json::json!({
        "version": 1,
        "seed": 1,
        "generator": { "contours": {
            "regions": [
                { "polygon": { "exterior": [[0, 0], [3000, 0], [3000, 2000], [0, 2000]] }, "height": 0 },
                { "polygon": { "exterior": [[1000, 600], [2000, 600], [2000, 1400], [1000, 1400]] } }
            ],
            "particles": 2000,
            "histogram": { "uniform": { "min": 0, "max": 500 } },
            "levels": { "count": 5 }
        } },
        "reconstruction": { "resolution": [64, 48] }
    })
}

/// The scene error of `value` (parsing, then running with no outputs).
#[track_caller]
fn scene_error(value: &serde_json::Value) -> (String, String) {
    let result = Scene::from_json(&value.to_string()).and_then(|scene| generate(&scene, &root(), &mut ()).map(|_| ()));
    match result {
        Err(ReliefError::Scene { path, source }) => (path, source.to_string()),
        Err(other) => panic!("expected a scene error, got {other}"),
        Ok(()) => panic!("expected a scene error for {value}"),
    }
}

#[track_caller]
fn assert_path(value: &serde_json::Value, expected_path: &str, message_contains: &str) {
    let (path, message) = scene_error(value);
    assert_eq!(path, expected_path, "message: {message}");
    assert!(message.contains(message_contains), "{path}: {message}");
}

#[test]
fn the_base_scene_is_valid() {
    let scene = Scene::from_json(&base().to_string()).unwrap();
    let terrain = generate(&scene, &root(), &mut ()).unwrap();
    assert_eq!(terrain.heightfield.nx(), 64);
}

#[test]
fn unknown_fields_are_named_with_their_path() {
    let mut v = base();
    v["generator"]["contours"]["regions"][1]["hieght"] = 3.into();
    assert_path(&v, "generator.contours.regions[1].hieght", "unknown field `hieght`, expected one of");
    let mut v = base();
    v["colour"] = "green".into();
    assert_path(&v, "colour", "unknown field `colour`");
}

#[test]
fn wrong_types_and_versions_are_named_with_their_path() {
    let mut v = base();
    v["generator"]["contours"]["particles"] = "many".into();
    assert_path(&v, "generator.contours.particles", "invalid type");
    let mut v = base();
    v["generator"]["contours"]["regions"][0]["polygon"]["exterior"][2] = serde_json::json!([1.0]);
    assert_path(&v, "generator.contours.regions[0].polygon.exterior[2]", "");
    let mut v = base();
    v["version"] = 2.into();
    assert_path(&v, "version", "not supported");
}

#[test]
fn bad_polygons_and_region_layouts_name_the_region() {
    let mut v = base();
    // A bow tie: the ring crosses itself.
    v["generator"]["contours"]["regions"][1]["polygon"]["exterior"] =
        serde_json::json!([[1000, 600], [2000, 1400], [2000, 600], [1000, 1400]]);
    assert_path(&v, "generator.contours.regions[1].polygon", "");
    let mut v = base();
    // Sticks out of the coastline.
    v["generator"]["contours"]["regions"][1]["polygon"]["exterior"] =
        serde_json::json!([[2500, 600], [3500, 600], [3500, 1400], [2500, 1400]]);
    assert_path(&v, "generator.contours.regions[1].polygon", "overlap");
    let mut v = base();
    v["generator"]["contours"]["regions"][1]["depression"] = true.into();
    assert_path(&v, "generator.contours.regions[1].depression", "directly inside the coastline");
    let mut v = base();
    v["generator"]["contours"]["regions"][1]["height"] = (-10.0).into();
    assert_path(&v, "generator.contours.regions", "not above");
}

#[test]
fn out_of_range_values_are_named_with_their_path() {
    let cases: Vec<(&str, serde_json::Value, &str, &str)> = vec![
        ("/generator/contours/particles", 0.into(), "generator.contours.particles", "at least 1"),
        ("/generator/contours/radius", (-1.0).into(), "generator.contours", "not both"),
        ("/generator/contours/levels", serde_json::json!({ "count": 0 }), "generator.contours.levels", "levels"),
        ("/generator/contours/levels", serde_json::json!({ "interval": -5 }), "generator.contours.levels", "interval"),
        (
            "/generator/contours/histogram",
            serde_json::json!({ "bins": { "edges": [0, 1], "weights": [1, 2] } }),
            "generator.contours.histogram",
            "",
        ),
        ("/reconstruction/resolution", serde_json::json!([0, 10]), "reconstruction.resolution", "2..="),
        (
            "/generator/contours/probability",
            serde_json::json!({ "fbm": { "frequency": -1, "contrast": 2 } }),
            // Checked as it is read, so the path names the fBm map itself.
            "generator.contours.probability.fbm",
            "fBm",
        ),
        ("/domain", serde_json::json!({ "min": [5, 5], "max": [0, 10] }), "domain", "below max"),
    ];
    for (pointer, value, path, message) in cases {
        let mut v = base();
        let (parent, key) = pointer.rsplit_once('/').unwrap();
        let target = if parent.is_empty() { &mut v } else { v.pointer_mut(parent).unwrap() };
        target[key] = value;
        assert_path(&v, path, message);
    }
    let mut v = base();
    v["generator"]["contours"].as_object_mut().unwrap().remove("particles");
    v["generator"]["contours"]["radius"] = (-1.0).into();
    assert_path(&v, "generator.contours.radius", "> 0");
}

#[test]
fn bad_edits_name_the_edit() {
    let mut v = base();
    v["edits"] = serde_json::json!([
        { "smooth": {} },
        { "warp": { "stroke": [[100, 100], [200, 100]], "radius": -3 } }
    ]);
    assert_path(&v, "edits[1].warp.radius", "radius");
    v["edits"] = serde_json::json!([{ "warp": { "stroke": [[100, 100]], "radius": 50 } }]);
    assert_path(&v, "edits[0].warp.stroke", "");
    v["edits"] =
        serde_json::json!([{ "slope": { "point": [1, 1], "curve": [[0, 0], [1, 1]], "radius": 50, "strength": 1 } }]);
    assert_path(&v, "edits[0].slope", "exactly one");
    v["edits"] = serde_json::json!([{ "slope": { "point": [1, 1], "radius": 50, "strength": 5 } }]);
    assert_path(&v, "edits[0].slope.strength", "");
    v["edits"] = serde_json::json!([{ "smooth": { "alpha": 2 } }]);
    assert_path(&v, "edits[0].smooth.alpha", "(0, 1]");
}

#[test]
fn missing_and_malformed_files_name_the_field_and_the_file() {
    let mut v = base();
    let contours = v["generator"]["contours"].as_object_mut().unwrap();
    contours.remove("regions");
    contours.insert(
        "label_image".into(),
        serde_json::json!({ "path": "no/such/mask.png", "extent": { "min": [0, 0], "max": [10, 10] } }),
    );
    let (path, message) = scene_error(&v);
    assert_eq!(path, "generator.contours.label_image.path");
    assert!(message.contains("mask.png"), "{message}");

    let mut v = base();
    v["generator"]["contours"]["histogram"] = serde_json::json!({ "dem": "nowhere.asc" });
    let (path, message) = scene_error(&v);
    assert_eq!(path, "generator.contours.histogram.dem");
    assert!(message.contains("nowhere.asc"), "{message}");

    // A continuous image is not a label map.
    let mut v = base();
    let contours = v["generator"]["contours"].as_object_mut().unwrap();
    contours.remove("regions");
    contours.insert(
        "label_image".into(),
        serde_json::json!({ "path": "fixtures/dem/jacksboro.asc", "extent": { "min": [0, 0], "max": [10, 10] } }),
    );
    assert_path(&v, "generator.contours.label_image.path", "label map");
}

#[test]
fn unknown_output_formats_fail_before_any_work() {
    let mut v = base();
    v["outputs"] = serde_json::json!({ "heightfield": ["a.exr", "b.jpeg"] });
    let scene = Scene::from_json(&v.to_string()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let err = run(&scene, &root(), dir.path(), &mut ()).unwrap_err();
    assert!(matches!(&err, ReliefError::Scene { path, .. } if path == "outputs.heightfield[1]"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing is written");
}

/// A scene error names the JSON path and keeps the error behind it: the library's own typed
/// error for a value a library refused, the JSON parser's (with its line and column) for text
/// that does not fit the format.
#[test]
fn errors_keep_their_typed_source() {
    use std::error::Error as _;
    // Refused by the region tree (eden-growth) while the scene runs.
    let mut v = base();
    v["generator"]["contours"]["regions"][1]["polygon"]["exterior"] =
        serde_json::json!([[2500, 600], [3500, 600], [3500, 1400], [2500, 1400]]);
    let scene = Scene::from_json(&v.to_string()).unwrap();
    let e = generate(&scene, &root(), &mut ()).unwrap_err();
    assert_eq!(e.scene_path(), Some("generator.contours.regions[1].polygon"));
    let source = e.source().expect("the library error is kept");
    let eden = source.downcast_ref::<relief::eden_growth::EdenError>().expect("an EdenError");
    assert!(matches!(eden, relief::eden_growth::EdenError::RegionsOverlap { b: 1, .. }), "{eden:?}");
    assert_eq!(e.to_string(), format!("generator.contours.regions[1].polygon: {eden}"));

    // Refused by the diffusion crate's own rules as the scene is read: the path reaches the field.
    let scene = std::fs::read_to_string(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&scene).unwrap();
    v["generator"]["diffusion"]["curves"][1]["constraints"][0]["slope"]["theta"] = 95.into();
    let text = serde_json::to_string_pretty(&v).unwrap();
    let e = Scene::from_json(&text).unwrap_err();
    assert_eq!(e.scene_path(), Some("generator.diffusion.curves[1].constraints[0].slope.theta"));
    let json = e.source().and_then(|s| s.downcast_ref::<serde_json::Error>()).expect("a serde_json::Error");
    let line = text.lines().position(|l| l.contains("95")).unwrap() + 1;
    // serde_json reports where it stopped reading: on the value's line or the next.
    assert!((line..=line + 1).contains(&json.line()), "{json} (value on line {line})");
    assert!(json.to_string().contains("strictly between"), "{json}");

    // A rule of the scene format itself.
    let mut v = base();
    v["generator"]["contours"]["radius"] = 30.into();
    let e = generate(&Scene::from_json(&v.to_string()).unwrap(), &root(), &mut ()).unwrap_err();
    let rule = e.source().and_then(|s| s.downcast_ref::<relief::SceneError>()).expect("a SceneError");
    assert!(matches!(rule, relief::SceneError::Conflict("particles", "radius")), "{rule:?}");
}

/// A histogram is one of the library's forms or a DEM file; the key decides, the library checks
/// its own forms, and a bad value inside is named by its full path.
#[test]
fn histograms_are_the_librarys_or_a_dem() {
    use relief::contours::HistogramSpec;
    use relief::scene::{Generator, HistogramSource};
    let parse = |histogram: serde_json::Value| {
        let mut v = base();
        v["generator"]["contours"]["histogram"] = histogram;
        Scene::from_json(&v.to_string())
    };
    let histogram_of = |scene: Scene| match scene.generator {
        Generator::Contours(g) => g.histogram.expect("a histogram"),
        _ => unreachable!("a contour scene"),
    };
    let dem = histogram_of(parse(serde_json::json!({ "dem": "fixtures/dem/jacksboro.asc" })).unwrap());
    assert_eq!(dem, HistogramSource::Dem("fixtures/dem/jacksboro.asc".into()));
    let bins = histogram_of(parse(serde_json::json!({ "bins": { "edges": [0, 1, 3], "weights": [2, 1] } })).unwrap());
    let HistogramSource::Histogram(h) = &bins else { panic!("{bins:?}") };
    assert_eq!(h.spec(), &HistogramSpec::Bins { edges: vec![0.0, 1.0, 3.0], weights: vec![2.0, 1.0] });
    let samples = histogram_of(parse(serde_json::json!({ "samples": [1, 5, 2] })).unwrap());
    assert!(matches!(&samples, HistogramSource::Histogram(h) if h.max() == 5.0));
    // Both forms write back as they were read.
    for source in [dem, bins, samples] {
        let text = serde_json::to_string(&source).unwrap();
        let mut v = base();
        v["generator"]["contours"]["histogram"] = serde_json::from_str(&text).unwrap();
        assert_eq!(histogram_of(Scene::from_json(&v.to_string()).unwrap()), source);
    }
    for (histogram, path, says) in [
        (
            serde_json::json!({ "bins": { "edges": [0, "one"], "weights": [1] } }),
            "generator.contours.histogram.bins.edges[1]",
            "invalid type",
        ),
        (
            serde_json::json!({ "bins": { "edges": [0, 1], "weights": [1], "colour": 3 } }),
            "generator.contours.histogram.bins.colour",
            "unknown field",
        ),
        (
            serde_json::json!({ "bins": { "edges": [1, 0], "weights": [1] } }),
            "generator.contours.histogram",
            "histogram",
        ),
        (serde_json::json!({ "gaussian": 3 }), "generator.contours.histogram", "unknown variant `gaussian`"),
        (serde_json::json!({ "dem": "a.asc", "samples": [1] }), "generator.contours.histogram", "exactly one"),
        (serde_json::json!({}), "generator.contours.histogram", "a histogram"),
        (serde_json::json!({ "dem": 4 }), "generator.contours.histogram.dem", "invalid type"),
    ] {
        let e = parse(histogram.clone()).unwrap_err();
        assert_eq!(e.scene_path(), Some(path), "{histogram}: {e}");
        assert!(e.to_string().contains(says), "{histogram}: {e}");
    }
}

/// Every output is written in the format its extension names, and no two outputs share a file:
/// both checked before any work, at the output's JSON path.
#[test]
fn outputs_name_their_formats_and_files_apart() {
    for (outputs, path, says) in [
        (serde_json::json!({ "preview": "preview.exr" }), "outputs.preview", "written as PNG; give it a .png name"),
        (serde_json::json!({ "contours_svg": "c.png" }), "outputs.contours_svg", ".svg"),
        (serde_json::json!({ "contours_geojson": "c.txt" }), "outputs.contours_geojson", ".geojson"),
        (serde_json::json!({ "summary": "summary.txt" }), "outputs.summary", ".json"),
        (serde_json::json!({ "divide_tree": "tree.svg" }), "outputs.divide_tree", ".geojson"),
        (serde_json::json!({ "heightfield": ["t.png"], "preview": "t.png" }), "outputs", "named by two outputs"),
        // Nothing lands outside the output folder.
        (serde_json::json!({ "heightfield": ["ok.tif", "../up.tif"] }), "outputs.heightfield[1]", "inside the output"),
        (serde_json::json!({ "preview": "/tmp/relief-escape.png" }), "outputs.preview", "without `..`"),
        (serde_json::json!({ "summary": "a/../../s.json" }), "outputs.summary", "inside the output"),
        (serde_json::json!({ "engines": [{ "for": "unity", "dir": "../unity" }] }), "outputs.engines[0].dir", ".."),
    ] {
        let mut v = base();
        v["outputs"] = outputs.clone();
        let scene = Scene::from_json(&v.to_string()).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let err = run(&scene, &root(), dir.path(), &mut ()).unwrap_err();
        assert_eq!(err.scene_path(), Some(path), "{outputs}: {err}");
        assert!(err.to_string().contains(says), "{outputs}: {err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing is written");
    }
    // Upper-case extensions and GeoJSON as .json are fine.
    let mut v = base();
    v["outputs"] = serde_json::json!({ "preview": "P.PNG", "contours_geojson": "maps/c.json", "summary": null });
    assert!(relief::pipeline::check_outputs(&Scene::from_json(&v.to_string()).unwrap().outputs).is_ok());
}

/// A run into a folder an earlier run wrote removes the earlier run's files it does not write
/// again (the earlier summary lists them), and nothing else.
#[test]
fn a_run_replaces_the_files_of_the_run_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::from_json(&base().to_string()).unwrap();
    run(&scene, &root(), dir.path(), &mut ()).unwrap();
    std::fs::write(dir.path().join("mine.txt"), "kept").unwrap();
    let mut fewer = scene.clone();
    fewer.outputs.heightfield = vec!["t.tif".into()];
    fewer.outputs.contours_svg = None;
    let (_, written) = run(&fewer, &root(), dir.path(), &mut ()).unwrap();
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["contours.geojson", "mine.txt", "preview.png", "summary.json", "t.tif"]);
    assert_eq!(written.len(), 4);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["files"], serde_json::json!(["t.tif", "contours.geojson", "preview.png", "summary.json"]));
    // A summary naming files outside the folder never makes a run remove them.
    let outside = dir.path().join("../outside-relief-test.txt");
    std::fs::write(&outside, "x").unwrap();
    let tampered = serde_json::json!({ "files": ["../outside-relief-test.txt", "/etc/hostname"] });
    std::fs::write(dir.path().join("summary.json"), tampered.to_string()).unwrap();
    run(&fewer, &root(), dir.path(), &mut ()).unwrap();
    assert!(outside.is_file());
    std::fs::remove_file(outside).unwrap();
}

/// The names in `dir`, sorted, hidden ones included.
fn names_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// Outputs are staged and replace the earlier set only once all are written: a run that fails
/// part-way (here its preview cannot be written, after its heightfields were) leaves the earlier
/// run's files as they were, and a staging folder a killed run left is removed by the next run.
#[test]
fn a_run_that_fails_while_writing_leaves_the_earlier_set_whole() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::from_json(&base().to_string()).unwrap();
    run(&scene, &root(), dir.path(), &mut ()).unwrap();
    let before: Vec<(String, Vec<u8>)> =
        names_in(dir.path()).into_iter().map(|n| (n.clone(), std::fs::read(dir.path().join(&n)).unwrap())).collect();
    let mut failing = scene.clone();
    failing.seed = scene.seed + 1;
    failing.outputs.heightfield = vec!["t.tif".into(), "terrain.exr".into(), "d.png/u.tif".into()];
    failing.outputs.preview = Some("d.png".into());
    run(&failing, &root(), dir.path(), &mut ()).unwrap_err();
    let after: Vec<(String, Vec<u8>)> =
        names_in(dir.path()).into_iter().map(|n| (n.clone(), std::fs::read(dir.path().join(&n)).unwrap())).collect();
    assert!(before == after, "the earlier set changed: {:?}", names_in(dir.path()));
    // A killed run's staging folder: its process (beyond Linux's largest id) is gone.
    let abandoned = dir.path().join(format!(".relief-staging.{}.x1y2z3", (1u32 << 22) + 3));
    std::fs::create_dir_all(abandoned.join("engines")).unwrap();
    std::fs::write(abandoned.join("terrain.exr"), b"partial").unwrap();
    run(&scene, &root(), dir.path(), &mut ()).unwrap();
    if std::path::Path::new("/proc/self").exists() {
        assert!(!abandoned.exists(), "a killed run's staging folder stays");
    }
    assert!(names_in(dir.path()).iter().all(|n| !n.starts_with(".relief-staging.") || n.contains("x1y2z3")));
}

#[test]
fn a_fixed_vertical_range_too_narrow_for_the_terrain_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::from_json(&base().to_string()).unwrap();
    scene.outputs.heightfield = vec!["t.exr".into(), "t.r16".into()];
    scene.outputs.range = Some([0.0, 1.0]);
    let err = run(&scene, &root(), dir.path(), &mut ()).unwrap_err();
    assert_eq!(err.scene_path(), Some("outputs.range"), "{err}");
    assert!(err.to_string().contains("widen the range"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    // Without a quantised output the range has nothing to scale and is no obstacle.
    scene.outputs.heightfield = vec!["t.exr".into()];
    run(&scene, &root(), dir.path(), &mut ()).unwrap();
    // A wide enough range is written into the sidecar, whatever the terrain spans.
    scene.outputs.heightfield = vec!["t.r16".into()];
    scene.outputs.range = Some([-5000.0, 9000.0]);
    run(&scene, &root(), dir.path(), &mut ()).unwrap();
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("t.r16.json")).unwrap()).unwrap();
    assert_eq!((sidecar["min"].as_f64(), sidecar["max"].as_f64()), (Some(-5000.0), Some(9000.0)));
}

/// A coast at 0 m, a range at 600 m and a summit at 1200 m, with the histogram `histogram`
/// (left out when `None`).
fn stepped(histogram: Option<serde_json::Value>) -> Scene {
    let square = |a: f64, b: f64, c: f64, d: f64| serde_json::json!({ "exterior": [[a, b], [c, b], [c, d], [a, d]] });
    let mut generator = serde_json::json!({
        "regions": [
            { "polygon": square(0.0, 0.0, 8000.0, 6000.0), "height": 0 },
            { "polygon": square(2000.0, 1500.0, 6000.0, 4500.0), "height": 600 },
            { "polygon": square(3500.0, 2500.0, 4500.0, 3500.0), "height": 1200 }
        ],
        "particles": 6000
    });
    if let Some(h) = histogram {
        generator["histogram"] = h;
    }
    let scene = serde_json::json!({
        "version": 1, "seed": 3, "generator": { "contours": generator },
        "reconstruction": { "resolution": [120, 90] }
    });
    Scene::from_json(&scene.to_string()).unwrap()
}

#[test]
fn region_heights_alone_give_a_histogram_that_fits_them() {
    let terrain = generate(&stepped(None), &root(), &mut ()).unwrap();
    let fit = terrain.summary.histogram_match.as_ref().unwrap();
    assert!(fit.nodes < 1e-3, "nodes KS {}", fit.nodes);
    assert!(terrain.summary.warnings.is_empty(), "{:?}", terrain.summary.warnings);
    // One bin per slice between given heights, the top one height step above the last, each
    // weighted by its levels' share of the nodes.
    let relief::contours::HistogramSpec::Bins { edges, weights } = terrain.histogram.spec() else {
        panic!("{:?}", terrain.histogram.spec())
    };
    assert_eq!(edges, &[0.0, 600.0, 1200.0, 1800.0]);
    let graph = terrain.summary.graph.as_ref().unwrap();
    assert_eq!(weights.iter().sum::<f64>(), graph.inside as f64);
    // The range covers half the coast's square, the summit 1/48 of it.
    let share = |k: usize| weights[k] / graph.inside as f64;
    assert!((share(0) - 0.75).abs() < 0.03 && (share(2) - 1.0 / 48.0).abs() < 0.01, "{weights:?}");
    // Without heights inside the coastline there is nothing to derive a histogram from.
    let mut bare = stepped(None);
    let relief::scene::Generator::Contours(g) = &mut bare.generator else { unreachable!() };
    g.regions.iter_mut().skip(1).for_each(|r| r.height = None);
    let err = generate(&bare, &root(), &mut ()).unwrap_err();
    assert_eq!(err.scene_path(), Some("generator.contours.histogram"), "{err}");
    assert!(err.to_string().contains("give a histogram, or heights on the coastline"), "{err}");
}

#[test]
fn a_histogram_at_odds_with_region_heights_is_warned_about_with_one_that_fits() {
    let uniform = serde_json::json!({ "uniform": { "min": 0, "max": 2000 } });
    let terrain = generate(&stepped(Some(uniform)), &root(), &mut ()).unwrap();
    assert!(terrain.summary.histogram_match.as_ref().unwrap().nodes > 0.3);
    let [warning] = terrain.summary.warnings.as_slice() else { panic!("{:?}", terrain.summary.warnings) };
    assert!(warning.contains("the 600 m contour encloses 25 % of the land where the histogram puts 70 %"), "{warning}");
    // The histogram it suggests, used as it is, fits: no warning then.
    let start = warning.find("{ \"bins\"").unwrap();
    let end = start + warning[start..].find("] } }").unwrap() + 5;
    let suggested: serde_json::Value = serde_json::from_str(&warning[start..end]).unwrap();
    assert_eq!(suggested["bins"]["edges"], serde_json::json!([0, 600, 1200, 2000]));
    let weights: Vec<f64> = serde_json::from_value(suggested["bins"]["weights"].clone()).unwrap();
    assert!((weights.iter().sum::<f64>() - 100.0).abs() < 0.05 && (weights[0] - 75.0).abs() < 1.0, "{weights:?}");
    let terrain = generate(&stepped(Some(suggested)), &root(), &mut ()).unwrap();
    assert!(terrain.summary.warnings.is_empty(), "{:?}", terrain.summary.warnings);
    assert!(terrain.summary.histogram_match.as_ref().unwrap().nodes < 0.02);
}

#[test]
fn the_suggested_histogram_keeps_the_shape_of_the_one_given() {
    let bins = serde_json::json!({ "bins": { "edges": [0, 300, 900, 2000], "weights": [4, 2, 1] } });
    let terrain = generate(&stepped(Some(bins)), &root(), &mut ()).unwrap();
    let [warning] = terrain.summary.warnings.as_slice() else { panic!("{:?}", terrain.summary.warnings) };
    let start = warning.find("{ \"bins\"").unwrap();
    let end = start + warning[start..].find("] } }").unwrap() + 5;
    let suggested: serde_json::Value = serde_json::from_str(&warning[start..end]).unwrap();
    // The given bins split at the region heights.
    assert_eq!(suggested["bins"]["edges"], serde_json::json!([0, 300, 600, 900, 1200, 2000]));
    let w: Vec<f64> = serde_json::from_value(suggested["bins"]["weights"].clone()).unwrap();
    // Within a slice the bins keep their masses' ratio: 4/7 on [0, 300] against 1/7 on [300, 600]
    // (half of the [300, 900] bin), 1/7 on [600, 900] against 1/11 · 3/7 on [900, 1200].
    assert!((w[0] / w[1] - 4.0).abs() < 0.02, "{w:?}");
    assert!((w[2] / w[3] - 11.0 / 3.0).abs() < 0.05, "{w:?}");
    // And the slices their share of the land: 3/4 below 600 m.
    assert!((w[0] + w[1] - 75.0).abs() < 1.0, "{w:?}");
}

/// The scene's `inputs` block says what its files do not, as the command line's read flags do:
/// a plain 8-bit image used as the histogram DEM spans 0..1 alone, and the z range it is given.
#[test]
fn scene_inputs_say_what_plain_heightmaps_do_not() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root().join("fixtures/images/gray.bmp"), dir.path().join("h.bmp")).unwrap();
    let mut v = base();
    v["generator"]["contours"]["histogram"] = serde_json::json!({ "dem": "h.bmp" });
    // The outer region's height 0 lies outside a 0.25..0.84 histogram: let the histogram place it.
    v["generator"]["contours"]["regions"][0].as_object_mut().unwrap().remove("height");
    let highest = |v: &serde_json::Value| {
        let scene = Scene::from_json(&v.to_string()).unwrap();
        let terrain = generate(&scene, dir.path(), &mut ()).unwrap();
        terrain.heightfield.min_max().unwrap().1
    };
    let plain = highest(&v);
    assert!(plain <= 1.0, "codes read as 0..1: {plain}");
    v["inputs"] = serde_json::json!({ "z_range": [0, 1000], "crs": { "epsg": 32617 } });
    let scaled = highest(&v);
    assert!(scaled > 500.0, "codes read as 0..1000: {scaled}");
    let scene = Scene::from_json(&v.to_string()).unwrap();
    assert_eq!(Scene::from_json(&scene.to_json()).unwrap(), scene, "inputs round trip");
    v["inputs"] = serde_json::json!({ "z_ragne": [0, 1] });
    assert!(Scene::from_json(&v.to_string()).is_err(), "unknown input options are refused");
}
