//! `cargo xtask gallery`: renders the demo and every fixture scene with the release `relief`
//! binary, copies their previews into `docs/gallery/` and writes the index `docs/gallery.md`.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result};

/// One rendered scene.
struct Entry {
    name: String,
    scene: String,
    description: String,
    summary: serde_json::Value,
    /// Whether `{name}-dem.png`, the source DEM's preview, was written.
    dem_beside: bool,
    /// For a feature-curve scene, Table 1's statistics: its curves (presets expanded) and their
    /// size as compact JSON, in bytes.
    curves: Option<(usize, usize)>,
}

/// Table 1 of Hnaidi et al. for a scene: the number of feature curves (a `multiple_ridges` preset
/// counts one per ridge) and the bytes of the curves and presets written as compact JSON.
fn curve_statistics(scene: &serde_json::Value) -> Option<(usize, usize)> {
    let g = scene["generator"]["diffusion"].as_object()?;
    let empty = Vec::new();
    let curves = g.get("curves").and_then(|c| c.as_array()).unwrap_or(&empty);
    let presets = g.get("presets").and_then(|p| p.as_array()).unwrap_or(&empty);
    let expanded: usize = presets.iter().map(|p| p["multiple_ridges"]["ends"].as_array().map_or(1, Vec::len)).sum();
    let bytes = serde_json::to_string(curves).ok()?.len()
        + if presets.is_empty() { 0 } else { serde_json::to_string(presets).ok()?.len() };
    Some((curves.len() + expanded, bytes))
}

/// The release `relief` binary, built first.
pub(crate) fn release_relief(root: &Path) -> Result<PathBuf> {
    crate::run(Command::new(env!("CARGO")).current_dir(root).args(["build", "--release", "-p", "relief-cli"]))?;
    Ok(root.join("target/release/relief"))
}

/// The fixture scenes, by name.
pub(crate) fn fixture_scenes(root: &Path) -> Result<Vec<PathBuf>> {
    let mut scenes: Vec<PathBuf> = fs::read_dir(root.join("fixtures/scenes"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    scenes.sort();
    Ok(scenes)
}

/// Generates `scene` with `relief` into `out`; the scene's name.
pub(crate) fn generate(relief: &Path, root: &Path, scene: &Path, out: &Path) -> Result<String> {
    let name = scene.file_stem().context("scene without a name")?.to_string_lossy().into_owned();
    eprintln!("generating {name}");
    crate::run(
        Command::new(relief).current_dir(root).args(["-q", "--force", "generate"]).arg(scene).arg("--out").arg(out),
    )?;
    Ok(name)
}

pub(crate) fn run(root: &Path) -> Result<()> {
    let relief = release_relief(root)?;
    let work = root.join("target/gallery");
    let images = root.join("docs/gallery");
    fs::create_dir_all(&images).with_context(|| format!("creating {}", images.display()))?;

    let mut scenes = fixture_scenes(root)?;
    scenes.insert(0, root.join("crates/relief/scenes/demo.json"));

    let mut entries = Vec::new();
    for scene in &scenes {
        let stem = scene.file_stem().context("scene without a name")?;
        let out = work.join(stem);
        let name = generate(&relief, root, scene, &out)?;
        fs::copy(out.join("preview.png"), images.join(format!("{name}.png")))
            .with_context(|| format!("copying the preview of {name}"))?;
        let text = fs::read_to_string(scene)?;
        let json: serde_json::Value = serde_json::from_str(&text)?;
        // A scene regrown from a DEM's contours (Fig. 24) or vectorized from a DEM shows the DEM
        // beside it.
        let source = &json["generator"]["gaussian"]["source"];
        let vectorized = (source["kind"] == "dem").then(|| source["path"].as_str()).flatten();
        if let Some(dem) = json["generator"]["contours"]["contours"]["dem"].as_str().or(vectorized) {
            let dem = scene.parent().context("scene without a folder")?.join(dem);
            crate::run(
                Command::new(&relief)
                    .current_dir(root)
                    .args(["-q", "--force", "preview"])
                    .arg(&dem)
                    .arg("-o")
                    .arg(images.join(format!("{name}-dem.png")))
                    .args(["--max-size", "512"])
                    // The contours paper's DEMs with their 50 m contours; a vectorized DEM with
                    // its relief alone (its contours would be drawn at its own interval).
                    .args(if vectorized.is_some() { &[][..] } else { &["--contours", "50"][..] }),
            )?;
        }
        let summary: serde_json::Value = serde_json::from_str(&fs::read_to_string(out.join("summary.json"))?)?;
        entries.push(Entry {
            curves: curve_statistics(&json),
            dem_beside: vectorized.is_some(),
            scene: scene.strip_prefix(root).unwrap_or(scene).display().to_string(),
            description: json["description"].as_str().unwrap_or("").to_owned(),
            name,
            summary,
        });
    }
    let index = root.join("docs/gallery.md");
    let tmp = index.with_extension("md.tmp");
    fs::write(&tmp, render(&entries)).with_context(|| format!("writing {}", tmp.display()))?;
    fs::rename(&tmp, &index)?;
    println!("wrote {} ({} scenes)", index.display(), entries.len());
    Ok(())
}

fn render(entries: &[Entry]) -> String {
    let mut md = String::from(
        "# Gallery\n\nEvery fixture scene and the demo, rendered by `cargo xtask gallery` (the previews are \
         the `preview.png` each run writes: hillshade × hypsometric tint, sea below the coastline, the \
         generated contours drawn on). Regenerate after changing a scene or the pipeline.\n",
    );
    for e in entries {
        let s = &e.summary;
        let total_ms: f64 = s["timings_ms"].as_array().map_or(0.0, |t| t.iter().filter_map(|x| x["ms"].as_f64()).sum());
        let source = if s["diffusion"].is_object() {
            format!(
                "`relief diffuse {scene}`: {curves} feature curves, {kb:.2} kB as JSON (Table 1's statistics), \
                 {solver} solve in {it} iterations (relative residual {res:.1e}), ",
                scene = e.scene,
                curves = e.curves.map_or(0, |c| c.0),
                kb = e.curves.map_or(0.0, |c| c.1 as f64 / 1000.0),
                solver = s["diffusion"]["solver"].as_str().unwrap_or("?"),
                it = s["diffusion"]["iterations"],
                res = s["diffusion"]["relative_residual"].as_f64().unwrap_or(f64::NAN),
            )
        } else if s["island"].is_object() {
            let i = &s["island"];
            format!(
                "`relief generate {scene}`: a coast of {coast} vertices, {hills} hill(s), {filters} perturbation \
                 filters, ",
                scene = e.scene,
                coast = i["coast_vertices"],
                hills = i["hills"],
                filters = i["perturbations"],
            )
        } else if s["gaussian"].is_object() {
            format!(
                "`relief generate {scene}`: {n} Gaussian primitives, ",
                scene = e.scene,
                n = s["gaussian"]["primitives"]
            )
        } else if s["orometry"].is_object() {
            let o = &s["orometry"];
            let t = &o["terrain"];
            let error = |name: &str| {
                let f = t["features"].as_array().and_then(|fs| fs.iter().find(|f| f[0] == name));
                100.0 * f.and_then(|f| f[2].as_f64()).unwrap_or(f64::NAN)
            };
            let types = o["types"].as_u64().unwrap_or(1);
            let target =
                if types > 1 { format!("the first of the type map's {types} types") } else { "the target".into() };
            let target_short = if types > 1 { "the first type" } else { "the target" };
            format!(
                "`relief generate {scene}`: a divide tree of {peaks} peaks (prominence EMD {emd:.3} against \
                 {target}); the terrain analysed again has {tpeaks} peaks at least {min} m prominent ({target_short} \
                 {target_peaks}), with largest histogram errors of {p:.1} % (prominence), {d:.1} % (dominance) and \
                 {i:.1} % (isolation) against the paper's 2–3, 2–3 and 8 %; ",
                scene = e.scene,
                peaks = o["peaks"],
                emd = o["prominence_emd"].as_f64().unwrap_or(f64::NAN),
                tpeaks = t["peaks"],
                min = t["min_prominence"],
                target_peaks = t["target_peaks"],
                p = error("prominence"),
                d = error("dominance"),
                i = error("isolation_distance"),
            )
        } else {
            format!(
                "`relief generate {scene}`: {nodes} nodes, histogram match KS {ks:.4}, ",
                scene = e.scene,
                nodes = s["graph"]["nodes"],
                ks = s["histogram_match"]["raster"].as_f64().unwrap_or(f64::NAN),
            )
        };
        let comparison = if e.dem_beside {
            format!(
                " ![{name}: the DEM](gallery/{name}-dem.png)\n\nThe scene's vector terrain (left, after its edits) beside the DEM it was \
                 vectorized from (right).\n",
                name = e.name
            )
        } else {
            comparison(&s["comparison"], &e.name)
        };
        let _ = write!(
            md,
            "\n## {name}\n\n{description}\n\n{source}{contours} contours on {levels} levels, {nx} × {ny} \
             heightfield, {total_ms:.0} ms.\n\n![{name}](gallery/{name}.png){comparison}\n",
            name = e.name,
            description = e.description,
            contours = s["contours"]["contours"],
            levels = s["contours"]["levels"],
            nx = s["heightfield"]["nx"],
            ny = s["heightfield"]["ny"],
        );
    }
    md
}

/// The §6.5 comparison of a terrain regrown from a DEM's contours, as a table, and the DEM's
/// preview to set beside ours; empty without one.
fn comparison(c: &serde_json::Value, name: &str) -> String {
    if !c.is_object() {
        return String::new();
    }
    let pair = |v: &serde_json::Value, digits: usize| {
        format!("{:.digits$} | {:.digits$}", v[0].as_f64().unwrap_or(f64::NAN), v[1].as_f64().unwrap_or(f64::NAN))
    };
    let d = &c["distance"];
    let mut out = format!(
        " ![{name}: the DEM](gallery/{name}-dem.png)\n\nOurs (left) against the DEM (right), as the paper's §6.5: \
         earth mover's distances of {e:.1} m (elevation), {s:.2}° (slope) and {a:.3} decades (MFD drainage area).\n\n\
         | | ours | DEM |\n|---|---|---|\n| max Strahler order | {st} |\n| mean slope (°) | {sl} |\n",
        e = d["elevation"].as_f64().unwrap_or(f64::NAN),
        s = d["slope_deg"].as_f64().unwrap_or(f64::NAN),
        a = d["log10_drainage_area"].as_f64().unwrap_or(f64::NAN),
        st = pair(&c["max_strahler"], 0),
        sl = pair(&c["mean_slope_deg"], 1),
    );
    for p in c["peaks"].as_array().into_iter().flatten() {
        let _ = writeln!(out, "| peaks ≥ {} m prominent | {} |", p["min_prominence"], pair(&p["peaks"], 0));
    }
    out
}
