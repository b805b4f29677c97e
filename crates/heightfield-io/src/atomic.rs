//! Atomic file replacement: write a temporary file beside the target, sync it, rename it over.

use std::io::Write;
use std::path::Path;

use crate::{IoError, IoErrorKind};

/// Writes `bytes` to `path` so that readers see either the old file or the complete new one.
///
/// The temporary file lives in the target's directory (a rename across file systems would not be
/// atomic) and is named `.<name>.<random>.tmp`; on any failure it is removed and no file appears
/// under the final name.
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_with(path, |w| w.write_all(bytes))
}

/// As [`write`], with the contents streamed by `fill` through a buffer (so large outputs need not
/// be held in memory first).
pub(crate) fn write_with(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<(), IoError> {
    let err = |e: std::io::Error| IoError::new(path, IoErrorKind::Io(e));
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let prefix = format!(".{}.", path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // Temporary files are private (0600) by default; the final file should get the usual
    // permissions, 0666 less the umask, like any file a program creates.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(err)?;
    {
        let mut buffered = std::io::BufWriter::with_capacity(1 << 16, tmp.as_file_mut());
        fill(&mut buffered).map_err(err)?;
        buffered.flush().map_err(err)?;
    }
    tmp.as_file().sync_all().map_err(err)?;
    // On failure `PersistError` hands the temporary file back; dropping it deletes it.
    tmp.persist(path).map_err(|e| err(e.error))?;
    Ok(())
}
