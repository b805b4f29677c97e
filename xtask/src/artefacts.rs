//! `cargo xtask artefacts`: generates every gallery scene with the release `relief` binary and
//! prints the artefact measures its summary holds (`drainage.artefacts`: the border step beside
//! the next step in, closed pits, one-cell slots, planar facets), with the real Jacksboro DEM's
//! as the yardstick (`relief analyze --json`). It also writes the table to `docs/artefacts.md`,
//! so a change that brings an artefact back shows in the diff.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};

/// One table row from an `artefacts` JSON object.
fn row(name: &str, a: &serde_json::Value) -> String {
    let metres = |key: &str| a[key].as_f64().map_or_else(|| "–".to_owned(), |m| format!("{m:.1}"));
    let ratio = match (a["border_step_m"].as_f64(), a["next_step_m"].as_f64()) {
        (Some(b), Some(n)) if n > 0.0 => format!("{:.2}", b / n),
        _ => "–".to_owned(),
    };
    format!(
        "| {name} | {} | {} | {ratio} | {} | {} | {:.1} | {} | {:.1} |\n",
        metres("border_step_m"),
        metres("next_step_m"),
        a["pits_over_1m"],
        a["pits_over_20m"],
        a["deepest_pit_m"].as_f64().unwrap_or(0.0),
        a["slots"],
        100.0 * a["planar_share"].as_f64().unwrap_or(0.0),
    )
}

pub(crate) fn run(root: &Path) -> Result<()> {
    let relief = crate::gallery::release_relief(root)?;
    let work = root.join("target/artefacts");
    let mut table = String::from(
        "| scene | border step (m) | next step in (m) | ratio | pits > 1 m | pits > 20 m | deepest pit (m) | slots | planar (%) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let real = Command::new(&relief)
        .current_dir(root)
        .args(["analyze", "fixtures/dem/jacksboro.asc", "--json"])
        .output()
        .context("running relief analyze")?;
    let real: serde_json::Value = serde_json::from_slice(&real.stdout).context("relief analyze --json")?;
    table.push_str(&row("*Jacksboro (real DEM)*", &real["artefacts"]));
    for scene in &crate::gallery::fixture_scenes(root)? {
        let out = work.join(scene.file_stem().context("scene without a name")?);
        let name = crate::gallery::generate(&relief, root, scene, &out)?;
        let text = fs::read_to_string(out.join("summary.json")).with_context(|| format!("the summary of {name}"))?;
        let summary: serde_json::Value = serde_json::from_str(&text)?;
        table.push_str(&row(&name, &summary["drainage"]["artefacts"]));
    }
    print!("{table}");
    let mut doc = String::from(
        "# Artefact measures\n\n\
         Written by `cargo xtask artefacts`: every gallery scene generated as `relief generate` does, and\n\
         the measures its `summary.json` holds (`drainage.artefacts`), with the real Jacksboro DEM's\n\
         (`relief analyze --json`) as the yardstick. Land only (above the scene's sea level).\n\n\
         - *border step*: median |step| from each border sample to the one inward; *next step in*: the\n  \
           step after it, over the same samples. A ratio well over 1 is a trench along the border.\n\
         - *pits*: closed basins (not draining to the border, the sea or no-data) deeper than 1 m and\n  \
           20 m; craters and lakes a scene asks for count too.\n\
         - *slots*: samples lower than both neighbours along a row or a column, each rising steeper\n  \
           than 30°: slots one sample wide.\n\
         - *planar*: share of sloping land samples (gradient over 1 %) whose 3 × 3 neighbourhood is a\n  \
           plane to within 1 cm: flat facets.\n\n",
    );
    let _ = writeln!(doc, "{table}");
    fs::write(root.join("docs/artefacts.md"), doc).context("writing docs/artefacts.md")
}
