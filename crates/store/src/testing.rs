//! What the store's unit tests share.

use std::path::PathBuf;

/// A fresh scratch folder of a test (`vibroatlas-store-NAME` in the temp
/// dir), emptied first: one folder however often the tests run, left to
/// look at after a failure.
pub(crate) fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vibroatlas-store-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
