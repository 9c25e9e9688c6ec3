//! The fixed-point Bhattacharyya coefficient against an f64 computation of the same
//! quantity.
//!
//! For each trial: a model window, optionally blended with a second window by the adaptive
//! update `q <- (1 - a) q + a p`, and a candidate window, on random structured frames.
//! The reference takes the pixel set that `window::visit` visits, but computes its own
//! kernel weights `1 - d^2` in f64 from the ellipse, its own bin indices from the raw
//! bytes, normalises in f64 and sums `sqrt(p_u q_u)` in f64. The fixed-point path is
//! `Histogram::fill`, `Model::from_histogram` / `Model::update` and
//! `Histogram::bhattacharyya`.

use rbtrack::fixed::Q16;
use rbtrack::hist::{Histogram, Model};
use rbtrack::image::{ImageView, PixelFormat, Rgb565Le, Rgb8x8x8, Uyvy, Yuv8x8x4, Yuyv};
use rbtrack::rng::Rng;
use rbtrack::window::{visit, Ellipse};

const W: usize = 120;
const H: usize = 90;

/// A frame of `W x H` 2-byte pixels: random rectangles over a background, coloured from a
/// palette shared by all frames, plus per-pixel noise of random amplitude.
fn frame(rng: &mut Rng, palette: &[[u8; 2]]) -> Vec<u8> {
    let colour = |rng: &mut Rng| palette[rng.below(palette.len() as u32) as usize];
    let mut px = vec![colour(rng); W * H];
    for _ in 0..1 + rng.below(12) {
        let (x0, y0) = (rng.below(W as u32) as usize, rng.below(H as u32) as usize);
        let (w, h) = (1 + rng.below(60) as usize, 1 + rng.below(45) as usize);
        let colour = colour(rng);
        for y in y0..(y0 + h).min(H) {
            for x in x0..(x0 + w).min(W) {
                px[y * W + x] = colour;
            }
        }
    }
    let noise = rng.below(4);
    for p in px.iter_mut() {
        for b in p.iter_mut() {
            if noise > 0 && rng.below(4) == 0 {
                *b ^= (rng.next_u32() as u8) & ((1 << (2 * noise)) - 1);
            }
        }
    }
    px.concat()
}

fn random_ellipse(rng: &mut Rng) -> Ellipse {
    let q = |v: f64| Q16::from_f64(v);
    let u = |rng: &mut Rng| rng.uniform().to_f64();
    Ellipse::new(
        q(u(rng) * (W as f64 + 20.0) - 10.0),
        q(u(rng) * (H as f64 + 16.0) - 8.0),
        q(0.5 + 60.0 * u(rng)),
        q(0.5 + 45.0 * u(rng)),
    )
}

/// f64 histogram of the pixels `visit` visits, with f64 kernel weights; `None` if empty.
fn reference_hist<P: PixelFormat>(
    img: &ImageView<'_, P>,
    e: &Ellipse,
    cap: u32,
    bins: usize,
    bin_of: impl Fn(&[u8], usize) -> usize,
) -> Option<Vec<f64>> {
    let (cx, cy, hx, hy) = (e.cx.to_f64(), e.cy.to_f64(), e.hx.to_f64(), e.hy.to_f64());
    let mut hist = vec![0f64; bins];
    visit(img, e, cap, |row, x, _| {
        let y = row.y();
        let d2 = ((x as f64 - cx) / hx).powi(2) + ((y as f64 - cy) / hy).powi(2);
        hist[bin_of(row.bytes(), x)] += (1.0 - d2).max(0.0);
    });
    let mass: f64 = hist.iter().sum();
    (mass > 0.0).then(|| hist.iter().map(|v| v / mass).collect())
}

/// Bin of RGB565 little-endian pixel `x` by the top 3 bits of each channel.
fn rgb565_bin(row: &[u8], x: usize) -> usize {
    let v = u16::from_le_bytes([row[2 * x], row[2 * x + 1]]) as usize;
    let (r5, g6, b5) = (v >> 11, (v >> 5) & 63, v & 31);
    ((r5 >> 2) << 6) | ((g6 >> 3) << 3) | (b5 >> 2)
}

/// Bin of YUV 4:2:2 pixel `x` by the top 3 bits of U and V and the top 2 of its Y: pairs
/// `Y0 U Y1 V` (YUYV) or, when `CHROMA_FIRST`, `U Y0 V Y1` (UYVY).
fn yuv422_bin<const CHROMA_FIRST: bool>(row: &[u8], x: usize) -> usize {
    let pair = 4 * (x / 2);
    let (y, u, v) = if CHROMA_FIRST {
        (row[2 * x + 1], row[pair], row[pair + 2])
    } else {
        (row[2 * x], row[pair + 1], row[pair + 3])
    };
    let (y, u, v) = (y as usize, u as usize, v as usize);
    ((u >> 5) << 5) | ((v >> 5) << 2) | (y >> 6)
}

fn rho_f64(p: &Option<Vec<f64>>, q: &Option<Vec<f64>>) -> f64 {
    match (p, q) {
        (Some(p), Some(q)) => p.iter().zip(q).map(|(a, b)| (a * b).sqrt()).sum(),
        _ => 0.0,
    }
}

struct Stats {
    max: f64,
    sum_sq: f64,
    n: usize,
    nonzero: usize,
    high: usize,
    pixels: u64,
}

/// Runs `trials` trials of format `P` with binning `Bn` of `B` bins.
fn run<P: PixelFormat, Bn: rbtrack::image::Binning, const B: usize>(
    seed: u64,
    trials: usize,
    bin_of: fn(&[u8], usize) -> usize,
) -> Stats {
    let mut rng = Rng::new(seed);
    let palette: Vec<[u8; 2]> = (0..10)
        .map(|_| [rng.next_u32() as u8, rng.next_u32() as u8])
        .collect();
    let frames: Vec<Vec<u8>> = (0..40).map(|_| frame(&mut rng, &palette)).collect();
    let mut stats = Stats {
        max: 0.0,
        sum_sq: 0.0,
        n: 0,
        nonzero: 0,
        high: 0,
        pixels: 0,
    };
    let (mut h, mut g) = (Histogram::<B>::new(), Histogram::<B>::new());
    for _ in 0..trials {
        let pick = |rng: &mut Rng| rng.below(frames.len() as u32) as usize;
        let (fa, fb, fc) = (pick(&mut rng), pick(&mut rng), pick(&mut rng));
        let img = |i: usize| ImageView::<P>::new(&frames[i], W, H, W).unwrap();
        let spread = 1 << (6 + rng.below(7));
        let cap = 16 + rng.below(spread); // 16..=4111, log-spread
        let (ea, ec) = (random_ellipse(&mut rng), random_ellipse(&mut rng));
        // Candidate: half the time a perturbed model window on the model's frame.
        let (fb, eb) = if rng.below(2) == 0 {
            let mut jitter =
                |v: Q16, by: f64| v + Q16::from_f64(by * (rng.uniform().to_f64() - 0.5));
            let eb = Ellipse::new(
                jitter(ea.cx, 8.0),
                jitter(ea.cy, 8.0),
                jitter(ea.hx, 4.0).max(Q16::HALF),
                jitter(ea.hy, 4.0).max(Q16::HALF),
            );
            (fa, eb)
        } else {
            (fb, random_ellipse(&mut rng))
        };

        // Model: window a, then maybe blended with window c.
        h.fill::<Bn, P>(&img(fa), &ea, cap);
        let mut model = Model::<B>::from_histogram(&h);
        let mut q_ref = reference_hist(&img(fa), &ea, cap, B, bin_of);
        if rng.below(3) == 0 {
            let alpha = rng.uniform();
            h.fill::<Bn, P>(&img(fc), &ec, cap);
            model.update(&h, alpha);
            let p_ref = reference_hist(&img(fc), &ec, cap, B, bin_of);
            let a = alpha.to_f64();
            q_ref = match (q_ref, p_ref) {
                (Some(q), Some(p)) => Some(
                    q.iter()
                        .zip(&p)
                        .map(|(q, p)| (1.0 - a) * q + a * p)
                        .collect(),
                ),
                (None, Some(p)) => Some(p.iter().map(|p| a * p).collect()),
                (q, None) => q,
            };
        }

        // Candidate window b.
        stats.pixels += g.fill::<Bn, P>(&img(fb), &eb, cap) as u64;
        let rho = g.bhattacharyya(&model).to_f64();
        let reference = rho_f64(&reference_hist(&img(fb), &eb, cap, B, bin_of), &q_ref);
        assert!((0.0..=1.0).contains(&rho));
        let err = (rho - reference).abs();
        stats.max = stats.max.max(err);
        stats.sum_sq += err * err;
        stats.n += 1;
        stats.nonzero += (reference > 0.0) as usize;
        stats.high += (reference > 0.8) as usize;
    }
    stats
}

#[test]
fn bhattacharyya_matches_f64_reference() {
    for (name, stats) in [
        (
            "RGB565 LE, 8x8x8 bins",
            run::<Rgb565Le, Rgb8x8x8, 512>(2024, 10_000, rgb565_bin),
        ),
        (
            "YUYV, 8x8x4 chroma bins",
            run::<Yuyv, Yuv8x8x4, 256>(7, 2_000, yuv422_bin::<false>),
        ),
        (
            "UYVY, 8x8x4 chroma bins",
            run::<Uyvy, Yuv8x8x4, 256>(8, 2_000, yuv422_bin::<true>),
        ),
    ] {
        let rms = (stats.sum_sq / stats.n as f64).sqrt();
        println!(
            "{name}: {} windows ({} with rho > 0, {} with rho > 0.8): \
             {:.0} px per window on average; |rho - rho_f64| max {:.2e}, RMS {:.2e}",
            stats.n,
            stats.nonzero,
            stats.high,
            stats.pixels as f64 / stats.n as f64,
            stats.max,
            rms
        );
        assert!(stats.nonzero > stats.n / 2 && stats.high > stats.n / 10);
        assert!(stats.max <= 2e-3, "{name}: max error {}", stats.max);
    }
}
