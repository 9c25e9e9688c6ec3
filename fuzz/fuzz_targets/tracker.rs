//! `ImageView::new`, then `Tracker::new`, `step`, `step_profiled`, `reset`, `relocate` and
//! `camera_moved` on frames of any size, stride, pixel format and content, with any
//! configuration and any camera motion.
//!
//! Oracles: no panic (the build keeps overflow checks and debug assertions on); `new`
//! succeeds exactly when the configuration validates and the initial ellipse is
//! acceptable; a failed `reset` or `relocate` leaves the tracker unchanged, `relocate`
//! and `camera_moved` keep the model; every estimate keeps the documented guarantees ([`rbtrack_fuzz::check_estimate`]).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::image::{Binning, ImageView, Luma64, PixelFormat, Rgb8x8x4, Rgb8x8x8, Yuv8x8x4};
use rbtrack::profile::CycleCounter;
use rbtrack::tracker::{CameraMotion, Tracker};
use rbtrack_fuzz::{
    check_estimate, init_is_valid, with_format, ConfigSpec, EllipseSpec, Format, FrameSpec, Q,
};

/// Tracker sizes: binning, particles `N`, bins `B`.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Shape {
    Rgb8x8x8N8,
    Luma64N1,
    Yuv8x8x4N3,
    Rgb8x8x4N64,
}

#[derive(Arbitrary, Debug, Clone)]
enum Op {
    /// A step on a new frame, or on the first one (`None`).
    Step(Option<FrameSpec>),
    /// A profiled step on the first frame, with a counter that runs backwards.
    Profiled(u32),
    /// A reset on a new frame (or the first) at an ellipse.
    Reset(Option<FrameSpec>, EllipseSpec),
    /// A relocation on a new frame (or the first) to an ellipse, keeping the model.
    Relocate(Option<FrameSpec>, EllipseSpec),
    /// The picture moved: shift `(dx, dy)`, zoom, zoom centre.
    CameraMoved([Q; 5]),
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    shape: Shape,
    format: Format,
    config: ConfigSpec,
    first: FrameSpec,
    init: EllipseSpec,
    ops: Vec<Op>,
}

/// Most operations run per input (the fuzzer's speed matters more than long sequences).
const MAX_OPS: usize = 12;

/// A counter that wraps and goes backwards: the profile must not panic on it.
struct Wild(u32);

impl CycleCounter for Wild {
    fn now(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(2_654_435_761).wrapping_sub(7);
        self.0
    }
}

fn run<Bn: Binning, const N: usize, const B: usize, P: PixelFormat>(input: &Input) {
    let first = input.first.build(input.format.bytes_per_pixel());
    let Ok(frame) = ImageView::<P>::new(&first.buf, first.width, first.height, first.stride) else {
        return;
    };
    let config = input.config.build();
    let init = input.init.get(frame.width(), frame.height());
    let acceptable = config.validate().is_ok()
        && init_is_valid(&init, config.min_half_axis, frame.width(), frame.height());
    let mut tracker = match Tracker::<Bn, N, B>::new(config, &frame, init) {
        Ok(t) => {
            assert!(acceptable, "accepted {config:?} {init:?}");
            t
        }
        Err(e) => {
            assert!(!acceptable, "rejected ({e}) {config:?} {init:?}");
            return;
        }
    };
    for op in input.ops.iter().take(MAX_OPS) {
        // A step, reset or relocation on a new frame (or the first one again); a profiled
        // step on the first frame.
        let (spec, move_to) = match op {
            Op::Step(spec) => (spec, None),
            Op::Reset(spec, ellipse) => (spec, Some((ellipse, false))),
            Op::Relocate(spec, ellipse) => (spec, Some((ellipse, true))),
            Op::CameraMoved([dx, dy, zoom, centre_x, centre_y]) => {
                let before = tracker.model().clone();
                tracker.camera_moved(&CameraMotion {
                    dx: dx.get(),
                    dy: dy.get(),
                    zoom: zoom.get(),
                    centre_x: centre_x.get(),
                    centre_y: centre_y.get(),
                });
                assert_eq!(tracker.model(), &before, "a camera motion keeps the model");
                continue;
            }
            Op::Profiled(start) => {
                let (e, _cycles) = tracker.step_profiled(&frame, Wild(*start));
                let pixels = tracker.pixels_visited();
                check_estimate(&e, &config, N, pixels, frame.width(), frame.height());
                continue;
            }
        };
        let built = spec
            .as_ref()
            .map(|s| s.build(input.format.bytes_per_pixel()));
        let view = match &built {
            Some(f) => ImageView::<P>::new(&f.buf, f.width, f.height, f.stride),
            None => Ok(frame),
        };
        let Ok(view) = view else { continue };
        let Some((ellipse, keep_model)) = move_to else {
            let e = tracker.step(&view);
            assert_eq!(e, tracker.estimate());
            let pixels = tracker.pixels_visited();
            check_estimate(&e, &config, N, pixels, view.width(), view.height());
            continue;
        };
        let e = ellipse.get(view.width(), view.height());
        let ok = init_is_valid(&e, config.min_half_axis, view.width(), view.height());
        let before = tracker.clone();
        let moved = match keep_model {
            true => tracker.relocate(&view, e),
            false => tracker.reset(&view, e),
        };
        match moved {
            Ok(()) => {
                assert!(ok, "moved to {e:?}");
                assert_eq!(tracker.estimate().ellipse, e);
            }
            Err(err) => {
                assert!(!ok, "refused ({err}) {e:?}");
                assert_eq!(tracker.estimate(), before.estimate());
                assert_eq!(tracker.particles(), before.particles());
            }
        }
        if keep_model {
            assert_eq!(
                tracker.model(),
                before.model(),
                "a relocation keeps the model"
            );
        }
    }
}

fuzz_target!(|input: Input| {
    with_format!(input.format, P => match input.shape {
        Shape::Rgb8x8x8N8 => run::<Rgb8x8x8, 8, 512, P>(&input),
        Shape::Luma64N1 => run::<Luma64, 1, 64, P>(&input),
        Shape::Yuv8x8x4N3 => run::<Yuv8x8x4, 3, 256, P>(&input),
        Shape::Rgb8x8x4N64 => run::<Rgb8x8x4, 64, 256, P>(&input),
    });
});
