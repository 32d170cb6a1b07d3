//! Checks of output paths, made before any work: a typo in `-o` must not cost a whole load
//! and render first, nor leave an empty file behind.

use std::path::Path;

use anyhow::{Result, bail};

/// Fails unless `path` ends in one of `extensions` (case-insensitive, without the dot) and
/// its folder exists.
pub fn check(path: &Path, extensions: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !ext.as_deref().is_some_and(|e| extensions.contains(&e)) {
        bail!(
            "{}: the output must be a .{} file",
            path.display(),
            extensions.join(", .")
        );
    }
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(folder) = folder
        && !folder.is_dir()
    {
        bail!(
            "{}: the folder {} does not exist",
            path.display(),
            folder.display()
        );
    }
    Ok(())
}

/// Removes what a failed write left at `path` (a partial or empty file), so that a failure
/// leaves nothing that looks like a result.
pub fn discard(path: &Path) {
    if path.is_file() {
        let _ = std::fs::remove_file(path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_and_folder_are_checked() {
        assert!(check(Path::new("a.png"), &["png"]).is_ok());
        assert!(check(Path::new("A.PNG"), &["png"]).is_ok());
        assert!(check(Path::new("a.jpg"), &["png"]).is_err());
        assert!(check(Path::new("noext"), &["png"]).is_err());
        assert!(check(Path::new("/no/such/folder/a.png"), &["png"]).is_err());
        let dir = std::env::temp_dir();
        assert!(check(&dir.join("x.glb"), &["glb", "stl"]).is_ok());
    }
}
