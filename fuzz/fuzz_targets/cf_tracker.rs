//! The correlation-filter tracker: `ImageView::new`, then `CfTracker::start` (in place, on
//! the heap: the tracker is large), `step`, `step_profiled`, restarts and `camera_moved`
//! on frames of any size, stride, pixel format and content, with any configuration
//! (every field possibly out of range), any initial box and any camera motion.
//!
//! Oracles: no panic (the build keeps overflow checks and debug assertions on); `start`
//! succeeds exactly when the configuration validates and the box is at least 4 x 4 px with
//! its centre inside the frame ([`rbtrack_fuzz::cf_init_is_valid`], computed apart from
//! the core), and a refused `start` leaves the tracker as it was; an unstarted tracker's
//! step changes nothing; after every step or camera motion the centre lies inside the
//! frame the tracker started on (a frame of another size is read clamped, the estimate
//! stays in the start frame), the size keeps the first box's aspect ratio, each side is at
//! least 4 px and at most the frame's (or the first box's, if larger), the score is in
//! `[0, 1]` and the confidence its table's; a step changes the size by at most
//! `max_scale_change`, not at all below a score of `scale_above`, and its status is the
//! one its confidence and the last status give
//! ([`rbtrack_fuzz::check_cf_estimate`]).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::image::{Binning, ImageView, Luma64, PixelFormat, Rgb8x8x8, Yuv8x8x4};
use rbtrack::profile::CycleCounter;
use rbtrack::tracker::{CameraMotion, CfTracker};
use rbtrack::window::Ellipse;
use rbtrack_fuzz::{
    cf_init_is_valid, check_cf_estimate, with_format, CfConfigSpec, CfStart, Format, FrameSpec,
    RectSpec, Q,
};

/// Tracker sizes: binning, bins `B`, grid `G`, scales `S`.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Shape {
    Rgb8x8x8B512G16S4,
    Luma64B64G8S4,
    Yuv8x8x4B256G32S8,
}

#[derive(Arbitrary, Debug, Clone)]
enum Op {
    /// A step on a new frame, or on the first one (`None`).
    Step(Option<FrameSpec>),
    /// A profiled step on the first frame, with a counter that runs backwards.
    Profiled(u32),
    /// A restart on a new frame (or the first) at a box, with a new configuration (or the
    /// first).
    Restart(Option<FrameSpec>, RectSpec, Option<Box<CfConfigSpec>>),
    /// The picture moved: shift `(dx, dy)`, zoom, zoom centre.
    CameraMoved([Q; 5]),
    /// A detector's box on a new frame (or the first): the models kept.
    Relocate(Option<FrameSpec>, RectSpec),
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    shape: Shape,
    format: Format,
    config: CfConfigSpec,
    first: FrameSpec,
    init: RectSpec,
    ops: Vec<Op>,
}

/// Most operations run per input (the fuzzer's speed matters more than long sequences).
const MAX_OPS: usize = 8;

/// A counter that wraps and goes backwards: the profile must not panic on it.
struct Wild(u32);

impl CycleCounter for Wild {
    fn now(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(2_654_435_761).wrapping_sub(7);
        self.0
    }
}

fn run<Bn: Binning, const B: usize, const G: usize, const S: usize, P: PixelFormat>(input: &Input) {
    let bpp = input.format.bytes_per_pixel();
    let first = input.first.build(bpp);
    let Ok(frame) = ImageView::<P>::new(&first.buf, first.width, first.height, first.stride) else {
        return;
    };
    // On the heap, started in place: up to ~180 KB.
    let mut tracker: Box<CfTracker<Bn, B, G, S>> = Box::new(CfTracker::unstarted());
    // The frame and box the tracker (re)started on, once started.
    let mut started: Option<CfStart> = None;
    let restart = |tracker: &mut CfTracker<Bn, B, G, S>,
                   started: &mut Option<CfStart>,
                   config: &CfConfigSpec,
                   view: &ImageView<'_, P>,
                   spec: RectSpec| {
        let config = config.build();
        let init = spec.get(view.width(), view.height());
        let acceptable =
            config.validate().is_ok() && cf_init_is_valid(&init, view.width(), view.height());
        let (before, before_config) = (*tracker.estimate(), *tracker.config());
        match tracker.start(config, view, init) {
            Ok(()) => {
                assert!(acceptable, "accepted {config:?} {init:?}");
                assert_eq!(tracker.config(), &config);
                assert_eq!(tracker.estimate().ellipse, Ellipse::from(init));
                *started = Some(CfStart {
                    width: view.width(),
                    height: view.height(),
                    size: (init.w, init.h),
                });
            }
            Err(e) => {
                assert!(!acceptable, "refused ({e}) {config:?} {init:?}");
                assert_eq!(
                    tracker.estimate(),
                    &before,
                    "a refused start keeps the tracker"
                );
                assert_eq!(tracker.config(), &before_config);
            }
        }
    };
    restart(
        &mut tracker,
        &mut started,
        &input.config,
        &frame,
        input.init,
    );

    let check = |tracker: &CfTracker<Bn, B, G, S>,
                 started: Option<CfStart>,
                 before: &rbtrack::tracker::Estimate,
                 e: &rbtrack::tracker::Estimate,
                 stepped: bool| {
        assert_eq!(e, tracker.estimate());
        let previous = stepped.then_some((before, tracker.peak()));
        match started {
            Some(start) => check_cf_estimate(e, tracker.config(), &start, previous),
            None => assert_eq!(e, before, "an unstarted tracker stays as it is"),
        }
    };
    for op in input.ops.iter().take(MAX_OPS) {
        let before = *tracker.estimate();
        match op {
            Op::CameraMoved([dx, dy, zoom, centre_x, centre_y]) => {
                tracker.camera_moved(&CameraMotion {
                    dx: dx.get(),
                    dy: dy.get(),
                    zoom: zoom.get(),
                    centre_x: centre_x.get(),
                    centre_y: centre_y.get(),
                });
                let e = *tracker.estimate();
                assert_eq!(
                    e.confidence, before.confidence,
                    "a camera motion keeps the confidence"
                );
                check(&tracker, started, &before, &e, false);
            }
            Op::Profiled(start) => {
                let (e, _cycles) = tracker.step_profiled(&frame, Wild(*start));
                check(&tracker, started, &before, &e, true);
            }
            Op::Step(spec) | Op::Restart(spec, ..) | Op::Relocate(spec, _) => {
                let built = spec.as_ref().map(|s| s.build(bpp));
                let view = match &built {
                    Some(f) => ImageView::<P>::new(&f.buf, f.width, f.height, f.stride),
                    None => Ok(frame),
                };
                let Ok(view) = view else { continue };
                match op {
                    Op::Restart(_, rect, config) => {
                        let config = config.as_deref().unwrap_or(&input.config);
                        restart(&mut tracker, &mut started, config, &view, *rect);
                    }
                    Op::Relocate(_, rect) => {
                        let init = rect.get(view.width(), view.height());
                        let acceptable = started.is_some()
                            && cf_init_is_valid(&init, view.width(), view.height());
                        let config = *tracker.config();
                        match tracker.relocate(&view, init) {
                            Ok(()) => {
                                assert!(acceptable, "relocated {init:?}");
                                assert_eq!(tracker.config(), &config);
                                assert_eq!(tracker.estimate().ellipse, Ellipse::from(init));
                                started = Some(CfStart {
                                    width: view.width(),
                                    height: view.height(),
                                    size: (init.w, init.h),
                                });
                            }
                            Err(e) => {
                                assert!(!acceptable, "refused ({e}) {init:?}");
                                assert_eq!(tracker.estimate(), &before, "a refusal keeps it");
                            }
                        }
                    }
                    _ => {
                        let e = tracker.step(&view);
                        check(&tracker, started, &before, &e, true);
                    }
                }
            }
        }
    }
}

fuzz_target!(|input: Input| {
    with_format!(input.format, P => match input.shape {
        Shape::Rgb8x8x8B512G16S4 => run::<Rgb8x8x8, 512, 16, 4, P>(&input),
        Shape::Luma64B64G8S4 => run::<Luma64, 64, 8, 4, P>(&input),
        Shape::Yuv8x8x4B256G32S8 => run::<Yuv8x8x4, 256, 32, 8, P>(&input),
    });
});
