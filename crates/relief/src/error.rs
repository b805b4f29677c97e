//! Errors of the facade, and the one place where a library error gets its scene location.
//!
//! **Convention.** A library error that concerns one element of its input says which, as
//! structured fields, and its `location()` turns them into a JSON path relative to the value the
//! library was given, using the library types' own field names (`curves[3].constraints[1].slope.theta`,
//! `regions[2].polygon`, `radius`). Since scenes embed the library types, that path continues the
//! scene path of the value: [`ReliefError::located`] joins the two, whatever the error, and keeps
//! the library error as the source.

use std::error::Error;
use std::path::PathBuf;

use thiserror::Error;

/// Why a scene could not be read, validated or run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReliefError {
    /// The scene is malformed or a value in it is invalid. `path` is the JSON path of the
    /// offending value (`generator.diffusion.curves[3].constraints[1].slope.theta`; empty for the
    /// whole document); `source` says why: the `serde_json::Error` (with line and column) of JSON
    /// that does not parse or does not fit the format, the library's own error for a value a
    /// library refused, a [`SceneError`] for a rule of the scene format, or the I/O error of an
    /// input file.
    #[error("{}: {source}", if path.is_empty() { "scene" } else { path.as_str() })]
    Scene {
        /// JSON path of the offending value (empty for the whole document).
        path: String,
        /// What is wrong.
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] crate::io::IoError),
    /// A scene or summary file could not be read or written.
    #[error("{}: {source}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// The failure.
        #[source]
        source: std::io::Error,
    },
    /// The scene asks for more than the [`crate::Budget`] allows; `path` is the JSON path of the
    /// value (or file) that does.
    #[error(
        "{path}: {requested} {what} is over the budget of {limit} (raise `Budget::max_{what}`, or `--max-{what}` in the CLI)"
    )]
    OverBudget {
        /// JSON path of the offending value.
        path: String,
        /// What is counted: `cells`, `particles`, `primitives`, `peaks` or `bytes` (of estimated
        /// memory).
        what: &'static str,
        /// How many the scene asks for.
        requested: u64,
        /// The cap.
        limit: u64,
    },
    /// The caller cancelled the run ([`crate::Progress::cancelled`]).
    #[error("cancelled")]
    Cancelled,
    /// A step of the pipeline failed on valid input (a bug or an exhausted resource).
    #[error("{step}: {source}")]
    Pipeline {
        /// The step.
        step: &'static str,
        /// What happened.
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
}

impl ReliefError {
    /// A scene error at `path`, caused by `source`.
    pub(crate) fn at(path: impl Into<String>, source: impl Into<Box<dyn Error + Send + Sync>>) -> Self {
        Self::Scene { path: path.into(), source: source.into() }
    }

    /// A scene error for a library error about the value at `prefix`: the path is `prefix`
    /// continued by the error's own [`Located::location`].
    pub(crate) fn located<E: Located>(prefix: &str, error: E) -> Self {
        let path = match error.location() {
            rel if rel.is_empty() => prefix.to_owned(),
            rel if prefix.is_empty() => rel,
            rel => format!("{prefix}.{rel}"),
        };
        Self::at(path, error)
    }

    /// A failure of pipeline step `step`.
    pub(crate) fn step(step: &'static str, source: impl Into<Box<dyn Error + Send + Sync>>) -> Self {
        Self::Pipeline { step, source: source.into() }
    }

    /// The JSON path of the offending scene value, for scene and budget errors.
    pub fn scene_path(&self) -> Option<&str> {
        match self {
            Self::Scene { path, .. } | Self::OverBudget { path, .. } => Some(path),
            _ => None,
        }
    }

    /// Whether the request was refused for asking more than a budget or read limit allows
    /// (before any of it was allocated), rather than failing: the CLI exits 2 for these.
    pub fn is_over_budget(&self) -> bool {
        match self {
            Self::OverBudget { .. } => true,
            Self::Io(e) => e.is_over_limit(),
            _ => false,
        }
    }
}

/// A rule of the scene format (rather than of a library) that a scene breaks.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene's `version` is not one this build reads.
    #[error("version {found} is not supported (this build reads {supported})")]
    UnsupportedVersion {
        /// The version found.
        found: u32,
        /// The version read.
        supported: u32,
    },
    /// Two alternatives were both given.
    #[error("give `{0}` or `{1}`, not both")]
    Conflict(&'static str, &'static str),
    /// Something required is missing.
    #[error("give {0}")]
    Missing(&'static str),
    /// A value is out of its range.
    #[error("{value} {rule}")]
    OutOfRange {
        /// The value, as written.
        value: String,
        /// What it must be.
        rule: &'static str,
    },
    /// A raster size is outside what a scene may ask for.
    #[error("{nx} x {ny}: each side must be in 2..={max}")]
    Resolution {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// Largest side.
        max: usize,
    },
    /// An output file's extension names no heightfield format relief writes.
    #[error("{}: not a heightfield format relief writes (use .exr, .png, .r16, .r32, .asc, .tif or .hgt)", path.display())]
    UnknownExtension {
        /// The output path.
        path: PathBuf,
    },
    /// An output's extension is not the one of the format it is written in.
    #[error("{}: this output is written as {format}; give it a .{extension} name", path.display())]
    WrongExtension {
        /// The output path.
        path: PathBuf,
        /// The format written.
        format: &'static str,
        /// The extension to give it.
        extension: &'static str,
    },
    /// Two outputs name the same file, so one would replace the other.
    #[error("{} is named by two outputs", path.display())]
    SharedOutput {
        /// The file.
        path: PathBuf,
    },
    /// An output path leaves the output folder (absolute, or climbing with `..`).
    #[error("{}: outputs are written inside the output folder (a relative path without `..`)", path.display())]
    OutsideOutputFolder {
        /// The path.
        path: PathBuf,
    },
    /// The terrain reaches outside the fixed vertical range its 16-bit outputs were asked to use.
    #[error("the terrain spans [{low}, {high}], outside [{min}, {max}]: widen the range or leave it out")]
    RangeTooNarrow {
        /// The range asked for.
        min: f32,
        /// Its top.
        max: f32,
        /// The terrain's lowest elevation.
        low: f32,
        /// Its highest.
        high: f32,
    },
    /// The generator needs an explicit `domain`.
    #[error("an {0} scene needs a domain in metres")]
    NeedsDomain(&'static str),
    /// A JSON input file (a vector terrain, atlas or descriptor) could not be read or parsed.
    #[error("{}: {source}", file.display())]
    JsonFile {
        /// The file.
        file: PathBuf,
        /// Why.
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
}

/// A library error that knows which element of its input it is about (see the module docs).
pub(crate) trait Located: Error + Send + Sync + 'static {
    /// JSON path of the offending value relative to the value the library was given; empty when
    /// the error concerns that value as a whole.
    fn location(&self) -> String;
}

/// Every library error with a `location()` of its own.
macro_rules! located {
    ($($error:ty),* $(,)?) => {$(
        impl Located for $error {
            fn location(&self) -> String {
                <$error>::location(self)
            }
        }
    )*};
}

located!(
    crate::contours::ContoursError,
    crate::diffusion::DiffusionError,
    crate::eden_growth::EdenError,
    crate::hydrology::HydrologyError,
    crate::island::IslandError,
    crate::warp::WarpError,
);

/// Errors about a value as a whole (no finer location).
macro_rules! whole {
    ($($error:ty),* $(,)?) => {$(
        impl Located for $error {
            fn location(&self) -> String {
                String::new()
            }
        }
    )*};
}

whole!(
    crate::gaussian_terrain::GaussianError,
    crate::heightfield::HeightfieldError,
    crate::io::IoError,
    crate::orometry::OrometryError,
    crate::poisson_sampling::PolygonError,
    SceneError,
);

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    use super::*;
    use crate::diffusion::DiffusionError;

    #[test]
    fn located_errors_join_the_scene_path_with_the_librarys_and_keep_the_source() {
        let theta = DiffusionError::InvalidConstraint {
            curve: 3,
            constraint: 1,
            field: "theta",
            value: 95.0,
            reason: "is bad",
        };
        let e = ReliefError::located("generator.diffusion", theta.clone());
        assert_eq!(e.scene_path(), Some("generator.diffusion.curves[3].constraints[1].slope.theta"));
        assert_eq!(e.to_string(), format!("generator.diffusion.curves[3].constraints[1].slope.theta: {theta}"));
        assert_eq!(e.source().and_then(|s| s.downcast_ref::<DiffusionError>()), Some(&theta));
        // An error about the value as a whole is located at the value; an empty prefix is the root.
        let grid = DiffusionError::GridTooSmall { nx: 1, ny: 1 };
        assert_eq!(ReliefError::located("generator.diffusion", grid.clone()).scene_path(), Some("generator.diffusion"));
        assert_eq!(ReliefError::located("", DiffusionError::NoElevation).scene_path(), Some("curves"));
        let whole = ReliefError::located("", grid);
        assert_eq!(whole.scene_path(), Some(""));
        assert!(whole.to_string().starts_with("scene: "), "{whole}");
        // Pipeline and I/O errors name no scene value.
        assert_eq!(ReliefError::step("drainage", SceneError::Missing("x")).scene_path(), None);
        let budget =
            ReliefError::OverBudget { path: "reconstruction.resolution".into(), what: "cells", requested: 9, limit: 1 };
        assert_eq!(budget.scene_path(), Some("reconstruction.resolution"));
    }
}
