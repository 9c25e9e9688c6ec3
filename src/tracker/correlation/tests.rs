//! The correlation-filter tracker's unit tests.

use super::*;
use crate::image::{Gray8, Luma64};
use std::vec;
use std::vec::Vec;

type Small = CfTracker<Luma64, 64, 16, 8>;

/// A 96 x 72 grey frame: a textured 16 x 20 px block at `(x0, 26)` on a darker ramp.
fn frame(x0: usize) -> Vec<u8> {
    frame_at(x0, 26)
}

/// The 96 x 72 ramp alone.
fn ramp() -> Vec<u8> {
    (0..96 * 72).map(|i| (40 + (i % 96) / 4) as u8).collect()
}

/// [`frame`] with the block at `(x0, y0)`.
fn frame_at(x0: usize, y0: usize) -> Vec<u8> {
    let w = 96;
    let mut buf = ramp();
    for y in y0..y0 + 20 {
        for x in x0..x0 + 16 {
            buf[y * w + x] = if (x - x0) / 4 % 2 == ((y - y0 + 26) / 5) % 2 {
                230
            } else {
                150
            };
        }
    }
    buf
}

#[test]
fn follows_a_moving_block() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    let mut tracker = Small::new(CfConfig::default(), &view, Rect::new(20, 26, 16, 20)).unwrap();
    for x0 in (22..50).step_by(2) {
        let buf = frame(x0);
        let e = tracker.step(&ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap());
        let cx = e.ellipse.cx.to_f64();
        assert!((cx - (x0 as f64 + 7.5)).abs() < 1.5, "x0 {x0}: centre {cx}");
        assert_eq!(e.status, Status::Tracking);
    }
}

#[test]
fn start_refuses_bad_settings_and_boxes_and_keeps_the_tracker() {
    let buf = frame(20);
    let view = ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap();
    let mut tracker = Small::unstarted();
    let bad = CfConfig {
        merge: Q16::from_int(2),
        ..CfConfig::default()
    };
    let good = CfConfig::default();
    let steep = CfConfig {
        scale: ScaleSettings {
            step: Q16::from_ratio(8, 5),
            ..good.scale
        },
        ..good
    };
    let cases = [
        (
            bad,
            Rect::new(20, 26, 16, 20),
            ConfigError::OutOfRange("merge"),
        ),
        (
            steep,
            Rect::new(20, 26, 16, 20),
            ConfigError::OutOfRange("scale.step"),
        ),
        (
            CfConfig {
                redetect: 9,
                ..good
            },
            Rect::new(20, 26, 16, 20),
            ConfigError::OutOfRange("redetect"),
        ),
        (good, Rect::new(20, 26, 3, 20), ConfigError::InitialTooSmall),
        (
            good,
            Rect::new(100, 26, 16, 20),
            ConfigError::InitialOutside,
        ),
    ];
    for (config, init, error) in cases {
        assert_eq!(tracker.start(config, &view, init), Err(error));
        assert_eq!(tracker.config().cell, 0, "left unstarted");
    }
    // Unstarted, a step changes nothing.
    let before = *tracker.estimate();
    assert_eq!(tracker.step(&view), before);
    assert_eq!(tracker.estimate().status, Status::Lost);
}

#[test]
fn relocate_keeps_the_models_and_moves_the_target() {
    fn view(buf: &[u8]) -> ImageView<'_, Gray8> {
        ImageView::new(buf, 96, 72, 96).unwrap()
    }
    let first = frame(20);
    let mut tracker = Small::new(
        CfConfig::default(),
        &view(&first),
        Rect::new(20, 26, 16, 20),
    )
    .unwrap();
    for x0 in (22..30).step_by(2) {
        tracker.step(&view(&frame(x0)));
    }
    let models = |t: &Small| std::format!("{:?} {:?} {:?}", t.filter, t.colour, t.scale);
    let learnt = models(&tracker);
    // The block jumps 40 px, beyond the search; a detector's box brings the tracker there.
    let jumped = frame(68);
    let before = *tracker.estimate();
    let bad = [
        (Rect::new(68, 26, 3, 20), ConfigError::InitialTooSmall),
        (Rect::new(100, 26, 16, 20), ConfigError::InitialOutside),
    ];
    for (init, error) in bad {
        assert_eq!(tracker.relocate(&view(&jumped), init), Err(error));
        assert_eq!(*tracker.estimate(), before, "unchanged");
    }
    tracker
        .relocate(&view(&jumped), Rect::new(68, 26, 16, 20))
        .unwrap();
    assert_eq!(
        models(&tracker),
        learnt,
        "nothing learnt, nothing forgotten"
    );
    let e = tracker.estimate();
    assert_eq!((e.ellipse.cx.to_f64(), e.status), (75.5, Status::Tracking));
    for x0 in (70..78).step_by(2) {
        let e = tracker.step(&view(&frame(x0)));
        let cx = e.ellipse.cx.to_f64();
        assert!((cx - (x0 as f64 + 7.5)).abs() < 1.5, "x0 {x0}: centre {cx}");
    }
    // Unstarted, there is nothing to keep.
    let mut fresh = Small::unstarted();
    let init = Rect::new(68, 26, 16, 20);
    let refused = fresh.relocate(&view(&jumped), init);
    assert_eq!(refused, Err(ConfigError::ModelSettings));
}

#[test]
fn the_least_size_is_never_below_min_side() {
    let buf = frame(20);
    let view = ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap();
    let mut tracker = Small::unstarted();
    let q = |bits: i32| Q16::from_bits(bits);
    // Sides (Q16.16 bits) whose floored 4 / side times side falls short of 4 px, and one
    // of 4 px, whose least factor is 1.
    for (w, h) in [
        (18 << 16, 20 << 16),
        (7 << 16, 11 << 16),
        (1_000_003, 458_761),
        (30 << 16, 4 << 16),
    ] {
        let init = Rect {
            x: Q16::from_int(10),
            y: Q16::from_int(10),
            w: q(w),
            h: q(h),
        };
        tracker.start(CfConfig::default(), &view, init).unwrap();
        tracker.resize(Q16::ONE);
        assert_eq!(tracker.size, (init.w, init.h), "the first box's size at 1");
        tracker.resize(Q16::ZERO);
        let min = Q16::from_int(MIN_SIDE);
        assert!(
            tracker.size.0.min(tracker.size.1) >= min,
            "{:?} from {init:?}",
            tracker.size
        );
    }
}

/// [`frame`] with a copy of its block `dx` px to the right of it.
fn with_copy(dx: usize) -> Vec<u8> {
    let (mut buf, copy) = (frame(20), frame(20 + dx));
    for y in 26..46 {
        let row = y * 96 + 20 + dx..y * 96 + 36 + dx;
        buf[row.clone()].copy_from_slice(&copy[row]);
    }
    buf
}

/// A copy of the block 14 px beside it (3.5 cells of the patch, beyond the peak's lobe)
/// answers nearly as well: the score, the margin over it, falls by more than a third,
/// the peak by far less, and the tracker stays on the block.
#[test]
fn a_look_alike_beside_the_target_lowers_the_score_more_than_the_peak() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    let step = |buf: &[u8]| {
        let mut tracker =
            Small::new(CfConfig::default(), &view, Rect::new(20, 26, 16, 20)).unwrap();
        let e = tracker.step(&ImageView::<Gray8>::new(buf, 96, 72, 96).unwrap());
        assert!((e.ellipse.cx.to_f64() - 27.5).abs() < 0.5, "{e:?}");
        (e.score.to_f64(), tracker.peak().to_f64())
    };
    let (alone, alone_peak) = step(&first);
    let (beside, beside_peak) = step(&with_copy(14));
    assert!(beside < 0.65 * alone, "score {beside} against {alone}");
    assert!(
        beside_peak > 0.85 * alone_peak,
        "peak {beside_peak} against {alone_peak}"
    );
}

/// With little context (padding 0.25) the search reaches no move beyond the peak's lobe:
/// the score is then the peak itself.
#[test]
fn without_moves_beyond_the_lobe_the_score_is_the_peak() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    let config = CfConfig {
        padding: Q16::from_ratio(1, 4),
        ..CfConfig::default()
    };
    let mut tracker = Small::new(config, &view, Rect::new(20, 26, 16, 20)).unwrap();
    let reach = |t: &Small| {
        let g = t.geometry();
        let side = Q16::from_int((16 * config.cell) as i32);
        side.saturating_sub(g.target.0.max(g.target.1)).to_f64() / 2.0 / config.cell as f64
    };
    assert!(reach(&tracker) < f64::from(LOBE + 1), "{}", reach(&tracker));
    for x0 in [21, 22, 23] {
        let buf = frame(x0);
        let e = tracker.step(&ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap());
        assert!(tracker.peak() > Q16::ZERO);
        assert_eq!(e.score, tracker.peak(), "block at {x0}");
    }
}

/// A search begins when the peak falls below `search_below` and lasts until it reaches
/// `search_until`, whatever the status.
#[test]
fn a_search_lasts_until_the_peak_reaches_search_until() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    let empty = ramp();
    for (until, searching) in [(0.95, 2), (0.8, 0)] {
        let config = CfConfig {
            search_below: Q16::from_f64(0.5),
            search_until: Q16::from_f64(until),
            ..CfConfig::default()
        };
        let mut tracker = Small::new(config, &view, Rect::new(20, 26, 16, 20)).unwrap();
        let mut step = |buf: &[u8]| {
            tracker.step(&ImageView::<Gray8>::new(buf, 96, 72, 96).unwrap());
            (tracker.peak().to_f64(), tracker.search_frames)
        };
        let (peak, frames) = step(&first);
        assert!(peak > 0.8 && peak < 0.95 && frames == 0, "{peak} {frames}");
        let (peak, frames) = step(&empty);
        assert!(peak < 0.5 && frames == 1, "{peak} {frames}");
        let (peak, frames) = step(&first);
        assert!(peak > 0.8 && peak < 0.95, "{peak}");
        assert_eq!(frames, searching, "until {until}");
    }
}

#[test]
fn a_camera_motion_moves_the_target_with_the_picture() {
    let buf = frame(20);
    let view = ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap();
    let mut tracker = Small::new(CfConfig::default(), &view, Rect::new(20, 26, 16, 20)).unwrap();
    let (cx, cy) = (tracker.estimate().ellipse.cx, tracker.estimate().ellipse.cy);
    tracker.camera_moved(&CameraMotion::shift(Q16::from_int(5), Q16::from_int(-3)));
    let e = tracker.estimate().ellipse;
    assert_eq!((e.cx, e.cy), (cx + Q16::from_int(5), cy - Q16::from_int(3)));
    // The picture moved with the camera: the block 5 px right and 3 px up.
    let moved = frame(25);
    let shifted: Vec<u8> = moved[3 * 96..]
        .iter()
        .copied()
        .chain(vec![40; 3 * 96])
        .collect();
    let view2 = ImageView::<Gray8>::new(&shifted, 96, 72, 96).unwrap();
    let e = tracker.step(&view2);
    assert!(
        (e.ellipse.cx.to_f64() - 32.5).abs() < 1.5,
        "{:?}",
        e.ellipse
    );
    assert!(
        (e.ellipse.cy.to_f64() - 32.5).abs() < 1.5,
        "{:?}",
        e.ellipse
    );
}

/// Steps of 1 count: each stage's lap is 1 per stopwatch lap.
struct Laps(u32);

impl CycleCounter for Laps {
    fn now(&mut self) -> u32 {
        self.0 += 1;
        self.0
    }
}

/// A search frame searches one region besides the usual one: the anchor's for the first
/// [`ANCHOR_FRAMES`], then the anchor's and `redetect` ring regions in turn, the ring's
/// next ones each round; none with `redetect` 0.
#[test]
fn a_search_frame_searches_one_more_region() {
    assert_eq!(search_offset(0, 0), None);
    assert_eq!(search_offset(ANCHOR_FRAMES + 1, 0), None);
    for k in 0..ANCHOR_FRAMES {
        assert_eq!(search_offset(k, 2), Some((0, 0)), "frame {k}");
    }
    let after: Vec<_> = (ANCHOR_FRAMES..ANCHOR_FRAMES + 12)
        .map(|k| search_offset(k, 2).unwrap())
        .collect();
    let (a, r) = ((0, 0), RING);
    assert_eq!(
        after,
        [a, r[0], r[1], a, r[2], r[3], a, r[4], r[5], a, r[6], r[7]]
    );
    assert_eq!(search_offset(ANCHOR_FRAMES + 13, 2), Some(r[0]));
    assert_eq!(search_offset(ANCHOR_FRAMES + 1, 1), Some(r[0]));
    assert_eq!(search_offset(ANCHOR_FRAMES + 3, 1), Some(r[1]));
}

/// The block leaves (the tracker is lost) and comes back half a region and 6 px right of
/// where it was last seen, beyond the usual search's reach, on the search frame that searches the
/// ring's first region: with re-detection (one region a frame, 3 laps, and none more for
/// the region that takes over) that region finds it on that frame; without, the tracker is
/// still lost.
#[test]
fn re_detection_finds_the_target_half_a_region_away() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    let empty = ramp();
    let empty = ImageView::<Gray8>::new(&empty, 96, 72, 96).unwrap();
    for redetect in [0, 2] {
        let config = CfConfig {
            redetect,
            ..CfConfig::default()
        };
        let mut tracker = Small::new(config, &view, Rect::new(20, 26, 16, 20)).unwrap();
        // The search begins on the second empty frame; its frame `ANCHOR_FRAMES + 1`
        // searches the ring's first region.
        for k in 0..ANCHOR_FRAMES + 2 {
            let (e, cycles) = tracker.step_profiled(&empty, Laps(0));
            assert_eq!(e.status, Status::Lost, "redetect {redetect}, frame {k}");
            let more = match (k, redetect) {
                (0, _) | (_, 0) => 0,
                _ => 3,
            };
            assert_eq!(cycles.redetect, more, "redetect {redetect}, frame {k}");
        }
        // The next step's region is the ring's first, half a region right of the first box;
        // the block comes back 6 px beyond its centre (the usual search, a few px right of
        // the first box after its drift on the empty ramp, does not reach it).
        let half = tracker.geometry().region.0.to_f64() / 2.0;
        let x0 = (20.0 + half).round() as usize + 6;
        let back = frame_at(x0, 26);
        let back = ImageView::<Gray8>::new(&back, 96, 72, 96).unwrap();
        let (e, cycles) = tracker.step_profiled(&back, Laps(0));
        let cx = e.ellipse.cx.to_f64();
        if redetect == 0 {
            assert_eq!(cycles.redetect, 0);
            assert!(
                (cx - (x0 as f64 + 7.5)).abs() > 4.0,
                "found without re-detection: centre {cx}, block at {x0}"
            );
        } else {
            assert_eq!(cycles.redetect, 3, "the ring's region alone");
            assert_ne!(e.status, Status::Lost);
            assert!(
                (cx - (x0 as f64 + 7.5)).abs() < 1.5,
                "centre {cx}, block at {x0}"
            );
        }
    }
}

/// A plain bright 16 x 20 px box (the block's look-alike in size, not in texture) at
/// `x1` on `buf`, a frame of [`ramp`].
fn with_box(mut buf: Vec<u8>, x1: usize) -> Vec<u8> {
    for y in 26..46 {
        buf[y * 96 + x1..y * 96 + x1 + 16].fill(200);
    }
    buf
}

/// The block is hidden while a box drifts off from where it was (3 px a frame): the lost
/// tracker's usual search follows the box's peak away. The block then shows again where
/// it was last seen: with re-detection the anchor's region finds it on that frame;
/// without, the tracker is still away on the box.
#[test]
fn re_detection_finds_the_target_where_it_was_last_seen() {
    let first = frame(20);
    let view = ImageView::<Gray8>::new(&first, 96, 72, 96).unwrap();
    for redetect in [0, 2] {
        let config = CfConfig {
            redetect,
            ..CfConfig::default()
        };
        let mut tracker = Small::new(config, &view, Rect::new(20, 26, 16, 20)).unwrap();
        let mut away = 0.0;
        for x1 in (26..=74).step_by(3) {
            let buf = with_box(ramp(), x1);
            let e = tracker.step(&ImageView::<Gray8>::new(&buf, 96, 72, 96).unwrap());
            away = e.ellipse.cx.to_f64();
        }
        assert!(
            away > 50.0,
            "redetect {redetect}: the search stayed at {away}"
        );
        let back = with_box(frame(20), 74);
        let e = tracker.step(&ImageView::<Gray8>::new(&back, 96, 72, 96).unwrap());
        let cx = e.ellipse.cx.to_f64();
        std::println!("redetect {redetect}: {:?}, centre {cx}", e.status);
        match redetect {
            0 => assert!(cx > 50.0, "found again without re-detection: {cx}"),
            _ => {
                assert_ne!(e.status, Status::Lost);
                assert!((cx - 27.5).abs() < 1.5, "centre {cx}, block at 20");
            }
        }
    }
}

#[test]
fn the_default_tracker_fits_in_128_kib() {
    let size = core::mem::size_of::<crate::tracker::RgbCfTracker>();
    std::println!("RgbCfTracker: {size} B");
    assert!(size <= 128 * 1024, "{size} B");
}
