//! DEM tools: `contours`, `convert`, `info` and `preview` work on an existing heightfield file.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result, bail};
use glam::DVec2;
use relief::contours::{ContourSet, Levels, extract_dem};
use relief::heightfield::Heightfield;
use relief::io::{Format, Quantisation};

use crate::cli::{ContoursArgs, ConvertArgs, ExportArgs, HeightfieldFormat, InfoArgs, PreviewArgs, TiffType};
use crate::ui::Ui;
use crate::writes::Written;

/// `relief contours`: contour lines of a DEM as GeoJSON and/or SVG.
pub(crate) fn contours(args: &ContoursArgs, ui: &mut Ui) -> Result<()> {
    let levels = match (args.interval, args.levels) {
        (Some(m), _) => Levels::Interval(m),
        (None, Some(k)) => Levels::Count(k),
        (None, None) => bail!("give --interval or --levels"),
    };
    let geojson = match (&args.geojson, &args.svg) {
        (None, None) => Some(PathBuf::from(format!(
            "{}.contours.geojson",
            args.dem.file_stem().unwrap_or(args.dem.as_os_str()).to_string_lossy()
        ))),
        (g, _) => g.clone(),
    };
    let mut writes = ui.writes();
    writes.reads(&args.dem);
    if let Some(path) = &geojson {
        writes.writes(path, Written::GeoJson)?;
    }
    if let Some(path) = &args.svg {
        writes.writes(path, Written::Svg)?;
    }
    writes.check()?;
    let dem = ui.read(&args.dem)?;
    let set = ui.step("contours", || dem_contours(&dem, &levels))?;
    ui.step("write", || -> Result<()> {
        if let Some(path) = &geojson {
            relief::io::write_atomic_with(path, |w| relief::export::write_contours_geojson(&set, dem.crs(), w))?;
        }
        if let Some(path) = &args.svg {
            relief::io::write_atomic(path, relief::export::contours_svg(&set, &dem.extent(), 1024).as_bytes())?;
        }
        Ok(())
    })?;
    ui.say(format_args!("{} contours on {} levels, {} vertices", set.len(), set.levels().len(), set.vertex_count()));
    for path in geojson.iter().chain(&args.svg) {
        ui.say(format_args!("  {}", path.display()));
    }
    Ok(())
}

/// Contours of `dem` at `levels`, resolved over the DEM's elevation range: multiples of an
/// interval (like `gdal_contour -i`) or evenly spaced levels (none on a flat DEM).
fn dem_contours(dem: &Heightfield, levels: &Levels) -> Result<ContourSet> {
    let Some((lo, hi)) = dem.min_max() else { bail!("the DEM has no valid sample") };
    let levels = levels.resolve(f64::from(lo), f64::from(hi))?;
    Ok(extract_dem(dem, &levels)?)
}

/// `relief convert`: the same heightfield in the format the output's extension names.
pub(crate) fn convert(args: &ConvertArgs, ui: &mut Ui) -> Result<()> {
    let (input, output) = (&args.input, &args.output);
    ui.writes().reads(input).writes(output, Written::Heightfield)?.check()?;
    let named = Format::from_extension(output).context("a heightfield extension")?;
    // `--format` only chooses among the formats the extension names (png8 for a .png).
    let format = match args.format.map(HeightfieldFormat::io) {
        None => named,
        Some(f) if f == named || (f == Format::Png8 && named == Format::Png16) => f,
        Some(_) => bail!("--format: {} names another format", output.display()),
    };
    let dem = ui.read(input)?;
    let dem = match args.size {
        Some((nx, ny)) => ui.step("resample", || dem.resample(nx, ny))?,
        None => dem,
    };
    let sample = match args.tiff_type {
        TiffType::F32 => relief::io::TiffSample::F32,
        TiffType::I16 => relief::io::TiffSample::I16,
    };
    let mut options = relief::io::WriteOptions::default()
        .with_format(format)
        .with_tiff_sample(sample)
        .with_pixel_is_area(args.pixel_is_area);
    if args.no_compress || args.compress {
        options = options.with_compress(args.compress);
    }
    if let Some([min, max]) = args.range {
        options = options.with_range(min, max);
    }
    ui.step("write", || relief::io::write_with(output, &dem, &options))?;
    ui.say(format_args!("{} ({} x {}) -> {} ({format:?})", input.display(), dem.nx(), dem.ny(), output.display()));
    Ok(())
}

/// `relief export`: heightmaps for an engine, or a glTF mesh, from a DEM or a scene's terrain.
pub(crate) fn export(args: &ExportArgs, ui: &mut Ui) -> Result<()> {
    let input = &args.input;
    check_export_options(args)?;
    let is_scene = input.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let dem = if is_scene {
        let scene = super::scenes::load(input, None)?;
        let base = input.parent().unwrap_or(Path::new("."));
        ui.writes().reads(input).reads_all(scene.input_files().into_iter().map(|p| base.join(p))).check()?;
        let budget = ui.budget();
        relief::pipeline::generate_with(&scene, base, &budget, ui)?.heightfield
    } else {
        ui.read(input)?
    };
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = input.file_stem().map_or_else(|| "export".into(), |s| s.to_string_lossy().into_owned());
        Path::new("relief-out").join(format!("{stem}-{}", args.engine.engine().map_or("gltf", |e| e.name())))
    });
    let Some(engine) = args.engine.engine() else {
        return export_mesh(args, &dem, &out, ui);
    };
    let options = relief::engine::ExportOptions {
        size: args.size,
        tile: args.tile,
        name: args.name.clone().unwrap_or_else(|| "heightmap".to_owned()),
        splat: args.splat.then(relief::engine::SplatOptions::default),
    };
    let prepared = ui.step("resample", || relief::engine::prepare(&dem, engine, &options))?;
    let mut writes = ui.writes();
    writes.reads(input);
    for (k, file) in prepared.file_names(&options.name).into_iter().enumerate() {
        for splat in prepared.splat_names(&options.name, k) {
            writes.writes_file(&out.join(splat));
        }
        writes.writes_file(&out.join(file));
    }
    writes.writes_file(&out.join(relief::engine::Prepared::sidecar_name(&options.name))).check()?;
    let exported = ui.step("write", || prepared.write(&options.name, &out))?;
    if exported.filled_no_data > 0 {
        ui.warn(format_args!("{} no-data samples written as the lowest elevation", exported.filled_no_data));
    }
    ui.say(format_args!("{}", exported.settings.summary()));
    let splats = exported.splat_files.iter().map(Vec::len).sum::<usize>();
    let splats = if splats > 0 { format!(", {splats} splat map(s)") } else { String::new() };
    ui.say(format_args!(
        "{} heightmap(s){splats} and {} in {}",
        exported.files.len(),
        exported.sidecar.file_name().unwrap_or_default().to_string_lossy(),
        out.display()
    ));
    Ok(())
}

/// Options that only one kind of export takes are refused with the other, and bad mesh bounds
/// before any work.
fn check_export_options(args: &ExportArgs) -> Result<()> {
    let has_mesh_options = args.max_error.is_some() || args.triangles.is_some() || args.no_colours;
    if args.engine.engine().is_none() {
        if args.splat || args.size.is_some() || args.tile.is_some() {
            bail!("--splat, --size and --tile go with a heightmap engine (unity, unreal, godot, blender), not gltf");
        }
    } else if has_mesh_options {
        bail!("--max-error, --triangles and --no-colours go with --for gltf");
    }
    if let Err(relief::engine::EngineError::InvalidMesh { field, value, rule }) = mesh_options_of(args).validate() {
        let flag = if field == "max_error_m" { "--max-error" } else { "--triangles" };
        bail!("{flag} {value}: {rule}");
    }
    Ok(())
}

/// The library's mesh options from `--max-error`, `--triangles` and `--no-colours`.
fn mesh_options_of(args: &ExportArgs) -> relief::engine::MeshOptions {
    let defaults = relief::engine::MeshOptions::default();
    relief::engine::MeshOptions {
        max_error_m: args.max_error,
        max_triangles: args.triangles.unwrap_or(defaults.max_triangles),
        colours: !args.no_colours,
    }
}

/// `relief export --for gltf`: the terrain as a decimated `.glb` mesh.
fn export_mesh(args: &ExportArgs, dem: &Heightfield, out: &Path, ui: &mut Ui) -> Result<()> {
    let options = mesh_options_of(args);
    let path = out.join(format!("{}.glb", args.name.as_deref().unwrap_or("terrain")));
    ui.writes().reads(&args.input).writes_file(&path).check()?;
    let mesh = ui.step("decimate", || relief::engine::TerrainMesh::from_heightfield(dem, &options))?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    ui.step("write", || mesh.write_glb(&path, options.colours))?;
    let (lo, hi) = mesh.bounds();
    ui.say(format_args!(
        "gltf: {} triangles, {} vertices, within {:.3} m of every sample; {:.1} × {:.1} m, {:.1} … {:.1} m (y up, metres: import as is)",
        mesh.triangles.len(),
        mesh.positions.len(),
        mesh.max_error_m,
        hi.x - lo.x,
        hi.y - lo.y,
        lo.z,
        hi.z
    ));
    ui.say(format_args!("{}", path.display()));
    Ok(())
}

/// `relief info`: size, extent, elevation range and no-data of a heightfield, as text or JSON.
pub(crate) fn info(args: &InfoArgs, ui: &mut Ui) -> Result<()> {
    let dem = ui.read(&args.dem)?;
    let codes = relief::io::quantisation(&args.dem)?;
    let text = if args.json { info_json(&args.dem, &dem, codes) } else { info_text(&args.dem, &dem, codes) };
    ui.say(format_args!("{text}"));
    Ok(())
}

fn info_text(path: &Path, dem: &Heightfield, codes: Option<Quantisation>) -> String {
    let grid = dem.grid();
    let (e, o, c) = (grid.extent(), outer_extent(grid), grid.cell_size());
    let (unit, units) = (grid.units().symbol(), grid.units().name());
    let crs = dem.crs().map_or_else(
        || "unknown (give --crs EPSG:n to label outputs)".to_owned(),
        |c| if c.epsg().is_some() { format!("{} ({c})", c.name()) } else { c.name() },
    );
    let stats = dem.statistics();
    let range = stats.map_or_else(
        || "no valid sample".to_owned(),
        |s| format!("{} .. {} (mean {:.3}, std dev {:.3})", s.min, s.max, s.mean, s.std_dev),
    );
    format!(
        "{}\n  crs        {crs}, {units}\n  size       {} x {} ({} samples)\n  extent     x {} .. {}, y {} .. {} ({unit}, sample centres)\n  corners    x {} .. {}, y {} .. {} ({unit}, the cells' outer edges)\n  cell size  {} x {} {unit}\n  elevation  {range}\n  no-data    {}",
        path.display(),
        dem.nx(),
        dem.ny(),
        grid.len(),
        e.min.x,
        e.max.x,
        e.min.y,
        e.max.y,
        o.min.x,
        o.max.x,
        o.min.y,
        o.max.y,
        c.x,
        c.y,
        dem.no_data_count()
    ) + &codes.map(codes_text).unwrap_or_default()
}

/// The extent of the cells' outer edges: the samples' extent grown by half a cell each way.
fn outer_extent(grid: &relief::heightfield::GridSpec) -> relief::heightfield::Extent {
    let (e, half) = (grid.extent(), 0.5 * grid.cell_size());
    relief::heightfield::Extent::new(e.min - half, e.max + half)
}

/// How a quantised file's codes read, for `info`.
fn codes_text(q: Quantisation) -> String {
    let (lo, hi, bits) = (q.lowest_code, q.highest_code, q.bits);
    if !q.from_metadata {
        return format!(
            "\n  codes      {bits}-bit without relief metadata: code / {hi}, so 0 .. 1 on a 1 m grid unless --z-range MIN,MAX and --cell-size S say what it means"
        );
    }
    let no_data = q.no_data_code.map_or(String::new(), |c| format!("; code {c} = no-data"));
    format!(
        "\n  codes      {bits}-bit: code {lo} = {} m .. code {hi} = {} m, step {:.6} m{no_data}",
        q.min,
        q.max,
        q.step()
    )
}

fn info_json(path: &Path, dem: &Heightfield, codes: Option<Quantisation>) -> String {
    let grid = dem.grid();
    let (e, o, c) = (grid.extent(), outer_extent(grid), grid.cell_size());
    let stats = dem.statistics();
    let value = serde_json::json!({
        "path": path,
        "nx": dem.nx(),
        "ny": dem.ny(),
        "extent": { "min": [e.min.x, e.min.y], "max": [e.max.x, e.max.y] },
        "outer_extent": { "min": [o.min.x, o.min.y], "max": [o.max.x, o.max.y] },
        "cell_size": [c.x, c.y],
        "units": grid.units().name(),
        "crs": dem.crs().map(|c| serde_json::json!({ "name": c.name(), "epsg": c.epsg(), "wkt": c.wkt() })),
        "min": stats.map(|s| s.min),
        "max": stats.map(|s| s.max),
        "mean": stats.map(|s| s.mean),
        "no_data": dem.no_data_count(),
        "codes": codes.map(|q| serde_json::json!({
            "bits": q.bits,
            "lowest_code": q.lowest_code,
            "highest_code": q.highest_code,
            "min": q.min,
            "max": q.max,
            "step": q.step(),
            "no_data_code": q.no_data_code,
            "from_metadata": q.from_metadata,
        })),
    });
    serde_json::to_string_pretty(&value).unwrap_or_default()
}

/// `relief preview`: a shaded-relief PNG, decimated to `--max-size`, optionally with contours.
pub(crate) fn preview(args: &PreviewArgs, ui: &mut Ui) -> Result<()> {
    ui.writes().reads(&args.dem).reads_all(args.inputs.clone()).writes(&args.output, Written::Png)?.check()?;
    let scene = match &args.inputs {
        Some(path) => Some(super::scenes::load(path, None)?),
        None => None,
    };
    let marks = scene.as_ref().zip(args.inputs.as_deref()).map(|(scene, path)| input_marks(scene, path, ui));
    let scene_sea = scene.as_ref().and_then(relief::overlay::scene_sea_level);
    let sea_level = args.sea_level.or(scene_sea).unwrap_or(0.0);
    let dem = ui.read(&args.dem)?;
    let dem = match args.max_size {
        Some(m) => decimate(dem, m as usize)?,
        None => dem,
    };
    let set = match args.contours {
        Some(interval) => Some(ui.step("contours", || dem_contours(&dem, &Levels::Interval(interval)))?),
        None => None,
    };
    let mut image = ui.step("shade", || relief::export::preview_image(&dem, set.as_ref(), Some(sea_level)));
    if let Some(marks) = &marks {
        draw_inputs(&mut image, marks, &dem, &args.dem, ui);
    }
    ui.step("write", || relief::io::write_rgb_png(&args.output, &image))?;
    ui.say(format_args!("wrote {} ({} x {})", args.output.display(), image.width, image.height));
    Ok(())
}

/// Draws `marks` over the preview of `dem` (read from `path`), with a warning when none lies over
/// it.
fn draw_inputs(
    image: &mut relief::io::RgbImage,
    marks: &[relief::overlay::Mark],
    dem: &Heightfield,
    path: &Path,
    ui: &Ui,
) {
    let extent = dem.extent();
    let over = |p: &DVec2| extent.contains(*p);
    if !marks.is_empty() && !marks.iter().flat_map(|m| &m.points).any(over) {
        ui.warn(format_args!(
            "none of the scene's inputs lies over {} (its extent is {:?} to {:?}): is it the scene this \
             heightfield came from?",
            path.display(),
            extent.min.to_array(),
            extent.max.to_array()
        ));
    }
    relief::overlay::draw_marks(image, marks, &extent);
}

/// The drawable inputs of `scene` (read from `path`), with a warning when it has none.
fn input_marks(scene: &relief::Scene, path: &Path, ui: &Ui) -> Vec<relief::overlay::Mark> {
    let marks = relief::overlay::scene_marks(scene);
    if marks.is_empty() {
        ui.warn(format_args!(
            "{} has no inputs to draw (regions from a label image, or a DEM as the target, are files of \
             their own: look at them directly)",
            path.display()
        ));
    }
    marks
}

/// `dem` resampled by the smallest integer stride that brings its longer side to at most
/// `max_size` (each side at least 2); unchanged if it already fits.
fn decimate(dem: Heightfield, max_size: usize) -> Result<Heightfield> {
    let side = dem.nx().max(dem.ny());
    if side <= max_size {
        return Ok(dem);
    }
    let stride = side.div_ceil(max_size);
    Ok(dem.resample(dem.nx().div_ceil(stride).max(2), dem.ny().div_ceil(stride).max(2))?)
}
