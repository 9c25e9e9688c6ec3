//! The fixed-point gradient cue against an f64 evaluation of the same definition.
//!
//! The reference computes the angles, boundary points, unit normals and sample positions
//! in f64 (the same point set: `K` angles `2 pi k / K`, `2 search + 1` samples along the
//! normal, each rounded half up to a pixel, out-of-frame samples skipped), the 5-tap
//! gradient from the luma bytes with clamped taps, magnitudes by f64 `sqrt`, and the mean
//! of `min(m_k / saturation, 1)`.
//!
//! Tolerance: the fixed-point angle table and normals are Q16.16, so a sample that lies
//! within about 1e-4 px of a pixel boundary can round to the neighbouring pixel; that
//! changes one point's term, at most `1 / K`. We assert that 99 % of windows agree within
//! 1e-3, that the RMS error is below 1e-3, and that no window is off by more than `2 / K`.

use rbtrack::cue::{GradientConfig, GradientCue};
use rbtrack::fixed::Q16;
use rbtrack::image::{Gray8, ImageView, Rgb888};
use rbtrack::rng::Rng;
use rbtrack::window::Ellipse;

const W: usize = 96;
const H: usize = 72;

/// Luma frame: a few filled ellipses of random level over a random background, with
/// optional noise.
fn frame(rng: &mut Rng) -> Vec<u8> {
    let mut px = vec![rng.next_u32() as u8; W * H];
    for _ in 0..1 + rng.below(4) {
        let (cx, cy) = (rng.below(W as u32) as f64, rng.below(H as u32) as f64);
        let (rx, ry) = (3.0 + rng.below(30) as f64, 3.0 + rng.below(25) as f64);
        let level = rng.next_u32() as u8;
        for (i, p) in px.iter_mut().enumerate() {
            let (x, y) = ((i % W) as f64 - cx, (i / W) as f64 - cy);
            if (x / rx).powi(2) + (y / ry).powi(2) <= 1.0 {
                *p = level;
            }
        }
    }
    let noise = rng.below(3) * 8;
    if noise > 0 {
        for p in px.iter_mut() {
            *p = p.saturating_add(rng.below(noise) as u8);
        }
    }
    px
}

/// The cue in f64 on a luma frame `W x H`.
fn reference(luma: &[u8], e: &Ellipse, points: usize, search: i32, saturation: f64) -> f64 {
    let (cx, cy, hx, hy) = (e.cx.to_f64(), e.cy.to_f64(), e.hx.to_f64(), e.hy.to_f64());
    let at = |x: i64, y: i64| {
        let (x, y) = (x.clamp(0, W as i64 - 1), y.clamp(0, H as i64 - 1));
        luma[y as usize * W + x as usize] as f64
    };
    let mut sum = 0.0;
    for k in 0..points {
        let t = 2.0 * std::f64::consts::PI * k as f64 / points as f64;
        let (c, s) = (t.cos(), t.sin());
        let (bx, by) = (cx + hx * c, cy + hy * s);
        let (nx, ny) = (c / hx, s / hy);
        let len = nx.hypot(ny);
        let (ux, uy) = (nx / len, ny / len);
        let mut best = 0f64;
        for j in -search..=search {
            let x = (bx + j as f64 * ux + 0.5).floor() as i64;
            let y = (by + j as f64 * uy + 0.5).floor() as i64;
            if x < 0 || y < 0 || x >= W as i64 || y >= H as i64 {
                continue;
            }
            let gx = at(x + 2, y) + 2.0 * at(x + 1, y) - 2.0 * at(x - 1, y) - at(x - 2, y);
            let gy = at(x, y + 2) + 2.0 * at(x, y + 1) - 2.0 * at(x, y - 1) - at(x, y - 2);
            best = best.max(gx.hypot(gy));
        }
        sum += (best / saturation).min(1.0);
    }
    sum / points as f64
}

#[test]
fn gradient_cue_matches_f64_reference() {
    let mut rng = Rng::new(99);
    let frames: Vec<Vec<u8>> = (0..30).map(|_| frame(&mut rng)).collect();
    let trials = 5000;
    let (mut max, mut sum_sq, mut within, mut worst_allowed) = (0f64, 0f64, 0usize, true);
    for i in 0..trials {
        let mut cfg = GradientConfig::new();
        cfg.points = 1 + rng.below(64) as usize;
        cfg.search_px = rng.below(9);
        cfg.saturation = 40 + rng.below(400);
        let cue = GradientCue::new(&cfg).unwrap();
        let luma = &frames[rng.below(frames.len() as u32) as usize];
        let u = |rng: &mut Rng| rng.uniform().to_f64();
        let e = Ellipse::new(
            Q16::from_f64(u(&mut rng) * (W as f64 + 20.0) - 10.0),
            Q16::from_f64(u(&mut rng) * (H as f64 + 20.0) - 10.0),
            Q16::from_f64(0.5 + 40.0 * u(&mut rng)),
            Q16::from_f64(0.5 + 30.0 * u(&mut rng)),
        );
        // Alternate formats: grey bytes, or the same luma as grey RGB888.
        let got = if i % 2 == 0 {
            cue.evaluate(&ImageView::<Gray8>::new(luma, W, H, W).unwrap(), &e)
        } else {
            let rgb: Vec<u8> = luma.iter().flat_map(|&v| [v, v, v]).collect();
            cue.evaluate(&ImageView::<Rgb888>::new(&rgb, W, H, W).unwrap(), &e)
        }
        .to_f64();
        let want = reference(
            luma,
            &e,
            cfg.points,
            cfg.search_px as i32,
            cfg.saturation as f64,
        );
        assert!((0.0..=1.0).contains(&got));
        let err = (got - want).abs();
        max = max.max(err);
        sum_sq += err * err;
        within += (err <= 1e-3) as usize;
        worst_allowed &= err <= 2.0 / cfg.points as f64;
    }
    let rms = (sum_sq / trials as f64).sqrt();
    println!(
        "gradient cue: {trials} windows: |g - g_f64| max {max:.2e}, RMS {rms:.2e}, \
         {:.2} % within 1e-3",
        100.0 * within as f64 / trials as f64
    );
    assert!(
        within * 100 >= trials * 99,
        "{within} of {trials} within 1e-3"
    );
    assert!(rms < 1e-3, "RMS {rms}");
    assert!(worst_allowed, "a window differs by more than 2 / K");
}
