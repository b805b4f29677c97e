//! What can go wrong exporting for an engine.

use crate::Engine;

/// Why an engine export failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EngineError {
    /// An engine name that is none of ours.
    #[error("unknown engine `{0}`: choose one of unity, unreal, godot, blender")]
    UnknownEngine(String),
    /// A heightmap or tile size the engine does not import.
    #[error("{engine} does not import {size}-sample heightmaps: use one of {legal}")]
    IllegalSize {
        /// The engine.
        engine: Engine,
        /// The size asked for.
        size: usize,
        /// The sizes it takes, as text.
        legal: String,
    },
    /// Every sample is no-data: there is nothing to export.
    #[error("the heightfield has no valid sample")]
    NoData,
    /// The tiling would need more tiles or samples than the limits allow.
    #[error("{what}: at most {max}")]
    TooLarge {
        /// What is too large, with its value.
        what: String,
        /// The limit.
        max: usize,
    },
    /// A heightfield could not be resampled or cut.
    #[error(transparent)]
    Heightfield(#[from] relief_heightfield::HeightfieldError),
    /// A mesh could not be built from the heightfield or TIN.
    #[error(transparent)]
    Tin(#[from] relief_tin::TinError),
    /// A glTF document could not be assembled.
    #[error("glTF: {0}")]
    Mesh(String),
    /// A mesh option is out of range.
    #[error("mesh option `{field}` {value}: {rule}")]
    InvalidMesh {
        /// The option's field in [`crate::MeshOptions`].
        field: &'static str,
        /// The value given, as text.
        value: String,
        /// What it must be.
        rule: String,
    },
    /// A splat option is out of range.
    #[error("splat option `{field}`: {reason}")]
    InvalidSplat {
        /// The option.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The flow mask could not be routed.
    #[error(transparent)]
    Hydrology(#[from] relief_hydrology::HydrologyError),
    /// A splat image could not be encoded.
    #[error("encoding {}: {reason}", path.display())]
    Encode {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        reason: String,
    },
    /// A file could not be written.
    #[error(transparent)]
    Io(#[from] relief_heightfield_io::IoError),
    /// The output folder could not be created.
    #[error("creating {}: {source}", path.display())]
    CreateDir {
        /// The folder.
        path: std::path::PathBuf,
        /// Why.
        source: std::io::Error,
    },
}
