//! Helpers shared by the CLI's integration tests (each binary uses a part of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root (scenes, vehicles and tracks are named relative to it).
pub fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// Run the `railsim` binary from the repository root: (exit code, stdout, stderr).
pub fn railsim(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_railsim"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh, empty temporary directory unique to this process, `group` and `name`.
pub fn temp_dir(group: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("railsim-{group}-{}-{name}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A copy in `dir` of the shipped scene `scenes/<name>` with the contact model `polach` (five
/// times cheaper than the shipped scenes' `stripes`) and its relative paths made absolute.
pub fn polach_copy(dir: &Path, name: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("scenes").join(name))
        .unwrap()
        .replace("model = \"stripes\"", "model = \"polach\"")
        .replace("\"../", &format!("\"{}/", root().display()));
    assert!(text.contains("model = \"polach\""), "{name}");
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The text of the shipped vehicle `vehicles/<name>`, to be changed and written elsewhere (the
/// shipped vehicles use the built-in wheel profiles and name no file, so a copy reads alike).
pub fn vehicle_text(name: &str) -> String {
    std::fs::read_to_string(root().join("vehicles").join(name)).unwrap()
}
