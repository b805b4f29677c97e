//! Orometry through the facade: the `orometry` scene kind (pins, edits, drainage, errors named by
//! JSON path), divide tree GeoJSON and peak CSV exports of a real DEM.

use std::path::{Path, PathBuf};

use relief::orometry::{AnalysisOptions, Descriptor, DivideTree};
use relief::pipeline::{Progress, generate, run};
use relief::scene::{Generator, Scene};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

struct Quiet;
impl Progress for Quiet {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
}

fn fixture() -> (Scene, PathBuf) {
    let path = root().join("fixtures/scenes/orometry-jacksboro.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    (scene, path.parent().unwrap().to_owned())
}

/// Every sample of a synthesized terrain is filled at any resolution: at 256² over 24 km the
/// last column's `x / cell` rounds to 254.99…, which left it empty (NaN) and failed the run.
#[test]
fn every_resolution_fills_every_sample() {
    let (mut scene, base) = fixture();
    for n in [255, 256, 257] {
        scene.reconstruction.resolution = [n, n];
        let terrain = generate(&scene, &base, &mut Quiet).unwrap_or_else(|e| panic!("{n}: {e}"));
        assert_eq!(terrain.heightfield.no_data_count(), 0, "{n}");
    }
}

#[test]
fn orometry_scene_keeps_pins_applies_edits_and_drains() {
    let (scene, base) = fixture();
    let out = tempfile::tempdir().unwrap();
    let (terrain, written) = run(&scene, &base, out.path(), &mut Quiet).unwrap();
    let summary = terrain.summary.orometry.as_ref().unwrap();
    assert_eq!(summary.peaks, summary.tree.peaks.len());
    assert_eq!(summary.saddles + 1, summary.peaks, "one tree after inserting a peak");
    // The pinned summit and the inserted peak are in the tree and on the grid at their heights.
    let hf = &terrain.heightfield;
    for (x, y, h) in [(12_000.0, 12_000.0, 1150.0), (2000.0, 2000.0, 700.0)] {
        let p = glam::DVec2::new(x, y);
        assert!(summary.tree.peaks.iter().any(|q| q.position == p && q.elevation == h), "({x}, {y})");
        let (i, j) = hf.grid().nearest_sample(p).unwrap();
        assert!((f64::from(hf.value(i, j)) - h).abs() < 1e-3, "({x}, {y}): {}", hf.value(i, j));
    }
    assert_eq!(terrain.summary.drainage.closed_basins, 0);
    // The divide tree file holds every peak, saddle and ridge.
    let geojson = out.path().join("divide_tree.geojson");
    assert!(written.contains(&geojson));
    let value: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(geojson).unwrap()).unwrap();
    let features = value["features"].as_array().unwrap();
    assert_eq!(features.len(), summary.peaks + 2 * summary.saddles);
    // Same scene, same bytes.
    let again = generate(&scene, &base, &mut Quiet).unwrap();
    assert_eq!(again.heightfield.samples(), terrain.heightfield.samples());
}

#[test]
fn orometry_scene_errors_name_their_json_path() {
    let (scene, base) = fixture();
    let edit = |text: &str| {
        let mut s = scene.clone();
        let Generator::Orometry(g) = &mut s.generator else { panic!("an orometry fixture") };
        g.edits = serde_json::from_str(text).unwrap();
        generate(&s, &base, &mut Quiet).unwrap_err().to_string()
    };
    let e = edit(r#"[{"op": "delete_peak", "peak": 100000}]"#);
    assert!(e.contains("generator.orometry.edits[0]"), "{e}");
    let e = edit(r#"[{"op": "move_saddle", "saddle": 0, "position": [10, 10], "elevation": 99999}]"#);
    assert!(e.contains("generator.orometry.edits[0]") && e.contains("above"), "{e}");
    let mut s = scene.clone();
    s.domain = None;
    assert!(generate(&s, &base, &mut Quiet).unwrap_err().to_string().contains("domain"));
    let mut s = scene.clone();
    let Generator::Orometry(g) = &mut s.generator else { unreachable!() };
    g.peak_density = Some(PathBuf::from("inputs/missing.png"));
    assert!(generate(&s, &base, &mut Quiet).unwrap_err().to_string().contains("generator.orometry.peak_density"));
}

#[test]
fn a_real_dem_exports_its_divide_tree_and_peaks() {
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    let (oro, descriptor) =
        Descriptor::of(&dem, &AnalysisOptions { min_prominence: 30.0, ..Default::default() }).unwrap();
    assert!(oro.peaks.len() > 20);
    assert_eq!(descriptor.peaks, oro.peaks.len());
    let csv = relief::export::peaks_csv(&oro, true);
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("id,lon,lat,elevation,prominence"));
    assert_eq!(lines.len(), oro.peaks.len() + 1);
    // Geographic coordinates: the fixture lies around 84° W, 36.5° N.
    let first: Vec<&str> = lines[1].split(',').collect();
    let (lon, lat): (f64, f64) = (first[1].parse().unwrap(), first[2].parse().unwrap());
    assert!((-85.0..-84.0).contains(&lon) && (36.0..37.0).contains(&lat), "{lon}, {lat}");
    let tree = DivideTree::from_orometry(&oro);
    let value: serde_json::Value =
        serde_json::from_str(&relief::export::divide_tree_geojson(&tree, Some(&oro), None)).unwrap();
    let features = value["features"].as_array().unwrap();
    let ridges = features.iter().filter(|f| f["properties"]["kind"] == "ridge").count();
    assert_eq!(ridges, oro.saddles.len());
    let top = features.iter().find(|f| f["properties"]["kind"] == "peak").unwrap();
    assert_eq!(top["properties"]["prominence"].as_f64(), Some(oro.peaks[0].prominence));
    assert!(value.get("crs").is_none(), "no CRS, no crs member");
    // GDAL's crs member: an EPSG URN, or CRS84 for WGS 84 (longitude first); none for bare WKT.
    let crs_name = |crs: &relief::heightfield::Crs| {
        let text = relief::export::divide_tree_geojson(&tree, None, Some(crs));
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["crs"]["properties"]["name"].as_str().map(str::to_owned)
    };
    let epsg = |c| relief::heightfield::Crs::from_epsg(c).unwrap();
    assert_eq!(crs_name(&epsg(4269)).as_deref(), Some("urn:ogc:def:crs:EPSG::4269"));
    assert_eq!(crs_name(&epsg(4326)).as_deref(), Some("urn:ogc:def:crs:OGC:1.3:CRS84"));
    let wkt_only = relief::heightfield::Crs::from_wkt(r#"PROJCS["local grid",UNIT["metre",1]]"#).unwrap();
    assert_eq!(crs_name(&wkt_only), None);
}

#[test]
fn a_synthesized_terrain_has_the_targets_orometry_within_the_papers_errors() {
    // §7: "maximum histogram error … about 8 % for isolation, between 2 and 3 % for prominence
    // and dominance", measured on the generated terrain, for a target taken from a real DEM.
    let path = root().join("fixtures/scenes/orometry-jacksboro-synthesis.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let terrain = generate(&scene, path.parent().unwrap(), &mut Quiet).unwrap();
    // §6.1's rivers climb from the map's edge towards the ridges (Flint's law, bounded under the
    // cols): no flat lowlands. Measured 0.4 % of the map within 1 m of its lowest sample; rivers
    // routed over a flank surface that levels out at the base left 13 %.
    let hf = &terrain.heightfield;
    let lowest = hf.samples().iter().copied().fold(f32::INFINITY, f32::min);
    let flat = hf.samples().iter().filter(|&&v| v < lowest + 1.0).count() as f64 / hf.samples().len() as f64;
    assert!(flat < 0.02, "{:.1} % of the map lies within 1 m of the base", 100.0 * flat);
    let summary = terrain.summary.orometry.unwrap();
    let t = summary.terrain.as_ref().unwrap();
    let error = |f: &str| t.max_bin_error(f).unwrap();
    println!("{} tree peaks, {} on the terrain; {:?}", summary.tree.peaks.len(), t.peaks, t.features);
    // Measured: 443 tree peaks, 443 on the terrain; 1.2, 1.2 and 3.1 %.
    assert!(error("prominence") <= 0.03 && error("dominance") <= 0.03, "{t:?}");
    assert!(error("isolation_distance") <= 0.08, "{t:?}");
    let n = summary.tree.peaks.len();
    assert!(t.peaks * 100 >= 97 * n && t.peaks * 100 <= 103 * n, "{} peaks for the tree's {n}", t.peaks);
    // Peak density: the target's, over the whole domain.
    assert!((t.density_per_km2 / t.target_density_per_km2 - 1.0).abs() < 0.05, "{t:?}");
}

#[test]
fn a_dems_own_divide_tree_becomes_a_terrain_with_the_papers_errors() {
    let path = root().join("fixtures/scenes/orometry-jacksboro-tree.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let base = path.parent().unwrap();
    let terrain = generate(&scene, base, &mut Quiet).unwrap();
    let summary = terrain.summary.orometry.as_ref().unwrap();
    // akirmse lists 184 peaks at least 30 m prominent on this DEM; the tree keeps them all, in
    // the domain, with their elevations.
    assert_eq!(summary.tree.peaks.len(), 184);
    let domain = scene.domain.unwrap();
    assert!(summary.tree.peaks.iter().all(|p| domain.contains(p.position)));
    assert_eq!(summary.tree.peaks.iter().map(|p| p.elevation).fold(0.0, f64::max), 1076.0);
    // The terrain built on it, analysed again, keeps the tree's prominence and dominance within
    // the errors the paper reports for its synthesis (§7: about 3 %); measured 0.5 and 1.0 %,
    // with 191 peaks for the 184. Isolation, measured 9.9 % (8.9–11.2 % with seeds 1–3; 9.4–11.3 %
    // when rivers were routed on a raster), is looser than the paper's 8 % here: the tree's ridges are straight where the DEM's wind, so a few low peaks sit nearer
    // higher ground than on the DEM, and 184 peaks are few (one peak is half a percent of a
    // bin). Generated trees, which the paper's 8 % is about, reach it (the next test).
    let t = summary.terrain.as_ref().unwrap();
    assert!(t.peaks * 100 >= 97 * t.target_peaks, "{t:?}");
    let error = |f: &str| t.max_bin_error(f).unwrap();
    assert!(error("prominence") <= 0.03 && error("dominance") <= 0.03, "{t:?}");
    assert!(error("isolation_distance") <= 0.11, "{t:?}");
    // The terrain is analysed as the target was, at its sea level too.
    let mut s = scene.clone();
    let Generator::Orometry(g) = &mut s.generator else { panic!("an orometry fixture") };
    let relief::scene::OrometrySource::Dem { sea_level, .. } = &mut g.source else { panic!("a DEM source") };
    *sea_level = Some(300.0);
    let t = generate(&s, base, &mut Quiet).unwrap().summary.orometry.unwrap().terrain.unwrap();
    assert_eq!((t.sea_level, t.min_prominence), (Some(300.0), 30.0));
    // Pinned peaks and control maps shape generated trees only.
    let mut s = scene.clone();
    let Generator::Orometry(g) = &mut s.generator else { panic!("an orometry fixture") };
    g.pinned.push(relief::orometry::TreePeak { position: glam::DVec2::splat(12_000.0), elevation: 1200.0 });
    let e = generate(&s, base, &mut Quiet).unwrap_err().to_string();
    assert!(e.contains("use_tree") && e.contains("pinned"), "{e}");
}

#[test]
fn a_type_map_gives_each_region_its_own_orometry() {
    // §7.2, Fig. 24: the dark part of the painted map takes the Jacksboro DEM's orometry, the
    // light part an edited descriptor twice as prominent and twice as high above the base.
    let path = root().join("fixtures/scenes/orometry-types.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let terrain = generate(&scene, path.parent().unwrap(), &mut Quiet).unwrap();
    let tree = &terrain.summary.orometry.as_ref().unwrap().tree;
    tree.validate().unwrap();
    assert_eq!(tree.saddles.len() + 1, tree.peaks.len(), "one tree over both types");
    // The painted map, stretched over the domain: light (≥ half its range) is the second type.
    let png = relief::io::read(root().join("fixtures/scenes/inputs/orometry-types.png")).unwrap();
    let domain = scene.domain.unwrap();
    let light = |p: glam::DVec2| {
        let t = (p - domain.min) / domain.size();
        let (i, j) = ((t.x * (png.nx() - 1) as f64).round() as usize, (t.y * (png.ny() - 1) as f64).round() as usize);
        png.value(i, j) >= 0.5
    };
    // Peaks above the DEM's highest (1076 m) come from the second type only, in the light part
    // (a cell of the map either side of its edge is read bilinearly when placing).
    let high: Vec<_> = tree.peaks.iter().filter(|p| p.elevation > 1076.0).collect();
    assert!(high.len() >= 10, "{} peaks above the DEM's top", high.len());
    assert!(high.iter().all(|p| light(p.position)), "a high peak outside the light part");
    let (dark, bright) = tree.peaks.iter().partition::<Vec<_>, _>(|p| !light(p.position));
    let mean = |v: &[&relief::orometry::TreePeak]| v.iter().map(|p| p.elevation).sum::<f64>() / v.len() as f64;
    assert!(mean(&bright) > mean(&dark) + 150.0, "{} against {}", mean(&bright), mean(&dark));
    // Peak counts follow each type's density over its area: the light part is 37.5 % of the
    // map, and the second type's density half the DEM's 0.192 per km².
    let km2 = domain.size().x * domain.size().y / 1e6;
    let expected = [0.625 * km2 * 0.1925, 0.375 * km2 * 0.0962];
    for (n, e) in [dark.len(), bright.len()].into_iter().zip(expected) {
        assert!((n as f64 / e - 1.0).abs() < 0.2, "{n} peaks for {e:.0}");
    }
}

#[test]
fn a_type_map_is_refused_with_a_real_tree_and_names_what_conflicts() {
    let path = root().join("fixtures/scenes/orometry-types.json");
    let text = std::fs::read_to_string(&path).unwrap();
    // The generator's source as a real tree: nothing can shape it.
    let with_tree = text.replace(r#""min_prominence": 30 }"#, r#""min_prominence": 30, "use_tree": true }"#);
    let scene = Scene::from_json(&with_tree).unwrap();
    let err = generate(&scene, path.parent().unwrap(), &mut Quiet).unwrap_err().to_string();
    assert!(err.contains("source.use_tree") && err.contains("types"), "{err}");
    // A further type's source as a real tree.
    let further = text.replace(
        r#"{ "kind": "descriptor", "path": "inputs/jacksboro-twice-as-prominent.json" }"#,
        r#"{ "kind": "dem", "path": "../dem/jacksboro.asc", "use_tree": true }"#,
    );
    let scene = Scene::from_json(&further).unwrap();
    let err = generate(&scene, path.parent().unwrap(), &mut Quiet).unwrap_err().to_string();
    assert!(err.contains("generator.orometry.types.sources[0]") && err.contains("use_tree"), "{err}");
}
