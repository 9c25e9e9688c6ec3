//! The `rbtrack` binary end to end: `demo`, `track` and `eval` on tiny generated OTB
//! sequences (synthetic scene frames written as PNG), a video made from them by ffmpeg and
//! a raw dump of them; their JSON, box and per-frame files; configuration by `--set` and
//! `--config`; and the error cases (one line on stderr, non-zero exit, no panic).

use rbtrack_host::cli::TrackerKind;
use rbtrack_host::config_fields::FIELDS;
use rbtrack_host::pixels::{Format, Frame};
use rbtrack_host::scene::{Scene, SceneConfig, Variant};
use rbtrack_host::sequence::GROUNDTRUTH_FILE;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// Frames of the generated sequences.
const FRAMES: usize = 6;

mod common;

fn temp_dir(name: &str) -> PathBuf {
    common::temp_dir("cli", name)
}

/// Frame width of the generated sequences, px.
const W: u32 = 96;
/// Frame height of the generated sequences, px.
const H: u32 = 72;

/// The frames of a tiny perspective scene.
fn scene(seed: u64) -> Scene {
    let mut config = SceneConfig::new(Variant::Perspective, seed);
    (config.width, config.height, config.frames) = (W, H, 10);
    Scene::new(config).unwrap()
}

/// Writes a tiny OTB-layout sequence into `dir`: `FRAMES` PNG frames of a 96x72
/// perspective scene and a 1-based ground-truth file. Returns the ground-truth lines.
fn write_sequence(dir: &Path, seed: u64) -> Vec<String> {
    let scene = scene(seed);
    std::fs::create_dir_all(dir.join("img")).unwrap();
    let mut lines = Vec::new();
    for i in 0..FRAMES {
        let rgb = scene.render(i).unwrap();
        let path = dir.join("img").join(format!("{:04}.png", i + 1));
        image::save_buffer(path, &rgb, W, H, image::ExtendedColorType::Rgb8).unwrap();
        let b = scene.truth(i).unwrap().bbox.to_one_based();
        lines.push(format!("{:.2},{:.2},{:.2},{:.2}", b.x, b.y, b.w, b.h));
    }
    std::fs::write(dir.join(GROUNDTRUTH_FILE), lines.join("\n") + "\n").unwrap();
    lines
}

/// Rewrites the ground truth of the sequence in `dir` from `truth`, the lines
/// [`write_sequence`] wrote, each box's `x, y, w, h` plus `change`. Returns the new lines.
fn rewrite_groundtruth(dir: &Path, truth: &[String], change: [f64; 4]) -> Vec<String> {
    let lines: Vec<String> = truth
        .iter()
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            let b: Vec<String> = v
                .iter()
                .zip(change)
                .map(|(v, d)| format!("{:.2}", v + d))
                .collect();
            b.join(",")
        })
        .collect();
    std::fs::write(dir.join(GROUNDTRUTH_FILE), lines.join("\n")).unwrap();
    lines
}

/// Rewrites the ground truth of the sequence in `dir` as 0-based boxes: `truth`, the
/// 1-based lines [`write_sequence`] wrote, each corner moved up and left by 1 px. Returns
/// the new lines.
fn rewrite_zero_based(dir: &Path, truth: &[String]) -> Vec<String> {
    rewrite_groundtruth(dir, truth, [-1.0, -1.0, 0.0, 0.0])
}

/// Rewrites the ground truth of the sequence in `dir`, `truth`, each box grown by 2 px on
/// every side. Returns the new lines.
fn grown(dir: &Path, truth: &[String]) -> Vec<String> {
    rewrite_groundtruth(dir, truth, [-2.0, -2.0, 4.0, 4.0])
}

fn rbtrack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rbtrack"))
        .args(args)
        .output()
        .expect("run rbtrack")
}

/// Runs rbtrack in `dir` (for commands that write into the working folder by default).
fn rbtrack_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rbtrack"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run rbtrack")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn json(o: &Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    let out = stdout(o);
    assert_eq!(out.trim().lines().count(), 1, "{out}");
    serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("{e}: {out}"))
}

/// A failure: non-zero exit, exactly one line on stderr naming the program, no panic.
fn assert_one_line_error(o: &Output, what: &str, contains: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "{what}: succeeded\n{err}");
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "{what}: {:?}",
        o.status
    );
    assert!(!err.contains("panicked"), "{what}: {err}");
    assert_eq!(err.lines().count(), 1, "{what}: {err:?}");
    assert!(err.starts_with("rbtrack"), "{what}: {err}");
    assert!(err.contains(contains), "{what}: {err:?} lacks {contains:?}");
}

#[test]
fn help_and_version() {
    let o = rbtrack(&["--help"]);
    assert!(o.status.success());
    let out = stdout(&o);
    for cmd in [
        "rbtrack demo",
        "rbtrack track",
        "rbtrack eval",
        "rbtrack paper",
    ] {
        assert!(out.contains(cmd), "{cmd} missing from {out}");
    }
    let o = rbtrack(&[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("Usage: rbtrack <COMMAND>"),
        "{}",
        stderr(&o)
    );
    for cmd in ["demo", "track", "eval", "paper"] {
        let o = rbtrack(&[cmd, "--help"]);
        assert!(o.status.success(), "{cmd} --help");
        assert!(
            stdout(&o).contains(&format!("Usage: rbtrack {cmd}")),
            "{}",
            stdout(&o)
        );
    }
    for flag in ["--version", "-V"] {
        let o = rbtrack(&[flag]);
        assert!(o.status.success());
        assert_eq!(
            stdout(&o).trim(),
            format!("rbtrack {}", env!("CARGO_PKG_VERSION"))
        );
    }
}

/// A reader that stops reading (`rbtrack ... | head -1`) ends the program quietly.
#[test]
fn closed_stdout_is_no_panic() {
    let dir = temp_dir("closed");
    write_sequence(&dir.join("data/Tiny"), 3);
    let data = dir.join("data");
    for args in [
        &["--help"][..],
        &[
            "eval",
            path(&data),
            "--particles",
            "25",
            "--out",
            path(&dir.join("plots")),
        ][..],
        &["track", path(&data.join("Tiny")), "--json"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_rbtrack"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(o.status.success(), "{args:?}: {:?} {err}", o.status);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn demo_writes_files_and_prints_a_table() {
    let dir = temp_dir("demo");
    let out = dir.join("out");
    let o = rbtrack(&["demo", "--out", path(&out), "--frames", "12"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let header = text
        .lines()
        .find(|l| l.starts_with("tracker"))
        .unwrap_or_else(|| panic!("no table header in {text}"));
    for col in ["AUC", "prec@20", "mIoU", "success", "ms/frame"] {
        assert!(header.contains(col), "{header}");
    }
    for tracker in ["cf", "rbpf", "pf"] {
        let row = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(tracker))
            .unwrap_or_else(|| panic!("no {tracker} row in {text}"));
        let numbers: Vec<f64> = row
            .split_whitespace()
            .skip(1)
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(numbers.len(), 5, "{row}");
        assert!(
            numbers[..4].iter().all(|v| (0.0..=1.0).contains(v)),
            "{row}"
        );
    }
    for file in ["strip.png", "demo.gif", "success.png", "precision.png"] {
        let p = out.join(file);
        assert!(p.is_file(), "{} missing", p.display());
        assert!(text.contains(&format!("wrote {}", p.display())), "{text}");
    }
    let strip = image::open(out.join("strip.png")).unwrap();
    assert!(strip.width() > 4 * 320 && strip.height() > 2 * 240);
    // Each tracker in its one colour: its ellipses and its curves.
    for file in ["strip.png", "success.png", "precision.png"] {
        let picture = image::open(out.join(file)).unwrap().into_rgb8();
        for tracker in TrackerKind::CORE {
            let drawn = picture.pixels().filter(|p| p.0 == tracker.colour()).count();
            assert!(drawn > 100, "{file}: {drawn} px of {tracker}'s colour");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn demo_runs_another_scene() {
    let dir = temp_dir("demo-scene");
    let out = dir.join("out");
    let o = rbtrack(&[
        "demo",
        "--out",
        path(&out),
        "--scene",
        "distractor",
        "--frames",
        "12",
        "--no-gif",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.starts_with("synthetic scene: distractor,"), "{text}");
    assert!(out.join("strip.png").is_file());
    assert!(!out.join("demo.gif").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// Every binning tracks, and the JSON names it.
#[test]
fn every_binning_tracks() {
    let dir = temp_dir("bins");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 4);
    for bins in ["rgb8x8x8", "rgb8x8x4", "yuv8x8x4", "luma64"] {
        let o = rbtrack(&[
            "track",
            path(&seq),
            "--json",
            "--bins",
            bins,
            "--tracker",
            "pf",
        ]);
        let json = json(&o);
        assert_eq!(json["bins"], bins);
        assert_eq!(json["frames"], FRAMES);
        assert!(json["miou"].as_f64().unwrap() > 0.3, "{bins}: {json}");
    }
    let o = rbtrack(&["track", path(&seq), "--bins", "rgb4"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--bins"), "{}", stderr(&o));
}

#[test]
fn track_json_boxes_and_overlay() {
    let dir = temp_dir("track");
    let seq = dir.join("Tiny");
    let truth = write_sequence(&seq, 3);
    let boxes = dir.join("boxes.txt");
    let overlay = dir.join("overlay");
    let o = rbtrack(&[
        "track",
        path(&seq),
        "--tracker",
        "rbpf",
        "--json",
        "--particles",
        "50",
        "--boxes",
        path(&boxes),
        "--overlay",
        path(&overlay),
    ]);
    let json = json(&o);
    assert_eq!(json["frames"], FRAMES);
    for key in ["auc", "prec20", "miou", "success_rate"] {
        let v = json[key].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&v), "{key} = {v}");
    }
    assert!(json["ms_per_frame"].as_f64().unwrap() >= 0.0);
    assert_eq!(json["sequence"], "Tiny");
    assert_eq!(json["tracker"], "rbpf");
    assert_eq!(json["particles"], 50);
    assert_eq!(json["box_origin"], "one-based");
    // The configuration used, every field, as --set spells it.
    let config = json["config"].as_object().unwrap();
    assert_eq!(config.len(), FIELDS.len());
    assert_eq!(config["variant"], "rbpf");
    assert_eq!(config["seed"], 1);
    assert_eq!(config["cue_mix"], "product");

    // One box per frame, in the ground truth's (1-based) convention, starting at the
    // initial box.
    let written = std::fs::read_to_string(&boxes).unwrap();
    let lines: Vec<&str> = written.lines().collect();
    assert_eq!(lines.len(), FRAMES);
    assert_eq!(lines[0], truth[0]);
    for l in &lines {
        assert_eq!(
            l.split(',').filter_map(|v| v.parse::<f64>().ok()).count(),
            4
        );
    }
    for i in 1..=FRAMES {
        assert!(overlay.join(format!("{i:04}.png")).is_file());
    }
    // The overlay carries a text panel in its top-left corner.
    let frame = image::open(overlay.join("0002.png")).unwrap().into_rgb8();
    let source = image::open(seq.join("img/0002.png")).unwrap().into_rgb8();
    assert!(frame.get_pixel(1, 1).0.iter().all(|&c| c < 100));
    assert_ne!(frame.get_pixel(1, 1), source.get_pixel(1, 1));

    // The text form: a table with the sequence's row.
    let o = rbtrack(&["track", path(&seq), "--tracker", "pf", "--format", "rgb565"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("prec@20"), "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("Tiny") && l.contains(" pf ")),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn per_frame_csv() {
    let dir = temp_dir("per-frame");
    let seq = dir.join("Tiny");
    let truth = write_sequence(&seq, 5);
    let csv = dir.join("sub/frames.csv");
    let o = rbtrack(&["track", path(&seq), "--per-frame", path(&csv)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header,
        [
            "frame",
            "x",
            "y",
            "w",
            "h",
            "cx",
            "cy",
            "hx",
            "hy",
            "vx",
            "vy",
            "confidence",
            "status"
        ]
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), FRAMES);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), header.len());
        assert_eq!(row[0], (i + 1).to_string());
        let confidence: f64 = row[11].parse().unwrap();
        assert!((0.0..=1.0).contains(&confidence), "{row:?}");
        assert!(
            ["tracking", "uncertain", "lost"].contains(&row[12]),
            "{row:?}"
        );
        // Box and ellipse agree: the box is the ellipse's, same centre.
        let v: Vec<f64> = row[1..9].iter().map(|v| v.parse().unwrap()).collect();
        assert!((v[0] + (v[2] - 1.0) / 2.0 - v[4]).abs() < 0.02, "{row:?}");
        assert!((v[1] + (v[3] - 1.0) / 2.0 - v[5]).abs() < 0.02, "{row:?}");
        assert!((v[2] - 2.0 * v[6]).abs() < 0.02, "{row:?}");
    }
    assert_eq!(rows[0][1..5].join(","), truth[0]);
    assert_eq!(rows[0][12], "tracking");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn set_and_config_file() {
    let dir = temp_dir("set");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 6);
    let s = path(&seq);

    let o = rbtrack(&[
        "track",
        s,
        "--tracker",
        "rbpf",
        "--json",
        "--set",
        "scale_per_row=0.1",
    ]);
    let with_slope = json(&o);
    assert_eq!(with_slope["config"]["scale_per_row"], 0.1);
    let o = rbtrack(&[
        "track",
        s,
        "--tracker",
        "rbpf",
        "--json",
        "--set",
        "cue_mix=average:0.5",
        "--set",
        "readout=robust_mean:8",
        "--set",
        "resampling=residual",
    ]);
    let config = &json(&o)["config"];
    assert_eq!(config["cue_mix"], "average:0.5");
    assert_eq!(config["readout"], "robust_mean:8.0");
    assert_eq!(config["resampling"], "residual");

    // TOML with the same names; --set wins over the file; `variant` and `seed` are the
    // defaults of --tracker and --seed.
    let toml = dir.join("tracker.toml");
    std::fs::write(
        &toml,
        "colour_sigma = 0.15\ncue_mix = \"average:0.25\"\nseed = 7\nvariant = \"pf\"\n\
         pixels_per_window = 200\n",
    )
    .unwrap();
    let o = rbtrack(&[
        "track",
        s,
        "--json",
        "--config",
        path(&toml),
        "--set",
        "colour_sigma=0.3",
    ]);
    let doc = json(&o);
    let config = &doc["config"];
    assert_eq!(config["colour_sigma"], 0.3);
    assert_eq!(config["cue_mix"], "average:0.25");
    assert_eq!(config["pixels_per_window"], 200);
    assert_eq!(
        (doc["tracker"].clone(), doc["seed"].clone()),
        ("pf".into(), 7.into())
    );
    assert_eq!(
        (config["variant"].clone(), config["seed"].clone()),
        ("pf".into(), 7.into())
    );
    let o = rbtrack(&[
        "track",
        s,
        "--json",
        "--config",
        path(&toml),
        "--seed",
        "2",
        "--tracker",
        "rbpf",
    ]);
    let doc = json(&o);
    assert_eq!(
        (doc["tracker"].clone(), doc["config"]["seed"].clone()),
        ("rbpf".into(), 2.into())
    );

    // The printed configuration reproduces the run: as a TOML file it gives the same scores.
    let printed = &with_slope["config"];
    let lines: Vec<String> = printed
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect();
    std::fs::write(&toml, lines.join("\n")).unwrap();
    let again = json(&rbtrack(&["track", s, "--json", "--config", path(&toml)]));
    assert_eq!(again["config"], *printed);
    assert_eq!(again["auc"], with_slope["auc"]);

    // Mistakes name the field, on one line.
    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "rbpf", "--set", "no_such_field=1"]),
        "unknown field",
        "no_such_field",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "rbpf", "--set", "colour_sigma=abc"]),
        "bad value",
        "colour_sigma",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "rbpf", "--set", "cue_mix=sum"]),
        "bad enum",
        "cue_mix",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "rbpf", "--set", "lost_below=0.9"]),
        "out of range (Config::validate)",
        "lost_below",
    );
    std::fs::write(&toml, "colour_sigma = 0.2\nno_such_key = 3\n").unwrap();
    assert_one_line_error(
        &rbtrack(&["track", s, "--config", path(&toml)]),
        "unknown field in the file",
        "no_such_key",
    );
    std::fs::write(&toml, "colour_sigma = [0.2]\n").unwrap();
    assert_one_line_error(
        &rbtrack(&["track", s, "--config", path(&toml)]),
        "bad TOML value",
        "colour_sigma",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Without --tracker, `track` runs the core's correlation-filter tracker, which takes the
/// `cf.` fields it has (its grid and scales among them) and refuses the others and the
/// particle filters' settings, naming the field.
#[test]
fn correlation_filter_by_default() {
    let dir = temp_dir("cf-default");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 9);
    let s = path(&seq);
    let doc = json(&rbtrack(&["track", s, "--json"]));
    assert_eq!(doc["tracker"], "cf");
    assert_eq!(doc["config"]["grid"], 16);
    let doc = json(&rbtrack(&[
        "track",
        s,
        "--json",
        "--set",
        "cf.grid=8",
        "--set",
        "cf.scales=4",
        "--set",
        "cf.cell=8",
    ]));
    let config = &doc["config"];
    assert_eq!((&config["grid"], &config["scales"]), (&8.into(), &4.into()));
    assert_eq!(config["cell"], 8);
    assert_one_line_error(
        &rbtrack(&["track", s, "--set", "colour_sigma=0.15"]),
        "a particle filter's setting",
        "colour_sigma",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--set", "cf.hog=31"]),
        "a setting the integer tracker has fixed",
        "cf.hog",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--set", "cf.grid=32"]),
        "a grid the host does not run",
        "cf.grid=32",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// The box convention is a flag: a 0-based file with --zero-based tracks as its 1-based
/// twin does.
#[test]
fn box_convention_is_stated() {
    let dir = temp_dir("convention");
    let one = dir.join("Tiny");
    let truth = write_sequence(&one, 8);
    let zero = dir.join("Tiny0");
    write_sequence(&zero, 8);
    let zero_lines = rewrite_zero_based(&zero, &truth);
    let boxes = dir.join("boxes0.txt");
    let a = json(&rbtrack(&["track", path(&one), "--json"]));
    let b = json(&rbtrack(&[
        "track",
        path(&zero),
        "--json",
        "--zero-based",
        "--boxes",
        path(&boxes),
    ]));
    assert_eq!(a["auc"], b["auc"]);
    assert_eq!(b["box_origin"], "zero-based");
    let written = std::fs::read_to_string(&boxes).unwrap();
    assert_eq!(written.lines().next(), Some(zero_lines[0].as_str()));
    // Read as 1-based, the same file is one pixel off.
    let c = json(&rbtrack(&["track", path(&zero), "--json", "--one-based"]));
    assert_eq!(c["box_origin"], "one-based");
    let o = rbtrack(&["track", path(&one), "--zero-based", "--one-based"]);
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn track_without_groundtruth_from_init() {
    let dir = temp_dir("nogt");
    let seq = dir.join("Tiny");
    let truth = write_sequence(&seq, 4);
    std::fs::remove_file(seq.join(GROUNDTRUTH_FILE)).unwrap();
    let boxes = dir.join("sub/boxes.txt");

    // Without --init the ground truth is needed.
    let o = rbtrack(&["track", path(&seq)]);
    assert_one_line_error(&o, "no ground truth", GROUNDTRUTH_FILE);

    let o = rbtrack(&[
        "track",
        path(&seq),
        "--init",
        &truth[0],
        "--json",
        "--boxes",
        path(&boxes),
    ]);
    let json = json(&o);
    assert_eq!(json["frames"], FRAMES);
    for key in ["auc", "prec20", "miou"] {
        assert!(json[key].is_null(), "{key}");
    }
    assert!(json["ms_per_frame"].as_f64().unwrap() >= 0.0);
    let written = std::fs::read_to_string(&boxes).unwrap();
    assert_eq!(written.lines().count(), FRAMES);
    assert_eq!(written.lines().next(), Some(truth[0].as_str()));
    let _ = std::fs::remove_dir_all(dir);
}

/// A raw dump replays exactly what the tracker saw: the frames as RGB565 back to back give
/// the same boxes as the PNG sequence converted to RGB565.
#[test]
fn raw_dump() {
    let dir = temp_dir("raw");
    let seq = dir.join("Tiny");
    let truth = write_sequence(&seq, 9);
    let scene = scene(9);
    for format in [Format::Rgb565Le, Format::Yuyv, Format::Uyvy, Format::Gray8] {
        let dump = dir.join(format!("dump.{format}"));
        let bytes: Vec<u8> = (0..FRAMES)
            .flat_map(|i| {
                let rgb = scene.render(i).unwrap();
                Frame::rgb888(W, H, rgb)
                    .unwrap()
                    .convert(format)
                    .unwrap()
                    .bytes
            })
            .collect();
        std::fs::write(&dump, bytes).unwrap();
        let (from_raw, from_png) = (dir.join("raw.txt"), dir.join("png.txt"));
        let layout = format!("{W}x{H}:{format}");
        let o = rbtrack(&[
            "track",
            path(&dump),
            "--raw",
            &layout,
            "--init",
            &truth[0],
            "--groundtruth",
            path(&seq.join(GROUNDTRUTH_FILE)),
            "--boxes",
            path(&from_raw),
            "--json",
        ]);
        let doc = json(&o);
        assert_eq!(doc["frames"], FRAMES);
        assert_eq!(doc["format"], format.name());
        assert_eq!(doc["sequence"], "dump");
        let o = rbtrack(&[
            "track",
            path(&seq),
            "--format",
            format.name(),
            "--boxes",
            path(&from_png),
            "--json",
        ]);
        assert_eq!(json(&o)["auc"], doc["auc"], "{format}");
        assert_eq!(
            std::fs::read_to_string(&from_raw).unwrap(),
            std::fs::read_to_string(&from_png).unwrap(),
            "{format}"
        );
    }
    // A size that does not divide the file, and --raw with --format, are refused.
    let dump = dir.join("dump.rgb565le");
    assert_one_line_error(
        &rbtrack(&[
            "track",
            path(&dump),
            "--raw",
            "95x72:rgb565le",
            "--init",
            &truth[0],
        ]),
        "bad size",
        "not whole",
    );
    assert_one_line_error(
        &rbtrack(&[
            "track",
            path(&dump),
            "--raw",
            "96x72:bgr",
            "--init",
            &truth[0],
        ]),
        "bad format",
        "--raw",
    );
    let o = rbtrack(&[
        "track",
        path(&dump),
        "--raw",
        "96x72:rgb565le",
        "--format",
        "rgb888",
        "--init",
        &truth[0],
    ]);
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(dir);
}

/// An mp4 made by ffmpeg from the scene's frames is tracked frame by frame.
#[test]
fn mp4_video() {
    let dir = temp_dir("video");
    let seq = dir.join("Tiny");
    let truth = write_sequence(&seq, 10);
    let clip = dir.join("clip.mp4");
    let made = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-framerate", "10", "-i"])
        .arg(seq.join("img/%04d.png"))
        .args(["-pix_fmt", "yuv420p"])
        .arg(&clip)
        .status();
    match made {
        Ok(status) => assert!(status.success(), "ffmpeg could not make {}", clip.display()),
        Err(e) => {
            println!("SKIPPED mp4_video: cannot run ffmpeg ({e}); install ffmpeg to run it");
            return;
        }
    }
    let csv = dir.join("clip.csv");
    let o = rbtrack(&[
        "track",
        path(&clip),
        "--init",
        &truth[0],
        "--groundtruth",
        path(&seq.join(GROUNDTRUTH_FILE)),
        "--per-frame",
        path(&csv),
        "--tracker",
        "rbpf",
        "--json",
    ]);
    let doc = json(&o);
    assert_eq!(doc["sequence"], "clip");
    assert_eq!(doc["frames"], FRAMES);
    assert!(doc["auc"].as_f64().unwrap() > 0.3, "{doc}");
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    assert_eq!(rows, FRAMES + 1);
    let _ = std::fs::remove_dir_all(dir);
}

/// A damaged or cut video ends with a one-line error naming the last frame read and a
/// non-zero exit, the files keeping the frames tracked before it: an MP4 cut short (index
/// at the front, so ffmpeg decodes what is left without failing) and an MPEG-TS stream
/// cut in the middle of a frame. A video without --init is asked for one.
#[test]
fn damaged_videos_end_with_an_error() {
    let dir = temp_dir("damaged");
    const MADE: usize = 60;
    for (name, extra, kept_tenths) in [
        ("whole.mp4", &["-movflags", "+faststart"][..], 7),
        ("whole.ts", &[][..], 4),
    ] {
        let whole = dir.join(name);
        let made = Command::new("ffmpeg")
            .args(["-v", "error", "-nostdin", "-f", "lavfi", "-i"])
            .arg(format!("testsrc=size={W}x{H}:rate=25"))
            .args(["-frames:v", &MADE.to_string(), "-pix_fmt", "yuv420p"])
            .args(extra)
            .arg(&whole)
            .status();
        match made {
            Ok(status) => assert!(status.success(), "ffmpeg could not make {name}"),
            Err(e) => {
                println!("SKIPPED damaged_videos_end_with_an_error: cannot run ffmpeg ({e})");
                return;
            }
        }
        let bytes = std::fs::read(&whole).unwrap();
        let cut = dir.join(format!("cut-{name}"));
        std::fs::write(&cut, &bytes[..bytes.len() * kept_tenths / 10]).unwrap();
        let (boxes, csv) = (dir.join("boxes.txt"), dir.join("frames.csv"));
        let o = rbtrack(&[
            "track",
            path(&cut),
            "--init",
            "30,20,20,20",
            "--boxes",
            path(&boxes),
            "--per-frame",
            path(&csv),
        ]);
        assert_one_line_error(&o, name, "frame");
        assert_eq!(o.status.code(), Some(1), "{name}");
        let err = stderr(&o);
        let kept = std::fs::read_to_string(&boxes).unwrap().lines().count();
        assert!(0 < kept && kept < MADE, "{name}: {kept} boxes");
        assert!(
            err.contains(&format!("the {kept} frames before it")),
            "{err}"
        );
        let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
        assert_eq!(rows, kept + 1, "{name}");
        // The whole video tracks to its end.
        let o = rbtrack(&["track", path(&whole), "--init", "30,20,20,20", "--json"]);
        assert_eq!(json(&o)["frames"], MADE, "{name}");
    }
    assert_one_line_error(
        &rbtrack(&["track", path(&dir.join("whole.mp4"))]),
        "video without --init",
        "a video or raw dump has no ground truth: give the first frame's box with --init",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Without ffmpeg on PATH a video is refused with a hint, not a panic.
#[test]
fn video_without_ffmpeg() {
    let dir = temp_dir("no-ffmpeg");
    let clip = dir.join("clip.mp4");
    std::fs::write(&clip, b"not really a video").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rbtrack"))
        .args(["track", path(&clip), "--init", "1,1,8,8"])
        .env("PATH", &dir)
        .output()
        .unwrap();
    assert_one_line_error(&o, "no ffprobe", "install ffmpeg");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn errors_are_one_line_without_panic() {
    let dir = temp_dir("errors");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 5);
    let s = path(&seq);

    let missing = dir.join("no-such-sequence");
    assert_one_line_error(
        &rbtrack(&["track", path(&missing)]),
        "missing dir",
        "not found",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--init", "500,10,20,20"]),
        "init outside",
        "outside",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--init", "-100,-100,20,20"]),
        "init outside (negative)",
        "outside",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--init", "1,2,3"]),
        "bad init",
        "x,y,w,h",
    );
    // Which fault of the box it is, said plainly.
    assert_one_line_error(
        &rbtrack(&["track", s, "--init", "10,10,3,20"]),
        "init too small",
        "3.00x20.00 px is too small: its width and height must be at least 4 px",
    );
    for bad in ["7", "0", "many", "-1"] {
        assert_one_line_error(
            &rbtrack(&["track", s, "--particles", bad]),
            "bad --particles",
            "--particles",
        );
    }
    assert_one_line_error(
        &rbtrack(&["track", s, "--particles"]),
        "no value",
        "a value is required",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--seed", "x"]),
        "bad --seed",
        "--seed",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--format", "yuv"]),
        "bad --format",
        "rgb565le",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "kcf"]),
        "bad --tracker",
        "rbpf",
    );
    assert_one_line_error(
        &rbtrack(&["demo", "--frames", "2"]),
        "bad --frames",
        "--frames",
    );
    assert_one_line_error(
        &rbtrack(&["demo", "--scene", "crowd"]),
        "bad --scene",
        "crowd",
    );

    assert_one_line_error(
        &rbtrack(&["eval", s, "--seed", "1", "--seeds", "1,2"]),
        "--seed with --seeds",
        "cannot be used with",
    );

    // Unreadable frame (after the first).
    std::fs::write(seq.join("img/0003.png"), b"not a png").unwrap();
    assert_one_line_error(&rbtrack(&["track", s]), "unreadable image", "0003.png");
    std::fs::remove_file(seq.join("img/0003.png")).unwrap();

    // Malformed ground-truth line, named with its line number.
    std::fs::write(seq.join(GROUNDTRUTH_FILE), "10,10,8,16\n11,11,8\n").unwrap();
    assert_one_line_error(&rbtrack(&["track", s]), "malformed groundtruth", ":2:");

    // Unknown options and subcommands: rejected with the usage text.
    for args in [
        &["track", s, "--bogus"][..],
        &["track"][..],
        &["eval", s, "--init", "1,1,8,8"][..],
        &["demo", "--json"][..],
        &["frobnicate"][..],
    ] {
        let o = rbtrack(args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.starts_with("rbtrack"), "{err}");
        assert!(
            err.to_lowercase().contains("usage: rbtrack"),
            "{args:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn eval_two_sequences() {
    let dir = temp_dir("eval");
    let data = dir.join("data");
    write_sequence(&data.join("Beta"), 7);
    write_sequence(&data.join("Alpha"), 6);
    std::fs::create_dir_all(data.join("notes")).unwrap();
    let out = dir.join("plots");

    let o = rbtrack(&[
        "eval",
        path(&data),
        "--out",
        path(&out),
        "--particles",
        "25",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let rows: Vec<&str> = text
        .lines()
        .take_while(|l| !l.starts_with("loss detection"))
        .filter(|l| ["Alpha", "Beta", "mean"].iter().any(|n| l.starts_with(n)))
        .collect();
    assert_eq!(rows.len(), 3, "{text}");
    assert!(
        rows[0].starts_with("Alpha") && rows[1].starts_with("Beta"),
        "{text}"
    );
    assert!(rows[2].contains(&(2 * FRAMES).to_string()), "{text}");
    assert!(
        stderr(&o).contains("skipping"),
        "no note for notes/: {}",
        stderr(&o)
    );
    for f in ["success.png", "precision.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }

    // JSON writes no plots unless asked.
    let o = rbtrack_in(
        &dir,
        &[
            "eval",
            path(&data),
            "--particles",
            "25",
            "--tracker",
            "both",
            "--json",
            "--boxes",
            path(&dir.join("boxes")),
        ],
    );
    let json = json(&o);
    assert!(!dir.join("out").exists(), "plots written with --json");
    let seqs = json["sequences"].as_array().unwrap();
    assert_eq!(seqs.len(), 4);
    assert_eq!(seqs[0]["sequence"], "Alpha");
    for s in seqs {
        assert_eq!(s["frames"], FRAMES);
        assert!((0.0..=1.0).contains(&s["auc"].as_f64().unwrap()));
    }
    let mean = json["mean"].as_array().unwrap();
    assert_eq!(mean.len(), 2);
    assert_eq!(mean[0]["sequences"], 2);
    assert_eq!(mean[0]["frames"], 2 * FRAMES);
    assert_eq!(json["seeds"], serde_json::json!([1]));
    assert_eq!(json["config"]["pf"]["variant"], "pf");
    for f in ["Alpha_rbpf.txt", "Beta_pf.txt"] {
        let text = std::fs::read_to_string(dir.join("boxes").join(f)).unwrap();
        assert_eq!(text.lines().count(), FRAMES, "{f}");
    }
    let o = rbtrack_in(
        &dir,
        &[
            "eval",
            path(&data),
            "--particles",
            "25",
            "--json",
            "--plots",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("out/eval/success.png").is_file());

    // An empty data folder is an error, and so is naming a sequence that is not there.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert_one_line_error(&rbtrack(&["eval", path(&empty)]), "empty data", "no usable");
    std::fs::remove_dir_all(data.join("notes")).unwrap();
    assert_one_line_error(
        &rbtrack(&["eval", path(&data), "--zero-based-sequences", "Gamma"]),
        "unknown 0-based sequence",
        "Gamma",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// `eval` over two data folders: one table of their sequences, each folder's mean and the
/// pooled mean (the mean over all sequences), per folder in the JSON's `sets`; a sequence
/// name in both folders is an error.
#[test]
fn eval_two_folders() {
    let dir = temp_dir("folders");
    let (dev, val) = (dir.join("dev"), dir.join("val"));
    write_sequence(&dev.join("Beta"), 41);
    write_sequence(&dev.join("Alpha"), 42);
    let gamma = write_sequence(&val.join("Gamma"), 43);
    rewrite_zero_based(&val.join("Gamma"), &gamma);
    let common = [
        "eval",
        path(&dev),
        path(&val),
        "--zero-based-sequences",
        "Gamma",
    ];

    let doc = json(&rbtrack(&[&common[..], &["--json"]].concat()));
    assert_eq!(
        doc["data_dirs"],
        serde_json::json!([path(&dev), path(&val)])
    );
    assert!(doc.get("data_dir").is_none(), "{doc}");
    let aucs: Vec<f64> = doc["sequences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["auc"].as_f64().unwrap())
        .collect();
    let names: Vec<&str> = doc["sequences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["sequence"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["Alpha", "Beta", "Gamma"]);
    let mean_of = |aucs: &[f64]| aucs.iter().sum::<f64>() / aucs.len() as f64;
    let sets = doc["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 2);
    for (set, (folder, aucs)) in sets.iter().zip([(&dev, &aucs[..2]), (&val, &aucs[2..])]) {
        assert_eq!(set["data_dir"], path(folder));
        assert_eq!(set["sequences"], aucs.len());
        let auc = set["mean"][0]["auc"].as_f64().unwrap();
        assert!((auc - mean_of(aucs)).abs() < 1e-12, "{set}");
    }
    let pooled = &doc["mean"][0];
    assert_eq!(pooled["sequences"], 3);
    assert_eq!(pooled["frames"], 3 * FRAMES);
    assert!(
        (pooled["auc"].as_f64().unwrap() - mean_of(&aucs)).abs() < 1e-12,
        "{pooled}"
    );

    // The table: the three sequences, each folder's mean row, the pooled one; the loss
    // table likewise.
    let o = rbtrack(&[&common[..], &["--out", path(&dir.join("plots"))]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.starts_with(&format!(
            "{}, {}: 3 sequences (2 + 1);",
            path(&dev),
            path(&val)
        )),
        "{text}"
    );
    // The cells after a row's label (its first cell), in the first table that has it.
    let row = |label: &str| -> Vec<&str> {
        let line = text
            .lines()
            .find(|l| l.split("  ").next() == Some(label))
            .unwrap_or_else(|| panic!("no row {label:?} in {text}"));
        line[label.len()..].split_whitespace().collect()
    };
    for (scope, frames, mean) in [
        (format!(" {}", path(&dev)), 2 * FRAMES, &sets[0]["mean"][0]),
        (format!(" {}", path(&val)), FRAMES, &sets[1]["mean"][0]),
        (String::new(), 3 * FRAMES, pooled),
    ] {
        let auc = format!("{:.3}", mean["auc"].as_f64().unwrap());
        let cells = row(&format!("mean{scope}"));
        assert_eq!(
            cells[..3],
            ["cf", frames.to_string().as_str(), auc.as_str()]
        );
        assert_eq!(row(&format!("all{scope}"))[0], "cf", "{scope}");
    }

    // A sequence name in both folders.
    write_sequence(&val.join("Alpha"), 44);
    let o = rbtrack(&["eval", path(&dev), path(&val)]);
    assert_one_line_error(&o, "a name in both folders", path(&dev.join("Alpha")));
    assert!(
        stderr(&o).contains(path(&val.join("Alpha"))),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// `frames`: the sequence's frames as one RGB888 dump, the PNGs' pixels exactly, which
/// `track --raw` tracks as it tracks the folder.
#[test]
fn frames_dump_is_what_track_reads() {
    let dir = temp_dir("frames");
    let seq = dir.join("Alpha");
    write_sequence(&seq, 31);
    let dump = dir.join("out/alpha.rgb");
    let o = rbtrack(&["frames", path(&seq), path(&dump)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), format!("{W}x{H}:rgb888 {FRAMES}\n"));
    let bytes = std::fs::read(&dump).unwrap();
    assert_eq!(bytes.len(), (W * H * 3) as usize * FRAMES);
    let frame = (W * H * 3) as usize;
    for i in [0, FRAMES - 1] {
        let png = image::open(seq.join(format!("img/{:04}.png", i + 1)))
            .unwrap()
            .to_rgb8();
        assert_eq!(&bytes[i * frame..(i + 1) * frame], png.as_raw().as_slice());
    }
    let groundtruth = seq.join(GROUNDTRUTH_FILE);
    let from_folder = json(&rbtrack(&[
        "track",
        path(&seq),
        "--particles",
        "25",
        "--json",
    ]));
    let from_dump = json(&rbtrack(&[
        "track",
        path(&dump),
        "--raw",
        &format!("{W}x{H}:rgb888"),
        "--groundtruth",
        path(&groundtruth),
        "--particles",
        "25",
        "--json",
    ]));
    assert_eq!(from_folder["auc"], from_dump["auc"]);
    assert_one_line_error(
        &rbtrack(&["frames", path(&dir.join("missing")), path(&dump)]),
        "missing sequence",
        "missing",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// `eval --starts spatial`: every seed runs from the seven starts (the box, four 2 px
/// shifts, two scales); each run's first box is its start, the set's mean per start is the
/// mean over sequences and seeds of that start's runs, and the box start alone scores as
/// a plain `eval`.
#[test]
fn eval_from_spatial_starts() {
    let dir = temp_dir("starts");
    let data = dir.join("data");
    // The scene's first box is 4 px wide, the smallest a tracker starts from: grow the
    // boxes by 4 px so that the 0.95 start stays usable.
    let lines = grown(
        &data.join("Alpha"),
        &write_sequence(&data.join("Alpha"), 21),
    );
    grown(&data.join("Beta"), &write_sequence(&data.join("Beta"), 22));
    let common = [
        "eval",
        path(&data),
        "--tracker",
        "rbpf",
        "--particles",
        "25",
        "--seeds",
        "1,2",
    ];
    let mut args = common.to_vec();
    let boxes = dir.join("boxes");
    args.extend(["--starts", "spatial", "--json", "--boxes", path(&boxes)]);
    let doc = json(&rbtrack(&args));
    let names = [
        "box",
        "left2",
        "right2",
        "up2",
        "down2",
        "scale0.95",
        "scale1.05",
    ];
    let starts: Vec<&str> = doc["starts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(starts, names);
    let seqs = doc["sequences"].as_array().unwrap();
    for s in seqs {
        assert_eq!(s["per_seed"].as_array().unwrap().len(), 14, "{s}");
    }
    let mean = &doc["mean"][0];
    for (k, p) in mean["per_start"].as_array().unwrap().iter().enumerate() {
        assert_eq!(p["start"], names[k]);
        let runs: Vec<f64> = seqs
            .iter()
            .flat_map(|s| s["per_seed"].as_array().unwrap())
            .filter(|r| r["start"] == names[k])
            .map(|r| r["auc"].as_f64().unwrap())
            .collect();
        assert_eq!(runs.len(), 4);
        let expected = runs.iter().sum::<f64>() / 4.0;
        assert!((p["auc"].as_f64().unwrap() - expected).abs() < 1e-12, "{p}");
    }
    // Each box file starts from its start: the first ground-truth box moved.
    let truth: Vec<f64> = lines[0].split(',').map(|v| v.parse().unwrap()).collect();
    for (file, [dx, dy, scale]) in [
        ("Alpha_seed1_box.txt", [0.0, 0.0, 1.0]),
        ("Alpha_seed2_left2.txt", [-2.0, 0.0, 1.0]),
        ("Alpha_seed1_down2.txt", [0.0, 2.0, 1.0]),
        ("Alpha_seed2_scale1.05.txt", [0.0, 0.0, 1.05]),
    ] {
        let text = std::fs::read_to_string(boxes.join(file)).unwrap();
        let first: Vec<f64> = text
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        let (w, h) = (truth[2] * scale, truth[3] * scale);
        let expected = [
            truth[0] + (truth[2] - w) / 2.0 + dx,
            truth[1] + (truth[3] - h) / 2.0 + dy,
            w,
            h,
        ];
        for (got, want) in first.iter().zip(expected) {
            assert!(
                (got - want).abs() <= 0.005 + 1e-9,
                "{file}: {first:?} {expected:?}"
            );
        }
    }
    // The box start's runs are a plain eval's.
    let plain = json(&rbtrack(&[&common[..], &["--json"]].concat()));
    let alpha = |doc: &Value| -> Vec<f64> {
        doc["sequences"][0]["per_seed"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r.get("start").is_none_or(|s| s == "box"))
            .map(|r| r["auc"].as_f64().unwrap())
            .collect()
    };
    assert_eq!(alpha(&doc), alpha(&plain));
    assert_eq!(
        mean["per_start"][0]["auc"], plain["mean"][0]["auc"],
        "{mean}"
    );

    // The table names the starts and prints the mean per start.
    let o = rbtrack(
        &[
            &common[..],
            &["--starts", "spatial", "--out", path(&dir.join("plots"))],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("7 starts per seed"), "{text}");
    let per_start = text
        .lines()
        .find(|l| l.starts_with("mean AUC per start"))
        .unwrap();
    assert!(
        per_start.contains("rbpf: box ") && per_start.contains("perturbed mean"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// `eval --seeds`: each sequence's mean and range over the seeds, the set's mean with its
/// range over the seeds' set means, and every seed's figures in the JSON.
#[test]
fn eval_over_seeds() {
    let dir = temp_dir("seeds");
    let data = dir.join("data");
    write_sequence(&data.join("Alpha"), 11);
    write_sequence(&data.join("Beta"), 12);
    let zero = write_sequence(&data.join("Zero"), 13);
    let zero_lines = rewrite_zero_based(&data.join("Zero"), &zero);
    let common = [
        "eval",
        path(&data),
        "--particles",
        "25",
        "--tracker",
        "both",
        "--seeds",
        "1,2,3",
        "--zero-based-sequences",
        "Zero",
        "--set",
        "colour_sigma=0.15",
    ];
    let mut args = common.to_vec();
    let boxes = dir.join("boxes");
    args.extend(["--json", "--boxes", path(&boxes)]);
    let doc = json(&rbtrack(&args));
    assert_eq!(doc["seeds"], serde_json::json!([1, 2, 3]));
    assert_eq!(doc["config"]["rbpf"]["colour_sigma"], 0.15);
    assert_eq!(doc["zero_based_sequences"], serde_json::json!(["Zero"]));
    let seqs = doc["sequences"].as_array().unwrap();
    assert_eq!(seqs.len(), 6);
    for s in seqs {
        let per_seed = s["per_seed"].as_array().unwrap();
        let seeds: Vec<u64> = per_seed
            .iter()
            .map(|p| p["seed"].as_u64().unwrap())
            .collect();
        assert_eq!(seeds, [1, 2, 3]);
        let aucs: Vec<f64> = per_seed
            .iter()
            .map(|p| p["auc"].as_f64().unwrap())
            .collect();
        let mean = aucs.iter().sum::<f64>() / 3.0;
        assert!((s["auc"].as_f64().unwrap() - mean).abs() < 1e-12, "{s}");
        assert_eq!(s["auc_min"].as_f64(), aucs.iter().copied().reduce(f64::min));
        assert_eq!(s["auc_max"].as_f64(), aucs.iter().copied().reduce(f64::max));
    }
    for m in doc["mean"].as_array().unwrap() {
        let tracker = m["tracker"].as_str().unwrap();
        let lost = m["loss"]["lost_share"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&lost), "{m}");
        let per_seed = m["per_seed"].as_array().unwrap();
        for (k, p) in per_seed.iter().enumerate() {
            // A seed's set mean is the mean over sequences of that seed's AUC.
            let of_seed: Vec<f64> = seqs
                .iter()
                .filter(|s| s["tracker"] == tracker)
                .map(|s| s["per_seed"][k]["auc"].as_f64().unwrap())
                .collect();
            let set_mean = of_seed.iter().sum::<f64>() / of_seed.len() as f64;
            assert!((p["auc"].as_f64().unwrap() - set_mean).abs() < 1e-12, "{m}");
        }
        let (lo, auc, hi) = (
            m["auc_min"].as_f64().unwrap(),
            m["auc"].as_f64().unwrap(),
            m["auc_max"].as_f64().unwrap(),
        );
        assert!(lo <= auc && auc <= hi, "{m}");
    }
    // The 0-based sequence is read as stated: it scores as its 1-based twin would.
    let twin = json(&rbtrack(&[
        "track",
        path(&data.join("Zero")),
        "--tracker",
        "rbpf",
        "--zero-based",
        "--particles",
        "25",
        "--set",
        "colour_sigma=0.15",
        "--json",
    ]));
    let zero_rbpf = seqs
        .iter()
        .find(|s| s["sequence"] == "Zero" && s["tracker"] == "rbpf")
        .unwrap();
    assert_eq!(zero_rbpf["per_seed"][0]["auc"], twin["auc"]);
    for f in ["Alpha_rbpf_seed1.txt", "Zero_pf_seed3.txt"] {
        let text = std::fs::read_to_string(dir.join("boxes").join(f)).unwrap();
        assert_eq!(text.lines().count(), FRAMES, "{f}");
    }
    // Box files keep each sequence's convention.
    let first = std::fs::read_to_string(dir.join("boxes/Zero_rbpf_seed1.txt")).unwrap();
    assert_eq!(first.lines().next(), Some(zero_lines[0].as_str()));

    // The table: means over seeds with the AUC's range, and the set's mean per seed.
    let mut args = common.to_vec();
    let plots = dir.join("plots");
    args.extend(["--out", path(&plots), "--calibrate"]);
    let o = rbtrack(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(plots.join("reliability.png").is_file(), "{text}");
    // --calibrate: per tracker, the fitted table of 10 knots from score 0 to 1.
    let tables: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("  table: [(0, "))
        .collect();
    assert_eq!(tables.len(), 2, "{text}");
    assert!(
        tables
            .iter()
            .all(|t| t.matches('(').count() == 10 && t.contains("(1000, ")),
        "{text}"
    );
    let header = text.lines().find(|l| l.starts_with("sequence")).unwrap();
    assert!(
        header.contains("AUC min") && header.contains("AUC max"),
        "{text}"
    );
    let mean_rows = text.lines().filter(|l| {
        let cells: Vec<&str> = l.split_whitespace().collect();
        cells.len() > 2 && cells[0] == "mean" && ["rbpf", "pf"].contains(&cells[1])
    });
    assert_eq!(mean_rows.count(), 2, "{text}");
    assert!(text.contains("config rbpf: colour_sigma=0.15"), "{text}");
    // The loss-detection table: a row per sequence and tracker and one per tracker.
    let loss_rows = text
        .lines()
        .skip_while(|l| !l.starts_with("loss detection"))
        .take_while(|l| !l.starts_with("reliability"))
        .filter(|l| {
            ["Alpha", "Beta", "Zero", "all"].contains(&l.split_whitespace().next().unwrap_or(""))
        })
        .count();
    assert_eq!(loss_rows, 8, "{text}");
    // The reliability table: a row per tracker, ten tenths and the largest distance.
    let reliability: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("reliability"))
        .filter(|l| l.starts_with("all"))
        .collect();
    assert_eq!(reliability.len(), 2, "{text}");
    assert!(
        reliability
            .iter()
            .all(|l| l.matches(')').count() + l.matches(" - ").count() >= 10),
        "{text}"
    );
    let per_seed = text
        .lines()
        .find(|l| l.starts_with("mean AUC per seed"))
        .unwrap();
    assert!(
        per_seed.contains("rbpf: 1 ") && per_seed.contains("pf: 1 "),
        "{per_seed}"
    );
    assert!(plots.join("success_rbpf.png").is_file());
    assert_one_line_error(
        &rbtrack(&["eval", path(&data), "--seeds", "1,2,1"]),
        "repeated seed",
        "seed 1",
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// The README's host quick start, run as written: every `cargo run ... --` line of its
/// `sh` block, with the rbtrack binary, in a folder holding what the lines name
/// (`clip.mp4` and `dump.raw`, 320x240, and a tiny `../shared/data` with a 0-based
/// `ball1_vot15`, as the shared data has, its boxes grown by 4 px).
#[test]
fn readme_host_quick_start_runs_as_written() {
    const PREFIX: &str = "cargo run --release -p rbtrack-host -- ";
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))
        .expect("README.md");
    let section = readme
        .split("## Host quick start")
        .nth(1)
        .expect("README has a host quick start");
    let block = section
        .split("```sh")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("the host quick start has an sh block");
    let commands: Vec<Vec<&str>> = block
        .lines()
        .filter_map(|line| line.trim().strip_prefix(PREFIX))
        .map(|line| {
            line.split(" #")
                .next()
                .unwrap_or("")
                .split_whitespace()
                .collect()
        })
        .collect();
    assert!(commands.len() >= 3, "{block}");

    let root = temp_dir("readme");
    let work = root.join("work");
    // Boxes grown by 4 px, so that the 7 starts' 0.95 stays at least 4 px wide.
    let tiny = root.join("shared/data/Tiny");
    grown(&tiny, &write_sequence(&tiny, 11));
    let ball = root.join("shared/data/ball1_vot15");
    let ball_truth = grown(&ball, &write_sequence(&ball, 12));
    rewrite_zero_based(&ball, &ball_truth);
    let mut config = SceneConfig::new(Variant::Perspective, 11);
    (config.width, config.height, config.frames) = (320, 240, 10);
    let scene = Scene::new(config).unwrap();
    let frames: Vec<Vec<u8>> = (0..FRAMES).map(|i| scene.render(i).unwrap()).collect();
    std::fs::create_dir_all(work.join("png")).unwrap();
    let mut raw = Vec::new();
    for (i, rgb) in frames.iter().enumerate() {
        let png = work.join("png").join(format!("{:04}.png", i + 1));
        image::save_buffer(png, rgb, 320, 240, image::ExtendedColorType::Rgb8).unwrap();
        let frame = Frame::rgb888(320, 240, rgb.clone()).unwrap();
        raw.extend(frame.convert(Format::Rgb565Le).unwrap().bytes);
    }
    std::fs::write(work.join("dump.raw"), raw).unwrap();
    let made = Command::new("ffmpeg")
        .args(["-v", "error", "-nostdin", "-framerate", "10", "-i"])
        .arg(work.join("png/%04d.png"))
        .args(["-pix_fmt", "yuv420p"])
        .arg(work.join("clip.mp4"))
        .status();
    if !made.is_ok_and(|s| s.success()) {
        println!("SKIPPED readme_host_quick_start_runs_as_written: ffmpeg cannot make clip.mp4");
        return;
    }

    for args in &commands {
        let o = rbtrack_in(&work, args);
        assert!(
            o.status.success(),
            "rbtrack {}: {}",
            args.join(" "),
            stderr(&o)
        );
    }
    // What the lines promise to write.
    assert!(work.join("out/demo/strip.png").is_file());
    assert!(work.join("out/follow/error.png").is_file());
    assert!(work.join("out/follow/view.gif").is_file());
    let rows = std::fs::read_to_string(work.join("out/track.csv")).unwrap();
    assert_eq!(rows.lines().count(), FRAMES + 1, "{rows}");
    assert_eq!(
        std::fs::read_dir(work.join("out/frames")).unwrap().count(),
        FRAMES
    );
    let _ = std::fs::remove_dir_all(root);
}

#[test]
fn follow_runs_the_closed_loop_and_draws_it() {
    let dir = temp_dir("follow");
    let out = dir.join("out");
    let o = rbtrack(&["follow", "--out", path(&out), "--no-gif", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc = json(&o);
    assert_eq!(doc["scene"], "synthetic perspective scene");
    assert_eq!(doc["view"], serde_json::json!([320, 240]));
    assert_eq!(doc["band"], 32.0);
    let settling = doc["settling"].as_array().unwrap();
    assert_eq!(settling.len(), 2, "the start and the knock");
    assert!(
        settling.iter().all(|s| s.as_u64().is_some_and(|n| n <= 5)),
        "{doc}"
    );
    let centred = doc["centred"].as_f64().unwrap();
    assert!((0.9..=1.0).contains(&centred), "{doc}");
    for file in ["strip.png", "error.png"] {
        let (w, _) = image::image_dimensions(out.join(file)).unwrap();
        assert!(w > 0);
    }
    assert!(!out.join("view.gif").exists());
    let missing = rbtrack(&["follow", path(&dir.join("none"))]);
    assert_one_line_error(&missing, "follow without a sequence folder", "none");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn camera_motion_file_is_applied_and_checked() {
    let dir = temp_dir("camera-motion");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 5);
    let csv = |name: &str, motion: Option<&Path>| {
        let file = dir.join(name);
        let mut args = vec!["track", path(&seq), "--per-frame", path(&file)];
        if let Some(m) = motion {
            args.extend(["--camera-motion", path(m)]);
        }
        let o = rbtrack(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read_to_string(&file).unwrap()
    };
    let still = csv("still.csv", None);
    let motion = dir.join("motion.csv");
    std::fs::write(&motion, "frame,dx,dy,zoom\n2,0,0\n").unwrap();
    assert_eq!(
        csv("zero.csv", Some(&motion)),
        still,
        "no motion changes nothing"
    );
    std::fs::write(&motion, "frame,dx,dy,zoom\n3,-12.5,4,1.1\n").unwrap();
    let moved = csv("moved.csv", Some(&motion));
    let lines = |t: &str| t.lines().map(str::to_owned).collect::<Vec<_>>();
    let (a, b) = (lines(&still), lines(&moved));
    assert_eq!(a[..3], b[..3], "frames before the motion are unchanged");
    assert_ne!(a[3], b[3], "frame 3 is tracked after the motion");
    for (text, says) in [
        (
            "frame,dx,dy\n1,2,3\n",
            "line 2: the frame must be a number from 2",
        ),
        ("4,a,0\n", "line 1: dx, dy and zoom must be numbers"),
    ] {
        std::fs::write(&motion, text).unwrap();
        let o = rbtrack(&["track", path(&seq), "--camera-motion", path(&motion)]);
        assert_one_line_error(&o, text, says);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// The f64 correlation-filter tracker runs in `track` and `eval` under its own name, takes
/// its settings as `cf.FIELD`, prints them in its JSON with the cost model's estimate, and
/// refuses a bad one on one line.
#[test]
fn cf64_tracker_in_track_and_eval() {
    let dir = temp_dir("cf64");
    let seq = dir.join("Tiny");
    write_sequence(&seq, 4);
    let s = path(&seq);

    let doc = json(&rbtrack(&[
        "track",
        s,
        "--tracker",
        "cf64",
        "--json",
        "--set",
        "cf.grid=16",
    ]));
    assert_eq!(doc["tracker"], "cf64");
    assert_eq!(doc["config"]["grid"], 16);
    assert_eq!(doc["config"]["hog"], "27");
    assert_eq!(doc["frames"], 6);

    let doc = json(&rbtrack(&[
        "eval",
        path(&dir),
        "--tracker",
        "all",
        "--json",
        "--set",
        "cf.merge=0.4",
    ]));
    let trackers: Vec<&str> = doc["mean"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["tracker"].as_str().unwrap())
        .collect();
    assert_eq!(trackers, ["rbpf", "pf", "cf64", "cf"]);
    assert_eq!(doc["config"]["cf"]["grid"], 16);
    assert_eq!(doc["config"]["cf64"]["merge"], 0.4);
    assert!(doc["cf64_cost"]["instructions"].as_u64().unwrap() > 1_000_000);

    assert_one_line_error(
        &rbtrack(&["track", s, "--tracker", "cf64", "--set", "cf.grid=3"]),
        "grid out of range",
        "cf.grid",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--set", "cf.no_such=1"]),
        "unknown cf field",
        "cf.no_such",
    );
}

/// The budget example's correlation-filter tables, each stage `factor[i]` times the cost
/// model's estimate: its configurations, and the defaults against the target's size.
fn budget_output(factor: [f64; 5]) -> String {
    use rbtrack_host::cf64::cost::{budget_row, Operations, Target};
    use rbtrack_host::cf64::Params;
    let mut text = String::from(
        "correlation-filter tracker, instructions per frame by stage (mean), total (mean, max):\n \
         G  S cell area ring  size_of B  features   filter   colour    scale    learn     total       max      lost redetect  box h\n",
    );
    let configurations = [
        (16, 4, 4, 512, 2),
        (16, 4, 2, 512, 2),
        (16, 5, 4, 512, 2),
        (16, 8, 4, 512, 2),
        (16, 4, 4, 256, 2),
        (8, 8, 8, 512, 2),
        (8, 4, 4, 256, 2),
        (8, 4, 4, 128, 0),
        (8, 4, 4, 96, 0),
    ];
    let estimate = |params: &Params, target: Target| -> Vec<u64> {
        let stages = Operations::of(params, target).stages();
        stages
            .iter()
            .zip(factor)
            .map(|(e, f)| (e * f).round() as u64)
            .collect()
    };
    for (g, s, cell, area, ring) in configurations {
        let stages = estimate(&budget_row(g, s, cell, area, ring), Target::scene(1.0));
        let total: u64 = stages.iter().sum();
        let list: Vec<String> = stages.iter().map(u64::to_string).collect();
        text += &format!(
            "{g} {s} {cell} {area} {ring} 70616 {} {total} {total} 0 0 54\n",
            list.join(" ")
        );
    }
    text +=
        "\ncorrelation-filter tracker against target size, defaults (mean target height and box height, px):\n";
    text += "height  box h  features    scale     total       max\n";
    let defaults = budget_row(16, 4, 4, 512, 2);
    for height in [19, 40, 81, 122] {
        let stages = estimate(&defaults, Target::scene(f64::from(height) / 54.0));
        let total: u64 = stages.iter().sum();
        text += &format!(
            "{height} {height} {} {} {total} {total}\n",
            stages[0], stages[3]
        );
    }
    text + "\n"
}

#[test]
fn cost_checks_the_model_against_the_budget_example() {
    let dir = temp_dir("cost");
    let file = dir.join("budget.txt");
    std::fs::write(&file, budget_output([1.0; 5])).unwrap();
    let o = rbtrack(&["cost", path(&file)]);
    assert!(o.status.success(), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("largest error 0.0 % (within"),
        "{}",
        stdout(&o)
    );
    assert!(stdout(&o).contains("G 8 S 4 cell 4 area 128 ring 0"));

    // The scale stage 20 % off the model: beyond 10 %, exit 1.
    std::fs::write(&file, budget_output([1.0, 1.0, 1.0, 1.2, 1.0])).unwrap();
    let o = rbtrack(&["cost", path(&file)]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("beyond the 10 % allowed"),
        "{}",
        stdout(&o)
    );

    // Fitted to rows the model made, the costs are the model's own.
    std::fs::write(&file, budget_output([1.0; 5])).unwrap();
    let o = rbtrack(&["cost", path(&file), "--fit"]);
    assert!(
        stdout(&o).contains("filter: [27.0, 41.4]"),
        "{}",
        stdout(&o)
    );

    std::fs::write(&file, "no rows here\n").unwrap();
    assert_one_line_error(
        &rbtrack(&["cost", path(&file)]),
        "no rows",
        "no correlation-filter rows",
    );
}
