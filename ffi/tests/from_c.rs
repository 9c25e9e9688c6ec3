//! `from_c.c`, compiled by the system's C compiler (`$CC`, else `cc`) against
//! `include/rbtrack.h` and linked with the `librbtrack_ffi.a` built for this test, runs
//! clean: the status numbers and the error names as a C program sees them. Linux: the
//! link names the system libraries the host library needs there (as `c/build.sh host`).
#![cfg(target_os = "linux")]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The static library cargo built with this test's copy of the crate (the newest in its
/// `deps` folder).
fn static_library() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's path");
    let deps = exe.parent().expect("the test's folder");
    let libraries = std::fs::read_dir(deps)
        .expect("the deps folder")
        .filter_map(|e| {
            let path = e.ok()?.path();
            let name = path.file_name()?.to_str()?;
            let modified = path.metadata().ok()?.modified().ok()?;
            (name.starts_with("librbtrack_ffi-") && name.ends_with(".a"))
                .then_some((modified, path))
        });
    libraries
        .max()
        .map(|(_, path)| path)
        .expect("librbtrack_ffi.a beside the test")
}

#[test]
fn c_reads_the_status_order_and_the_error_names() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let library = static_library();
    let program = library.with_file_name("from_c");
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let built = Command::new(&cc)
        .args(["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(crate_dir.join("include"))
        .arg(crate_dir.join("tests/from_c.c"))
        .arg(&library)
        .args([
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
            "-o",
        ])
        .arg(&program)
        .output()
        .unwrap_or_else(|e| panic!("cannot run the C compiler {cc}: {e}"));
    assert!(
        built.status.success(),
        "{cc} from_c.c: {}",
        String::from_utf8_lossy(&built.stderr)
    );
    let run = Command::new(&program).output().expect("runs from_c");
    let out = String::from_utf8_lossy(&run.stdout);
    println!("{out}");
    assert!(run.status.success(), "{out}");
}
