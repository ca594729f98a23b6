//! Files written whole or not at all (issue 37): the bytes go to a temporary file beside the
//! destination, which is renamed over it only once complete. A process killed mid-write
//! (a closed window, a cluster's time limit, a full disk) leaves the previous file, or none,
//! never a truncated PNG, EXR or sidecar under the final name. A rename within one folder is
//! atomic on POSIX file systems; a destination that is a symbolic link is replaced by the file.

use anyhow::Context;
use std::path::{Path, PathBuf};

/// The temporary name `path` is written under first: hidden, beside it, per process.
pub fn partial_path(path: &Path) -> anyhow::Result<PathBuf> {
    let name = path
        .file_name()
        .with_context(|| format!("cannot write '{}': no file name", path.display()))?;
    let tmp = format!(".{}.partial-{}", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp))
}

/// Write `path` by way of [`partial_path`]: `write` fills the temporary file, which is then
/// renamed over `path`; on any error the temporary file is removed and `path` is untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let tmp = partial_path(path)?;
    let result = write(&tmp).and_then(|()| {
        std::fs::rename(&tmp, path).with_context(|| format!("cannot write '{}'", path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("refract-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp dir");
        d
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_partial_one() {
        let d = folder("fail");
        let out = d.join("image.exr");
        std::fs::write(&out, b"old").expect("old file");
        let r = write_atomically(&out, |tmp| {
            std::fs::write(tmp, b"half")?;
            anyhow::bail!("killed mid-write")
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&out).expect("old file"), b"old");
        let left: Vec<_> = std::fs::read_dir(&d).expect("dir").collect();
        assert_eq!(left.len(), 1, "the partial file is removed");
    }

    #[test]
    fn a_complete_write_replaces_the_file() {
        let d = folder("ok");
        let out = d.join("a.json");
        std::fs::write(&out, b"old").expect("old file");
        write_atomically(&out, |tmp| Ok(std::fs::write(tmp, b"new")?)).expect("write");
        assert_eq!(std::fs::read(&out).expect("new file"), b"new");
        assert!(!partial_path(&out).expect("partial").exists());
    }
}
