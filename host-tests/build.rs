//! Says in `cargo test`'s output which browser test cannot run and what enables it.
//!
//! `tests/browser.rs` drives the page in Chromium through the harness's packages
//! (`web/test/node_modules`). Without either, this sets the cfg `no_browser`, under which
//! that test is `#[ignore]`d (listed as ignored, with the reason), and prints a warning
//! naming it and the command that installs what is missing. With `RBTRACK_REQUIRE_BROWSER`
//! set, as CI sets it, the test runs and fails instead.

use std::env;
use std::path::{Path, PathBuf};

/// The test that needs Chromium and the packages.
const TEST: &str = "browser::the_page_tracks_as_the_host_and_runs_the_firmware_scene";

fn main() {
    println!("cargo::rustc-check-cfg=cfg(no_browser)");
    println!("cargo::rerun-if-env-changed=CHROMIUM");
    println!("cargo::rerun-if-env-changed=RBTRACK_REQUIRE_BROWSER");
    let chromium = PathBuf::from(env::var_os("CHROMIUM").unwrap_or("/usr/bin/chromium".into()));
    let manifest = env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let web_test = Path::new(&manifest).join("../web/test");
    // Runs again when the packages come or go, and when Chromium does (its folder, while
    // it is missing).
    println!("cargo::rerun-if-changed={}", web_test.display());
    let watched = match chromium.parent() {
        Some(folder) if !chromium.is_file() && !folder.as_os_str().is_empty() => folder,
        _ => &chromium,
    };
    println!("cargo::rerun-if-changed={}", watched.display());

    let mut missing = Vec::new();
    if !chromium.is_file() {
        missing.push(format!(
            "no Chromium at {} (install it, e.g. `apt-get install chromium`, or set CHROMIUM)",
            chromium.display()
        ));
    }
    if !web_test.join("node_modules/puppeteer-core").is_dir() {
        missing.push("no web/test/node_modules (run `npm ci --prefix web/test`)".into());
    }
    if missing.is_empty() || env::var_os("RBTRACK_REQUIRE_BROWSER").is_some() {
        return;
    }
    println!("cargo::rustc-cfg=no_browser");
    println!(
        "cargo::warning=the browser test {TEST} will not run: {}",
        missing.join("; ")
    );
}
