//! Atomic file replacement: write a temporary file beside the target, sync it, rename it over.

use std::io::Write;
use std::path::Path;

use crate::{IoError, IoErrorKind};

/// Writes `bytes` to `path` so that readers see either the old file or the complete new one.
///
/// The temporary file lives in the target's directory (a rename across file systems would not be
/// atomic) and is named `.<name>.<pid>.<random>.tmp`; on any failure it is removed and no file
/// appears under the final name. A process killed outright (SIGKILL, a power cut) cannot remove
/// its own: the next write of the same name removes those whose process is gone ([`remove_stale`]).
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
    let name = path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
    remove_stale(dir, &name);
    let prefix = format!(".{name}.{}.", std::process::id());
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

/// How old a temporary file must be before it counts as abandoned where its writer's process
/// cannot be looked up (no `/proc`, or a name without a process id).
const STALE_AGE: std::time::Duration = std::time::Duration::from_secs(3600);

/// Removes the temporary files `.<name>.<pid>.<random>.tmp` in `dir` that a killed process left:
/// those of a process no longer running (Linux's `/proc`), or, where that cannot be told, older
/// than an hour. A live writer's file, this process's included, is left alone. Best effort:
/// failures are ignored, as the write that follows does not depend on it.
fn remove_stale(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let prefix = format!(".{name}.");
    for entry in entries.filter_map(Result::ok) {
        let file = entry.file_name();
        let Some(middle) = file.to_str().and_then(|f| f.strip_prefix(&prefix)).and_then(|f| f.strip_suffix(".tmp"))
        else {
            continue;
        };
        if abandoned(middle, &entry, STALE_AGE) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether the temporary file or folder `entry`, whose name (less its own prefix) starts
/// `<pid>.`, was abandoned by the process that made it: that process is no longer running
/// (Linux's `/proc`), or, where that cannot be told (no `/proc`, no number), `entry` is older than
/// `max_age`. This process's own are never abandoned. Atomic writes ([`write`]) and the facade's
/// output staging share this rule for cleaning up after a killed process.
pub fn abandoned(rest: &str, entry: &std::fs::DirEntry, max_age: std::time::Duration) -> bool {
    // `<pid>.<random>`; a name of its own (`a.b` beside `a`'s temporaries) has no number.
    match rest.split_once('.').and_then(|(pid, _)| pid.parse::<u32>().ok()) {
        Some(pid) if pid == std::process::id() => false,
        Some(pid) if Path::new("/proc/self").exists() => !Path::new("/proc").join(pid.to_string()).exists(),
        _ => entry.metadata().and_then(|m| m.modified()).is_ok_and(|t| t.elapsed().is_ok_and(|age| age > max_age)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_killed_writers_temporaries_go_and_live_ones_stay() {
        let dir = tempfile::tempdir().unwrap();
        let at = |f: &str| dir.path().join(f);
        // Process ids beyond Linux's maximum (2^22) are never running.
        let dead = format!(".out.tif.{}.aB3dE9.tmp", (1u32 << 22) + 7);
        let mine = format!(".out.tif.{}.Zz9Zz9.tmp", std::process::id());
        let other_output = format!(".other.tif.{}.aB3dE9.tmp", (1u32 << 22) + 7);
        for f in [&dead, &mine, &other_output, ".out.tif.notes"] {
            std::fs::write(at(f), b"partial").unwrap();
        }
        write(&at("out.tif"), b"whole").unwrap();
        assert_eq!(std::fs::read(at("out.tif")).unwrap(), b"whole");
        assert!(!at(&dead).exists() || !Path::new("/proc/self").exists(), "a dead writer's file stays");
        for kept in [&mine, &other_output, ".out.tif.notes"] {
            assert!(at(kept).exists(), "{kept} was removed");
        }
        // Nothing of this write is left behind.
        let left = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(left, if Path::new("/proc/self").exists() { 4 } else { 5 });
    }
}
