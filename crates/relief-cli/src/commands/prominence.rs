//! `relief prominence`: the peaks, key saddles and divide tree of a DEM, and nothing else (no
//! basins, no descriptors): what a prominence user waits for, in the memory the flood needs.

use anyhow::Result;
use relief::heightfield::Units;
use relief::orometry::{AnalysisOptions, DivideTree, Orometry, Peak, analyze};

use crate::cli::ProminenceArgs;
use crate::ui::Ui;
use crate::writes::Written;

/// `relief prominence`: analyses the DEM, writes the files asked for, prints the most prominent
/// peaks (or everything as JSON).
pub(crate) fn prominence(args: &ProminenceArgs, ui: &mut Ui) -> Result<()> {
    let mut writes = ui.writes();
    writes.reads(&args.dem);
    if let Some(p) = &args.peaks {
        writes.writes(p, Written::Csv)?;
    }
    if let Some(p) = &args.divide_tree {
        writes.writes(p, Written::GeoJson)?;
    }
    writes.check()?;
    let read = ui.read_options();
    let dem = ui.read_with(&args.dem, &read)?;
    let options = AnalysisOptions { sea_level: args.sea_level, min_prominence: args.min_prominence };
    let oro = ui.step("prominence", || analyze(&dem, &options))?;
    let geographic = dem.grid().units() == Units::Degrees;
    let crs = dem.crs().cloned();
    drop(dem);
    if let Some(p) = &args.peaks {
        ui.step("write", || relief::io::write_atomic(p, relief::export::peaks_csv(&oro, geographic).as_bytes()))?;
    }
    if let Some(p) = &args.divide_tree {
        let text = relief::export::divide_tree_geojson(&DivideTree::from_orometry(&oro), Some(&oro), crs.as_ref());
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if ui.quiet() {
        return Ok(());
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&oro)?);
    } else {
        print_text(args, &oro);
    }
    Ok(())
}

/// The count and the most prominent peaks, with the neighbour their key saddle's ridge leads to.
fn print_text(args: &ProminenceArgs, oro: &Orometry) {
    println!(
        "{}: {} peaks at least {} m prominent, {} saddles in the divide tree",
        args.dem.display(),
        oro.peaks.len(),
        args.min_prominence,
        oro.saddles.len()
    );
    let mut by_prominence: Vec<(usize, &Peak)> = oro.peaks.iter().enumerate().collect();
    by_prominence.sort_by(|x, y| y.1.prominence.total_cmp(&x.1.prominence));
    for (k, p) in by_prominence.into_iter().take(args.top) {
        let saddle = p.key_saddle.map(|s| &oro.saddles[s]);
        println!(
            "  #{k:<5} {:>9.1} m  prominence {:>8.1} m  at ({}, {}){}{}",
            p.elevation,
            p.prominence,
            p.position[0],
            p.position[1],
            saddle.map_or_else(String::new, |s| format!(
                "  col {:.1} m to #{} (parent #{})",
                s.elevation,
                s.peaks[1],
                p.parent.unwrap_or(s.peaks[1])
            )),
            if p.edge_effect { "  (edge effect)" } else { "" }
        );
    }
}
