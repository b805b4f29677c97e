use std::path::PathBuf;

use thiserror::Error;

/// Why a scene could not be read, validated or run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReliefError {
    /// The scene is malformed; `path` is the JSON path of the offending value
    /// (e.g. `generator.contours.regions[2].polygon`).
    #[error("{}: {message}", if path.is_empty() { "scene" } else { path.as_str() })]
    Scene {
        /// JSON path of the offending value (empty for the whole document).
        path: String,
        /// What is wrong.
        message: String,
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
        source: std::io::Error,
    },
    /// A step of the pipeline failed on valid input (a bug or an exhausted resource).
    #[error("{step}: {message}")]
    Pipeline {
        /// The step.
        step: &'static str,
        /// What happened.
        message: String,
    },
}

impl ReliefError {
    /// A scene error at `path`.
    pub fn scene(path: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Self::Scene { path: path.into(), message: message.to_string() }
    }

    /// A pipeline error in `step`.
    pub fn pipeline(step: &'static str, message: impl std::fmt::Display) -> Self {
        Self::Pipeline { step, message: message.to_string() }
    }
}
