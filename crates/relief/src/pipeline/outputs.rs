//! Writing a generated terrain: heightfields, contours, the divide tree, the preview and the
//! summary, each atomically.

use std::path::{Path, PathBuf};

use super::Terrain;
use super::progress::{Progress, Timer};
use crate::error::SceneError;
use crate::heightfield::Heightfield;
use crate::io::Format;
use crate::scene::Outputs;
use crate::{ReliefError, ReliefError as E};

/// Width of the SVG drawing, in pixels.
const SVG_WIDTH: u32 = 1024;

/// Checks a scene's outputs before any work: every output's extension names the format it is
/// written in, and no two outputs share a file.
///
/// # Errors
/// [`ReliefError::Scene`] at the offending output's JSON path.
pub fn check_outputs(outputs: &Outputs) -> Result<(), ReliefError> {
    for (i, path) in outputs.heightfield.iter().enumerate() {
        if !Format::from_extension(path).is_some_and(Format::is_writable) {
            return Err(E::at(
                format!("outputs.heightfield[{i}]"),
                SceneError::UnknownExtension { path: path.clone() },
            ));
        }
    }
    if let Some(path) = &outputs.island_layers
        && !Format::from_extension(path).is_some_and(Format::is_writable)
    {
        return Err(E::at("outputs.island_layers", SceneError::UnknownExtension { path: path.clone() }));
    }
    let text = [
        ("contours_geojson", &outputs.contours_geojson, "GeoJSON", &["geojson", "json"][..]),
        ("contours_svg", &outputs.contours_svg, "SVG", &["svg"]),
        ("divide_tree", &outputs.divide_tree, "GeoJSON", &["geojson", "json"]),
        ("vector_terrain", &outputs.vector_terrain, "JSON", &["json"]),
        ("skeleton", &outputs.skeleton, "GeoJSON", &["geojson", "json"]),
        ("atlas", &outputs.atlas, "JSON", &["json"]),
        ("preview", &outputs.preview, "PNG", &["png"]),
        ("summary", &outputs.summary, "JSON", &["json"]),
    ];
    for (field, path, format, extensions) in text {
        let Some(path) = path else { continue };
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !extension.is_some_and(|e| extensions.contains(&e.as_str())) {
            let error = SceneError::WrongExtension { path: path.clone(), format, extension: extensions[0] };
            return Err(E::at(format!("outputs.{field}"), error));
        }
    }
    if let Some([min, max]) = outputs.range
        && !(min.is_finite() && max.is_finite() && min < max)
    {
        let error = SceneError::OutOfRange { value: format!("[{min}, {max}]"), rule: "must be finite with min < max" };
        return Err(E::at("outputs.range", error));
    }
    for (k, e) in outputs.engines.iter().enumerate() {
        for (field, size) in [("size", e.size), ("tile", e.tile)] {
            if let Some(size) = size {
                e.engine.check_size(size).map_err(|error| E::at(format!("outputs.engines[{k}].{field}"), error))?;
            }
        }
        if e.size.is_some() && e.tile.is_some() && e.size != e.tile {
            return Err(E::at(format!("outputs.engines[{k}]"), SceneError::Conflict("size", "tile")));
        }
        if outputs.engines[..k].iter().any(|o| o.folder() == e.folder()) {
            return Err(E::at(format!("outputs.engines[{k}].dir"), SceneError::SharedOutput { path: e.folder() }));
        }
        if let Some(splat) = &e.splat {
            splat.validate().map_err(|error| E::at(format!("outputs.engines[{k}].splat"), error))?;
        }
    }
    if let Some(mesh) = &outputs.mesh {
        check_mesh(mesh)?;
    }
    check_inside(outputs)?;
    let layers = outputs.island_layers.as_deref().map(layer_files).unwrap_or_default();
    let mut names: Vec<&Path> = outputs.heightfield.iter().map(PathBuf::as_path).collect();
    names.extend(layers.iter().map(PathBuf::as_path));
    names.extend(
        [
            &outputs.contours_geojson,
            &outputs.contours_svg,
            &outputs.divide_tree,
            &outputs.vector_terrain,
            &outputs.skeleton,
            &outputs.atlas,
            &outputs.preview,
            &outputs.summary,
        ]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path),
    );
    for (k, a) in names.iter().enumerate() {
        if names[..k].contains(a) {
            return Err(E::at("outputs", SceneError::SharedOutput { path: a.to_path_buf() }));
        }
    }
    Ok(())
}

/// Writes the outputs of `terrain` under `out_dir` (created if needed) and returns the files
/// written, in order. The summary, written last, includes the time spent writing the others and
/// lists the files written. When `out_dir` holds the summary of an earlier run, the files it
/// listed that this run does not write again are removed, so the folder ends with exactly this
/// run's files (files the earlier summary did not list are left alone).
///
/// The set is replaced as a whole: every file is first written to a hidden staging folder inside
/// `out_dir` (`.relief-staging.<pid>.<random>`), and only once all of them are complete are they
/// renamed into place, the summary last. A run that fails or is killed while writing leaves the
/// earlier set untouched; the staging folder a killed run leaves is removed by the next run into
/// the same folder once its process is gone.
///
/// # Errors
/// [`ReliefError::Scene`] for an output path with an unknown extension or two outputs naming one
/// file (checked before anything is written), [`ReliefError::Io`] / [`ReliefError::File`] when a
/// file cannot be written or a stale one removed.
pub fn write_outputs(
    terrain: &Terrain,
    outputs: &Outputs,
    out_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<Vec<PathBuf>, ReliefError> {
    check_outputs(outputs)?;
    std::fs::create_dir_all(out_dir).map_err(|source| ReliefError::File { path: out_dir.to_owned(), source })?;
    let earlier = outputs.summary.as_ref().map(|p| earlier_files(&out_dir.join(p))).unwrap_or_default();
    let staging = Staging::new(out_dir, outputs)?;
    let mut timer = Timer::new(progress);
    let mut staged = timer.step("write", || write_files(terrain, outputs, staging.path()))?;
    if let Some(p) = &outputs.summary {
        let path = staging.path().join(p);
        let mut summary = terrain.summary.clone();
        summary.timings_ms.extend(timer.timings);
        let files = staged.iter().chain([&path]).filter_map(|f| f.strip_prefix(staging.path()).ok());
        summary.files = files.map(Path::to_path_buf).collect();
        let mut text = serde_json::to_string_pretty(&summary).map_err(|e| E::step("summary", e))?;
        text.push('\n');
        crate::io::write_atomic(&path, text.as_bytes())?;
        staged.push(path);
    }
    let written = staging.publish(&staged, out_dir)?;
    for stale in earlier.iter().map(|f| out_dir.join(f)).filter(|f| !written.contains(f)) {
        match std::fs::remove_file(&stale) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(ReliefError::File { path: stale, source: e });
            }
            _ => {}
        }
    }
    Ok(written)
}

/// The hidden folder a run's outputs are written to before they replace the earlier set. Dropped
/// (the run failed), it is removed with whatever it holds.
struct Staging(tempfile::TempDir);

/// The name every staging folder starts with; the process id follows.
const STAGING: &str = ".relief-staging.";

impl Staging {
    /// A new staging folder in `out_dir`, after removing those that killed runs left, holding
    /// the folders the outputs' paths name.
    fn new(out_dir: &Path, outputs: &Outputs) -> Result<Self, ReliefError> {
        remove_abandoned_staging(out_dir);
        let prefix = format!("{STAGING}{}.", std::process::id());
        let dir = tempfile::Builder::new()
            .prefix(&prefix)
            .tempdir_in(out_dir)
            .map_err(|source| ReliefError::File { path: out_dir.to_owned(), source })?;
        for (_, path) in output_paths(outputs) {
            if let Some(parent) = dir.path().join(path).parent() {
                std::fs::create_dir_all(parent).map_err(|source| ReliefError::File { path: parent.into(), source })?;
            }
        }
        Ok(Self(dir))
    }

    fn path(&self) -> &Path {
        self.0.path()
    }

    /// Renames the `staged` files (complete, in order) to the same places under `out_dir`,
    /// creating the folders they need, and returns their final paths.
    fn publish(self, staged: &[PathBuf], out_dir: &Path) -> Result<Vec<PathBuf>, ReliefError> {
        let mut written = Vec::with_capacity(staged.len());
        for file in staged {
            let relative = file.strip_prefix(self.path()).map_err(|_| E::step("write", "a file outside staging"))?;
            let target = out_dir.join(relative);
            if let Some(parent) = target.parent() {
                std::fs::create_dir_all(parent).map_err(|source| ReliefError::File { path: parent.into(), source })?;
            }
            std::fs::rename(file, &target).map_err(|source| ReliefError::File { path: target.clone(), source })?;
            written.push(target);
        }
        debug_assert!(holds_no_file(self.path()), "every file staged is listed and published");
        Ok(written)
    }
}

/// Whether the folder `dir` (and its subfolders) holds no file.
fn holds_no_file(dir: &Path) -> bool {
    std::fs::read_dir(dir).into_iter().flatten().filter_map(Result::ok).all(|e| {
        let path = e.path();
        path.is_dir() && holds_no_file(&path)
    })
}

/// Removes the staging folders in `out_dir` whose run's process is no longer running (Linux's
/// `/proc`; elsewhere, those older than a day). Best effort: a folder that cannot be removed
/// only takes space.
fn remove_abandoned_staging(out_dir: &Path) {
    let Ok(entries) = std::fs::read_dir(out_dir) else { return };
    for entry in entries.filter_map(Result::ok) {
        let name = entry.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(STAGING)) else { continue };
        let day = std::time::Duration::from_secs(24 * 3600);
        if crate::io::abandoned(rest, &entry, day) && entry.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// The files an earlier run's summary at `path` lists, if it is one: plain relative names only
/// (nothing absolute and no `..`), so a run never removes anything outside its folder.
fn earlier_files(path: &Path) -> Vec<PathBuf> {
    let Ok(text) = crate::budget::read_json_text(path) else { return Vec::new() };
    let Ok(summary) = serde_json::from_str::<serde_json::Value>(&text) else { return Vec::new() };
    let Some(files) = summary.get("files").and_then(serde_json::Value::as_array) else { return Vec::new() };
    files
        .iter()
        .filter_map(serde_json::Value::as_str)
        .map(PathBuf::from)
        .filter(|f| f.components().all(|c| matches!(c, std::path::Component::Normal(_))))
        .collect()
}

/// A fixed vertical range must hold the whole terrain; checked before any file is written, so
/// that a range too narrow leaves no half-written set behind.
fn check_range(terrain: &Terrain, min: f32, max: f32) -> Result<(), ReliefError> {
    match terrain.heightfield.min_max() {
        Some((low, high)) if low < min || high > max => {
            Err(E::at("outputs.range", SceneError::RangeTooNarrow { min, max, low, high }))
        }
        _ => Ok(()),
    }
}

/// Every output but the summary, in order: heightfields, contours, divide tree, preview.
fn write_files(terrain: &Terrain, outputs: &Outputs, out_dir: &Path) -> Result<Vec<PathBuf>, ReliefError> {
    let mut written = Vec::new();
    let options = match outputs.range {
        Some([min, max]) => {
            let quantised = outputs
                .heightfield
                .iter()
                .any(|p| matches!(Format::from_extension(p), Some(Format::Png16 | Format::Png8 | Format::R16)));
            if quantised {
                check_range(terrain, min, max)?;
            }
            crate::io::WriteOptions::default().with_range(min, max)
        }
        None => crate::io::WriteOptions::default(),
    };
    for name in &outputs.heightfield {
        write_heightfield(&out_dir.join(name), &terrain.heightfield, &options, &mut written)?;
    }
    if let Some(name) = &outputs.contours_geojson {
        let path = out_dir.join(name);
        crate::io::write_atomic_with(&path, |w| {
            crate::export::write_contours_geojson(&terrain.contours, terrain.heightfield.crs(), w)
        })?;
        written.push(path);
    }
    if let Some(name) = &outputs.contours_svg {
        let text = crate::export::contours_svg(&terrain.contours, &terrain.heightfield.extent(), SVG_WIDTH);
        written.push(write_text(out_dir, name, &text)?);
    }
    if let (Some(name), Some(o)) = (&outputs.divide_tree, &terrain.summary.orometry) {
        written.push(write_text(
            out_dir,
            name,
            &crate::export::divide_tree_geojson(&o.tree, None, terrain.heightfield.crs()),
        )?);
    }
    if let Some(vector) = &terrain.vector {
        written.extend(write_vector(terrain, vector, outputs, out_dir)?);
    }
    if let (Some(name), Some(layers)) = (&outputs.island_layers, &terrain.layers) {
        for (path, layer) in layer_files(name).into_iter().zip([&layers.base, &layers.hills, &layers.filters]) {
            write_heightfield(&out_dir.join(path), layer, &crate::io::WriteOptions::default(), &mut written)?;
        }
    }
    for (k, e) in outputs.engines.iter().enumerate() {
        let dir = out_dir.join(e.folder());
        let exported = crate::engine::export(&terrain.heightfield, e.engine, &e.options(), &dir)
            .map_err(|error| E::at(format!("outputs.engines[{k}]"), error))?;
        written.extend(exported.files);
        written.extend(exported.splat_files.into_iter().flatten());
        written.push(exported.sidecar);
    }
    if let Some(m) = &outputs.mesh {
        let path = out_dir.join(&m.file);
        crate::engine::TerrainMesh::from_heightfield(&terrain.heightfield, &m.options())
            .and_then(|mesh| mesh.write_glb(&path, m.colours))
            .map_err(|error| E::at("outputs.mesh", error))?;
        written.push(path);
    }
    if let Some(name) = &outputs.preview {
        let path = out_dir.join(name);
        let image = crate::export::preview_image(&terrain.heightfield, Some(&terrain.contours), terrain.sea_level);
        crate::io::write_rgb_png(&path, &image)?;
        written.push(path);
    }
    Ok(written)
}

/// Refuses an output that would land outside the output folder: every path is relative and made
/// of plain names (no `..`, no root, no drive), so `--out` bounds what a scene can write.
fn check_inside(outputs: &Outputs) -> Result<(), E> {
    for (field, path) in output_paths(outputs) {
        let plain =
            path.components().all(|c| matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir));
        if !plain || path.as_os_str().is_empty() {
            return Err(E::at(field, SceneError::OutsideOutputFolder { path }));
        }
    }
    Ok(())
}

/// Every path the outputs name (files, and engine folders), each with its JSON path.
fn output_paths(outputs: &Outputs) -> Vec<(String, PathBuf)> {
    let mut paths: Vec<(String, PathBuf)> =
        outputs.heightfield.iter().enumerate().map(|(i, p)| (format!("outputs.heightfield[{i}]"), p.clone())).collect();
    let single = [
        ("island_layers", &outputs.island_layers),
        ("contours_geojson", &outputs.contours_geojson),
        ("contours_svg", &outputs.contours_svg),
        ("divide_tree", &outputs.divide_tree),
        ("vector_terrain", &outputs.vector_terrain),
        ("skeleton", &outputs.skeleton),
        ("atlas", &outputs.atlas),
        ("preview", &outputs.preview),
        ("summary", &outputs.summary),
    ];
    paths.extend(single.into_iter().filter_map(|(f, p)| p.clone().map(|p| (format!("outputs.{f}"), p))));
    paths.extend(outputs.engines.iter().enumerate().map(|(k, e)| (format!("outputs.engines[{k}].dir"), e.folder())));
    paths.extend(outputs.mesh.iter().map(|m| ("outputs.mesh.file".to_owned(), m.file.clone())));
    paths
}

/// A mesh output's file ends in `.glb` and its options pass [`crate::engine::MeshOptions::validate`].
fn check_mesh(mesh: &crate::scene::MeshOutput) -> Result<(), E> {
    if !mesh.file.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb")) {
        let error =
            SceneError::OutOfRange { value: mesh.file.display().to_string(), rule: "a mesh is written as .glb" };
        return Err(E::at("outputs.mesh.file", error));
    }
    match mesh.options().validate() {
        Err(error @ crate::engine::EngineError::InvalidMesh { field, .. }) => {
            Err(E::at(format!("outputs.mesh.{field}"), error))
        }
        _ => Ok(()),
    }
}

/// Writes `hf` to `path` in the format of its extension and records the file, after its companion
/// files (a raw format's sidecar), in `written`.
fn write_heightfield(
    path: &Path,
    hf: &Heightfield,
    options: &crate::io::WriteOptions,
    written: &mut Vec<PathBuf>,
) -> Result<(), ReliefError> {
    crate::io::write_with(path, hf, options)?;
    written.extend(Format::from_extension(path).map(|f| crate::io::companion_files(path, f)).unwrap_or_default());
    written.push(path.to_owned());
    Ok(())
}

/// The files `outputs.island_layers` names: `NAME-base.EXT`, `NAME-hills.EXT`, `NAME-filters.EXT`
/// beside `NAME.EXT`.
pub(crate) fn layer_files(name: &Path) -> Vec<PathBuf> {
    let stem = name.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let extension = name.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    ["base", "hills", "filters"].map(|layer| name.with_file_name(format!("{stem}-{layer}{extension}"))).to_vec()
}

/// A gaussian scene's vector terrain (compact JSON), crest skeleton and session atlas, as asked.
fn write_vector(
    terrain: &Terrain,
    vector: &super::VectorResult,
    outputs: &Outputs,
    out_dir: &Path,
) -> Result<Vec<PathBuf>, ReliefError> {
    let mut written = Vec::new();
    if let Some(name) = &outputs.vector_terrain {
        let text = serde_json::to_string(&vector.terrain).map_err(|e| E::step("vector terrain", e))?;
        written.push(write_text(out_dir, name, &text)?);
    }
    if let Some(name) = &outputs.skeleton {
        // The skeleton a scene reloading the terrain extracts: from its raster on this grid.
        let grid = terrain.heightfield.grid();
        let hf = crate::gaussian_terrain::rasterize(
            &vector.terrain,
            grid,
            &crate::gaussian_terrain::RasterOptions::default(),
        )
        .map_err(|e| E::at("outputs.skeleton", e))?;
        let (min_cells, spacing) = vector.skeleton.resolve(grid.len(), grid.extent().size().max_element());
        let skeleton = crate::vector::crest_skeleton(&hf, min_cells, spacing)?;
        let text = crate::export::skeleton_geojson(&skeleton, &vector.terrain, terrain.heightfield.crs())
            .map_err(|e| E::at("outputs.skeleton", e))?;
        written.push(write_text(out_dir, name, &text)?);
    }
    if let Some(name) = &outputs.atlas {
        let text = serde_json::to_string(&vector.atlas).map_err(|e| E::step("atlas", e))?;
        written.push(write_text(out_dir, name, &text)?);
    }
    Ok(written)
}

/// Writes `text` to `out_dir/name` atomically and returns the path.
fn write_text(out_dir: &Path, name: &Path, text: &str) -> Result<PathBuf, ReliefError> {
    let path = out_dir.join(name);
    crate::io::write_atomic(&path, text.as_bytes())?;
    Ok(path)
}
