//! `include/rbtrack.h` is what cbindgen makes of `src/capi/` now; `RBTRACK_BLESS=1`
//! rewrites it.

use std::path::Path;

#[test]
fn the_header_is_current() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).unwrap();
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(crate_dir.join("src/capi/mod.rs"))
        .generate()
        .expect("cbindgen reads src/capi/")
        .write(&mut generated);
    let generated = String::from_utf8(generated).unwrap();
    let path = crate_dir.join("include/rbtrack.h");
    if std::env::var_os("RBTRACK_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let kept = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        kept == generated,
        "{} is stale: run `RBTRACK_BLESS=1 cargo test -p rbtrack-ffi --test header` and commit it",
        path.display()
    );
}
