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
    /// The scene asks for more than the [`crate::Budget`] allows; `path` is the JSON path of the
    /// value (or file) that does.
    #[error(
        "{path}: {requested} {what} is over the budget of {limit} (raise `Budget::max_{what}`, or `--max-{what}` in the CLI)"
    )]
    OverBudget {
        /// JSON path of the offending value.
        path: String,
        /// What is counted: `cells`, `particles`, `primitives` or `peaks`.
        what: &'static str,
        /// How many the scene asks for.
        requested: u64,
        /// The cap.
        limit: u64,
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
