//! The browser page (`web/`) in headless Chromium: it tracks a real sequence, given as
//! lossless PNG frames, to the same boxes as `rbtrack track` on the same pixels, frame for
//! frame, for the three trackers (colour PF, RBPF, correlation filter); its runs of the
//! firmwares' synthetic scene give the firmwares' checksums; it loads again from its service worker with the network cut; and it tracks a
//! video file and the (fake) webcam as a person uses it, box dragged with the mouse.
//!
//! Needs Chromium (`$CHROMIUM`, else `/usr/bin/chromium`), Node with the harness's
//! packages (`npm ci --prefix web/test`), the `wasm32-unknown-unknown` target and the
//! shared sequences. Without Chromium or the packages the test is ignored, and the build
//! warns which is missing and how to install it (`build.rs`); without another of them it
//! says which and passes without running. With `RBTRACK_REQUIRE_BROWSER` set, as CI sets
//! it, a missing tool fails it. The screenshots and the boxes stay in `target/browser/`.

use rbtrack::tracker::Status;
use rbtrack_host::cli::TrackerKind;
use rbtrack_host::sequence::{shared_data_dir, GtOrigin, Sequence, GROUNDTRUTH_FILE};
use rbtrack_web::{cf_firmware_checksum, firmware_checksum};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Frames of the sequence tracked.
const FRAMES: usize = 40;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// What of the browser's tools the test needs may be missing, or `None` when all is there.
fn missing() -> Option<String> {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !Path::new(&chromium).is_file() {
        return Some(format!("no Chromium at {chromium} (set $CHROMIUM)"));
    }
    let node = Command::new("node").arg("--version").output();
    if !node.is_ok_and(|o| o.status.success()) {
        return Some("no node".into());
    }
    if !repo().join("web/test/node_modules/puppeteer-core").is_dir() {
        return Some("no web/test/node_modules: run npm ci --prefix web/test".into());
    }
    let targets = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output();
    if !targets.is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("wasm32-unknown-unknown"))
    {
        return Some("no wasm32-unknown-unknown target: rustup target add it".into());
    }
    None
}

/// Runs `command`, failing the test with its output if it fails; returns stdout.
fn run(command: &mut Command) -> String {
    let out = command.output().expect("runs");
    assert!(
        out.status.success(),
        "{command:?}: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
#[cfg_attr(
    no_browser,
    ignore = "needs Chromium and `npm ci --prefix web/test` (the build's warning says which is missing)"
)]
fn the_page_tracks_as_the_host_and_runs_the_firmware_scene() {
    if let Some(why) = missing() {
        assert!(
            std::env::var_os("RBTRACK_REQUIRE_BROWSER").is_none(),
            "RBTRACK_REQUIRE_BROWSER is set, but {why}"
        );
        println!("SKIPPED the browser test: {why}");
        return;
    }
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED the browser test: no ../shared/data folder with the real sequences");
        return;
    };
    let out = repo().join("target/browser");
    let _ = std::fs::remove_dir_all(&out);
    let dist = out.join("dist");
    run(Command::new("bash")
        .arg(repo().join("web/build.sh"))
        .arg(&dist));

    // The first frames of a real sequence, decoded by rbtrack, as PNG, and their ground truth.
    let name = "Crossing";
    let seq = Sequence::open(data.join(name), GtOrigin::of_shared(name)).unwrap();
    let dir = out.join(name);
    std::fs::create_dir_all(dir.join("img")).unwrap();
    for i in 0..FRAMES {
        let f = seq.frame(i).unwrap();
        let png = dir.join(format!("img/{:04}.png", i + 1));
        image::save_buffer(
            png,
            &f.bytes,
            f.width,
            f.height,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
    }
    let truth = std::fs::read_to_string(seq.dir.join(GROUNDTRUTH_FILE)).unwrap();
    let first: Vec<&str> = truth.lines().take(FRAMES).collect();
    std::fs::write(dir.join(GROUNDTRUTH_FILE), first.join("\n") + "\n").unwrap();
    let init = seq.init_box().unwrap();
    let init = format!("{},{},{},{}", init.x, init.y, init.w, init.h);

    let mut checksums = Vec::new();
    for (tracker, code) in [("pf", "1"), ("rbpf", "0"), ("cf", "2")] {
        let host_csv = out.join(format!("host_{tracker}.csv"));
        run(Command::new(env!("CARGO_BIN_EXE_rbtrack"))
            .args(["track", "--tracker", tracker, "--per-frame"])
            .arg(&host_csv)
            .arg(&dir));
        let page_out = out.join(format!("page_{tracker}"));
        let figures = run(Command::new("node")
            .arg(repo().join("web/test/browser.mjs"))
            .arg("--dist")
            .arg(&dist)
            .arg("--frames")
            .arg(dir.join("img"))
            .args(["--box", &init, "--tracker", code, "--out"])
            .arg(&page_out));
        println!("{tracker}: {figures}");
        let host = std::fs::read_to_string(&host_csv).unwrap();
        let page = std::fs::read_to_string(page_out.join("boxes.csv")).unwrap();
        assert_eq!(host.lines().count(), FRAMES + 1);
        for (h, p) in host.lines().zip(page.lines()) {
            assert_eq!(p, h, "{tracker}: the page's row differs from the host's");
        }
        assert_eq!(page.lines().count(), host.lines().count());
        let doc: serde_json::Value = serde_json::from_str(figures.trim()).unwrap();
        checksums
            .push([&doc["checksum"], &doc["cf_checksum"]].map(|c| c.as_str().unwrap().to_owned()));
        assert_eq!(doc["offline"], true, "a reload without the network works");
        assert!(page_out.join("screenshot.png").is_file());
    }
    // As a person uses it: the frames as a video, opened, the box dragged, Track pressed.
    let clip = out.join("clip.webm");
    let made = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-framerate", "30", "-i"])
        .arg(dir.join("img/%04d.png"))
        .args(["-c:v", "libvpx", "-b:v", "4M"])
        .arg(&clip)
        .status();
    if made.is_ok_and(|s| s.success()) {
        let video_out = out.join("page_video");
        let figures = run(Command::new("node")
            .arg(repo().join("web/test/browser.mjs"))
            .arg("--dist")
            .arg(&dist)
            .arg("--video")
            .arg(&clip)
            .args(["--box", &init, "--out"])
            .arg(&video_out));
        println!("video: {figures}");
        let doc: serde_json::Value = serde_json::from_str(figures.trim()).unwrap();
        let tracked = doc["frames"].as_u64().unwrap() as usize;
        assert!((FRAMES * 9 / 10..=FRAMES).contains(&tracked), "{figures}");
        let csv = std::fs::read_to_string(video_out.join("boxes.csv")).unwrap();
        // The page tracks a video with its default tracker, the correlation filter.
        let host = std::fs::read_to_string(out.join("host_cf.csv")).unwrap();
        let (page_rows, host_rows): (Vec<&str>, Vec<&str>) =
            (csv.lines().collect(), host.lines().collect());
        assert_eq!(
            page_rows[..2],
            host_rows[..2],
            "the header and the dragged box"
        );
        assert_eq!(page_rows.len(), tracked + 1);
    } else {
        println!("no ffmpeg with libvpx: the video path is not tried");
    }

    // The webcam path, on Chromium's fake camera (a moving test pattern), for 2 s.
    let figures = run(Command::new("node")
        .arg(repo().join("web/test/browser.mjs"))
        .arg("--dist")
        .arg(&dist)
        .args(["--webcam", "2", "--box", "280,200,80,80", "--out"])
        .arg(out.join("page_webcam")));
    println!("webcam: {figures}");
    let doc: serde_json::Value = serde_json::from_str(figures.trim()).unwrap();
    assert!(doc["steps"].as_u64().unwrap() >= 10, "{figures}");

    let host = [firmware_checksum(), cf_firmware_checksum()]
        .map(|c| format!("{:#018x}", c.expect("the firmware scene's run starts")));
    for page in &checksums {
        assert_eq!(page, &host, "the page's firmware-scene checksums");
    }
    for (host, var) in host
        .iter()
        .zip(["RBTRACK_FIRMWARE_CHECKSUM", "RBTRACK_CF_FIRMWARE_CHECKSUM"])
    {
        if let Ok(qemu) = std::env::var(var) {
            assert_eq!(host, qemu.trim(), "QEMU's ({var})");
        }
    }
    let host = host.join(", ");
    println!(
        "page, host checksum {host}; screenshots in {}",
        out.display()
    );
}

/// What `script` (an ES module, `MODULE` standing for `web/www/rbtrack.js`'s URL) prints
/// under Node, or `None` without Node.
fn page_module(script: &str, args: &[String]) -> Option<String> {
    let node = Command::new("node").arg("--version").output();
    if !node.is_ok_and(|o| o.status.success()) {
        println!("SKIPPED: no node");
        return None;
    }
    let module = format!(
        "{:?}",
        format!("file://{}", repo().join("web/www/rbtrack.js").display())
    );
    Some(run(Command::new("node")
        .args([
            "--input-type=module",
            "-e",
            &script.replace("MODULE", &module),
        ])
        .args(args)))
}

/// The page writes its CSV with `fixed` (`web/www/rbtrack.js`), which must round as Rust's
/// `{:.N}` does (half to even on the exact value; JavaScript's `toFixed` rounds halves up):
/// on multiples of 1/8 (a tie at 2 decimals every other one), Q16.16 values and others.
#[test]
fn the_pages_decimals_are_rusts() {
    let mut values: Vec<(f64, usize)> = (-40..40).map(|i| (i as f64 / 8.0, 2)).collect();
    let mut state = 12345u32;
    for digits in [2, 3, 4] {
        for _ in 0..200 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            values.push((f64::from(state as i32 >> 8) / 65536.0, digits));
        }
        values.push((0.1 + 0.2, digits));
        values.push((-0.0, digits));
    }
    let json: Vec<String> = values.iter().map(|(v, d)| format!("[{v:?},{d}]")).collect();
    let Some(out) = page_module(
        "import { fixed } from MODULE; \
         const values = JSON.parse(process.argv[1]); \
         console.log(values.map(([v, d]) => fixed(v, d)).join(' '));",
        &[format!("[{}]", json.join(","))],
    ) else {
        return;
    };
    let page: Vec<&str> = out.split_whitespace().collect();
    assert_eq!(page.len(), values.len());
    for ((v, d), p) in values.iter().zip(page) {
        assert_eq!(p, format!("{v:.d$}", d = *d), "{v:?} to {d} decimals");
    }
}

/// The page names the status numbers of its report (the core's `Status as u8`) as the
/// core names its statuses.
#[test]
fn the_pages_status_names_are_the_cores() {
    let Some(out) = page_module(
        "import { STATUS } from MODULE; console.log(STATUS.join(' '));",
        &[],
    ) else {
        return;
    };
    let page: Vec<&str> = out.split_whitespace().collect();
    for status in [Status::Lost, Status::Uncertain, Status::Tracking] {
        let name = format!("{status:?}").to_lowercase();
        assert_eq!(page.get(status as usize), Some(&name.as_str()), "{page:?}");
    }
}

/// The page draws each tracker in the host tool's colour for it (`web/www/rbtrack.js`'s
/// `TRACKER_COLOURS`, by the page's tracker codes: 0 RBPF, 1 colour PF, 2 correlation
/// filter).
#[test]
fn the_pages_tracker_colours_are_the_hosts() {
    let Some(out) = page_module(
        "import { TRACKER_COLOURS } from MODULE; console.log(TRACKER_COLOURS.join(' '));",
        &[],
    ) else {
        return;
    };
    let host: Vec<String> = [TrackerKind::Rbpf, TrackerKind::Pf, TrackerKind::Cf]
        .map(|t| {
            let [r, g, b] = t.colour();
            format!("#{r:02x}{g:02x}{b:02x}")
        })
        .to_vec();
    assert_eq!(out.split_whitespace().collect::<Vec<_>>(), host);
}
