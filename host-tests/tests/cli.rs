//! The `rbtrack` binary end to end: `demo`, `track` and `eval` on tiny generated OTB
//! sequences (synthetic scene frames written as PNG), their JSON and box files, and the
//! error cases (one line on stderr, non-zero exit, no panic).

use rbtrack_host::scene::{Scene, SceneConfig, Variant};
use rbtrack_host::sequence::GROUNDTRUTH_FILE;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Frames of the generated sequences.
const FRAMES: usize = 6;

fn temp_dir(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let dir =
        std::env::temp_dir().join(format!("rbtrack-cli-{name}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a tiny OTB-layout sequence into `dir`: `FRAMES` PNG frames of a 96x72
/// perspective scene and a 1-based ground-truth file. Returns the ground-truth lines.
fn write_sequence(dir: &Path, seed: u64) -> Vec<String> {
    let mut config = SceneConfig::new(Variant::Perspective, seed);
    (config.width, config.height, config.frames) = (96, 72, 10);
    let scene = Scene::new(config).unwrap();
    std::fs::create_dir_all(dir.join("img")).unwrap();
    let mut lines = Vec::new();
    for i in 0..FRAMES {
        let rgb = scene.render(i).unwrap();
        let path = dir.join("img").join(format!("{:04}.png", i + 1));
        image::save_buffer(path, &rgb, 96, 72, image::ExtendedColorType::Rgb8).unwrap();
        let b = scene.truth(i).unwrap().bbox.to_one_based();
        lines.push(format!("{:.2},{:.2},{:.2},{:.2}", b.x, b.y, b.w, b.h));
    }
    std::fs::write(dir.join(GROUNDTRUTH_FILE), lines.join("\n") + "\n").unwrap();
    lines
}

fn rbtrack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rbtrack"))
        .args(args)
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

/// A parsed JSON value (enough of JSON for the program's output).
#[derive(Clone, Debug, PartialEq)]
enum Json {
    Null,
    Bool(bool),
    Num(f64),
    Str(String),
    Arr(Vec<Json>),
    Obj(BTreeMap<String, Json>),
}

impl Json {
    fn parse(text: &str) -> Result<Json, String> {
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
        };
        let v = p.value()?;
        p.ws();
        if p.i != p.s.len() {
            return Err(format!("trailing text at byte {}", p.i));
        }
        Ok(v)
    }

    fn get(&self, key: &str) -> &Json {
        match self {
            Json::Obj(m) => m.get(key).unwrap_or_else(|| panic!("no key {key:?}")),
            other => panic!("{other:?} is not an object"),
        }
    }

    fn num(&self) -> f64 {
        match self {
            Json::Num(v) => *v,
            other => panic!("{other:?} is not a number"),
        }
    }

    fn arr(&self) -> &[Json] {
        match self {
            Json::Arr(v) => v,
            other => panic!("{other:?} is not an array"),
        }
    }
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.s.get(self.i).is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    fn eat(&mut self, c: u8) -> Result<(), String> {
        self.ws();
        if self.s.get(self.i) == Some(&c) {
            self.i += 1;
            Ok(())
        } else {
            Err(format!("expected {:?} at byte {}", c as char, self.i))
        }
    }

    fn lit(&mut self, word: &str, v: Json) -> Result<Json, String> {
        if self.s[self.i..].starts_with(word.as_bytes()) {
            self.i += word.len();
            Ok(v)
        } else {
            Err(format!("bad literal at byte {}", self.i))
        }
    }

    fn string(&mut self) -> Result<String, String> {
        self.eat(b'"')?;
        let mut out = String::new();
        loop {
            let c = *self.s.get(self.i).ok_or("unterminated string")?;
            self.i += 1;
            match c {
                b'"' => return Ok(out),
                b'\\' => {
                    let e = *self.s.get(self.i).ok_or("bad escape")?;
                    self.i += 1;
                    match e {
                        b'n' => out.push('\n'),
                        b't' => out.push('\t'),
                        b'r' => out.push('\r'),
                        b'u' => {
                            let hex = std::str::from_utf8(&self.s[self.i..self.i + 4]).unwrap();
                            out.push(
                                char::from_u32(u32::from_str_radix(hex, 16).unwrap()).unwrap(),
                            );
                            self.i += 4;
                        }
                        other => out.push(other as char),
                    }
                }
                c => out.push(c as char),
            }
        }
    }

    fn value(&mut self) -> Result<Json, String> {
        self.ws();
        match self.s.get(self.i).copied().ok_or("unexpected end")? {
            b'n' => self.lit("null", Json::Null),
            b't' => self.lit("true", Json::Bool(true)),
            b'f' => self.lit("false", Json::Bool(false)),
            b'"' => self.string().map(Json::Str),
            b'[' => {
                self.i += 1;
                let mut v = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b']') {
                    self.i += 1;
                    return Ok(Json::Arr(v));
                }
                loop {
                    v.push(self.value()?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Arr(v));
                        }
                        _ => return Err(format!("bad array at byte {}", self.i)),
                    }
                }
            }
            b'{' => {
                self.i += 1;
                let mut m = BTreeMap::new();
                self.ws();
                if self.s.get(self.i) == Some(&b'}') {
                    self.i += 1;
                    return Ok(Json::Obj(m));
                }
                loop {
                    let k = self.string()?;
                    self.eat(b':')?;
                    let v = self.value()?;
                    if m.insert(k.clone(), v).is_some() {
                        return Err(format!("duplicate key {k:?}"));
                    }
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Obj(m));
                        }
                        _ => return Err(format!("bad object at byte {}", self.i)),
                    }
                }
            }
            _ => {
                let start = self.i;
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|c| matches!(c, b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9'))
                {
                    self.i += 1;
                }
                std::str::from_utf8(&self.s[start..self.i])
                    .unwrap()
                    .parse()
                    .map(Json::Num)
                    .map_err(|_| format!("bad number at byte {start}"))
            }
        }
    }
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
fn help_lists_every_subcommand() {
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
    assert!(stderr(&o).contains("rbtrack track SEQ_DIR"));
    for cmd in ["demo", "track", "eval", "paper"] {
        let o = rbtrack(&[cmd, "--help"]);
        assert!(o.status.success(), "{cmd} --help");
        assert!(stdout(&o).starts_with(&format!("usage: rbtrack {cmd}")));
    }
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
    for tracker in ["rbpf", "pf"] {
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
        "--json",
        "--particles",
        "50",
        "--boxes",
        path(&boxes),
        "--overlay",
        path(&overlay),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert_eq!(out.trim().lines().count(), 1, "{out}");
    let json = Json::parse(out.trim()).unwrap();
    assert_eq!(json.get("frames").num(), FRAMES as f64);
    for key in ["auc", "prec20", "miou", "success_rate"] {
        let v = json.get(key).num();
        assert!((0.0..=1.0).contains(&v), "{key} = {v}");
    }
    assert!(json.get("ms_per_frame").num() >= 0.0);
    assert_eq!(json.get("sequence"), &Json::Str("Tiny".into()));
    assert_eq!(json.get("tracker"), &Json::Str("rbpf".into()));
    assert_eq!(json.get("particles").num(), 50.0);

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
    assert!(o.status.success(), "{}", stderr(&o));
    let json = Json::parse(stdout(&o).trim()).unwrap();
    assert_eq!(json.get("frames").num(), FRAMES as f64);
    for key in ["auc", "prec20", "miou"] {
        assert_eq!(json.get(key), &Json::Null, "{key}");
    }
    assert!(json.get("ms_per_frame").num() >= 0.0);
    let written = std::fs::read_to_string(&boxes).unwrap();
    assert_eq!(written.lines().count(), FRAMES);
    assert_eq!(written.lines().next(), Some(truth[0].as_str()));
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
        "needs a value",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--seed", "x"]),
        "bad --seed",
        "--seed",
    );
    assert_one_line_error(
        &rbtrack(&["track", s, "--format", "yuv"]),
        "bad --format",
        "rgb565",
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
        assert!(err.contains("usage: rbtrack"), "{args:?}: {err}");
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

    let o = rbtrack(&[
        "eval",
        path(&data),
        "--out",
        path(&out),
        "--particles",
        "25",
        "--tracker",
        "both",
        "--json",
        "--boxes",
        path(&dir.join("boxes")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json = Json::parse(stdout(&o).trim()).unwrap();
    let seqs = json.get("sequences").arr();
    assert_eq!(seqs.len(), 4);
    assert_eq!(seqs[0].get("sequence"), &Json::Str("Alpha".into()));
    for s in seqs {
        assert_eq!(s.get("frames").num(), FRAMES as f64);
        assert!((0.0..=1.0).contains(&s.get("auc").num()));
    }
    let mean = json.get("mean").arr();
    assert_eq!(mean.len(), 2);
    assert_eq!(mean[0].get("sequences").num(), 2.0);
    assert_eq!(mean[0].get("frames").num(), (2 * FRAMES) as f64);
    for f in ["success_rbpf.png", "precision_pf.png", "success.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    for f in ["Alpha_rbpf.txt", "Beta_pf.txt"] {
        let text = std::fs::read_to_string(dir.join("boxes").join(f)).unwrap();
        assert_eq!(text.lines().count(), FRAMES, "{f}");
    }

    // An empty data folder is an error.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert_one_line_error(&rbtrack(&["eval", path(&empty)]), "empty data", "no usable");
    let _ = std::fs::remove_dir_all(dir);
}
