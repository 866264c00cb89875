//! The files a scene refers to (decks, robot descriptions): found relative to the scene's
//! directory, and each deck read once however many joints refer to it.

use super::checks::listed;
use crate::scene::{FieldPath, SceneError, Source};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The directory of the scene file, against which the files it names are resolved.
pub(super) fn scene_dir(src: &Source) -> &Path {
    src.file.parent().unwrap_or(Path::new(""))
}

/// The files of one kind read so far, by resolved path.
pub(super) type ReadOnce<D> = HashMap<PathBuf, D>;

/// The file `name` (at `path` in the scene), resolved, and its contents as `read` gives
/// them, read on its first use only; a reading error (its message) is at `path`.
pub(super) fn read_once<'a, D>(
    src: &Source,
    path: &FieldPath,
    name: &str,
    files: &'a mut ReadOnce<D>,
    read: impl FnOnce(&Path) -> Result<D, String>,
) -> Result<(PathBuf, &'a D), SceneError> {
    let file = scene_dir(src).join(name);
    if !files.contains_key(&file) {
        let d = read(&file).map_err(|e| src.error(path, e))?;
        files.insert(file.clone(), d);
    }
    let d = &files[&file];
    Ok((file, d))
}

/// The error of a reference at `path` to `missing` (e.g. `no *FLEXJOINT element 7`) that
/// deck `file` does not hold, listing the ids it does.
pub(super) fn not_in_file<T: ToString>(
    src: &Source,
    path: &FieldPath,
    missing: String,
    file: &Path,
    ids: impl Iterator<Item = T>,
) -> SceneError {
    let known: Vec<String> = ids.map(|k| k.to_string()).collect();
    let message = format!(
        "{missing} in {} (it has: {})",
        file.display(),
        listed(known)
    );
    src.error(path, message)
}
