//! What a command may write, checked before it does any work: no output is one of its inputs
//! (relief never writes over what it reads), every output's extension names the format written
//! there, no two outputs share a file, and no output replaces an existing file unless `--force`.
//! The outputs' folders are created as needed.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result, bail};
use relief::io::Format;

/// What a command writes to a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Written {
    /// A heightfield, in the format its extension names.
    Heightfield,
    /// A PNG image.
    Png,
    /// JSON (a vector terrain, a descriptor, a scene summary).
    Json,
    /// GeoJSON (contours, a divide tree).
    GeoJson,
    /// An SVG drawing.
    Svg,
    /// A CSV table.
    Csv,
    /// A divide tree: GeoJSON, or akirmse/mountains' `.dvt` text.
    DivideTree,
    /// Lines of akirmse/mountains' `prominence.txt` (comma-separated, no header).
    AkirmsePeaks,
}

impl Written {
    /// The extensions that name this format (the first is the one to suggest).
    fn extensions(self) -> &'static [&'static str] {
        match self {
            Self::Heightfield => &["exr", "png", "r16", "r32", "asc", "tif", "hgt"],
            Self::Png => &["png"],
            Self::Json => &["json"],
            Self::GeoJson => &["geojson", "json"],
            Self::Svg => &["svg"],
            Self::Csv => &["csv"],
            Self::DivideTree => &["geojson", "json", "dvt"],
            Self::AkirmsePeaks => &["txt", "csv"],
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Heightfield => "a heightfield",
            Self::Png => "a PNG image",
            Self::Json => "JSON",
            Self::GeoJson => "GeoJSON",
            Self::Svg => "an SVG drawing",
            Self::Csv => "CSV",
            Self::DivideTree => "a divide tree (GeoJSON, or akirmse's .dvt)",
            Self::AkirmsePeaks => "akirmse's prominence.txt lines",
        }
    }

    /// Whether `path`'s extension names this format.
    fn fits(self, path: &Path) -> bool {
        if self == Self::Heightfield {
            return Format::from_extension(path).is_some_and(Format::is_writable);
        }
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        extension.is_some_and(|e| self.extensions().contains(&e.as_str()))
    }
}

/// The files one command reads and writes.
#[derive(Debug, Default)]
pub(crate) struct Writes {
    force: bool,
    inputs: Vec<PathBuf>,
    outputs: Vec<PathBuf>,
}

impl Writes {
    /// Nothing read or written yet; with `force`, existing outputs may be replaced.
    pub(crate) fn new(force: bool) -> Self {
        Self { force, ..Self::default() }
    }

    /// The command reads `path`.
    pub(crate) fn reads(&mut self, path: &Path) -> &mut Self {
        self.inputs.push(path.to_path_buf());
        self
    }

    /// The command reads every one of `paths`.
    pub(crate) fn reads_all(&mut self, paths: impl IntoIterator<Item = PathBuf>) -> &mut Self {
        self.inputs.extend(paths);
        self
    }

    /// The command writes `what` to `path`.
    ///
    /// # Errors
    /// When `path`'s extension is not that of the format written.
    pub(crate) fn writes(&mut self, path: &Path, what: Written) -> Result<&mut Self> {
        if !what.fits(path) {
            bail!(
                "{}: this command writes {} there; give it a .{} name",
                path.display(),
                what.name(),
                what.extensions()[0]
            );
        }
        self.outputs.push(path.to_path_buf());
        Ok(self)
    }

    /// The command writes `path`, in a format checked elsewhere (a scene's outputs, which the
    /// facade checks with their JSON paths).
    pub(crate) fn writes_file(&mut self, path: &Path) -> &mut Self {
        self.outputs.push(path.to_path_buf());
        self
    }

    /// Checks every output, then creates their folders.
    ///
    /// # Errors
    /// An output that is one of the inputs (naming both), that another output also names, that is
    /// a folder, or that exists without `--force`; a folder that cannot be created.
    pub(crate) fn check(&self) -> Result<()> {
        for (k, output) in self.outputs.iter().enumerate() {
            if let Some(input) = self.inputs.iter().find(|input| same_file(input, output)) {
                bail!("{}: refusing to write over {}, which this command reads", output.display(), input.display());
            }
            if self.outputs[..k].iter().any(|other| other == output || same_file(other, output)) {
                bail!("{}: named by two outputs, so one would replace the other", output.display());
            }
            if output.is_dir() {
                bail!("{}: is a folder, not a file", output.display());
            }
            if output.exists() && !self.force {
                bail!("{}: exists; give --force to replace it", output.display());
            }
        }
        for output in &self.outputs {
            create_parent(output)?;
        }
        Ok(())
    }
}

/// Creates the folder `path` goes into, if it has one.
pub(crate) fn create_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).with_context(|| format!("creating the folder {}", dir.display()))
        }
        _ => Ok(()),
    }
}

/// Whether `a` and `b` are the same existing file (through links, `..` or another spelling).
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b || same_inode(&a, &b),
        _ => false,
    }
}

#[cfg(unix)]
fn same_inode(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_: &Path, _: &Path) -> bool {
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_checked_against_inputs_formats_and_each_other() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("dem.asc");
        std::fs::write(&input, "x").unwrap();
        let spelled = dir.path().join("sub/../dem.asc");
        std::fs::create_dir(dir.path().join("sub")).unwrap();

        let mut w = Writes::new(true);
        w.reads(&input).writes(&spelled, Written::Heightfield).unwrap();
        let e = w.check().unwrap_err().to_string();
        assert!(e.contains("refusing to write over") && e.contains("dem.asc"), "{e}");

        for (path, what) in [("out.exr", Written::Png), ("t.asc", Written::Json), ("c.svg", Written::GeoJson)] {
            let e = Writes::new(false).writes(Path::new(path), what).unwrap_err().to_string();
            assert!(e.contains("give it a ."), "{e}");
        }
        assert!(Writes::new(false).writes(Path::new("T.PNG"), Written::Png).is_ok());
        assert!(Writes::new(false).writes(Path::new("c.json"), Written::GeoJson).is_ok());

        // An existing output needs --force; two outputs may not share a file.
        let e = Writes::new(false).writes(&input, Written::Heightfield).unwrap().check().unwrap_err().to_string();
        assert!(e.contains("--force"), "{e}");
        assert!(Writes::new(true).writes(&input, Written::Heightfield).unwrap().check().is_ok());
        let twice = dir.path().join("a.geojson");
        let mut w = Writes::new(true);
        w.writes(&twice, Written::GeoJson).unwrap().writes(&twice, Written::GeoJson).unwrap();
        assert!(w.check().unwrap_err().to_string().contains("two outputs"));

        // Folders are created for the outputs.
        let deep = dir.path().join("x/y/z.png");
        Writes::new(false).writes(&deep, Written::Png).unwrap().check().unwrap();
        assert!(deep.parent().unwrap().is_dir());
        let e = Writes::new(true).writes(&dir.path().join("x.png"), Written::Png).unwrap().check();
        assert!(e.is_ok());
    }
}
