//! A link-time proof that the tracker's public API cannot panic on any data.
//!
//! ```sh
//! cargo build --release --example no_panic --target thumbv7em-none-eabihf
//! ```
//!
//! The panic handler calls `rbtrack_panic_path_is_reachable`, a function declared (by
//! `rbtrack_firmware::board::unlinkable`) and defined nowhere, so the example links only if
//! the optimiser removed every call to the panic handler: every bounds check, `unwrap`,
//! division by zero, `clamp` and slice split on the paths below was proven unreachable.
//! Otherwise the link fails with `undefined symbol: rbtrack_panic_path_is_reachable`. To
//! find the panic site, link with the symbol defined and list the functions that branch to
//! `core::panicking`:
//!
//! ```sh
//! RUSTFLAGS="-C link-arg=-Tlink.x -C link-arg=--defsym=rbtrack_panic_path_is_reachable=0" \
//!   cargo build --release --example no_panic --target thumbv7em-none-eabihf --target-dir target/probe
//! llvm-objdump -d -C target/probe/thumbv7em-none-eabihf/release/examples/no_panic \
//!   | grep -E '^[0-9a-f]+ <|bl.*<core::panicking' | grep -B1 'core::panicking'
//! ```
//!
//! Reached for every pixel format (`Gray8`, `Rgb565Le`, `Rgb565Be`, `Rgb888`, `Bgr888`,
//! `Yuyv`, `Uyvy`), on frames made by `ImageView::new` and `ImageView::from_words` from a buffer,
//! width, height and stride the optimiser cannot see (through [`core::hint::black_box`]),
//! for every binning (`Tracker<Rgb8x8x8, 100, 512>`, `Tracker<Rgb8x8x4, 200, 256>`,
//! `Tracker<Yuv8x8x4, 1, 256>`, `Tracker<Luma64, 8, 64>`), with a `Config` and initial
//! ellipses it cannot see either (so both variants and every setting are live):
//! `Tracker::unstarted`, `start`, `new`, `reset`, `relocate` (on a box), `set_model`,
//! `camera_moved` (on a motion it cannot see), `step`, `step_profiled` (with a counter
//! that may read anything) and the getters
//! `estimate` (and its box), `model`, `config`, `particles`,
//! `last_resampling`, `last_scale_factor`, `pixels_visited`, `weight_recoveries`,
//! `size_covariance` and `scale_per_row`; the correlation-filter tracker
//! (`CfTracker<Rgb8x8x8, 512, 16, 4>`, `<Luma64, 64, 8, 4>` and `<Yuv8x8x4, 256, 32, 16>`,
//! every pixel format): `unstarted`, `start` (on a configuration and a box it cannot see),
//! `step`, `step_profiled`, `estimate`, `config` and `relocate`; and the pan/tilt controller's
//! `PanTilt::new`
//! (with settings it cannot see), `step` on those estimates and `command`; and the FFT's
//! `forward`, `inverse` (8 to 64 points), `forward_2d`, `inverse_2d` (16 x 16 to 64 x 64)
//! and `normalise` on samples it cannot see.
//!
//! The proof is the link; the program is not meant to be run. On a hosted target it is an
//! empty program.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("no_panic: build with --target thumbv7em-none-eabihf (see examples/no_panic.rs)");
}

#[cfg(target_os = "none")]
mod proof {
    use core::hint::black_box;
    use cortex_m_rt::entry;
    use rbtrack::fft::{self, Complex};
    use rbtrack::fixed::Q16;
    use rbtrack::image::{
        Bgr888, Binning, Gray8, ImageView, Luma64, PixelFormat, Rgb565Be, Rgb565Le, Rgb888,
        Rgb8x8x4, Rgb8x8x8, Uyvy, Yuv8x8x4, Yuyv,
    };
    use rbtrack::pantilt::{PanTilt, PanTiltConfig};
    use rbtrack::profile::CycleCounter;
    use rbtrack::rect::Rect;
    use rbtrack::tracker::{CameraMotion, CfConfig, CfTracker, Config, Tracker, Variant};
    use rbtrack::window::Ellipse;

    /// The frames' bytes, as bytes and as the 32-bit words a DMA engine fills.
    static BYTES: [u8; 4096] = [0; 4096];
    static WORDS: [u32; 1024] = [0; 1024];

    /// A counter that may read any value, in any order.
    struct AnyCounter;

    impl CycleCounter for AnyCounter {
        fn now(&mut self) -> u32 {
            black_box(0)
        }
    }

    /// A frame of format `P` whose bytes, width, height and stride the optimiser cannot
    /// see, from bytes or from words; `None` if `ImageView` refuses it.
    fn any_frame<P: PixelFormat>() -> Option<ImageView<'static, P>> {
        let (width, height, stride) = black_box((32, 24, 32));
        let frame = if black_box(false) {
            ImageView::from_words(black_box(&WORDS[..]), width, height, stride)
        } else {
            ImageView::new(black_box(&BYTES[..]), width, height, stride)
        };
        frame.ok()
    }

    /// An ellipse the optimiser cannot see.
    fn any_ellipse() -> Ellipse {
        black_box(Ellipse::new(
            Q16::from_int(16),
            Q16::from_int(12),
            Q16::from_int(6),
            Q16::from_int(8),
        ))
    }

    /// A configuration the optimiser cannot see: any variant, any value of every field.
    fn any_config() -> Config {
        black_box(Config::new(Variant::Rbpf))
    }

    /// Every getter, its result made observable.
    fn read<Bn: Binning, const N: usize, const B: usize>(tracker: &Tracker<Bn, N, B>) {
        black_box(tracker.estimate());
        black_box(tracker.config());
        black_box(tracker.particles());
        black_box(tracker.last_resampling());
        black_box(tracker.last_scale_factor());
        black_box(tracker.pixels_visited());
        black_box(tracker.weight_recoveries());
        black_box(tracker.size_covariance());
        black_box(tracker.scale_per_row());
    }

    /// The whole public life of a tracker on frames of format `P`: built in place and by
    /// value, stepped, profiled, reset, read.
    fn exercise<Bn: Binning, const N: usize, const B: usize, P: PixelFormat>(
        tracker: &mut Tracker<Bn, N, B>,
    ) {
        let Some(frame) = any_frame::<P>() else {
            return;
        };
        black_box(tracker.step(&frame));
        black_box(tracker.start(any_config(), &frame, any_ellipse()).is_ok());
        read(tracker);
        for _ in 0..black_box(2) {
            black_box(tracker.step(&frame));
            black_box(tracker.step_profiled(&frame, AnyCounter));
            read(tracker);
        }
        black_box(tracker.reset(&frame, any_ellipse()).is_ok());
        black_box(tracker.step(&frame));
        black_box(tracker.relocate(&frame, Rect::from(any_ellipse())).is_ok());
        tracker.camera_moved(&black_box(CameraMotion::shift(Q16::ONE, Q16::ZERO)));
        black_box(tracker.step(&frame));
        black_box(tracker.estimate().rect());
        let head = PanTiltConfig::new(32, 24, Q16::from_int(60), Q16::from_int(45));
        if let Ok(mut head) = PanTilt::new(black_box(head)) {
            black_box(head.step(&tracker.step(&frame)));
            black_box(head.command());
        }
        if let Ok(mut built) = Tracker::<Bn, N, B>::new(any_config(), &frame, any_ellipse()) {
            black_box(built.step(&frame));
            read(&built);
            black_box(tracker.set_model(built.model()).is_ok());
        }
    }

    /// The correlation-filter tracker's public life on frames of format `P`, with a
    /// configuration and boxes the optimiser cannot see: started in place, stepped,
    /// profiled, restarted, read, relocated.
    fn exercise_cf<Bn: Binning, const B: usize, const G: usize, const S: usize, P: PixelFormat>(
        tracker: &mut CfTracker<Bn, B, G, S>,
    ) {
        let Some(frame) = any_frame::<P>() else {
            return;
        };
        black_box(tracker.step(&frame));
        let config = black_box(CfConfig::default());
        black_box(
            tracker
                .start(config, &frame, Rect::from(any_ellipse()))
                .is_ok(),
        );
        for _ in 0..black_box(2) {
            black_box(tracker.step(&frame));
            black_box(tracker.step_profiled(&frame, AnyCounter));
            black_box(tracker.estimate());
            black_box(tracker.config());
            black_box(tracker.relocate(&frame, Rect::from(any_ellipse())).is_ok());
        }
    }

    /// [`exercise_cf`] for every pixel format.
    fn every_format_cf<Bn: Binning, const B: usize, const G: usize, const S: usize>(
        tracker: &mut CfTracker<Bn, B, G, S>,
    ) {
        exercise_cf::<Bn, B, G, S, Gray8>(tracker);
        exercise_cf::<Bn, B, G, S, Rgb565Le>(tracker);
        exercise_cf::<Bn, B, G, S, Rgb565Be>(tracker);
        exercise_cf::<Bn, B, G, S, Rgb888>(tracker);
        exercise_cf::<Bn, B, G, S, Bgr888>(tracker);
        exercise_cf::<Bn, B, G, S, Yuyv>(tracker);
        exercise_cf::<Bn, B, G, S, Uyvy>(tracker);
    }

    /// The 1-D FFTs of `N` points and the 2-D FFTs of `N x N`, both ways, on samples the
    /// optimiser cannot see.
    fn fourier<const N: usize>() {
        let mut row = black_box([Complex::ZERO; N]);
        black_box(fft::normalise(&mut row));
        black_box(fft::forward(&mut row));
        black_box(fft::inverse(&mut row));
        let mut grid = black_box([[Complex::ZERO; N]; N]);
        black_box(fft::normalise(grid.as_flattened_mut()));
        black_box(fft::forward_2d(&mut grid));
        black_box(fft::inverse_2d(&mut grid));
        black_box(row);
        black_box(grid);
    }

    /// [`exercise`] for every pixel format.
    fn every_format<Bn: Binning, const N: usize, const B: usize>(tracker: &mut Tracker<Bn, N, B>) {
        exercise::<Bn, N, B, Gray8>(tracker);
        exercise::<Bn, N, B, Rgb565Le>(tracker);
        exercise::<Bn, N, B, Rgb565Be>(tracker);
        exercise::<Bn, N, B, Rgb888>(tracker);
        exercise::<Bn, N, B, Bgr888>(tracker);
        exercise::<Bn, N, B, Yuyv>(tracker);
        exercise::<Bn, N, B, Uyvy>(tracker);
    }

    #[entry]
    fn main() -> ! {
        let mut colour = Tracker::<Rgb8x8x8, 100, 512>::unstarted();
        let mut coarse = Tracker::<Rgb8x8x4, 200, 256>::unstarted();
        let mut chroma = Tracker::<Yuv8x8x4, 1, 256>::unstarted();
        let mut grey = Tracker::<Luma64, 8, 64>::unstarted();
        let mut cf = CfTracker::<Rgb8x8x8, 512, 16, 4>::unstarted();
        let mut cf_small = CfTracker::<Luma64, 64, 8, 4>::unstarted();
        let mut cf_large = CfTracker::<Yuv8x8x4, 256, 32, 16>::unstarted();
        loop {
            every_format_cf(&mut cf);
            every_format_cf(&mut cf_small);
            every_format_cf(&mut cf_large);
            every_format(&mut colour);
            every_format(&mut coarse);
            every_format(&mut chroma);
            every_format(&mut grey);
            fourier::<8>();
            fourier::<16>();
            fourier::<32>();
            fourier::<64>();
        }
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
        rbtrack_firmware::board::unlinkable()
    }
}
