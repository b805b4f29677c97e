//! `relief analyze`: hydrology (closed basins, the contours paper's §6.5 descriptors, an optional
//! comparison and filled output) and orometry (peaks, divide tree, descriptor, nearest reference)
//! of a heightfield, computed first and then printed as text or JSON.

use anyhow::{Context as _, Result};
use relief::heightfield::{Heightfield, Units};
use relief::hydrology::{CountHistogram, Depressions, DescriptorDistance, DescriptorOptions, Descriptors, Outlets};
use relief::orometry::{AnalysisOptions, Descriptor, DivideTree, Orometry, Peak};

use crate::cli::AnalyzeArgs;
use crate::ui::Ui;
use crate::writes::Written;

/// What `relief analyze` found.
struct Analysis {
    /// Closed basins of the DEM.
    closed: Depressions,
    /// The DEM's hydrological descriptors.
    descriptors: Descriptors,
    /// Distances to the descriptors of the `--compare` heightfield.
    distance: Option<DescriptorDistance>,
    /// Peaks and saddles of the DEM.
    orometry: Orometry,
    /// The DEM's orometric descriptor (Table 1 histograms).
    oro_descriptor: Descriptor,
    /// Its artefact measures (border trench, pits, slots, planar facets).
    artefacts: relief::hydrology::Artefacts,
    /// The nearest `--classify` reference: label and mean EMD.
    nearest: Option<(String, f64)>,
}

/// `relief analyze`: closed basins, descriptors, orometry, an optional comparison and filled output.
pub(crate) fn analyze(args: &AnalyzeArgs, ui: &mut Ui) -> Result<()> {
    check_files(args, ui)?;
    let analysis = compute(args, ui)?;
    if ui.quiet() {
        return Ok(());
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&json(args, &analysis))?);
    } else {
        print_text(args, &analysis);
    }
    Ok(())
}

/// The files `analyze` reads and writes, checked before any work.
fn check_files(args: &AnalyzeArgs, ui: &Ui) -> Result<()> {
    let mut writes = ui.writes();
    writes.reads(&args.dem);
    for path in args.compare.iter().chain(&args.classify) {
        writes.reads(path);
    }
    let outputs = [
        (&args.filled, Written::Heightfield),
        (&args.peaks, Written::Csv),
        (&args.divide_tree, Written::DivideTree),
        (&args.descriptor, Written::Json),
    ];
    for (path, what) in outputs {
        if let Some(path) = path {
            writes.writes(path, what)?;
        }
    }
    writes.check()
}

/// Reads the DEM, runs orometry then hydrology on it, and writes the files the flags ask for.
fn compute(args: &AnalyzeArgs, ui: &mut Ui) -> Result<Analysis> {
    let read = ui.read_options();
    let read = if args.degrees { read.with_units(Units::Degrees) } else { read };
    let dem = ui.read_with(&args.dem, &read)?;
    let (orometry, oro_descriptor) = orometry(ui, &dem, args)?;
    let nearest = nearest_reference(&oro_descriptor, args)?;
    let outlets = args.sea_level.map_or_else(Outlets::new, |s| Outlets::new().with_sea_level(s));
    let options = DescriptorOptions { outlets, ..DescriptorOptions::default() };
    let closed = ui.step("depressions", || relief::hydrology::depressions(&dem, outlets))?;
    let descriptors = ui.step("descriptors", || Descriptors::of(&dem, &options))?;
    let other = match &args.compare {
        Some(p) => {
            let dem = ui.read(p)?;
            Some(ui.step("descriptors", || Descriptors::of(&dem, &options))?)
        }
        None => None,
    };
    if let Some(out) = &args.filled {
        let dem = ui.step("fill", || relief::hydrology::fill(&dem, outlets))?;
        ui.step("write", || relief::io::write(out, &dem))?;
    }
    let distance = other.as_ref().map(|o| descriptors.distance(o));
    let sea = args.sea_level.map(f64::from);
    let artefacts = relief::hydrology::measure_artefacts_with_basins(&dem, sea, &closed.basins);
    Ok(Analysis { closed, descriptors, distance, orometry, oro_descriptor, artefacts, nearest })
}

/// Orometry of `dem` and its descriptor, with the peaks, divide tree and descriptor files the
/// flags ask for written.
fn orometry(ui: &mut Ui, dem: &Heightfield, args: &AnalyzeArgs) -> Result<(Orometry, Descriptor)> {
    let options = AnalysisOptions {
        sea_level: args.sea_level,
        min_prominence: args.min_prominence,
        ridge_lines: args.divide_tree.as_deref().is_some_and(|p| !super::prominence::is_dvt(p)),
        ..AnalysisOptions::default()
    };
    let (oro, descriptor) = ui.step("orometry", || Descriptor::of(dem, &options))?;
    let geographic = dem.grid().units() == Units::Degrees;
    if let Some(p) = &args.peaks {
        ui.step("write", || relief::io::write_atomic(p, relief::export::peaks_csv(&oro, geographic).as_bytes()))?;
    }
    if let Some(p) = &args.divide_tree {
        let tree = DivideTree::from_orometry(&oro);
        let text = if super::prominence::is_dvt(p) {
            relief::export::divide_tree_dvt(&tree, dem.grid(), dem.crs()).with_context(|| p.display().to_string())?
        } else {
            relief::export::divide_tree_geojson(&tree, Some(&oro), dem.crs())
        };
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    if let Some(p) = &args.descriptor {
        let text = serde_json::to_string_pretty(&descriptor)?;
        ui.step("write", || relief::io::write_atomic(p, text.as_bytes()))?;
    }
    Ok((oro, descriptor))
}

/// The `--classify` reference nearest to `descriptor` (label = file stem, mean EMD), if any.
fn nearest_reference(descriptor: &Descriptor, args: &AnalyzeArgs) -> Result<Option<(String, f64)>> {
    let mut references = Vec::with_capacity(args.classify.len());
    for p in &args.classify {
        let text = relief::budget::read_json_text(p).with_context(|| format!("reading {}", p.display()))?;
        let d: Descriptor =
            serde_json::from_str(&text).with_context(|| format!("{} is not a descriptor", p.display()))?;
        d.validate().with_context(|| format!("{}", p.display()))?;
        let label = p.file_stem().map_or_else(|| p.display().to_string(), |s| s.to_string_lossy().into_owned());
        references.push((label, d));
    }
    let nearest = relief::orometry::classify(descriptor, references.iter().map(|r| &r.1))?;
    Ok(nearest.map(|(k, d)| (references[k].0.clone(), d)))
}

/// The whole analysis as one JSON value.
fn json(args: &AnalyzeArgs, a: &Analysis) -> serde_json::Value {
    let basins = &a.closed.basins;
    serde_json::json!({
        "path": args.dem,
        "closed_basins": basins.len(),
        "closed_volume_m3": basins.iter().map(|b| b.volume_m3).sum::<f64>(),
        "basins": basins,
        "descriptors": a.descriptors,
        "compared_with": args.compare,
        "distance": a.distance,
        "artefacts": a.artefacts,
        "orometry": {
            "peaks": a.orometry.peaks.len(),
            "min_prominence": args.min_prominence,
            "highest": a.orometry.peaks.first(),
            "descriptor": a.oro_descriptor,
            "nearest": a.nearest.as_ref().map(|(label, d)| serde_json::json!({ "label": label, "mean_emd": d })),
        },
    })
}

/// The analysis as an aligned text report on stdout.
fn print_text(args: &AnalyzeArgs, a: &Analysis) {
    let basins = &a.closed.basins;
    let deepest = basins.iter().max_by(|x, y| x.depth().total_cmp(&y.depth()));
    let volume: f64 = basins.iter().map(|b| b.volume_m3).sum();
    let d = &a.descriptors;
    println!("{}", args.dem.display());
    println!(
        "  closed basins   {}{}",
        basins.len(),
        deepest.map_or_else(String::new, |b| format!(
            " (holding {volume:.4e} m³; deepest {:.3} at ({}, {}), spills at {:.3})",
            b.depth(),
            b.pit.0,
            b.pit.1,
            b.fill_level
        ))
    );
    println!("  max Strahler    {} (streams from {:.4e} m²)", d.max_strahler, d.stream_area_m2);
    println!("  median slope    {:.2}°", median(&d.slope_deg));
    println!("  median log10 A  {:.3} (drainage area in m², Freeman MFD)", median(&d.log10_drainage_area));
    let t = &a.artefacts;
    let step = |m: Option<f64>| m.map_or_else(|| "–".to_owned(), |m| format!("{m:.2} m"));
    println!(
        "  artefacts       border step {} (next step in {}); pits over 1 m {}, over 20 m {}; slots {}; planar {:.1} %",
        step(t.border_step_m),
        step(t.next_step_m),
        t.pits_over_1m,
        t.pits_over_20m,
        t.slots,
        100.0 * t.planar_share
    );
    println!("  peaks           {} (prominence ≥ {} m)", a.orometry.peaks.len(), args.min_prominence);
    let mut by_prominence: Vec<&Peak> = a.orometry.peaks.iter().collect();
    by_prominence.sort_by(|x, y| y.prominence.total_cmp(&x.prominence));
    for p in by_prominence.iter().take(5) {
        println!(
            "    {:>9.1} m  prominence {:>8.1} m  at ({}, {}){}",
            p.elevation,
            p.prominence,
            p.position[0],
            p.position[1],
            if p.edge_effect { "  (edge effect)" } else { "" }
        );
    }
    if let Some((label, d)) = &a.nearest {
        println!("  nearest type    {label} (mean EMD {d:.4})");
    }
    if let (Some(d), Some(p)) = (&a.distance, &args.compare) {
        println!("compared with {} (earth mover's distances)", p.display());
        println!("  elevation       {:.3}", d.elevation);
        println!("  slope           {:.3}°", d.slope_deg);
        println!("  log10 area      {:.3}", d.log10_drainage_area);
        println!("  Strahler        {:+}", d.strahler);
    }
}

/// The median of a histogram: where its CDF crosses ½, by bisection to f64 precision over
/// `[lo, hi]` (60 halvings).
fn median(h: &CountHistogram) -> f64 {
    let (mut lo, mut hi) = (h.lo, h.hi);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if h.cdf(mid) < 0.5 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}
