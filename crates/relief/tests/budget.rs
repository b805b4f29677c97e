//! Resource budgets: every cap refuses a scene over it with [`ReliefError::OverBudget`] (or the
//! reader's typed `TooLarge`) naming the JSON path, before the work that would allocate; the
//! default budget refuses requests that would otherwise exhaust memory.

use std::path::{Path, PathBuf};
use std::time::Duration;

use relief::io::IoErrorKind;
use relief::pipeline::{Progress, generate_with};
use relief::{Budget, ReliefError, Scene};
use serde_json::{Value, json};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scenes() -> PathBuf {
    root().join("fixtures/scenes")
}

struct Quiet;
impl Progress for Quiet {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: Duration) {}
}

/// The fixture scene `name` as JSON, to be edited.
fn fixture(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(scenes().join(name)).unwrap()).unwrap()
}

fn scene(v: &Value) -> Scene {
    Scene::from_json(&v.to_string()).unwrap()
}

/// Generates `v` under `budget`, expecting a failure; returns it.
#[track_caller]
fn refused(v: &Value, budget: Budget) -> ReliefError {
    match generate_with(&scene(v), &scenes(), &budget, &mut Quiet) {
        Ok(_) => panic!("generated a scene over its budget"),
        Err(e) => e,
    }
}

#[track_caller]
fn assert_over(e: &ReliefError, want_what: &str, want_path: &str, want_requested: u64) {
    match e {
        ReliefError::OverBudget { path, what, requested, .. } => {
            assert_eq!((path.as_str(), *what, *requested), (want_path, want_what, want_requested), "{e}");
            assert!(e.to_string().contains(&format!("--max-{want_what}")), "{e}");
        }
        other => panic!("expected OverBudget, got {other:?}"),
    }
}

#[test]
fn raster_cells_are_capped() {
    let mut v = fixture("mesa.json");
    v["reconstruction"]["resolution"] = json!([2000, 1500]);
    let e = refused(&v, Budget::default().with_max_cells(1_000_000));
    assert_over(&e, "cells", "reconstruction.resolution", 3_000_000);
    // The default budget allows it (the check alone; generating would take a while).
    assert!(Budget::default().check(&scene(&v)).is_ok());
}

#[test]
fn input_images_over_the_cell_cap_are_refused_by_their_header() {
    let mut v = fixture("range-label.json");
    v["reconstruction"]["resolution"] = json!([8, 8]);
    let e = refused(&v, Budget::default().with_max_cells(100));
    match &e {
        ReliefError::Scene { path, source } => {
            let message = source.to_string();
            assert_eq!(path, "generator.contours.label_image.path", "{e}");
            assert!(message.contains("100"), "{message}");
        }
        other => panic!("expected a scene error at the label image, got {other:?}"),
    }
    // The same read under the default budget succeeds; it was the cap that refused it.
    let image = relief::io::read_with(
        scenes().join("inputs/mask_lambda.png"),
        &relief::io::ReadOptions::default().with_limits(relief::io::Limits::default().with_max_cells(100)),
    );
    assert!(matches!(image.map_err(relief::io::IoError::into_kind), Err(IoErrorKind::TooLarge { limit: 100, .. })));
}

#[test]
fn particles_are_capped_whether_counted_or_from_a_radius() {
    let mut v = fixture("mesa.json");
    v["generator"]["contours"]["particles"] = json!(20_000);
    let e = refused(&v, Budget::default().with_max_particles(5_000));
    assert_over(&e, "particles", "generator.contours.particles", 20_000);

    // A radius: the growth graph estimates the count from Ω's area and refuses before sampling.
    let obj = v["generator"]["contours"].as_object_mut().unwrap();
    obj.remove("particles");
    obj.insert("radius".into(), json!(1.0));
    let e = refused(&v, Budget::default().with_max_particles(5_000));
    match &e {
        ReliefError::Scene { path, source } => {
            let message = source.to_string();
            assert_eq!(path, "generator.contours.radius");
            assert!(message.contains("5000"), "{message}");
        }
        other => panic!("expected a scene error at the radius, got {other:?}"),
    }
}

#[test]
fn gaussian_primitives_are_capped() {
    let v = fixture("gaussian-massif.json");
    let listed = v["generator"]["gaussian"]["source"]["primitives"].as_array().unwrap().len() as u64;
    assert!(listed > 2);
    let e = refused(&v, Budget::default().with_max_primitives(2));
    assert_over(&e, "primitives", "generator.gaussian.source.primitives", listed);

    // A fit from a DEM: its primitive count and its working grid.
    let mut v = fixture("gaussian-jacksboro.json");
    let source = &mut v["generator"]["gaussian"]["source"];
    source["primitives"] = json!(5000);
    let e = refused(&v, Budget::default().with_max_primitives(1000));
    assert_over(&e, "primitives", "generator.gaussian.source.primitives", 5000);
    v["generator"]["gaussian"]["source"]["primitives"] = json!(100);
    v["generator"]["gaussian"]["source"]["resolution"] = json!(4096);
    let e = refused(&v, Budget::default().with_max_cells(1 << 22));
    assert_over(&e, "cells", "generator.gaussian.source.resolution", 4096 * 4096);
}

#[test]
fn divide_tree_peaks_are_capped_asked_for_or_from_the_descriptor() {
    let mut v = fixture("orometry-jacksboro.json");
    v["generator"]["orometry"]["tree"] = json!({ "peaks": 5000 });
    let e = refused(&v, Budget::default().with_max_peaks(1000));
    assert_over(&e, "peaks", "generator.orometry.tree.peaks", 5000);

    // Without a count, the descriptor's density × the domain's area decides, checked before the
    // tree is generated.
    let v = fixture("orometry-jacksboro.json");
    assert!(v["generator"]["orometry"]["tree"].get("peaks").is_none_or(Value::is_null));
    let e = refused(&v, Budget::default().with_max_peaks(3));
    match &e {
        ReliefError::OverBudget { what: "peaks", path, requested, .. } => {
            assert_eq!(path, "generator.orometry.tree.peaks");
            assert!(*requested > 3);
        }
        other => panic!("expected OverBudget for peaks, got {other:?}"),
    }
}

#[test]
fn the_orometric_mesh_counts_as_cells() {
    // λ = 1 m over the fixture's ~30 km domain: a label raster of billions of cells at λ/2.
    let mut v = fixture("orometry-jacksboro.json");
    v["generator"]["orometry"]["terrain"] = json!({ "lambda_m": 1.0 });
    match &refused(&v, Budget::default()) {
        ReliefError::OverBudget { path, what: "cells", requested, .. } => {
            assert_eq!(path, "generator.orometry.terrain.lambda_m");
            assert!(*requested > 1 << 28, "{requested}");
        }
        other => panic!("expected OverBudget for cells, got {other:?}"),
    }
}

#[test]
fn the_default_budget_refuses_requests_that_would_exhaust_memory() {
    // Each would allocate terabytes if attempted; each fails at once instead.
    let mut v = fixture("mesa.json");
    v["reconstruction"]["resolution"] = json!([32_768, 16_384]);
    assert_over(&refused(&v, Budget::default()), "cells", "reconstruction.resolution", 1 << 29);
    let mut v = fixture("mesa.json");
    v["generator"]["contours"]["particles"] = json!(1u64 << 40);
    assert_over(&refused(&v, Budget::default()), "particles", "generator.contours.particles", 1 << 40);
    let mut v = fixture("orometry-jacksboro.json");
    v["generator"]["orometry"]["tree"] = json!({ "peaks": 1u64 << 33 });
    assert_over(&refused(&v, Budget::default()), "peaks", "generator.orometry.tree.peaks", 1 << 33);
}

/// The memory estimate (output cells × the generator's measured bytes a cell) is refused before
/// anything is generated, at the resolution's path; a raster read is capped at 32 bytes a cell.
#[test]
fn the_memory_estimate_is_refused_before_generating() {
    for (name, per_cell) in [
        ("mesa.json", 80),
        ("mountain.json", 96),
        ("craggy-island.json", 72),
        ("gaussian-massif.json", 64),
        ("orometry-jacksboro.json", 56),
    ] {
        let mut v = fixture(name);
        v["reconstruction"]["resolution"] = json!([4096, 2048]);
        let estimate = 4096 * 2048 * per_cell;
        assert_eq!(relief::budget::bytes_per_cell(&scene(&v).generator), per_cell, "{name}");
        let e = refused(&v, Budget::default().with_max_bytes(estimate - 1));
        assert_over(&e, "bytes", "reconstruction.resolution", estimate);
        assert!(Budget::default().with_max_bytes(estimate).check(&scene(&v)).is_ok(), "{name}: at the cap");
    }
    // The label image of this scene (a raster read) over what 32 bytes a cell allows.
    let mut v = fixture("range-label.json");
    v["reconstruction"]["resolution"] = json!([10, 10]);
    let budget = Budget::default().with_max_bytes(32 * 1000);
    assert_eq!(budget.max_read_cells(), 1000);
    let e = refused(&v, budget);
    assert!(e.to_string().contains("limit of 1000"), "{e}");
    assert!(generate_with(&scene(&v), &scenes(), &Budget::default(), &mut Quiet).is_ok());
    // For this machine: half its memory, where Linux tells it.
    assert_eq!(relief::budget::physical_memory().is_some(), cfg!(target_os = "linux"));
    if let Some(total) = relief::budget::physical_memory() {
        assert_eq!(Budget::for_this_machine().max_bytes, total / 2);
        assert!(total > 1 << 20, "{total} bytes of memory");
    }
}

#[test]
fn primitives_added_by_the_tools_are_capped() {
    // The listed source fits the cap exactly; the stamp that copies part of it does not.
    let v = fixture("gaussian-massif.json");
    let listed = v["generator"]["gaussian"]["source"]["primitives"].as_array().unwrap().len() as u64;
    match &refused(&v, Budget::default().with_max_primitives(listed)) {
        ReliefError::OverBudget { path, what: "primitives", requested, limit } => {
            assert_eq!(path, "generator.gaussian.operations[0]");
            assert!(*requested > listed && *limit == listed, "{requested} {limit}");
        }
        other => panic!("expected OverBudget for primitives, got {other:?}"),
    }

    // A paste is refused before the landform is placed: source + landform over the cap.
    let atlas: Value =
        serde_json::from_str(&std::fs::read_to_string(scenes().join("inputs/gaussian-atlas.json")).unwrap()).unwrap();
    let volcano = atlas["landforms"].as_array().unwrap().iter().find(|l| l["name"] == "volcano").unwrap();
    let landform = volcano["primitives"].as_array().unwrap().len() as u64;
    let mut v = fixture("gaussian-massif.json");
    let ops = v["generator"]["gaussian"]["operations"].as_array_mut().unwrap();
    ops.retain(|op| op["op"] == "paste");
    assert_eq!(ops.len(), 1);
    let e = refused(&v, Budget::default().with_max_primitives(listed + landform - 1));
    assert_over(&e, "primitives", "generator.gaussian.operations[0].landform", listed + landform);
    // One more primitive of budget and the same scene generates.
    let budget = Budget::default().with_max_primitives(listed + landform);
    assert!(generate_with(&scene(&v), &scenes(), &budget, &mut Quiet).is_ok());
}

#[test]
fn inputs_that_are_not_regular_files_fail_at_once() {
    // A scene naming a device (or a FIFO) would otherwise read forever; a directory is no scene.
    if cfg!(unix) {
        let mut v = fixture("range-label.json");
        v["generator"]["contours"]["label_image"]["path"] = json!("/dev/zero");
        let e = refused(&v, Budget::default());
        assert!(e.to_string().contains("not a regular file"), "{e}");
        let mut v = fixture("gaussian-massif.json");
        v["generator"]["gaussian"]["operations"][4]["atlas"] = json!("/dev/zero");
        let e = refused(&v, Budget::default());
        assert!(e.to_string().contains("not a regular file") && e.to_string().contains("operations[4]"), "{e}");
    }
    let e = relief::pipeline::load_scene(scenes()).unwrap_err();
    assert!(matches!(&e, ReliefError::File { .. }) && e.to_string().contains("not a regular file"), "{e}");
}

#[test]
fn source_dems_are_read_under_the_cell_cap() {
    // The orometry and Gaussian fixtures read the same 403 × 344 DEM: under a cap of 100 000 cells
    // it is refused by its header, naming the scene value that points at it.
    for (name, at) in [
        ("orometry-jacksboro.json", "generator.orometry.source"),
        ("gaussian-jacksboro.json", "generator.gaussian.source"),
    ] {
        let mut v = fixture(name);
        v["reconstruction"]["resolution"] = json!([8, 8]);
        if name.starts_with("gaussian") {
            v["generator"]["gaussian"]["source"]["resolution"] = json!(16);
        }
        match &refused(&v, Budget::default().with_max_cells(100_000)) {
            ReliefError::Scene { path, source } => {
                let message = source.to_string();
                assert!(path.starts_with(at), "{name}: {path}");
                assert!(message.contains("138632") && message.contains("100000"), "{name}: {message}");
            }
            other => panic!("{name}: expected a scene error at the source, got {other:?}"),
        }
        // The same scene generates under a cap the DEM fits.
        let budget = Budget::default().with_max_cells(138_632);
        assert!(generate_with(&scene(&v), &scenes(), &budget, &mut Quiet).is_ok(), "{name}");
    }
}
