//! The workspace folder: the only place the studio reads and writes. Names coming from requests
//! are plain file names; paths inside scenes are relative and never climb out.

use std::path::{Component, Path, PathBuf};

use axum::http::StatusCode;
use relief::Scene;

use crate::StudioError;
use crate::error::ApiError;

/// The longest file name accepted.
const MAX_NAME: usize = 100;

/// The extensions an uploaded input may have: heightfields, images, vector terrains, GeoJSON.
const INPUT_EXTENSIONS: [&str; 13] =
    ["png", "jpg", "jpeg", "bmp", "webp", "exr", "tif", "tiff", "asc", "hgt", "r16", "json", "geojson"];

/// The workspace folder, resolved once.
#[derive(Debug)]
pub(crate) struct Workspace {
    root: PathBuf,
}

impl Workspace {
    /// Creates `dir` if missing and resolves it.
    pub(crate) fn open(dir: &Path) -> Result<Self, StudioError> {
        let at = |source| StudioError::Workspace { path: dir.to_owned(), source };
        std::fs::create_dir_all(dir).map_err(at)?;
        Ok(Self { root: dir.canonicalize().map_err(at)? })
    }

    /// The folder.
    pub(crate) fn root(&self) -> &Path {
        &self.root
    }

    /// The saved scenes' names (`*.json` that parse as scenes are not checked here), sorted.
    pub(crate) fn scenes(&self) -> Result<Vec<String>, ApiError> {
        let entries = std::fs::read_dir(&self.root).map_err(ApiError::internal)?;
        let mut names: Vec<String> = entries
            .filter_map(Result::ok)
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .filter_map(|e| e.file_name().into_string().ok())
            .filter(|n| is_json(n) && check_name(n).is_ok())
            .collect();
        names.sort();
        Ok(names)
    }

    /// The text of scene `name`.
    pub(crate) fn read_scene(&self, name: &str) -> Result<String, ApiError> {
        let path = self.scene_path(name)?;
        std::fs::read_to_string(&path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => ApiError::not_found(format!("no scene {name}")),
            _ => ApiError::internal(e),
        })
    }

    /// Saves `text` as scene `name`, atomically.
    pub(crate) fn write_scene(&self, name: &str, text: &str) -> Result<(), ApiError> {
        let path = self.scene_path(name)?;
        write_atomic(&path, text.as_bytes())
    }

    /// Saves an uploaded input file `name`, atomically.
    pub(crate) fn write_input(&self, name: &str, bytes: &[u8]) -> Result<(), ApiError> {
        check_name(name)?;
        let extension = Path::new(name).extension().and_then(|e| e.to_str()).unwrap_or_default().to_ascii_lowercase();
        if !INPUT_EXTENSIONS.contains(&extension.as_str()) {
            let error = format!("{name}: an input is one of .{}", INPUT_EXTENSIONS.join(", ."));
            return Err(ApiError::new(StatusCode::UNSUPPORTED_MEDIA_TYPE, error));
        }
        write_atomic(&self.root.join(name), bytes)
    }

    /// Refuses a scene that reads a file outside the workspace: every input path must be
    /// relative and made of plain names.
    pub(crate) fn check_inputs(scene: &Scene) -> Result<(), ApiError> {
        for file in scene.input_files() {
            if !file.components().all(|c| matches!(c, Component::Normal(_))) {
                let error = format!(
                    "{}: a studio scene reads files inside its workspace only (a relative path without `..`)",
                    file.display()
                );
                return Err(ApiError::new(StatusCode::FORBIDDEN, error));
            }
        }
        Ok(())
    }

    fn scene_path(&self, name: &str) -> Result<PathBuf, ApiError> {
        check_name(name)?;
        if !is_json(name) {
            return Err(ApiError::bad_request(format!("{name}: a scene's name ends in .json")));
        }
        Ok(self.root.join(name))
    }
}

/// Writes a temporary file beside `path`, then renames it over `path`; the library's atomic
/// write, which also removes what a killed studio's writes left (`.<name>.<pid>.….tmp`).
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ApiError> {
    relief::io::write_atomic(path, bytes).map_err(ApiError::internal)
}

/// Whether `name` ends in `.json` (any case).
fn is_json(name: &str) -> bool {
    Path::new(name).extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// A plain file name: 1 to 100 of `[A-Za-z0-9_.-]`, not starting with a dot.
pub(crate) fn check_name(name: &str) -> Result<(), ApiError> {
    let plain = name.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'-'));
    if !plain || name.is_empty() || name.len() > MAX_NAME || name.starts_with('.') {
        return Err(ApiError::bad_request(format!(
            "{name:?}: a file name is 1 to {MAX_NAME} letters, digits, `_`, `.` or `-`, not starting with a dot"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_plain() {
        for good in ["a.json", "island-2_b.json", "dem.tif", "x"] {
            assert!(check_name(good).is_ok(), "{good}");
        }
        let long = "a".repeat(MAX_NAME + 1);
        for bad in ["", ".json", "..", "../a.json", "a/b.json", "/etc/passwd", "a\\b", "a b.json", "é.json", &long] {
            assert!(check_name(bad).is_err(), "{bad}");
        }
        assert!(check_name(&"a".repeat(MAX_NAME)).is_ok());
    }
}
