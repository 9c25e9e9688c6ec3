//! Helpers shared by the integration tests.

use std::path::PathBuf;

/// A fresh directory under the system's temporary one, named after the test file `test`,
/// the case `name`, the process and the time.
pub fn temp_dir(test: &str, name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let process = std::process::id();
    let dir = std::env::temp_dir().join(format!("rbtrack-{test}-{name}-{process}-{nanos}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
