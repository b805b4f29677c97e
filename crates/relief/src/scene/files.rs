//! Which files a scene reads and which it writes, so that whoever runs it can check the two
//! apart (an output must never replace an input) and know what a run leaves in its folder.

use std::path::{Path, PathBuf};

use super::{GaussianSource, Generator, HistogramSource, OrometrySource, Outputs, Probability, Scene};
use crate::gaussian_terrain::Tool;
use crate::io::Format;

impl Scene {
    /// Every file the scene reads, as written in it (relative paths resolve against the scene
    /// file's directory): label and probability images, histogram and source DEMs, vector
    /// terrains, atlases, descriptors and control maps.
    pub fn input_files(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = Vec::new();
        match &self.generator {
            Generator::Contours(g) => {
                files.extend(g.label_image.as_ref().map(|l| l.path.as_path()));
                if let Some(HistogramSource::Dem(path)) = &g.histogram {
                    files.push(path);
                }
                if let Probability::Image { path, .. } = &g.probability {
                    files.push(path);
                }
                if let Some(input) = &g.contours {
                    files.extend(input.dem.as_deref());
                    files.extend(input.geojson.as_deref());
                }
            }
            Generator::Island(g) => files.extend(g.coastline_image.as_ref().map(|c| c.path.as_path())),
            Generator::Diffusion(_) => {}
            Generator::Gaussian(g) => {
                if let GaussianSource::Terrain { path } | GaussianSource::Dem { path, .. } = &g.source {
                    files.push(path);
                }
                files.extend(g.operations.iter().filter_map(|tool| match tool {
                    Tool::Paste { atlas, .. } => atlas.as_deref(),
                    _ => None,
                }));
            }
            Generator::Orometry(g) => {
                let (OrometrySource::Dem { path, .. } | OrometrySource::Descriptor { path }) = &g.source;
                files.push(path);
                files.extend(g.peak_density.as_deref());
                files.extend(g.elevation.as_deref());
                if let Some(types) = &g.types {
                    files.push(&types.map);
                    files.extend(types.sources.iter().map(|s| {
                        let (OrometrySource::Dem { path, .. } | OrometrySource::Descriptor { path }) = s;
                        path.as_path()
                    }));
                }
            }
        }
        files
    }

    /// Every file a run of the scene writes, relative to the output folder, in the order they are
    /// written (a raw heightfield's sidecar or an ASCII grid's `.prj` before it, the divide tree
    /// only for an orometry scene, the vector terrain, skeleton and atlas only for a gaussian one, the
    /// summary last).
    pub fn output_files(&self) -> Vec<PathBuf> {
        let o: &Outputs = &self.outputs;
        let mut files: Vec<PathBuf> = Vec::new();
        for path in &o.heightfield {
            files.extend(Format::from_extension(path).map(|f| crate::io::companion_files(path, f)).unwrap_or_default());
            files.push(path.clone());
        }
        files.extend(o.contours_geojson.clone());
        files.extend(o.contours_svg.clone());
        if matches!(self.generator, Generator::Orometry(_)) {
            files.extend(o.divide_tree.clone());
        }
        if matches!(self.generator, Generator::Gaussian(_)) {
            files.extend(o.vector_terrain.clone());
            files.extend(o.skeleton.clone());
            files.extend(o.atlas.clone());
        }
        if matches!(self.generator, Generator::Island(_))
            && let Some(name) = &o.island_layers
        {
            for path in crate::pipeline::layer_files(name) {
                files.extend(
                    Format::from_extension(&path).map(|f| crate::io::companion_files(&path, f)).unwrap_or_default(),
                );
                files.push(path);
            }
        }
        files.extend(o.preview.clone());
        files.extend(o.summary.clone());
        // The tiles' names depend on the terrain; the sidecar's does not.
        let sidecar = crate::engine::Prepared::sidecar_name(&crate::engine::ExportOptions::default().name);
        files.extend(o.engines.iter().map(|e| e.folder().join(&sidecar)));
        files.extend(o.mesh.as_ref().map(|m| m.file.clone()));
        files
    }
}
