//! The command line as a newcomer meets it: errors that point at the line, scenes from standard
//! input, `-q` everywhere, the global options described once, completions and a man page.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Stdio;

use assert_cmd::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn run(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::cargo_bin("relief").unwrap().current_dir(dir).args(args).output().unwrap()
}

/// stdout of a successful run.
#[track_caller]
fn ok(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    assert!(out.status.success(), "relief {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// stderr of a run failing with `code`.
#[track_caller]
fn fails(dir: &Path, args: &[&str], code: i32) -> String {
    let out = run(dir, args);
    assert_eq!(out.status.code(), Some(code), "relief {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stderr).unwrap()
}

#[test]
fn json_errors_name_the_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("bad.json"), "{\n  \"version\": 1,\n  \"seed\": 4,,\n}\n").unwrap();
    let stderr = fails(dir, &["generate", "bad.json"], 1);
    assert!(stderr.starts_with("error: bad.json:3:13: key must be a string"), "{stderr}");
    assert!(!stderr.contains("?:") && !stderr.contains(" at line "), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "no caret off a terminal: {stderr}");

    // A value error keeps its JSON path after the place.
    let text = std::fs::read_to_string(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["generator"]["diffusion"]["curves"][0]["constraints"][0]["slope"]["theta"] = 95.into();
    let pretty = serde_json::to_string_pretty(&v).unwrap();
    std::fs::write(dir.join("ridges.json"), &pretty).unwrap();
    let stderr = fails(dir, &["generate", "ridges.json"], 1);
    let line = pretty.lines().position(|l| l.contains("95")).unwrap() + 1;
    let at = |l: usize| format!("error: ridges.json:{l}:");
    assert!(stderr.starts_with(&at(line)) || stderr.starts_with(&at(line + 1)), "line {line}: {stderr}");
    assert!(stderr.contains(": generator.diffusion.curves[0].constraints[0].slope.theta: 95 must lie"), "{stderr}");

    // A missing file says so once.
    let stderr = fails(dir, &["generate", "nowhere.json"], 1);
    assert_eq!(stderr.matches("No such file").count(), 1, "{stderr}");
}

#[test]
fn a_scene_can_come_from_standard_input() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("fixtures/scenes/mesa.json")).unwrap()).unwrap();
    v["reconstruction"]["resolution"] = serde_json::json!([40, 40]);
    v["generator"]["contours"]["particles"] = serde_json::json!(2000);
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("relief"))
        .current_dir(dir)
        .args(["-q", "generate", "-"])
        .stdin(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(v.to_string().as_bytes()).unwrap();
    assert!(child.wait().unwrap().success());
    assert!(dir.join("relief-out/stdin/terrain.exr").is_file());
}

#[test]
fn quiet_silences_every_report() {
    let dem = root().join("fixtures/dem/jacksboro.asc");
    let dem = dem.to_str().unwrap();
    let dir = root();
    assert!(ok(&dir, &["info", dem]).contains("size"));
    assert_eq!(ok(&dir, &["-q", "info", dem]), "");
    assert_eq!(ok(&dir, &["info", dem, "-q", "--json"]), "");
    assert!(ok(&dir, &["analyze", dem, "--min-prominence", "100"]).contains("peaks"));
    assert_eq!(ok(&dir, &["-q", "analyze", dem, "--min-prominence", "100"]), "");
}

#[test]
fn help_describes_global_options_once_and_the_tool_describes_itself() {
    let dir = root();
    let top = ok(&dir, &["--help"]);
    for flag in ["--quiet", "--force", "--threads", "--max-cells", "--max-peaks"] {
        assert_eq!(top.matches(flag).count(), 1, "{flag} once in relief --help:\n{top}");
    }
    let sub = ok(&dir, &["generate", "--help"]);
    assert!(!sub.contains("--max-cells <N>") && sub.contains("relief --help"), "{sub}");
    // The flags still work after the subcommand.
    let stderr = fails(&dir, &["generate", "nowhere.json", "--max-cells", "5", "-q"], 1);
    assert!(stderr.contains("nowhere.json"), "{stderr}");

    let bash = ok(&dir, &["completions", "bash"]);
    assert!(bash.contains("_relief()") && bash.contains("generate") && bash.contains("--max-cells"), "{bash}");
    assert!(ok(&dir, &["completions", "zsh"]).contains("#compdef relief"));
    let man = ok(&dir, &["man"]);
    assert!(man.contains(".TH relief 1") && man.contains("vectorize") && man.contains(r"max\-particles"), "{man}");
}

#[test]
fn bad_sizes_say_what_to_give() {
    let tmp = tempfile::tempdir().unwrap();
    let stderr = fails(tmp.path(), &["rasterize", "t.json", "--size", "2x", "-o", "t.exr"], 2);
    assert!(stderr.contains("give W or WxH") && !stderr.contains("empty string"), "{stderr}");
}

#[test]
fn sizes_formats_and_vertical_ranges_from_the_command_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["-q", "demo", "--out", "d", "--resolution", "64x48", "--format", "exr,r16", "--range", "-500,3000"]);
    let mut names: Vec<String> = std::fs::read_dir(dir.join("d"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "contours.geojson",
            "contours.svg",
            "preview.png",
            "summary.json",
            "terrain.exr",
            "terrain.r16",
            "terrain.r16.json"
        ]
    );
    let exr = relief::io::read(dir.join("d/terrain.exr")).unwrap();
    let r16 = relief::io::read(dir.join("d/terrain.r16")).unwrap();
    assert_eq!((exr.nx(), exr.ny()), (64, 48));
    // Quantised over the fixed range: within half a code of 3500 m / 65535.
    let step = 3500.0 / 65535.0;
    assert!(exr.samples().iter().zip(r16.samples()).all(|(a, b)| f64::from((a - b).abs()) <= 0.5 * step + 1e-3));
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d/terrain.r16.json")).unwrap()).unwrap();
    assert_eq!((sidecar["min"].as_f64(), sidecar["max"].as_f64()), (Some(-500.0), Some(3000.0)));
    // info says how the codes read; a float format has no codes line.
    let info = ok(dir, &["info", "d/terrain.r16"]);
    assert!(info.contains("codes      16-bit: code 0 = -500 m .. code 65535 = 3000 m, step 0.053407 m"), "{info}");
    assert!(!ok(dir, &["info", "d/terrain.exr"]).contains("codes"));
    let json: serde_json::Value = serde_json::from_str(&ok(dir, &["info", "--json", "d/terrain.r16"])).unwrap();
    assert_eq!(json["codes"]["highest_code"], 65535);

    // convert: resampled, 8-bit, over a range; a range the DEM leaves is refused.
    let dem = root().join("fixtures/dem/jacksboro.asc");
    let dem = dem.to_str().unwrap();
    ok(dir, &["-q", "convert", dem, "small.png", "--size", "100x80", "--format", "png8", "--range", "0,2000"]);
    let small = relief::io::read(dir.join("small.png")).unwrap();
    assert_eq!((small.nx(), small.ny()), (100, 80));
    assert!(small.samples().iter().all(|v| (v * 255.0 / 2000.0 - (v * 255.0 / 2000.0).round()).abs() < 1e-3));
    let stderr = fails(dir, &["convert", dem, "x.exr", "--format", "png8"], 1);
    assert!(stderr.contains("names another format"), "{stderr}");
    let stderr = fails(dir, &["convert", dem, "y.png", "--range", "0,300"], 1);
    assert!(stderr.contains("outside [0, 300]"), "{stderr}");
    assert!(!dir.join("y.png").exists());
    let stderr = fails(dir, &["demo", "--format", "png8", "--out", "e"], 1);
    assert!(stderr.contains("16-bit"), "{stderr}");
    assert!(fails(dir, &["convert", dem, "z.png", "--range", "9,1"], 2).contains("MIN < MAX"));
}

/// The RGB pixels of a PNG written by `relief preview`.
fn rgb(path: &Path) -> Vec<[u8; 3]> {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut bytes = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut bytes).unwrap();
    bytes[..info.buffer_size()].chunks(3).map(|p| [p[0], p[1], p[2]]).collect()
}

#[test]
fn previews_show_the_inputs_that_made_the_terrain() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = root().join("fixtures/scenes/elongated-island.json");
    let scene = scene.to_str().unwrap();
    ok(dir, &["generate", scene, "--out", "out", "--resolution", "96", "-q"]);
    ok(dir, &["preview", "out/terrain.exr", "-o", "plain.png"]);
    ok(dir, &["preview", "out/terrain.exr", "-o", "inputs.png", "--inputs", scene]);
    let count = |path: &str, colour: [u8; 3]| rgb(&dir.join(path)).iter().filter(|&&p| p == colour).count();
    // Strokes in magenta and hills in yellow, over the relief that is otherwise the same.
    for colour in [[255, 0, 200], [255, 230, 0]] {
        assert_eq!(count("plain.png", colour), 0);
        assert!(count("inputs.png", colour) > 20, "{colour:?}: {}", count("inputs.png", colour));
    }
    // The scene's sea level (half the island's land floor) draws its sea as water; 0 would draw
    // the sea at exactly 0 as land.
    ok(dir, &["preview", "out/terrain.exr", "-o", "sea0.png", "--inputs", scene, "--sea-level", "0"]);
    let corner = |path: &str| rgb(&dir.join(path))[0];
    assert_eq!(corner("sea0.png"), corner("plain.png"));
    assert_ne!(corner("inputs.png"), corner("plain.png"));
    let [r, g, b] = corner("inputs.png");
    assert!(b > r && b > g, "water is blue: {:?}", [r, g, b]);
    // A scene from elsewhere is drawn too, with a word that it does not lie over the terrain.
    let text = std::fs::read_to_string(scene).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["generator"]["island"]["operations"] = serde_json::json!([{ "stroke": { "points": [[1e6, 0], [1e6, 10]] } }]);
    std::fs::write(dir.join("far.json"), v.to_string()).unwrap();
    let out = run(dir, &["preview", "out/terrain.exr", "-o", "far.png", "--inputs", "far.json"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stderr.contains("none of the scene's inputs lies over out/terrain.exr"),
        "{stderr}"
    );
    // A scene whose inputs are files has nothing to draw, and says so; a broken scene is an error.
    let label = root().join("fixtures/scenes/range-label.json");
    let out = run(dir, &["preview", "out/terrain.exr", "-o", "label.png", "--inputs", label.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("has no inputs to draw"));
    std::fs::write(dir.join("bad.json"), "{").unwrap();
    let stderr = fails(dir, &["preview", "out/terrain.exr", "-o", "bad.png", "--inputs", "bad.json"], 1);
    assert!(stderr.starts_with("error: bad.json:1:"), "{stderr}");
    assert!(!dir.join("bad.png").exists());
}

#[test]
fn read_flags_say_what_a_heightmap_means() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // An 8-bit heightmap as a paint program saves it: codes only, no range, no placement.
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 3, 2);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header().unwrap().write_image_data(&[0, 51, 255, 102, 204, 153]).unwrap();
    std::fs::write(dir.join("paint.png"), &bytes).unwrap();
    let info = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["info", "paint.png", "--json"];
        args.extend_from_slice(extra);
        serde_json::from_str(&ok(dir, &args)).unwrap()
    };
    let plain = info(&[]);
    assert_eq!((plain["min"].as_f64(), plain["max"].as_f64()), (Some(0.0), Some(1.0)));
    let meant = info(&["--z-range", "100,600", "--cell-size", "30", "--origin", "1000,-2000"]);
    assert_eq!((meant["min"].as_f64(), meant["max"].as_f64()), (Some(100.0), Some(600.0)));
    assert_eq!(meant["cell_size"], serde_json::json!([30.0, 30.0]));
    assert_eq!(meant["extent"]["min"], serde_json::json!([1000.0, -2000.0]), "the south-west sample");
    assert_eq!(meant["outer_extent"]["min"], serde_json::json!([985.0, -2015.0]), "its cell's corner, half a cell out");
    let text = ok(dir, &["info", "paint.png"]);
    assert!(text.contains("sample centres") && text.contains("outer edges") && text.contains("--z-range"), "{text}");
    // The flags reach every command that reads: the converted EXR keeps the meant elevations.
    ok(dir, &["convert", "paint.png", "paint.exr", "--z-range", "100,600", "-q"]);
    let converted: serde_json::Value = serde_json::from_str(&ok(dir, &["info", "paint.exr", "--json"])).unwrap();
    assert_eq!(converted["max"].as_f64(), Some(600.0));
    // A file that stores elevations refuses a z range; a raw file gets its size.
    let stderr = fails(dir, &["info", "paint.exr", "--z-range", "0,1"], 1);
    assert!(stderr.contains("stores elevations"), "{stderr}");
    ok(dir, &["convert", "paint.exr", "coded.png", "-q"]);
    let stderr = fails(dir, &["info", "coded.png", "--z-range", "0,1"], 1);
    assert!(stderr.contains("already stand for 100..600"), "{stderr}");
    std::fs::write(dir.join("six.r16"), [0u8; 2 * 6 * 4]).unwrap();
    let stderr = fails(dir, &["info", "six.r16"], 1);
    assert!(stderr.contains("six.r16"), "{stderr}");
    let raw: serde_json::Value =
        serde_json::from_str(&ok(dir, &["info", "six.r16", "--raw-size", "6x4", "--json"])).unwrap();
    assert_eq!((raw["nx"].as_u64(), raw["ny"].as_u64()), (Some(6), Some(4)));
    let stderr = fails(dir, &["info", "paint.png", "--cell-size", "0"], 2);
    assert!(stderr.contains("give S or SX,SY"), "{stderr}");
}
