//! Contours as a scene's input: a real DEM's, closed along its border and regrown with the DEM's
//! histogram (the contours paper's Fig. 24, with its §6.5 comparison), and a previous run's
//! GeoJSON fed back in (the loop of Fig. 2).

use std::path::{Path, PathBuf};

use relief::pipeline::{generate, run};
use relief::scene::Scene;
use serde_json::json;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[allow(clippy::needless_pass_by_value, reason = "called with json! literals")]
fn scene(contours: serde_json::Value, histogram: Option<serde_json::Value>) -> Scene {
    let mut generator = json!({ "contours": contours, "particles": 20000 });
    if let Some(h) = histogram {
        generator["histogram"] = h;
    }
    let value = json!({
        "version": 1,
        "seed": 5,
        "generator": { "contours": generator },
        "reconstruction": { "resolution": [160, 140] }
    });
    Scene::from_json(&value.to_string()).unwrap()
}

#[test]
fn jacksboro_regrown_from_its_own_contours_matches_it() {
    let dem = "fixtures/dem/jacksboro.asc";
    let scene = scene(json!({ "dem": dem, "interval": 100 }), Some(json!({ "dem": dem })));
    let terrain = generate(&scene, &root(), &mut ()).unwrap();
    let input = terrain.summary.contour_input.as_ref().unwrap();
    assert_eq!(input.heights[1..], [300.0, 400.0, 500.0, 600.0, 700.0, 800.0, 900.0, 1000.0]);
    assert!(input.closed_at_border > 20, "{input:?}");
    assert!(input.regions > 50, "{input:?}");
    terrain.contours.check_invariants().unwrap();
    // The given contours are iso-contours of the result: a sample inside a region lies above it.
    // And the §6.5 comparison with the DEM: the elevation distributions match (the histogram is
    // the DEM's), the river networks have the same order.
    let c = terrain.summary.comparison.as_ref().unwrap();
    assert!(c.distance.elevation < 10.0, "{c:?}");
    assert!(c.distance.strahler.abs() <= 1, "{c:?}");
    assert!(c.mean_slope_deg[1] > 5.0 && c.mean_slope_deg[1] < 30.0, "slopes in metres: {c:?}");
    assert!(c.mean_slope_deg[0] > 0.4 * c.mean_slope_deg[1], "{c:?}");
    assert!(c.peaks.iter().all(|p| p.peaks[1] > 0), "{c:?}");
}

#[test]
fn a_previous_runs_geojson_regrows_with_the_same_levels() {
    let dir = tempfile::tempdir().unwrap();
    let source = relief::pipeline::load_scene(root().join("fixtures/scenes/coastline-island.json")).unwrap();
    run(&source, &root().join("fixtures/scenes"), dir.path(), &mut ()).unwrap();
    let geojson = dir.path().join("contours.geojson");
    let again = scene(json!({ "geojson": geojson }), None);
    let terrain = generate(&again, dir.path(), &mut ()).unwrap();
    let input = terrain.summary.contour_input.as_ref().unwrap();
    assert_eq!(input.closed_at_border, 0, "a contour run writes closed rings");
    assert!(input.regions >= 5, "{input:?}");
    // Heights derive the histogram; the regrown contours include every input height.
    let heights: Vec<f64> = terrain.contours.levels().to_vec();
    for h in &input.heights {
        assert!(heights.iter().any(|l| (l - h).abs() < 1e-9), "{h} missing from {heights:?}");
    }
}

#[test]
fn gdal_style_lines_with_an_elev_property_are_closed_along_their_extent() {
    // Two lines of a tilted plane as gdal_contour writes them (`-a ELEV`), cut at the map's edge,
    // higher ground to their left, and a closed hilltop ring.
    let dir = tempfile::tempdir().unwrap();
    let line = |x: f64, elev: f64| {
        json!({ "type": "Feature", "properties": { "ELEV": elev },
                "geometry": { "type": "LineString", "coordinates": [[x, 1000.0], [x + 50.0, 500.0], [x, 0.0]] } })
    };
    let ring = json!({ "type": "Feature", "properties": { "ELEV": 300.0 },
        "geometry": { "type": "Polygon", "coordinates": [[[700.0, 400.0], [900.0, 400.0], [900.0, 600.0], [700.0, 600.0], [700.0, 400.0]]] } });
    let doc = json!({ "type": "FeatureCollection", "features": [line(200.0, 100.0), line(500.0, 200.0), ring] });
    std::fs::write(dir.path().join("lines.geojson"), doc.to_string()).unwrap();
    let terrain = generate(&scene(json!({ "geojson": "lines.geojson" }), None), dir.path(), &mut ()).unwrap();
    let input = terrain.summary.contour_input.as_ref().unwrap();
    assert_eq!((input.closed_at_border, input.regions), (2, 3), "{input:?}");
    let hf = &terrain.heightfield;
    let at = |x: f64, y: f64| f64::from(hf.sample_bilinear_clamped(glam::DVec2::new(x, y)).unwrap());
    // The lines' extent is the map: west of the 100 m line is outside the land, east of it
    // higher, the hilltop highest.
    assert!(at(210.0, 500.0) < 150.0 && at(400.0, 500.0) > 100.0 && at(400.0, 500.0) < 200.0, "west is lower");
    assert!(at(800.0, 500.0) > 300.0, "the hilltop");
    // Without the property the file is refused, naming what is missing.
    let err =
        generate(&scene(json!({ "geojson": "lines.geojson", "property": "height_m" }), None), dir.path(), &mut ())
            .unwrap_err();
    assert!(err.to_string().contains("height_m"), "{err}");
    // Both a DEM and a GeoJSON: refused.
    let err =
        generate(&scene(json!({ "geojson": "lines.geojson", "dem": "x.asc" }), None), dir.path(), &mut ()).unwrap_err();
    assert!(err.to_string().contains("not both"), "{err}");
}

/// A DEM that stores its sea as one flat elevation (a volcano island on 0 m): regrown from its
/// contours with its histogram, the sea stays sea (the coast runs just above it) and the land
/// keeps its share of the map, instead of the whole map regrowing as land.
#[test]
fn a_dems_flat_sea_stays_sea_when_regrown() {
    let dir = tempfile::tempdir().unwrap();
    let (nx, ny) = (120usize, 100usize);
    let cone = |i: usize, j: usize| {
        let d = ((i as f64 - 60.0).powi(2) + (j as f64 - 50.0).powi(2)).sqrt();
        (800.0 * (1.0 - d / 35.0)).max(0.0)
    };
    write_asc(&dir.path().join("volcano.asc"), nx, ny, cone);
    let dem_land = (0..nx * ny).filter(|k| cone(k % nx, k / nx) > 0.0).count() as f64 / (nx * ny) as f64;
    let mut volcano = scene(json!({ "dem": "volcano.asc", "interval": 100 }), Some(json!({ "dem": "volcano.asc" })));
    volcano.reconstruction.resolution = [nx, ny];
    let terrain = generate(&volcano, dir.path(), &mut ()).unwrap();
    let sea = terrain.sea_level.unwrap();
    let samples = terrain.heightfield.samples();
    let land = samples.iter().filter(|&&v| f64::from(v) > sea).count() as f64 / samples.len() as f64;
    assert!((land - dem_land).abs() < 0.05, "land is {land:.3} of the map, the DEM's {dem_land:.3}");
    // The histogram is the land's, not pulled down by the sea's zeros: the land's median
    // elevation is the DEM land's.
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let ours = median(samples.iter().map(|&v| f64::from(v)).filter(|&v| v > sea).collect());
    let dems = median((0..nx * ny).map(|k| cone(k % nx, k / nx)).filter(|&v| v > 0.0).collect());
    assert!((ours - dems).abs() < 0.15 * dems, "the land's median {ours:.1} m, the DEM land's {dems:.1} m");
    // The histogram checked on land is the land's, and no warning blames it.
    let fit = terrain.summary.histogram_match.as_ref().unwrap();
    assert!(fit.raster < 0.1, "{fit:?} {:?}", terrain.summary.warnings);
    assert!(terrain.summary.warnings.iter().all(|w| !w.contains("histogram")), "{:?}", terrain.summary.warnings);
    // The coast is the lowest land elevation (the cone's lowest samples, under 25 m), not the
    // sea's 0 m.
    let input = terrain.summary.contour_input.as_ref().unwrap();
    assert!(input.heights[0] > 0.0 && input.heights[0] < 25.0, "the coast at {} m", input.heights[0]);
    // The comparison reports how far the regrown land is from the DEM's, and both land shares.
    let c = terrain.summary.comparison.as_ref().unwrap();
    assert!((c.land_share[1] - dem_land).abs() < 0.01 && (c.land_share[0] - land).abs() < 0.01, "{c:?}");
    assert!(c.land_rmse_m > 1.0 && c.land_rmse_m < 20.0, "within a fifth of an interval of the cone (6.7 m): {c:?}");
    // Over the whole map the sea, right in both, brings the error down.
    assert!(c.rmse_m < c.land_rmse_m, "{c:?}");

    // An island of cliffs, its land 150 m and more above the sea: the contours start at the coast
    // and go up from the next multiple of the interval.
    let cliffs = |i: usize, j: usize| if cone(i, j) > 0.0 { 150.0 + cone(i, j) } else { 0.0 };
    write_asc(&dir.path().join("cliffs.asc"), nx, ny, cliffs);
    let mut cliff_scene = scene(json!({ "dem": "cliffs.asc", "interval": 100 }), Some(json!({ "dem": "cliffs.asc" })));
    cliff_scene.reconstruction.resolution = [nx, ny];
    let terrain = generate(&cliff_scene, dir.path(), &mut ()).unwrap();
    let heights = &terrain.summary.contour_input.as_ref().unwrap().heights;
    assert!(heights[0] > 150.0 && heights[0] < 175.0 && heights[1] == 200.0, "{heights:?}");
}

/// Writes an ASCII grid of `nx × ny` samples 30 m apart from `f(i, j)` (row 0 the southern).
fn write_asc(path: &Path, nx: usize, ny: usize, f: impl Fn(usize, usize) -> f64) {
    let mut asc = format!("ncols {nx}\nnrows {ny}\nxllcenter 0\nyllcenter 0\ncellsize 30\n");
    for j in (0..ny).rev() {
        let row: Vec<String> = (0..nx).map(|i| format!("{:.1}", f(i, j))).collect();
        asc.push_str(&row.join(" "));
        asc.push('\n');
    }
    std::fs::write(path, asc).unwrap();
}
