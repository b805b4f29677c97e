//! End to end: the real `relief` binary on the fixtures. Outputs exist and parse, the heightfield
//! follows the scene's histogram, the contours (read back from the GeoJSON) nest and never cross,
//! the same seed gives byte-identical files with one or two threads, and every failure is a
//! one-line error with the right exit code.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use glam::DVec2;
use relief::contours::{Contour, ContourSet, Histogram};
use relief::scene::{Generator, HistogramSource, Scene};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn relief() -> Command {
    let mut cmd = Command::cargo_bin("relief").unwrap();
    cmd.current_dir(root());
    cmd
}

/// Runs `relief args…`, expecting success; returns stdout.
#[track_caller]
fn ok(args: &[&str]) -> String {
    let out = relief().args(args).output().unwrap();
    assert!(out.status.success(), "relief {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// Runs `relief args…`, expecting exit code `code`; returns stderr.
#[track_caller]
fn fails(args: &[&str], code: i32) -> String {
    let out = relief().args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(code), "relief {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// The contours of a GeoJSON file, rebuilt into a [`ContourSet`] (which recomputes the nesting).
fn read_geojson(path: &Path) -> ContourSet {
    let value: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let features = value["features"].as_array().unwrap();
    let mut levels: Vec<f64> = features.iter().map(|f| f["properties"]["elevation"].as_f64().unwrap()).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    let contours = features
        .iter()
        .map(|f| {
            let height = f["properties"]["elevation"].as_f64().unwrap();
            let closed = f["properties"]["closed"].as_bool().unwrap();
            let mut points: Vec<DVec2> = f["geometry"]["coordinates"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| DVec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
                .collect();
            if closed {
                assert_eq!(points.first(), points.last(), "closed rings repeat their first point");
                points.pop();
            }
            let level = levels.iter().position(|&l| l == height).unwrap() as u32;
            Contour { level, height, points, closed }
        })
        .collect();
    ContourSet::new(levels, contours).unwrap()
}

fn scene_histogram(scene_path: &Path) -> Option<Histogram> {
    let scene = relief::pipeline::load_scene(scene_path).unwrap();
    let Generator::Contours(g) = &scene.generator else { return None };
    Some(match g.histogram.as_ref()? {
        HistogramSource::Histogram(h) => h.clone(),
        HistogramSource::Dem(p) => {
            let dem = relief::io::read(scene_path.parent().unwrap().join(p)).unwrap();
            Histogram::from_samples(dem.samples().iter().map(|&v| f64::from(v)).collect()).unwrap()
        }
    })
}

/// The checks every generated output directory passes (the histogram check for scenes that
/// prescribe one).
fn check_outputs(dir: &Path, histogram: Option<&Histogram>, depressions: bool) {
    for file in ["terrain.exr", "terrain.png", "contours.geojson", "contours.svg", "preview.png", "summary.json"] {
        assert!(dir.join(file).is_file(), "{} missing", dir.join(file).display());
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    // `null`: the terrain has no sea, and all of it is land.
    let sea_level = summary["heightfield"]["sea_level"].as_f64().unwrap_or(f64::NEG_INFINITY);
    // The heightfield follows the histogram on land.
    let dem = relief::io::read(dir.join("terrain.exr")).unwrap();
    let land: Vec<f64> = dem.samples().iter().map(|&v| f64::from(v)).filter(|&v| v >= sea_level).collect();
    if let Some(histogram) = histogram {
        let ks = histogram.ks_distance(&land);
        assert!(ks < 0.08, "{}: raster KS {ks}", dir.display());
    } else if summary["gaussian"].is_object() {
        assert!(summary["gaussian"]["primitives"].as_u64().unwrap() > 0);
    } else if summary["orometry"].is_object() {
        // The divide tree matches its target's prominence and dominance within a few percent.
        let o = &summary["orometry"];
        assert!(o["peaks"].as_u64().unwrap() > 0);
        assert_eq!(o["saddles"].as_u64().unwrap() + 1, o["peaks"].as_u64().unwrap());
        // With several terrain types the comparisons are against the first only (the type-map
        // test in the facade checks each region).
        if o["types"].as_u64().unwrap() == 1 {
            assert!(o["prominence_max_bin_error"].as_f64().unwrap() < 0.05, "{o}");
            assert!(o["dominance_max_bin_error"].as_f64().unwrap() < 0.05, "{o}");
            // The terrain analysed again: most of the tree's peaks survive as peaks of the raster,
            // and its histograms stay near the target's. (Regression bounds from the measured 87 of
            // 112 peaks and errors of 11, 10 and 23 %; the paper reaches 3, 3 and 8 %.)
            let t = &o["terrain"];
            assert!(t["peaks"].as_u64().unwrap() * 2 >= o["peaks"].as_u64().unwrap(), "{t}");
            assert_eq!(t["features"].as_array().unwrap().len(), 10, "{t}");
            let error = |name: &str| {
                let f = t["features"].as_array().unwrap().iter().find(|f| f[0] == name).unwrap();
                f[2].as_f64().unwrap()
            };
            assert!(error("prominence") < 0.2 && error("dominance") < 0.2 && error("isolation_distance") < 0.35, "{t}");
        }
    } else if summary["island"].is_object() {
        // Island: sea exactly 0, land above the sea level but in lakes (hollows dug below sea
        // level), which cover little of it.
        assert!(summary["island"]["area"].as_f64().unwrap() > 0.0);
        assert!(dem.samples().iter().all(|&v| v == 0.0 || f64::from(v) > sea_level || v < 0.0), "{}", dir.display());
        let lakes = dem.samples().iter().filter(|&&v| v < 0.0).count();
        assert!(lakes * 100 < dem.samples().len(), "{}: {lakes} samples in lakes", dir.display());
    } else {
        let report = &summary["diffusion"];
        assert_eq!(report["converged"], true, "{}: {report}", dir.display());
    }
    // The 16-bit PNG holds the same terrain, quantized.
    let png = relief::io::read(dir.join("terrain.png")).unwrap();
    let (lo, hi) = dem.min_max().unwrap();
    let step = f64::from(hi - lo) / 65535.0;
    let worst = png.samples().iter().zip(dem.samples()).map(|(a, b)| f64::from((a - b).abs())).fold(0.0, f64::max);
    assert!(worst <= step, "png differs by {worst} (step {step})");
    // The exported contours nest and never cross.
    let set = read_geojson(&dir.join("contours.geojson"));
    assert!(!set.is_empty());
    set.check_invariants().unwrap();
    if !depressions {
        assert_eq!(set.nests_by_level(), Ok(()), "{}", dir.display());
    }
    // The preview is a PNG of the raster's size.
    let preview = relief::io::read_gray_image(dir.join("preview.png"), &relief::io::ReadOptions::default()).unwrap();
    assert_eq!((preview.nx(), preview.ny()), (dem.nx(), dem.ny()));
}

#[test]
fn every_fixture_scene_generates_checked_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = root().join("fixtures/scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let out = tmp.path().join(path.file_stem().unwrap());
        let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
        // Contour scenes nest unless they have a depression; contours drawn from a diffused
        // terrain may enclose local minima, so only crossing is checked there.
        let (command, depressions) = match &scene.generator {
            // A DEM's contours may hold pits, which become depressions.
            Generator::Contours(g) => {
                let label_pits = g
                    .label_image
                    .as_ref()
                    .is_some_and(|l| l.depressions || l.levels.iter().flatten().any(|r| r.depression));
                ("generate", g.regions.iter().any(|r| r.depression) || g.contours.is_some() || label_pits)
            }
            Generator::Diffusion(_) => ("diffuse", true),
            // Hills and perturbations leave hollows (a crater, dents) on an island; sums of
            // Gaussians have hollows between primitives. Orometric terrain is filled (no closed
            // basins, checked in relief's tests), but its valley floors are ε-sloped flats at the
            // base level, so a contour drawn there need not sit inside one of the level below.
            // For all three only crossing is checked.
            Generator::Island(_) | Generator::Gaussian(_) | Generator::Orometry(_) => ("generate", true),
        };
        let stdout = ok(&[command, path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert!(stdout.contains("contours on"), "{stdout}");
        check_outputs(&out, scene_histogram(&path).as_ref(), depressions);
        count += 1;
    }
    assert!(count >= 14);
}

#[test]
fn demo_writes_its_outputs_and_says_where() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("demo");
    let stdout = ok(&["demo", "--out", out.to_str().unwrap()]);
    assert!(stdout.contains(&out.join("preview.png").display().to_string()), "{stdout}");
    let scene = Scene::demo();
    let Generator::Contours(g) = &scene.generator else { panic!("the demo is a contour scene") };
    let Some(HistogramSource::Histogram(h)) = &g.histogram else { panic!("the demo writes its histogram") };
    assert!(matches!(h.spec(), relief::contours::HistogramSpec::Bins { .. }), "the demo uses bins");
    check_outputs(&out, Some(h), true);
}

#[test]
fn same_seed_gives_byte_identical_outputs_with_one_or_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("fixtures/scenes/editing-session.json");
    let run = |threads: &str, seed: &str| {
        let out = tmp.path().join(format!("t{threads}-s{seed}"));
        ok(&[
            "generate",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--threads",
            threads,
            "--seed",
            seed,
        ]);
        out
    };
    let (one, two, other) = (run("1", "4"), run("2", "4"), run("2", "5"));
    for file in ["terrain.exr", "terrain.png", "contours.geojson", "contours.svg", "preview.png"] {
        let a = std::fs::read(one.join(file)).unwrap();
        assert!(a == std::fs::read(two.join(file)).unwrap(), "{file} differs between 1 and 2 threads");
        assert!(a != std::fs::read(other.join(file)).unwrap(), "{file} does not depend on the seed");
    }
    // The summaries agree on everything but the timings.
    let strip = |dir: &Path| {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        v.as_object_mut().unwrap().remove("timings_ms");
        v
    };
    assert_eq!(strip(&one), strip(&two));
    assert_eq!(strip(&one)["scene"]["seed"].as_u64(), Some(4), "--seed replaces the scene's seed");
}

#[test]
fn contours_of_a_dem_are_multiples_of_the_interval_and_nest() {
    let tmp = tempfile::tempdir().unwrap();
    let (geojson, svg) = (tmp.path().join("c.geojson"), tmp.path().join("c.svg"));
    let stdout = ok(&[
        "contours",
        "fixtures/dem/jacksboro.asc",
        "--interval",
        "100",
        "--geojson",
        geojson.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(stdout.contains("contours on 8 levels"), "{stdout}");
    let set = read_geojson(&geojson);
    assert_eq!(set.levels(), &[300.0, 400.0, 500.0, 600.0, 700.0, 800.0, 900.0, 1000.0]);
    set.check_invariants().unwrap();
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    // --levels picks evenly spaced levels.
    ok(&["--force", "contours", "fixtures/dem/jacksboro.asc", "--levels", "5", "--geojson", geojson.to_str().unwrap()]);
    assert_eq!(read_geojson(&geojson).levels().len(), 5);
}

#[test]
fn convert_info_and_preview_work_on_a_real_dem() {
    let tmp = tempfile::tempdir().unwrap();
    let exr = tmp.path().join("j.exr");
    ok(&["convert", "fixtures/dem/jacksboro.asc", exr.to_str().unwrap()]);
    let original = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    assert_eq!(relief::io::read(&exr).unwrap(), original, "asc -> exr is lossless");
    let info: serde_json::Value = serde_json::from_str(&ok(&["info", exr.to_str().unwrap(), "--json"])).unwrap();
    assert_eq!((info["nx"].as_u64(), info["ny"].as_u64()), (Some(403), Some(344)));
    assert_eq!(info["units"], "degrees");
    assert_eq!(info["min"].as_f64(), Some(f64::from(original.min_max().unwrap().0)));
    let text = ok(&["info", "fixtures/dem/jacksboro.asc"]);
    assert!(text.contains("403 x 344") && text.contains("no-data    0"), "{text}");
    let png = tmp.path().join("p.png");
    ok(&["preview", exr.to_str().unwrap(), "-o", png.to_str().unwrap(), "--contours", "100"]);
    let plain = tmp.path().join("q.png");
    ok(&["preview", exr.to_str().unwrap(), "-o", plain.to_str().unwrap(), "--max-size", "200"]);
    let read = |p: &Path| relief::io::read_gray_image(p, &relief::io::ReadOptions::default()).unwrap();
    assert_eq!((read(&png).nx(), read(&png).ny()), (403, 344));
    assert!(read(&plain).nx() <= 202);
}

#[test]
fn prominence_writes_peaks_and_a_divide_tree_of_neighbouring_peaks() {
    let tmp = tempfile::tempdir().unwrap();
    let (csv, tree) = (tmp.path().join("peaks.csv"), tmp.path().join("tree.geojson"));
    let dem = "fixtures/dem/jacksboro.asc";
    let args = ["prominence", dem, "--min-prominence", "30", "--json", "--peaks", csv.to_str().unwrap()];
    let report: serde_json::Value =
        serde_json::from_str(&ok(&[&args[..], &["--divide-tree", tree.to_str().unwrap()]].concat())).unwrap();
    // akirmse/mountains lists 184 peaks at least 30 m prominent on this DEM (fixtures/akirmse).
    let peaks = report["peaks"].as_array().unwrap();
    assert_eq!(peaks.len(), 184);
    assert_eq!(std::fs::read_to_string(&csv).unwrap().lines().count(), 185, "a header and a line per peak");
    // One ridge per saddle, drawn peak → saddle → peak between the saddle's two neighbours; one
    // of them is on the side of the peak whose key saddle it is.
    let geojson: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&tree).unwrap()).unwrap();
    let ridges: Vec<_> =
        geojson["features"].as_array().unwrap().iter().filter(|f| f["properties"]["kind"] == "ridge").collect();
    assert_eq!(ridges.len(), 183);
    // Drawn along the DEM's cells (3″ apart), not as straight jumps across valleys.
    let cell = 1.0 / 1200.0;
    let mut vertices = 0;
    for ridge in &ridges {
        let line = ridge["geometry"]["coordinates"].as_array().unwrap();
        vertices += line.len();
        for w in line.windows(2) {
            let d = |i: usize| (w[1][i].as_f64().unwrap() - w[0][i].as_f64().unwrap()).abs();
            assert!(d(0).max(d(1)) < 1.01 * cell, "a ridge jumps: {w:?}");
        }
    }
    assert!(vertices > 10 * ridges.len(), "{vertices} vertices");
    let saddles = report["saddles"].as_array().unwrap();
    let mut not_parent = 0;
    for (k, p) in peaks.iter().enumerate() {
        let Some(s) = p["key_saddle"].as_u64() else { continue };
        let ends = &saddles[s as usize]["peaks"];
        assert!(ends[0].as_u64().is_some() && ends[1] != ends[0], "peak {k}: {ends}");
        not_parent += usize::from(ends[1] != p["parent"]);
    }
    assert!(not_parent > 20, "ridges lead to neighbours, often not the prominence parent: {not_parent}");
    let text = ok(&["prominence", dem, "--min-prominence", "100", "--top", "3"]);
    assert!(text.contains("peaks at least 100 m prominent") && text.lines().count() == 4, "{text}");
}

#[test]
fn prominence_goes_through_akirmses_dvt_format_and_back() {
    let tmp = tempfile::tempdir().unwrap();
    let path = |name: &str| tmp.path().join(name).to_str().unwrap().to_owned();
    let dem = "fixtures/dem/jacksboro.asc";
    ok(&["prominence", dem, "--min-prominence", "30", "--divide-tree", &path("ours.dvt"), "--peaks", &path("p.csv")]);
    let ours = std::fs::read_to_string(path("ours.dvt")).unwrap();
    // On akirmse's canvas for this DEM, 184 peaks and 183 ridges.
    assert!(ours.lines().any(|l| l == "G,36.000000,-85.000000,1200,1200,37.000000,-84.000000"), "{ours}");
    assert_eq!(ours.lines().filter(|l| l.starts_with("P,")).count(), 184);
    assert_eq!(ours.lines().filter(|l| l.starts_with("N,") && !l.ends_with(",-1,-1")).count(), 183);
    // The CSV names both parents and the isolation limit point.
    let csv = std::fs::read_to_string(path("p.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for column in ["prominence_parent", "line_parent", "isolation_lon", "isolation_lat"] {
        assert!(header.contains(&column), "{header:?}");
    }
    // Read back, akirmse's tree and ours: prominences on the tree, tops measured from sea level.
    for tree in [path("ours.dvt"), "fixtures/akirmse/divide_tree.dvt".to_owned()] {
        let text =
            ok(&["prominence", &tree, "--min-prominence", "30", "--top", "1", "--peaks", &path("t.csv"), "--force"]);
        // The highest summit, 1076 m, counted from sea level as akirmse counts it.
        assert!(text.contains("1076.0 m  prominence   1076.0 m"), "{text}");
        let csv = std::fs::read_to_string(path("t.csv")).unwrap();
        assert!(csv.lines().count() >= 180, "{tree}: {}", csv.lines().count());
    }
    // Back to GeoJSON, and to .dvt again, unchanged.
    ok(&["prominence", &path("ours.dvt"), "--divide-tree", &path("again.dvt"), "--json"]);
    let again = std::fs::read_to_string(path("again.dvt")).unwrap();
    let body = |t: &str| t.lines().filter(|l| !l.starts_with('#')).map(str::to_owned).collect::<Vec<_>>();
    assert_eq!(body(&again), body(&ours));
    ok(&["prominence", &path("ours.dvt"), "--divide-tree", &path("t.geojson")]);
    // A grid the format cannot hold is refused before any work, naming the way out.
    let planar = path("planar.asc");
    std::fs::write(&planar, "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\n1 2 1\n2 5 2\n1 2 1\n").unwrap();
    let err = fails(&["prominence", &planar, "--divide-tree", &path("x.dvt")], 1);
    assert!(err.contains("GeoJSON") && !Path::new(&path("x.dvt")).exists(), "{err}");
}

#[test]
fn prominence_of_depressions_and_from_sea_level() {
    let tmp = tempfile::tempdir().unwrap();
    let bowl = tmp.path().join("bowl.asc").to_str().unwrap().to_owned();
    // A pit 30 deep in ground at 100, with a 5 m dip beside it.
    std::fs::write(&bowl, "ncols 5\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\n100 100 100 100 100\n100 70 100 95 100\n100 100 100 100 100\n").unwrap();
    let pits: serde_json::Value = serde_json::from_str(&ok(&["prominence", &bowl, "--depressions", "--json"])).unwrap();
    let p = &pits["peaks"];
    assert_eq!((p[0]["elevation"].as_f64(), p[0]["prominence"].as_f64()), (Some(70.0), Some(30.0)), "{pits}");
    assert_eq!((p[1]["elevation"].as_f64(), p[1]["prominence"].as_f64()), (Some(95.0), Some(5.0)), "{pits}");
    let dem = "fixtures/dem/jacksboro.asc";
    let top = |extra: &[&str]| -> f64 {
        let v: serde_json::Value =
            serde_json::from_str(&ok(&[&["prominence", dem, "--json"], extra].concat())).unwrap();
        v["peaks"][0]["prominence"].as_f64().unwrap()
    };
    assert_eq!(top(&[]), 1076.0, "down to the sea, as akirmse/mountains and summit lists count it");
    assert_eq!(top(&["--base", "sea-level"]), 1076.0);
    assert_eq!(top(&["--base", "outlet"]), 1076.0 - 244.0, "down to the lowest outlet, the DEM's lowest border cell");
}

#[test]
fn prominence_writes_akirmses_peak_lines_at_its_sample_positions() {
    let tmp = tempfile::tempdir().unwrap();
    let path = |name: &str| tmp.path().join(name).to_str().unwrap().to_owned();
    let dem = "fixtures/dem/jacksboro.asc";
    let lines = |extra: &[&str], name: &str| -> Vec<String> {
        let args = ["prominence", dem, "--min-prominence", "30", "--peaks-format", "akirmse", "--peaks", &path(name)];
        ok(&[&args[..], extra].concat());
        std::fs::read_to_string(path(name)).unwrap().lines().map(str::to_owned).collect()
    };
    // akirmse/mountains' own prominence.txt of the same DEM (fixtures/akirmse/README.md): this
    // DEM's cell centres are its canvas samples, so centre positions are its positions.
    let reference: Vec<String> =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/akirmse/prominence.txt"))
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect();
    let ours = lines(&[], "peaks.txt");
    assert_eq!(ours.len(), reference.len());
    assert_eq!(ours[0], "36.485000,-84.230833,1076.00,0.000000,0.000000,1076.00", "the top, from the sea, saddle 0,0");
    let fields = |l: &String| l.split(',').map(str::to_owned).collect::<Vec<_>>();
    let pick = |ls: &[String], f: &dyn Fn(&[String]) -> String| {
        let mut v: Vec<String> = ls.iter().map(|l| f(&fields(l))).collect();
        v.sort();
        v
    };
    // Every elevation with its prominence, as akirmse's.
    let heights = |f: &[String]| format!("{},{}", f[2], f[5]);
    assert_eq!(pick(&ours, &heights), pick(&reference, &heights));
    // Most lines byte for byte; the rest differ in which sample of a flat top or col is named.
    let same = ours.iter().filter(|l| reference.contains(l)).count();
    assert!(same >= 140, "{same} of {} lines as akirmse writes them", ours.len());
    let sorted = ours.windows(2).all(|w| fields(&w[0])[5].parse::<f64>().unwrap() >= fields(&w[1])[5].parse().unwrap());
    assert!(sorted, "most prominent first");
    // North-west corners: half a 3″ cell north and west of the centre.
    let corner = lines(&["--positions", "nw-corner"], "corner.txt");
    assert_eq!(corner[0], "36.485417,-84.231250,1076.00,0.000000,0.000000,1076.00");
    let saddle = |l: &String| [fields(l)[3].parse::<f64>().unwrap(), fields(l)[4].parse::<f64>().unwrap()];
    let (c, o) = (saddle(&corner[1]), saddle(&ours[1]));
    assert!((c[0] - o[0] - 0.5 / 1200.0).abs() < 2e-6 && (c[1] - o[1] + 0.5 / 1200.0).abs() < 2e-6, "{c:?} {o:?}");
    // From akirmse's own divide tree of the DEM, its own lines back (but where pruning differs).
    let tree = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/akirmse/divide_tree.dvt");
    ok(&["prominence", tree, "--min-prominence", "30", "--peaks-format", "akirmse", "--peaks", &path("tree.txt")]);
    let from_tree: Vec<String> =
        std::fs::read_to_string(path("tree.txt")).unwrap().lines().map(str::to_owned).collect();
    let same = from_tree.iter().filter(|l| reference.contains(l)).count();
    assert!(from_tree.len() == reference.len() && same >= 175, "{same} of {} lines", from_tree.len());
    let err = fails(&["prominence", dem, "--peaks-format", "akirmse", "--peaks", &path("p.geojson")], 1);
    assert!(err.contains("prominence.txt"), "{err}");
}

#[test]
fn analyze_reports_basins_and_compares_descriptors() {
    let tmp = tempfile::tempdir().unwrap();
    let filled = tmp.path().join("filled.tif");
    let dem = "fixtures/dem/jacksboro.asc";
    let report: serde_json::Value =
        serde_json::from_str(&ok(&["analyze", dem, "--json", "--filled", filled.to_str().unwrap()])).unwrap();
    // Raw SRTM has closed pits; the filled file written alongside has none and never lies lower.
    let basins = report["closed_basins"].as_u64().unwrap();
    assert!(basins > 0 && report["basins"].as_array().unwrap().len() as u64 == basins);
    let (raw, fixed) = (relief::io::read(root().join(dem)).unwrap(), relief::io::read(&filled).unwrap());
    assert!(!relief::hydrology::has_endorheic_basins(&fixed, relief::hydrology::NoData::Outlet));
    assert!(fixed.samples().iter().zip(raw.samples()).all(|(f, r)| f >= r));
    assert!(report["descriptors"]["max_strahler"].as_u64().unwrap() >= 2);
    // Against itself every distance is zero; the text report names the comparison.
    let same: serde_json::Value = serde_json::from_str(&ok(&["analyze", dem, "--compare", dem, "--json"])).unwrap();
    assert_eq!(same["distance"]["slope_deg"].as_f64(), Some(0.0));
    assert_eq!(same["distance"]["strahler"].as_i64(), Some(0));
    let text = ok(&["analyze", dem, "--compare", filled.to_str().unwrap()]);
    assert!(text.contains("closed basins") && text.contains("compared with"), "{text}");
}

#[test]
fn analyze_writes_descriptors_and_classifies_against_them() {
    let tmp = tempfile::tempdir().unwrap();
    let path = |name: &str| tmp.path().join(name).to_str().unwrap().to_owned();
    let dem = "fixtures/dem/jacksboro.asc";
    // A second landscape: the same DEM at a sixth of its resolution, smoother.
    ok(&["convert", dem, &path("coarse.asc"), "--size", "67x57"]);
    let (rugged, coarse) = (path("rugged.json"), path("coarse.json"));
    let args = ["analyze", dem, "--min-prominence", "30", "--descriptor", &rugged, "--peaks", &path("p.csv")];
    ok(&[&args[..], &["--divide-tree", &path("t.dvt")]].concat());
    ok(&["analyze", &path("coarse.asc"), "--min-prominence", "30", "--descriptor", &coarse]);
    let descriptor: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&rugged).unwrap()).unwrap();
    assert_eq!(descriptor["peaks"].as_u64(), Some(184));
    assert!(std::fs::read_to_string(path("t.dvt")).unwrap().lines().filter(|l| l.starts_with("P,")).count() == 184);
    // Each DEM is nearest its own descriptor, the file's stem naming it.
    for (input, label) in [(dem.to_owned(), "rugged"), (path("coarse.asc"), "coarse")] {
        let report: serde_json::Value = serde_json::from_str(&ok(&[
            "analyze",
            &input,
            "--min-prominence",
            "30",
            "--classify",
            &rugged,
            &coarse,
            "--json",
        ]))
        .unwrap();
        let nearest = &report["orometry"]["nearest"];
        assert_eq!(nearest["label"], label, "{input}: {nearest}");
        assert!(nearest["mean_emd"].as_f64().unwrap() < 1e-9, "{nearest}");
    }
}

#[test]
fn diffuse_refuses_contour_scenes_and_names_bad_curve_values() {
    let stderr = fails(&["diffuse", "fixtures/scenes/mesa.json"], 1);
    assert!(stderr.contains("relief generate"), "{stderr}");
    let tmp = tempfile::tempdir().unwrap();
    let bad = tmp.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{ "version": 1, "generator": { "diffusion": { "curves": [
            { "points": [[0, 0], [100, 0]], "constraints": [{ "u": 0, "elevation": { "h": 1 }, "slope": { "a": 5, "b": 5, "theta": 95, "phi": 0 } }] }
        ] } } }"#,
    )
    .unwrap();
    let stderr = fails(&["diffuse", bad.to_str().unwrap()], 1);
    assert!(stderr.contains("generator.diffusion.curves[0].constraints[0].slope.theta"), "{stderr}");
}

#[test]
fn schema_subcommand_prints_the_checked_in_schema() {
    let printed = ok(&["schema"]);
    assert_eq!(printed, std::fs::read_to_string(root().join("docs/scene.schema.json")).unwrap());
}

#[test]
fn failures_are_one_line_errors_with_exit_code_one() {
    let stderr = fails(&["generate", "no/such/scene.json"], 1);
    assert!(stderr.starts_with("error: ") && stderr.contains("scene.json"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");

    let tmp = tempfile::tempdir().unwrap();
    let bad = tmp.path().join("bad.json");
    std::fs::write(&bad, r#"{ "version": 1, "generator": { "contours": { "regions": [], "histogram": { "uniform": { "min": 0, "max": 1 } }, "particles": -4 } } }"#).unwrap();
    let stderr = fails(&["generate", bad.to_str().unwrap()], 1);
    assert!(stderr.contains("generator.contours.particles"), "{stderr}");

    let stderr = fails(&["analyze", "no/such/dem.asc"], 1);
    assert_eq!(stderr.matches("No such file").count(), 1, "the cause is told once: {stderr}");
    let stderr = fails(&["info", "fixtures/scenes/README.md"], 1);
    assert!(stderr.contains("README.md"), "{stderr}");
    let stderr = fails(&["convert", "fixtures/dem/jacksboro.asc", "out.jpeg"], 1);
    assert!(stderr.contains("out.jpeg"), "{stderr}");
}

#[test]
fn usage_errors_exit_with_code_two() {
    fails(&[], 2);
    fails(&["generate"], 2);
    fails(&["contours", "fixtures/dem/jacksboro.asc"], 2);
    fails(&["contours", "fixtures/dem/jacksboro.asc", "--interval", "10", "--levels", "3"], 2);
    fails(&["demo", "--threads", "0"], 2);
    fails(&["frobnicate"], 2);
    // A preview cannot be decimated below 2 samples a side (0 used to divide by zero).
    fails(&["preview", "fixtures/dem/jacksboro.asc", "-o", "never.png", "--max-size", "0"], 2);
}

/// `--beta-range 2,4` (the paper's kernel) keeps every primitive's exponent within it, where the
/// default range takes shapes outside it; a range below the fit's bound is refused by name.
#[test]
fn vectorize_takes_the_papers_exponents() {
    let tmp = tempfile::tempdir().unwrap();
    let dem = root().join("fixtures/dem/salish.tif");
    let betas = |range: Option<&str>| -> Vec<f64> {
        let json = tmp.path().join("salish.json");
        let mut args = vec!["vectorize", dem.to_str().unwrap(), "--primitives", "150", "--iterations", "40"];
        args.extend(["-o", json.to_str().unwrap(), "--force"]);
        if let Some(r) = range {
            args.extend(["--beta-range", r]);
        }
        ok(&args);
        let terrain: relief::gaussian_terrain::VectorTerrain =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        terrain.primitives.iter().map(|g| g.beta).collect()
    };
    let paper = betas(Some("2,4"));
    assert!(!paper.is_empty() && paper.iter().all(|b| (2.0..=4.0).contains(b)), "{paper:?}");
    let ours = betas(None);
    assert!(ours.iter().any(|b| !(2.0..=4.0).contains(b)), "{ours:?}");
    let json = tmp.path().join("refused.json");
    let stderr = fails(&["vectorize", dem.to_str().unwrap(), "--beta-range", "0.1,2", "-o", json.to_str().unwrap()], 1);
    assert!(stderr.contains("beta_range"), "{stderr}");
}

#[test]
fn vectorize_then_rasterize_a_real_dem() {
    let tmp = tempfile::tempdir().unwrap();
    let dem = root().join("fixtures/dem/jacksboro.asc");
    let json = tmp.path().join("jacksboro.json");
    let stdout = ok(&[
        "vectorize",
        dem.to_str().unwrap(),
        "--primitives",
        "150",
        "--iterations",
        "20",
        "--resolution",
        "96",
        "-o",
        json.to_str().unwrap(),
    ]);
    assert!(stdout.contains("primitives after 20 steps"), "{stdout}");
    let terrain: relief::gaussian_terrain::VectorTerrain =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(!terrain.primitives.is_empty() && terrain.primitives.len() <= 150);
    // Rendered at another size over the DEM's extent (recorded in the JSON), the relief matches.
    let exr = tmp.path().join("jacksboro.exr");
    ok(&["rasterize", json.to_str().unwrap(), "--size", "120x100", "-o", exr.to_str().unwrap()]);
    let source = relief::io::read(&dem).unwrap();
    let out = relief::io::read(&exr).unwrap();
    assert_eq!((out.nx(), out.ny()), (120, 100));
    let ((a, b), (c, d)) = (source.min_max().unwrap(), out.min_max().unwrap());
    assert!((a - c).abs() < 0.15 * (b - a) && (b - d).abs() < 0.15 * (b - a), "{a}..{b} vs {c}..{d}");
    // The fit's error is printed in metres, as a fraction of the relief (Table 3's unit, as the
    // paper's authors measure it) and of the relief's half-range (twice that).
    let line = stdout.lines().find(|l| l.contains("mean error")).expect("the error's line");
    let words: Vec<&str> = line.split("mean error ").nth(1).unwrap().split_whitespace().collect();
    let number = |k: usize| words[k].trim_start_matches('(').parse::<f64>().unwrap_or_else(|e| panic!("{line}: {e}"));
    let (metres, of_relief, of_half) = (number(0), number(1), number(8));
    assert!(words[2..8].join(" ").contains("relief, Table 3's unit;") && words[11].starts_with("half-range"), "{line}");
    let relief = f64::from(b - a);
    assert!((metres / relief - of_relief).abs() <= 0.01 * of_relief + 5e-4 / relief, "{line} ({relief} m of relief)");
    assert!((of_half - 2.0 * of_relief).abs() <= 0.01 * of_half, "{line}");
    // In the DEM's frame, recorded in the JSON and carried to the raster: degrees, in its CRS
    // (a raster of it once came out labelled as metres with no CRS).
    let degrees = relief::heightfield::Units::Degrees;
    assert_eq!((terrain.units, terrain.crs.as_ref()), (Some(degrees), source.crs()));
    assert!(source.crs().is_some());
    let tif = tmp.path().join("jacksboro.tif");
    ok(&["rasterize", json.to_str().unwrap(), "--size", "120x100", "-o", tif.to_str().unwrap()]);
    assert_eq!(relief::io::read(&tif).unwrap().grid().units(), degrees);
    assert_eq!((out.crs(), out.grid().units()), (source.crs(), degrees), "the EXR keeps the CRS's WKT");
    // On the DEM's own grid (`--like`), to set beside it sample for sample.
    let like = tmp.path().join("like.tif");
    let (json_s, like_s, exr_s) = (json.to_str().unwrap(), like.to_str().unwrap(), exr.to_str().unwrap());
    ok(&["rasterize", json_s, "--like", dem.to_str().unwrap(), "-o", like_s]);
    let on_dem = relief::io::read(&like).unwrap();
    let (g, s) = (on_dem.grid(), source.grid());
    assert_eq!(
        (g.nx(), g.ny(), g.origin(), g.cell_size(), g.units()),
        (s.nx(), s.ny(), s.origin(), s.cell_size(), s.units())
    );
    let mean = on_dem.samples().iter().zip(source.samples()).map(|(a, b)| f64::from((a - b).abs())).sum::<f64>()
        / source.samples().len() as f64;
    assert!(mean < 0.1 * f64::from(b - a), "mean error {mean} m");
    fails(&["rasterize", json_s, "-o", exr_s], 2);
    fails(&["rasterize", json_s, "--like", dem.to_str().unwrap(), "--size", "40", "-o", exr_s], 2);
    // Units overridden on reading win over the file's CRS, through the JSON to the raster.
    let feet = tmp.path().join("feet.json");
    let (dem_s, feet_s) = (dem.to_str().unwrap(), feet.to_str().unwrap());
    ok(&["--units", "feet", "vectorize", dem_s, "--primitives", "40", "--iterations", "5", "-o", feet_s]);
    // A grid in other units than the terrain's is refused, naming both.
    let err = fails(&["--force", "rasterize", feet_s, "--like", dem_s, "-o", exr_s], 1);
    assert!(err.contains("degrees") && err.contains("feet") && err.contains("--size"), "{err}");
    let exr_feet = tmp.path().join("feet.exr");
    ok(&["rasterize", feet_s, "--size", "40", "-o", exr_feet.to_str().unwrap()]);
    assert_eq!(relief::io::read(&exr_feet).unwrap().grid().units(), relief::heightfield::Units::Feet);
    // And `--crs` relabels a terrain's frame, its units with it.
    let tif_ftus = tmp.path().join("ftus.tif");
    ok(&["--crs", "EPSG:2274", "rasterize", feet_s, "--size", "40", "-o", tif_ftus.to_str().unwrap()]);
    let relabelled = relief::io::read(&tif_ftus).unwrap();
    assert_eq!(relabelled.crs().and_then(relief::heightfield::Crs::epsg), Some(2274));
    assert_eq!(relabelled.grid().units(), relief::heightfield::Units::UsSurveyFeet);
    // Bad sizes are usage errors; a broken terrain file is a one-line failure.
    fails(&["rasterize", json.to_str().unwrap(), "--size", "1x5", "-o", exr.to_str().unwrap()], 2);
    let bad = tmp.path().join("bad.json");
    std::fs::write(&bad, r#"{"primitives":[{"center":[0,0],"sigma":[-1,1],"amplitude":1}]}"#).unwrap();
    let err = fails(&["--force", "rasterize", bad.to_str().unwrap(), "--size", "64", "-o", exr.to_str().unwrap()], 1);
    assert!(err.contains("sigma.x"), "{err}");
    // The budget flags cap what the commands would allocate, before they do (exit 2, as nothing
    // was tried): the raster's cells,
    // the terrain's primitives, and a fit's primitives and working grid (`--force`: the outputs
    // exist from above, and must not be what stops them).
    let (json, exr, dem) = (json.to_str().unwrap(), exr.to_str().unwrap(), dem.to_str().unwrap());
    let err = fails(&["--force", "--max-cells", "10000", "rasterize", json, "--size", "120x100", "-o", exr], 2);
    assert!(err.contains("--size") && err.contains("12000") && err.contains("--max-cells"), "{err}");
    let err = fails(&["--force", "--max-primitives", "10", "rasterize", json, "--size", "64", "-o", exr], 2);
    assert!(err.contains("--max-primitives"), "{err}");
    let err = fails(&["--force", "--max-primitives", "100", "vectorize", dem, "--primitives", "150", "-o", json], 2);
    assert!(err.contains("--primitives") && err.contains("--max-primitives"), "{err}");
    let err = fails(&["--force", "--max-cells", "5000", "vectorize", dem, "--resolution", "96", "-o", json], 2);
    assert!(err.contains("--resolution") && err.contains("9216"), "{err}");
    // A DEM bigger than the read limit: refused from its header, exit 2 too.
    let err = fails(&["--max-cells", "100", "info", dem], 2);
    assert!(err.contains("exceed the limit of 100"), "{err}");
    // The memory estimate: 4096² cells at 80 bytes for a contour scene, refused before any work.
    let out = tmp.path().join("mesa");
    let args = ["--max-bytes", "1000000000", "generate", "fixtures/scenes/mesa.json", "--resolution", "4096"];
    let err = fails(&[&args[..], &["--out", out.to_str().unwrap()]].concat(), 2);
    assert!(err.contains("1342177280 bytes") && err.contains("--max-bytes"), "{err}");
    assert!(!out.exists(), "the output folder was made for a refused scene");
}

/// A coast whose sea is stored as 0: by default the terrain gets a floor at sea level and the
/// rasterized sea is exactly 0; `--plain` fits the paper's plain sum, which digs below it.
#[test]
fn vectorize_keeps_a_flat_sea_unless_plain() {
    let tmp = tempfile::tempdir().unwrap();
    let dem = root().join("fixtures/dem/salish-land.tif");
    let run = |plain: bool| {
        let json = tmp.path().join(format!("coast-{plain}.json"));
        let exr = tmp.path().join(format!("coast-{plain}.exr"));
        let mut args = vec!["vectorize", dem.to_str().unwrap(), "--primitives", "200", "--iterations", "60"];
        if plain {
            args.push("--plain");
        }
        args.extend(["-o", json.to_str().unwrap()]);
        ok(&args);
        ok(&["rasterize", json.to_str().unwrap(), "--size", "120x91", "-o", exr.to_str().unwrap()]);
        let terrain: relief::gaussian_terrain::VectorTerrain =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        // The DEM's CRS (EPSG:4326) on the raster, from the JSON.
        let crs = relief::io::read(&exr).unwrap().crs().and_then(relief::heightfield::Crs::epsg);
        assert_eq!((terrain.crs.as_ref().and_then(relief::heightfield::Crs::epsg), crs), (Some(4326), Some(4326)));
        (terrain.floor, relief::io::read(&exr).unwrap().min_max().unwrap().0)
    };
    assert_eq!(run(false), (Some(0.0), 0.0));
    let (floor, lowest) = run(true);
    assert_eq!(floor, None);
    assert!(lowest < -10.0, "the plain sum's lowest sample {lowest} m");
}

/// A DEM with no-data (a country masked beyond its border) is refused with the flag that fills
/// it; `--fill-no-data min` fills at the lowest elevation, which becomes the terrain's floor.
#[test]
fn vectorize_fills_no_data_when_asked() {
    let tmp = tempfile::tempdir().unwrap();
    let json = tmp.path().join("lux.json");
    let (dem, json_s) = ("fixtures/dem/luxembourg.tif", json.to_str().unwrap());
    let run = |fill: &[&str], code: i32| {
        let mut args = vec!["vectorize", dem, "--primitives", "40", "--iterations", "5", "-o", json_s];
        args.extend(fill);
        if code == 0 { ok(&args) } else { fails(&args, code) }
    };
    let err = run(&[], 1);
    assert!(err.contains("3942 no-data samples") && err.contains("--fill-no-data min"), "{err}");
    let err = run(&["--fill-no-data", "max"], 2);
    assert!(err.contains("max: give `min` or a finite elevation"), "{err}");
    let out = run(&["--fill-no-data", "min"], 0);
    assert!(out.contains("3942 no-data samples filled at 141"), "{out}");
    let terrain: relief::gaussian_terrain::VectorTerrain =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(terrain.floor, Some(141.0));
}

#[test]
fn gis_flags_label_crs_pick_bands_and_channels_and_convert_keeps_the_crs() {
    let info = ok(&["info", "fixtures/gdal/tn-ftus.tif"]);
    assert!(
        info.contains("NAD83 / Tennessee (ftUS) (EPSG:2274), us_survey_feet") && info.contains("300 x 300 ftUS"),
        "{info}"
    );
    // An ASCII grid without .prj in degrees: read as degrees, and the guess is said.
    let dir = tempfile::tempdir().unwrap();
    let bare = dir.path().join("bare.asc");
    std::fs::copy(root().join("fixtures/dem/jacksboro.asc"), &bare).unwrap();
    let out = relief().args(["info", bare.to_str().unwrap()]).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("read as geographic degrees"), "{stderr}");
    let labelled = ok(&["info", "--json", "--crs", "EPSG:4269", bare.to_str().unwrap()]);
    let json: serde_json::Value = serde_json::from_str(&labelled).unwrap();
    assert_eq!((json["crs"]["epsg"].as_u64(), json["units"].as_str()), (Some(4269), Some("degrees")));
    // convert keeps the CRS (GDAL would report EPSG:2274 for both) and compresses by default.
    let tif = dir.path().join("c.tif");
    ok(&["convert", "fixtures/gdal/tn-ftus.tif", tif.to_str().unwrap(), "-q"]);
    assert!(ok(&["info", tif.to_str().unwrap()]).contains("EPSG:2274"));
    let lines = dir.path().join("c.geojson");
    ok(&["contours", "fixtures/gdal/utm17.tif", "--interval", "50", "--geojson", lines.to_str().unwrap(), "-q"]);
    let text = std::fs::read_to_string(&lines).unwrap();
    assert!(
        text.starts_with(r#"{"crs":{"properties":{"name":"urn:ogc:def:crs:EPSG::32617"},"type":"name"}"#),
        "{}",
        &text[..80]
    );
    let band = ok(&["info", "--band", "2", "fixtures/images/three-band.tif"]);
    assert!(band.contains("449 .. 941"), "{band}");
    assert!(fails(&["info", "fixtures/images/three-band.tif"], 1).contains("--band"));
    assert!(fails(&["info", "fixtures/images/rgb-colour.png"], 1).contains("--channel"));
    assert!(ok(&["info", "--channel", "red", "fixtures/images/rgb-colour.png"]).contains("0 .. 0.1254902"));
    assert!(fails(&["info", "--crs", "UTM 17", "fixtures/gdal/utm17.tif"], 2).contains("EPSG:n"));
}

#[test]
fn export_writes_engine_heightmaps_from_a_dem_or_a_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ue");
    // Jacksboro (403 × 344 samples of 3″) as Unreal World Partition tiles of 253 samples.
    let stdout =
        ok(&["export", "fixtures/dem/jacksboro.asc", "--for", "unreal", "--tile", "253", "-o", out.to_str().unwrap()]);
    assert!(stdout.contains("unreal: 2 × 2 tiles, each 253 × 253 PNG; Scale X"), "{stdout}");
    for name in ["heightmap_x0_y0.png", "heightmap_x1_y1.png", "heightmap.import.json"] {
        assert!(out.join(name).is_file(), "{name}");
    }
    // A scene is generated first; Unity's RAW is 2ⁿ + 1 square, 16 bits a sample.
    let unity = tmp.path().join("unity");
    let scene = "fixtures/scenes/landforms-ridges.json";
    let stdout = ok(&["export", scene, "--for", "unity", "--size", "129", "-o", unity.to_str().unwrap()]);
    assert!(stdout.contains("Width 129, Height 129, Byte Order Windows"), "{stdout}");
    assert_eq!(std::fs::metadata(unity.join("heightmap.raw")).unwrap().len(), 129 * 129 * 2);
    // Existing files are kept without --force; illegal sizes name the legal ones.
    let stderr = fails(&["export", scene, "--for", "unity", "--size", "129", "-o", unity.to_str().unwrap()], 1);
    assert!(stderr.contains("--force"), "{stderr}");
    let stderr = fails(&["export", "fixtures/dem/jacksboro.asc", "--for", "godot", "--size", "100"], 1);
    assert!(stderr.contains("65, 129, 257"), "{stderr}");
    // A glTF mesh within 8 m of every sample; splat maps beside a heightmap.
    let gl = tmp.path().join("gl");
    let args =
        ["export", "fixtures/dem/jacksboro.asc", "--for", "gltf", "--max-error", "8", "-o", gl.to_str().unwrap()];
    let stdout = ok(&args);
    assert!(stdout.contains("within 8.000 m of every sample") && stdout.contains("236.0 … 1076.0 m"), "{stdout}");
    assert_eq!(&std::fs::read(gl.join("terrain.glb")).unwrap()[..4], b"glTF");
    let splat = tmp.path().join("splat");
    ok(&["export", "fixtures/dem/jacksboro.asc", "--for", "blender", "--splat", "-o", splat.to_str().unwrap()]);
    for name in ["heightmap.png", "heightmap_splat.png", "heightmap_masks.png"] {
        assert!(splat.join(name).is_file(), "{name}");
    }
    let stderr = fails(&["export", "fixtures/dem/jacksboro.asc", "--for", "gltf", "--splat"], 1);
    assert!(stderr.contains("heightmap engine"), "{stderr}");
    let stderr = fails(&["export", "fixtures/dem/jacksboro.asc", "--for", "unity", "--max-error", "2"], 1);
    assert!(stderr.contains("go with --for gltf"), "{stderr}");
    let stderr = fails(&["export", "fixtures/dem/jacksboro.asc", "--for", "gltf", "--triangles", "1"], 1);
    assert!(stderr.contains("--triangles 1: must be from 2 to"), "{stderr}");
    let stderr = fails(&["export", "fixtures/dem/jacksboro.asc", "--for", "gltf", "--max-error", "NaN"], 1);
    assert!(stderr.contains("--max-error NaN: must be finite"), "{stderr}");
}
