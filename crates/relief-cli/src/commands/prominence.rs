//! `relief prominence`: the peaks, key saddles and divide tree of a DEM, and nothing else (no
//! basins, no descriptors): what a prominence user waits for, in the memory the flood needs. It
//! also reads akirmse/mountains' `.dvt` divide trees, and writes them.

use std::path::Path;

use anyhow::{Context as _, Result, bail};
use relief::heightfield::{Crs, GridSpec, Units};
use relief::orometry::{AnalysisOptions, DivideTree, Dvt, DvtGrid, Orometry, Peak, ProminenceBase, analyze};

use crate::cli::{Base, PeaksFormat, Positions, ProminenceArgs};
use crate::ui::Ui;
use crate::writes::Written;

/// `relief prominence`: analyses the DEM (or reads the tree), writes the files asked for, prints
/// the most prominent peaks (or everything as JSON).
pub(crate) fn prominence(args: &ProminenceArgs, ui: &mut Ui) -> Result<()> {
    let mut writes = ui.writes();
    writes.reads(&args.dem);
    if let Some(p) = &args.peaks {
        let form = match args.peaks_format {
            PeaksFormat::Csv => Written::Csv,
            PeaksFormat::Akirmse => Written::AkirmsePeaks,
        };
        writes.writes(p, form)?;
    }
    if let Some(p) = &args.divide_tree {
        writes.writes(p, Written::DivideTree)?;
    }
    writes.check()?;
    if is_dvt(&args.dem) {
        return from_tree(args, ui);
    }
    let read = ui.read_options();
    let dem = ui.read_with(&args.dem, &read)?;
    let lattice = match &args.divide_tree {
        Some(p) if is_dvt(p) => {
            Some(DvtGrid::for_grid(dem.grid(), dem.crs()).with_context(|| p.display().to_string())?)
        }
        _ => None,
    };
    let base = match args.base {
        Some(Base::Outlet) => ProminenceBase::Outlet,
        None if args.depressions => ProminenceBase::Outlet,
        Some(Base::SeaLevel) | None => ProminenceBase::SeaLevel,
    };
    let options = AnalysisOptions {
        sea_level: args.sea_level,
        min_prominence: args.min_prominence,
        base,
        depressions: args.depressions,
        ridge_lines: args.divide_tree.as_deref().is_some_and(|p| !is_dvt(p)),
    };
    let mut oro = ui.step("prominence", || analyze(&dem, &options))?;
    let geographic = dem.grid().units() == Units::Degrees;
    let (grid, crs) = (*dem.grid(), dem.crs().cloned());
    drop(dem);
    if args.positions == Positions::NwCorner {
        to_north_west_corners(&mut oro, &grid);
    }
    if let Some(p) = &args.peaks {
        let text = match args.peaks_format {
            PeaksFormat::Csv => relief::export::peaks_csv(&oro, geographic),
            PeaksFormat::Akirmse => relief::export::peaks_akirmse(&oro),
        };
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if let Some(p) = &args.divide_tree {
        let tree = DivideTree::from_orometry(&oro);
        let text = match lattice {
            Some(lattice) => Dvt { grid: lattice, tree, unlinked_saddles: 0, runoffs: 0 }.to_string(),
            None => relief::export::divide_tree_geojson(&tree, Some(&oro), crs.as_ref()),
        };
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if ui.quiet() {
        return Ok(());
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&oro)?);
    } else {
        print_text(args, &oro, &grid);
    }
    Ok(())
}

/// Moves every position of `oro` (peaks, saddles and their ridge lines, isolation limit points)
/// from its sample's centre to the sample's north-west corner: half a cell west and half a cell
/// north, as akirmse/mountains places a tile's samples.
fn to_north_west_corners(oro: &mut Orometry, grid: &GridSpec) {
    let half = grid.cell_size() * 0.5;
    let shift = |p: &mut [f64; 2]| {
        p[0] -= half.x;
        p[1] += half.y;
    };
    for p in &mut oro.peaks {
        shift(&mut p.position);
        if let Some(i) = p.isolation.as_mut() {
            shift(&mut i.to);
        }
    }
    for s in &mut oro.saddles {
        shift(&mut s.position);
        s.ridge.iter_mut().for_each(shift);
    }
}

/// Whether `path` names a `.dvt` file.
pub(crate) fn is_dvt(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("dvt"))
}

/// `relief prominence TREE.dvt`: the tree's prominences (down to the sea level, or 0, as akirmse
/// counts a land mass's top), pruned to `--min-prominence`, written and printed.
fn from_tree(args: &ProminenceArgs, ui: &mut Ui) -> Result<()> {
    if args.depressions {
        bail!("{}: --depressions analyses a DEM; a .dvt tree is read as it is", args.dem.display());
    }
    let text = std::fs::read_to_string(&args.dem).with_context(|| args.dem.display().to_string())?;
    let dvt = Dvt::parse(&text).with_context(|| args.dem.display().to_string())?;
    if dvt.runoffs > 0 {
        ui.warn(format_args!(
            "{}: {} runoffs ignored; prominences near the tile's edges may be too high (merge with \
             `merge_divide_trees -f` first)",
            args.dem.display(),
            dvt.runoffs
        ));
    }
    let base = f64::from(args.sea_level.unwrap_or(0.0));
    let tree = dvt.tree.pruned(args.min_prominence, base);
    let geographic = matches!(dvt.grid, DvtGrid::Degrees { .. });
    if let Some(p) = &args.peaks {
        let text = match args.peaks_format {
            PeaksFormat::Csv => relief::export::tree_peaks_csv(&tree, base, geographic),
            PeaksFormat::Akirmse => relief::export::tree_peaks_akirmse(&tree, base),
        };
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if let Some(p) = &args.divide_tree {
        let text = if is_dvt(p) {
            Dvt { tree: tree.clone(), unlinked_saddles: 0, runoffs: 0, ..dvt }.to_string()
        } else {
            let crs = geographic.then(|| Crs::from_epsg(4326)).transpose()?;
            relief::export::divide_tree_geojson(&tree, None, crs.as_ref())
        };
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if ui.quiet() {
        return Ok(());
    }
    let oro = tree.orometry(base);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&tree)?);
        return Ok(());
    }
    println!(
        "{}: {} peaks at least {} m prominent, {} saddles in the divide tree",
        args.dem.display(),
        tree.peaks.len(),
        args.min_prominence,
        tree.saddles.len()
    );
    let mut order: Vec<usize> = (0..tree.peaks.len()).collect();
    order.sort_by(|&a, &b| oro.prominence[b].total_cmp(&oro.prominence[a]).then(a.cmp(&b)));
    for k in order.into_iter().take(args.top) {
        let p = &tree.peaks[k];
        println!(
            "  #{k:<5} {:>9.1} m  prominence {:>8.1} m  at ({}, {})",
            p.elevation, oro.prominence[k], p.position.x, p.position.y
        );
    }
    Ok(())
}

/// The count and the most prominent peaks, with the neighbour their key saddle's ridge leads to.
fn print_text(args: &ProminenceArgs, oro: &Orometry, grid: &GridSpec) {
    let what = if args.depressions { "pits" } else { "peaks" };
    println!(
        "{}: {} {what} at least {} m prominent, {} saddles in the divide tree ({} × {} cells)",
        args.dem.display(),
        oro.peaks.len(),
        args.min_prominence,
        oro.saddles.len(),
        grid.nx(),
        grid.ny()
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
