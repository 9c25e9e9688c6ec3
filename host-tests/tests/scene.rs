//! Synthetic scenes: determinism, appearance, and the ground truth of each variant.

use rbtrack::image::rgb888_to_rgb565;
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::{Format, Frame};
use rbtrack_host::scene::*;

fn scene(variant: Variant, seed: u64) -> Scene {
    Scene::new(SceneConfig::new(variant, seed)).unwrap()
}

/// Mean colour of the 3x3 patch around `(x, y)`.
fn patch(rgb: &[u8], w: u32, x: f64, y: f64) -> [f64; 3] {
    let (x, y) = (x.round() as i64, y.round() as i64);
    let mut sum = [0.0; 3];
    for dy in -1..=1 {
        for dx in -1..=1 {
            let i = (((y + dy) * w as i64 + x + dx) * 3) as usize;
            for c in 0..3 {
                sum[c] += rgb[i + c] as f64 / 9.0;
            }
        }
    }
    sum
}

fn distance(a: [f64; 3], b: [u8; 3], gain: f64) -> f64 {
    (0..3)
        .map(|c| (a[c] - b[c] as f64 * gain).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn same_seed_same_bytes_different_seed_different_bytes() {
    for v in Variant::ALL {
        let (a, b, c) = (scene(v, 11), scene(v, 11), scene(v, 12));
        for i in [0, 57] {
            let fa = a.render(i).unwrap();
            assert_eq!(fa, b.render(i).unwrap(), "{v} frame {i}");
            assert_ne!(fa, c.render(i).unwrap(), "{v} frame {i}");
        }
        assert_eq!(a.truths(), b.truths(), "{v}");
        // Noise differs from frame to frame.
        assert_ne!(a.render(1).unwrap(), a.render(2).unwrap());
    }
}

#[test]
fn frame_sizes_and_rgb565() {
    let s = scene(Variant::Perspective, 1);
    assert_eq!((s.width(), s.height(), s.len()), (320, 240, 100));
    let rgb = s.render(5).unwrap();
    assert_eq!(rgb.len(), 320 * 240 * 3);
    let packed = Frame::rgb888(320, 240, rgb.clone())
        .unwrap()
        .convert(Format::Rgb565Le)
        .unwrap();
    assert_eq!(packed.bytes.len(), 320 * 240 * 2);
    assert_eq!(
        packed.bytes[..2],
        rgb888_to_rgb565(rgb[0], rgb[1], rgb[2]).to_le_bytes()
    );
    assert_eq!(s.frames().count(), 100);

    let mut small = SceneConfig::new(Variant::Occlusion, 3);
    (small.width, small.height, small.frames) = (160, 120, 40);
    let s = Scene::new(small).unwrap();
    assert_eq!(s.render(39).unwrap().len(), 160 * 120 * 3);
    assert!(s.render(40).is_err());
}

#[test]
fn bad_configurations_are_errors() {
    let ok = SceneConfig::new(Variant::FastMotion, 0);
    for (cfg, what) in [
        (SceneConfig { width: 10, ..ok }, "size"),
        (SceneConfig { height: 5000, ..ok }, "size"),
        (SceneConfig { frames: 3, ..ok }, "frames"),
        (
            SceneConfig {
                noise_sigma: f64::NAN,
                ..ok
            },
            "noise",
        ),
        (
            SceneConfig {
                noise_sigma: -1.0,
                ..ok
            },
            "noise",
        ),
    ] {
        let e = Scene::new(cfg).unwrap_err();
        assert!(!e.to_string().is_empty(), "{what}");
    }
    assert!(matches!(
        scene(Variant::FastMotion, 0).render(100),
        Err(SceneError::FrameIndex {
            index: 100,
            len: 100
        })
    ));
}

#[test]
fn variant_names_round_trip() {
    for v in Variant::ALL {
        assert_eq!(Variant::from_name(v.name()), Some(v));
        assert_eq!(Variant::from_name(&v.to_string().to_uppercase()), Some(v));
    }
    assert_eq!(Variant::from_name("nope"), None);
}

#[test]
fn target_has_its_colours_at_the_ground_truth() {
    for v in Variant::ALL {
        let s = scene(v, 5);
        let mut checked = 0;
        for i in (0..s.len()).step_by(7) {
            let t = *s.truth(i).unwrap();
            if t.visible_fraction < 1.0 {
                continue;
            }
            if let Some((dx, dy, dhx, dhy)) = s.distractor(i) {
                // Skip frames where the distractor overlaps the target's box.
                if BBox::from_ellipse(dx, dy, dhx, dhy).iou(&t.bbox) > 0.0 {
                    continue;
                }
            }
            let rgb = s.render(i).unwrap();
            let top = patch(&rgb, s.width(), t.cx, t.cy - t.hy / 2.0);
            let bottom = patch(&rgb, s.width(), t.cx, t.cy + t.hy / 2.0);
            assert!(
                distance(top, TOP_COLOUR, t.brightness) < 15.0,
                "{v} frame {i}: top {top:?}"
            );
            assert!(
                distance(bottom, BOTTOM_COLOUR, t.brightness) < 15.0,
                "{v} frame {i}: bottom {bottom:?}"
            );
            // Outside the box, at the same rows, it is background.
            let left = patch(&rgb, s.width(), t.bbox.x - 4.0, t.cy - t.hy / 2.0);
            if t.bbox.x - 4.0 > 2.0 {
                assert!(distance(left, TOP_COLOUR, t.brightness) > 15.0, "{v} {i}");
            }
            checked += 1;
        }
        assert!(checked >= 8, "{v}: only {checked} frames checked");
    }
}

#[test]
fn background_is_textured_and_moderately_coloured() {
    let mut cfg = SceneConfig::new(Variant::Perspective, 9);
    cfg.noise_sigma = 0.0;
    let s = Scene::new(cfg).unwrap();
    let rgb = s.render(0).unwrap();
    // Left quarter of the frame: the target is not there in frame 0.
    let (mut sat, mut n, mut lum) = (0.0, 0.0, Vec::new());
    for y in 0..240 {
        for x in 0..60 {
            let i = (y * 320 + x) * 3;
            let p = &rgb[i..i + 3];
            let (mx, mn) = (*p.iter().max().unwrap(), *p.iter().min().unwrap());
            sat += (mx - mn) as f64;
            n += 1.0;
            lum.push(p.iter().map(|&c| c as f64).sum::<f64>() / 3.0);
        }
    }
    let mean_lum = lum.iter().sum::<f64>() / n;
    let sd = (lum.iter().map(|l| (l - mean_lum).powi(2)).sum::<f64>() / n).sqrt();
    let mean_chroma = sat / n;
    assert!(sd > 8.0, "luminance sd {sd}");
    assert!((15.0..90.0).contains(&mean_chroma), "chroma {mean_chroma}");
}

#[test]
fn noise_has_the_configured_sigma() {
    let mut cfg = SceneConfig::new(Variant::Perspective, 4);
    cfg.noise_sigma = 0.0;
    let clean = Scene::new(cfg).unwrap().render(0).unwrap();
    cfg.noise_sigma = 6.0;
    let noisy = Scene::new(cfg).unwrap().render(0).unwrap();
    let d: Vec<f64> = clean
        .iter()
        .zip(&noisy)
        .filter(|(c, _)| (10..245).contains(*c))
        .map(|(&c, &n)| n as f64 - c as f64)
        .collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let sd = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
    assert!(mean.abs() < 0.1, "mean {mean}");
    assert!((sd - 6.0).abs() < 0.2, "sd {sd}");
}

#[test]
fn perspective_grows_on_the_ground_plane() {
    let s = scene(Variant::Perspective, 2);
    let t = s.truths();
    let ratio = t[99].hy / t[0].hy;
    assert!((2.0..=3.0).contains(&ratio), "growth {ratio}");
    assert!(t[99].cy > t[0].cy + 60.0);
    for w in t.windows(2) {
        assert!(w[1].hy > w[0].hy);
    }
    for f in t {
        let expected = s.scale_per_row() * (f.cy - s.horizon_y());
        assert!((f.hy - expected).abs() < 1e-9);
        assert!((f.hx - s.aspect() * f.hy).abs() < 1e-9);
        assert!((f.hy - s.half_height_at(f.cy)).abs() < 1e-9);
        assert_eq!(f.bbox, BBox::from_ellipse(f.cx, f.cy, f.hx, f.hy));
        assert!(f.visible && f.visible_fraction == 1.0);
    }
    // Same relation at another size: scale_per_row is resolution-independent.
    let mut cfg = SceneConfig::new(Variant::Perspective, 2);
    (cfg.width, cfg.height, cfg.frames) = (640, 480, 50);
    let big = Scene::new(cfg).unwrap();
    assert_eq!(big.scale_per_row(), s.scale_per_row());
    let ratio = big.truths()[49].hy / big.truths()[0].hy;
    assert!((2.0..=3.0).contains(&ratio));
}

#[test]
fn occlusion_hides_the_target_for_15_frames() {
    let s = scene(Variant::Occlusion, 8);
    let hidden: Vec<usize> = (0..s.len())
        .filter(|&i| s.truth(i).unwrap().visible_fraction == 0.0)
        .collect();
    assert_eq!(hidden.len(), 15, "{hidden:?}");
    assert_eq!(hidden[14] - hidden[0], 14, "not consecutive: {hidden:?}");
    assert!(hidden.iter().all(|&i| !s.truth(i).unwrap().visible));
    let (x0, x1) = s.occluder_columns().unwrap();
    assert!(x0 > 0 && x1 < 319);
    // Just before and after, partly visible; at both ends, fully visible.
    assert!(s.truth(hidden[0] - 1).unwrap().visible_fraction > 0.0);
    assert!(s.truth(hidden[14] + 1).unwrap().visible_fraction > 0.0);
    assert_eq!(s.truth(0).unwrap().visible_fraction, 1.0);
    assert_eq!(s.truth(99).unwrap().visible_fraction, 1.0);
    // While hidden, no target colour shows inside the ellipse.
    let target_like = |i: usize| {
        let t = *s.truth(i).unwrap();
        let rgb = s.render(i).unwrap();
        let mut n = 0;
        for y in (t.cy - t.hy) as i64..=(t.cy + t.hy) as i64 {
            for x in (t.cx - t.hx) as i64..=(t.cx + t.hx) as i64 {
                let p = patch(&rgb, 320, x as f64, y as f64);
                if distance(p, TOP_COLOUR, 1.0) < 40.0 || distance(p, BOTTOM_COLOUR, 1.0) < 40.0 {
                    n += 1;
                }
            }
        }
        n
    };
    assert_eq!(target_like(hidden[7]), 0);
    assert!(target_like(0) > 300);
}

#[test]
fn leave_and_return() {
    let s = scene(Variant::LeaveAndReturn, 3);
    let out: Vec<usize> = (0..s.len())
        .filter(|&i| s.truth(i).unwrap().visible_fraction == 0.0)
        .collect();
    assert_eq!(out.len(), 20, "{out:?}");
    assert_eq!(out[19] - out[0], 19, "not consecutive: {out:?}");
    for &i in &out {
        let t = s.truth(i).unwrap();
        assert!(!t.visible);
        assert!(t.cx - t.hx > 319.0, "frame {i}: {t:?}");
        assert_eq!(t.bbox.clip(320.0, 240.0).w, 0.0);
    }
    assert!(s.truth(0).unwrap().visible);
    assert!(s.truth(99).unwrap().visible);
    assert_eq!(s.truth(99).unwrap().visible_fraction, 1.0);
    // Partly visible frames on the way out and in.
    assert!(s
        .truths()
        .iter()
        .any(|t| t.visible_fraction > 0.0 && t.visible_fraction < 1.0));
}

#[test]
fn distractor_crosses_in_front() {
    let s = scene(Variant::Distractor, 4);
    let gaps: Vec<f64> = (0..s.len())
        .map(|i| {
            let t = s.truth(i).unwrap();
            let (dx, dy, _, _) = s.distractor(i).unwrap();
            (t.cx - dx).hypot(t.cy - dy)
        })
        .collect();
    let closest = (0..s.len())
        .min_by(|&a, &b| gaps[a].total_cmp(&gaps[b]))
        .unwrap();
    assert!((40..=60).contains(&closest), "crossing at {closest}");
    let t = s.truth(closest).unwrap();
    assert!(t.visible_fraction < 0.6, "{t:?}");
    assert_eq!(s.truth(0).unwrap().visible_fraction, 1.0);
    // The distractor wears the same colours.
    let (dx, dy, _, dhy) = s.distractor(10).unwrap();
    let rgb = s.render(10).unwrap();
    assert!(distance(patch(&rgb, 320, dx, dy - dhy / 2.0), TOP_COLOUR, 1.0) < 15.0);
    assert!(distance(patch(&rgb, 320, dx, dy + dhy / 2.0), BOTTOM_COLOUR, 1.0) < 15.0);
    assert!(scene(Variant::Perspective, 4).distractor(10).is_none());
}

#[test]
fn brightness_ramps_down_then_up() {
    let s = scene(Variant::BrightnessRamp, 6);
    let g: Vec<f64> = s.truths().iter().map(|t| t.brightness).collect();
    assert_eq!(g[0], 1.0);
    assert!((g[50] - 0.6).abs() < 0.02, "{}", g[50]);
    assert!((g[99] - 1.1).abs() < 1e-9);
    let mean = |i: usize| {
        let f = s.render(i).unwrap();
        f.iter().map(|&v| v as f64).sum::<f64>() / f.len() as f64
    };
    let ratio = mean(50) / mean(0);
    assert!((ratio - 0.6).abs() < 0.04, "{ratio}");
    assert!(scene(Variant::Perspective, 6)
        .truths()
        .iter()
        .all(|t| t.brightness == 1.0));
}

#[test]
fn fast_motion_is_fast_and_turns() {
    let s = scene(Variant::FastMotion, 7);
    let t = s.truths();
    let steps: Vec<(f64, f64)> = t
        .windows(2)
        .map(|w| (w[1].cx - w[0].cx, w[1].cy - w[0].cy))
        .collect();
    let speeds: Vec<f64> = steps.iter().map(|(x, y)| x.hypot(*y)).collect();
    let in_range = speeds
        .iter()
        .filter(|&&v| (7.99..=15.01).contains(&v))
        .count();
    assert!(in_range as f64 >= 0.8 * speeds.len() as f64, "{speeds:?}");
    assert!(speeds.iter().all(|&v| v <= 15.01));
    let turns = steps
        .windows(2)
        .filter(|w| {
            let (a, b) = (w[0], w[1]);
            let cos = (a.0 * b.0 + a.1 * b.1) / (a.0.hypot(a.1) * b.0.hypot(b.1));
            cos < 0.87 // more than 30 degrees
        })
        .count();
    assert!(turns >= 5, "{turns} turns");
    assert!(t.iter().all(|f| f.visible_fraction == 1.0));
}
