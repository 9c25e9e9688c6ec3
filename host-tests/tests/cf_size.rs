//! The integer correlation-filter tracker and its f64 reference keep a target's size: a
//! textured box, still or moving slowly over a textured background, 8 to 200 px a side,
//! aspect 1:4 to 4:1, in frames from 160 x 120 to 1280 x 720. Over 300 frames each tracker
//! keeps the true size within 11 % every frame at the defaults' 4 scales of 1.18 (9.8 % at
//! worst measured, the reference 10.0 %: the peak read between samples 18 % apart, none of
//! them at the size itself), within 5 % at 8 scales of
//! 1.08, and the two agree within 2 % on average (the mean of `|ln(cf / reference)|` over
//! the frames and the two sides) and within 5 % every frame. Two runs of the reference
//! whose first boxes are 0.01 px apart agree as closely and no closer: each frame's sizes
//! within 2.3 % at worst, of 118 runs 1 beyond 2 % (`rbtrack port` reads the same floor on
//! real video).

use rbtrack::tracker::Variant;
use rbtrack_host::cf64::Params;
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::Frame;
use rbtrack_host::run::{start, CoreCf, Options};

/// Frames a run.
const FRAMES: usize = 300;

/// The scale filters run: scales, step and each tracker's size within this share of the
/// truth every frame.
const SCALES: [(usize, f64, f64); 2] = [(4, 1.18, 0.11), (8, 1.08, 0.05)];

/// The two trackers' sizes within this share of each other on average over the run...
const AGREE: f64 = 0.02;

/// ...and every frame.
const AGREE_EVERY: f64 = 0.05;

/// A deterministic hash of a pixel's coordinates and a salt, in `0..=255`.
fn hash(x: i64, y: i64, salt: u64) -> u8 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ salt.wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 31;
    h = h.wrapping_mul(0xD6E8_FEB8_6659_FD93);
    (h >> 56) as u8
}

/// The background: blotches of 12 px in muted colours with a fine grain.
fn background(x: i64, y: i64) -> [u8; 3] {
    let blotch = hash(x.div_euclid(12), y.div_euclid(12), 1);
    let grain = hash(x, y, 2) / 8;
    let v = 60 + blotch / 3 + grain;
    [v, v.saturating_add(10), v.saturating_sub(10)]
}

/// The target's pixel at `(u, v)` in `[0, 1)^2` of its box: a 4 x 4 pattern of patches in
/// saturated colours, so that its texture scales with it (as an object's does).
fn target(u: f64, v: f64) -> [u8; 3] {
    let (i, j) = ((u * 4.0) as i64, (v * 4.0) as i64);
    let k = hash(i, j, 3);
    match k % 4 {
        0 => [220, 60, 40],
        1 => [40, 200, 80],
        2 => [250, 230, 60],
        _ => [30, 40, 160],
    }
}

/// One scene: a `w x h` px target in a `width x height` frame, moving `speed` px a frame
/// to the right and half that down, centred in the frame half-way through the run.
#[derive(Clone, Copy, Debug)]
struct Case {
    width: usize,
    height: usize,
    w: usize,
    h: usize,
    speed: f64,
}

impl Case {
    /// The target's box in frame `k`, 0-based px (its top left on whole pixels).
    fn truth(&self, k: usize) -> BBox {
        let x0 = (self.width - self.w) as f64 / 2.0 - self.speed * FRAMES as f64 / 2.0;
        let y0 = (self.height - self.h) as f64 / 2.0 - self.speed * FRAMES as f64 / 4.0;
        let t = k as f64 * self.speed;
        BBox::new(
            (x0 + t).round(),
            (y0 + t / 2.0).round(),
            self.w as f64,
            self.h as f64,
        )
    }

    /// Frame `k`: the background with the target drawn at its box.
    fn frame(&self, back: &[u8], k: usize) -> Frame {
        let b = self.truth(k);
        let (x0, y0) = (b.x as usize, b.y as usize);
        let mut rgb = back.to_vec();
        for y in y0..y0 + self.h {
            for x in x0..x0 + self.w {
                let u = (x - x0) as f64 / self.w as f64;
                let v = (y - y0) as f64 / self.h as f64;
                let i = (y * self.width + x) * 3;
                rgb[i..i + 3].copy_from_slice(&target(u, v));
            }
        }
        Frame::rgb888(self.width as u32, self.height as u32, rgb).expect("frame")
    }
}

/// How a run's sizes compare, shares: the worst of each tracker against the truth, and the
/// two against each other at worst and on average.
#[derive(Clone, Copy, Debug, Default)]
struct Sizes {
    cf: f64,
    reference: f64,
    apart: f64,
    apart_mean: f64,
}

/// The sizes of the run of `case` at `scales` scales of `step`.
fn run(case: Case, scales: usize, step: f64) -> Sizes {
    let mut cf = CoreCf {
        scales,
        ..CoreCf::default()
    };
    cf.config.scale.step = rbtrack::fixed::Q16::from_f64(step);
    let base = Options::new(Variant::Rbpf);
    let core = Options {
        cf: Some(cf),
        ..base
    };
    let reference = Options {
        cf64: Some(Params::of_core(&cf.config, cf.grid, cf.scales)),
        ..base
    };
    let back: Vec<u8> = (0..case.height)
        .flat_map(|y| (0..case.width).flat_map(move |x| background(x as i64, y as i64)))
        .collect();
    let first = case.frame(&back, 0);
    let init = case.truth(0);
    let mut a = start(&core, &first, &init).expect("cf starts");
    let mut b = start(&reference, &first, &init).expect("reference starts");
    let off = |x: f64, y: f64| (x / y - 1.0).abs();
    let mut sizes = Sizes::default();
    let mut logs = 0.0;
    for k in 1..FRAMES {
        let frame = case.frame(&back, k);
        let (sa, sb) = (
            a.step(&frame).expect("steps").bbox,
            b.step(&frame).expect("steps").bbox,
        );
        let t = case.truth(k);
        sizes.cf = sizes.cf.max(off(sa.w, t.w)).max(off(sa.h, t.h));
        sizes.reference = sizes.reference.max(off(sb.w, t.w)).max(off(sb.h, t.h));
        sizes.apart = sizes.apart.max(off(sa.w, sb.w)).max(off(sa.h, sb.h));
        logs += ((sa.w / sb.w).ln().abs() + (sa.h / sb.h).ln().abs()) / 2.0;
    }
    sizes.apart_mean = logs / (FRAMES - 1) as f64;
    sizes
}

/// Every case: target sizes from 8 to 200 px a side at aspects 1:4 to 4:1, in the frames
/// they fit (at most half the frame each way), still and moving up to a third of a pixel a
/// frame.
fn cases() -> Vec<Case> {
    let frames = [(160, 120), (320, 240), (640, 480), (1280, 720)];
    let sizes = [
        (8, 8),
        (8, 16),
        (16, 8),
        (8, 32),
        (32, 8),
        (12, 12),
        (16, 16),
        (24, 24),
        (16, 64),
        (64, 16),
        (32, 32),
        (48, 48),
        (64, 64),
        (50, 200),
        (200, 50),
        (100, 100),
        (200, 200),
    ];
    let mut all = Vec::new();
    for (width, height) in frames {
        for (w, h) in sizes {
            if 2 * w > width || 2 * h > height {
                continue;
            }
            // A third of a pixel a frame where the target stays half its size from the
            // frame's edges, slower where it does not.
            let room = ((width - 2 * w) as f64).min(2.0 * (height - 2 * h) as f64);
            for speed in [0.0, (room / FRAMES as f64).min(1.0 / 3.0)] {
                all.push(Case {
                    width,
                    height,
                    w,
                    h,
                    speed,
                });
            }
        }
    }
    all
}

#[test]
fn both_trackers_keep_the_size_and_agree() {
    let cases: Vec<(Case, usize, f64, f64)> = SCALES
        .into_iter()
        .flat_map(|(scales, step, within)| {
            cases().into_iter().map(move |c| (c, scales, step, within))
        })
        .collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let results: Vec<((Case, usize, f64, f64), Sizes)> = std::thread::scope(|scope| {
        let chunks: Vec<_> = cases
            .chunks(cases.len().div_ceil(threads))
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|&(c, scales, step, within)| {
                            ((c, scales, step, within), run(c, scales, step))
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        chunks
            .into_iter()
            .flat_map(|h| h.join().expect("runs"))
            .collect()
    });
    let mut failed = Vec::new();
    for ((c, scales, step, within), s) in &results {
        let line = format!(
            "{scales} scales of {step}: {}x{} frame, {}x{} target, {:.2} px a frame: cf {:.3}, \
             reference {:.3} off the true size at worst, {:.3} apart at worst, {:.4} on average",
            c.width, c.height, c.w, c.h, c.speed, s.cf, s.reference, s.apart, s.apart_mean
        );
        println!("{line}");
        let true_size = s.cf <= *within && s.reference <= *within;
        if !true_size || s.apart > AGREE_EVERY || s.apart_mean > AGREE {
            failed.push(line);
        }
    }
    println!("{} cases", results.len());
    assert!(
        failed.is_empty(),
        "{} cases failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
}
