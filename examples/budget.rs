//! Instructions per frame against configuration, in QEMU (`thumbv7em-none-eabihf`,
//! Cortex-M4F, the example firmware's scene and counter): the cost half of the
//! accuracy-against-cost table in the README, and how the cost grows. It runs both
//! trackers over the scene's 60 frames and prints, as means and largest instructions per
//! frame:
//! - per configuration: particle count, pixel cap and gradient points;
//! - per particle count, 25 to 400, at the defaults, stage by stage;
//! - per target size, the scene's target scaled from 20 px to 120 px tall on average (at
//!   120 px it reaches 180 px, three quarters of the frame's height), N = 100, defaults;
//! - the pan/tilt controller's step (`rbtrack::pantilt`), over 1,000 steps, and a known
//!   camera motion applied to the tracker (`Tracker::camera_moved`, N = 100, shift and zoom);
//! - one 2-D forward FFT of a 32 x 32 grid of full-scale Q31 samples (`rbtrack::fft`, the
//!   correlation filter's transform), one of a 16 x 16 grid of Q16 samples (the
//!   correlation filter's at its defaults, shift-free), and the direct transform of 4 Q21
//!   samples (the scale filter's, `rbtrack::fft::forward_direct`, the mean of 256);
//! - the correlation-filter tracker (`rbtrack::tracker::CfTracker`) stage by stage, mean and
//!   largest, the largest step while lost (with its re-detection: the ring's searches) and
//!   its `size_of`: against its grid (`G`, 8 or 16 cells a side), cell side,
//!   scales (`S`), the scale model's area and the ring regions searched while lost, then
//!   against target size at the defaults.
//!   Its 10 feature channels are fixed. Its 32 x 32 grid does not fit beside the frame
//!   buffer and the stack in the board's RAM: the example prints its size instead.
//!
//! ```sh
//! cargo run --release --example budget --target thumbv7em-none-eabihf
//! ```
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("the budget example runs on thumbv7em-none-eabihf (QEMU): see its doc comment");
}

#[cfg(target_os = "none")]
mod budget {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use rbtrack::cf::scale::ScaleSettings;
    use rbtrack::fft::{self, Complex};
    use rbtrack::fixed::Q16;
    use rbtrack::image::{ImageView, Rgb565Le, Rgb8x8x8};
    use rbtrack::pantilt::{PanTilt, PanTiltConfig};
    use rbtrack::profile::{CycleCounter, StageCycles};
    use rbtrack::rng::Rng;
    use rbtrack::tracker::{CameraMotion, CfConfig, CfTracker, Config, Status, Tracker, Variant};
    use rbtrack_firmware::board::{self, SysTick};
    use rbtrack_firmware::cf::run_cf;
    use rbtrack_firmware::run::{self, FirmwareTracker, BINS, STACK_BUDGET_BYTES};
    use rbtrack_firmware::scene::{self, FRAMES};
    use static_cell::ConstStaticCell;

    /// Configurations: particles, pixels per window, gradient points.
    const CONFIGS: [(usize, u32, u8); 9] = [
        (100, 300, 24),
        (100, 300, 12),
        (100, 150, 24),
        (50, 300, 24),
        (50, 150, 24),
        (50, 150, 12),
        (50, 100, 12),
        (25, 150, 24),
        (25, 100, 12),
    ];

    /// Black frames stepped after the scene to measure a lost step.
    const LOST_FRAMES: usize = 3;

    /// Particle counts of the sweep.
    const COUNTS: [usize; 5] = [25, 50, 100, 200, 400];

    /// Target scales of the size sweep, in 1/8: the scene's target (54 px tall on average)
    /// times 3/8, 6/8, 12/8 and 18/8.
    const SCALES_EIGHTHS: [i32; 4] = [3, 6, 12, 18];

    /// The correlation-filter tracker of `G x G` cells and `S` scales.
    type Cf<const G: usize, const S: usize> = CfTracker<Rgb8x8x8, BINS, G, S>;

    /// Correlation-filter configurations: cells a side (`G`), scales (`S`), cell side (px),
    /// the scale model's largest area (px^2), ring regions searched while lost. The first is
    /// the default; `8 4 4 256 2` the budget configuration (docs/accuracy.md).
    const CF_CONFIGS: [(usize, usize, usize, u32, usize); 12] = [
        (16, 4, 4, 512, 2),
        (16, 4, 4, 512, 0),
        (16, 4, 2, 512, 2),
        (16, 5, 4, 512, 2),
        (16, 8, 4, 512, 2),
        (16, 4, 4, 256, 2),
        (8, 8, 8, 512, 2),
        (8, 4, 8, 256, 2),
        (8, 4, 4, 256, 2),
        (8, 4, 4, 128, 2),
        (8, 4, 4, 128, 0),
        (8, 4, 4, 96, 0),
    ];

    /// The trackers other than the board's N = 100, one at a time in one static the size
    /// of the largest: all of them side by side would not fit the board's 320 KiB.
    #[allow(clippy::large_enum_variant)] // one static, never moved: its size is the point
    enum Other {
        Idle,
        N25(Tracker<Rgb8x8x8, 25, BINS>),
        N50(Tracker<Rgb8x8x8, 50, BINS>),
        N200(Tracker<Rgb8x8x8, 200, BINS>),
        N400(Tracker<Rgb8x8x8, 400, BINS>),
        Cf16x5(Cf<16, 5>),
        Cf16x8(Cf<16, 8>),
        Cf16x4(Cf<16, 4>),
        Cf8x8(Cf<8, 8>),
        Cf8x4(Cf<8, 4>),
    }

    static OTHER: ConstStaticCell<Other> = ConstStaticCell::new(Other::Idle);

    /// The FFT's grid, 8 KiB: not on the stack.
    static FFT_GRID: ConstStaticCell<[[Complex; 32]; 32]> =
        ConstStaticCell::new([[Complex::ZERO; 32]; 32]);

    /// Means and largest of one run, per frame.
    struct Cost {
        /// Mean instructions per stage: propagate, weigh, update, estimate, resample.
        stages: [u64; 5],
        /// Mean and largest instructions of a step.
        total: (u64, u32),
        /// Mean pixels read into histograms.
        pixels: u64,
        /// Mean target height, px.
        height: u64,
    }

    /// The cost of `config` in `tracker` over the scene with its target times `scale`.
    fn measure<const N: usize>(
        tracker: &mut Tracker<Rgb8x8x8, N, BINS>,
        frame: &mut [u8],
        counter: &mut SysTick,
        config: Config,
        scale: Q16,
    ) -> Cost {
        let mut sums = [0u64; 8];
        let mut most = 0u32;
        let result = run::run_config(config, tracker, FRAMES, scale, frame, counter, |r| {
            let StageCycles {
                propagate,
                weigh,
                update,
                estimate,
                resample,
            } = r.cycles;
            let height = (2 * r.truth.hy.to_bits() as u32) >> 16;
            let row = [
                propagate, weigh, update, estimate, resample, r.pixels, height,
            ];
            for (sum, v) in sums.iter_mut().zip(row) {
                *sum += v as u64;
            }
            most = most.max(r.cycles.total());
        });
        if let Err(e) = result {
            panic!("configuration: {e}");
        }
        let mean = sums.map(|s| s / FRAMES as u64);
        Cost {
            stages: [mean[0], mean[1], mean[2], mean[3], mean[4]],
            total: (mean[..5].iter().sum(), most),
            pixels: mean[5],
            height: mean[6],
        }
    }

    /// The correlation-filter tracker's cost over the scene with its target times `scale`:
    /// mean instructions per stage (features, filter, colour, scale, learn) and of a step,
    /// then the largest of a step, then the largest step while lost and its re-detection
    /// (the scene's last frame followed by [`LOST_FRAMES`] black ones: the first reports
    /// `Lost`, the others search the ring too); and the mean target height and the mean
    /// height of the tracker's box, px (the frame rows read follow the second).
    fn measure_cf<const G: usize, const S: usize>(
        tracker: &mut Cf<G, S>,
        frame: &mut [u8],
        counter: &mut SysTick,
        config: CfConfig,
        scale: Q16,
    ) -> ([u64; 9], [u64; 2]) {
        let (mut sums, mut most, mut heights) = ([0u64; 6], 0u32, [0u64; 2]);
        let result = run_cf(config, tracker, scale, frame, &mut *counter, |r| {
            let c = r.cycles;
            let row = [c.features, c.filter, c.colour, c.scale, c.learn, c.total()];
            for (sum, v) in sums.iter_mut().zip(row) {
                *sum += v as u64;
            }
            most = most.max(c.total());
            let ellipses = [r.truth, r.estimate.ellipse];
            for (sum, e) in heights.iter_mut().zip(ellipses) {
                *sum += ((2 * e.hy.to_bits() as u32) >> 16) as u64;
            }
        });
        if let Err(e) = result {
            panic!("correlation-filter configuration: {e}");
        }
        let mean = sums.map(|s| s / FRAMES as u64);
        let [f, t, c, s, l, total] = mean;
        frame.fill(0);
        let mut lost = (0, 0);
        for _ in 0..LOST_FRAMES {
            let view = ImageView::<Rgb565Le>::new(frame, scene::WIDTH, scene::HEIGHT, scene::WIDTH);
            let Ok(view) = view else {
                panic!("the frame buffer holds a QVGA frame");
            };
            let (e, c) = tracker.step_profiled(&view, &mut *counter);
            if e.status == Status::Lost && c.total() > lost.0 {
                lost = (c.total(), c.redetect);
            }
        }
        let lost = [lost.0 as u64, lost.1 as u64];
        let row = [f, t, c, s, l, total, most as u64, lost[0], lost[1]];
        (row, heights.map(|h| h / FRAMES as u64))
    }

    /// [`measure_cf`] on a tracker of `g` cells and `s` scales made in place in [`OTHER`],
    /// with its `size_of`.
    fn measure_cf_in(
        (g, s): (usize, usize),
        other: &mut Other,
        frame: &mut [u8],
        counter: &mut SysTick,
        config: CfConfig,
        scale: Q16,
    ) -> (usize, [u64; 9], [u64; 2]) {
        // A constant, so that it is copied into the static without a stack temporary.
        macro_rules! in_other {
            ($variant:ident, $g:literal, $s:literal) => {{
                *other = const { Other::$variant(CfTracker::unstarted()) };
                let Other::$variant(t) = other else {
                    unreachable!()
                };
                let (cost, heights) = measure_cf(t, frame, counter, config, scale);
                (core::mem::size_of::<Cf<$g, $s>>(), cost, heights)
            }};
        }
        match (g, s) {
            (16, 8) => in_other!(Cf16x8, 16, 8),
            (16, 5) => in_other!(Cf16x5, 16, 5),
            (8, 8) => in_other!(Cf8x8, 8, 8),
            (8, 4) => in_other!(Cf8x4, 8, 4),
            _ => in_other!(Cf16x4, 16, 4),
        }
    }

    /// [`measure`] with `n` particles: the board's tracker for 100, else [`OTHER`] made
    /// a tracker of `n` in place.
    fn measure_n(
        n: usize,
        t100: &mut FirmwareTracker,
        other: &mut Other,
        frame: &mut [u8],
        counter: &mut SysTick,
        config: Config,
        scale: Q16,
    ) -> Cost {
        // A constant, so that it is copied into the static without a stack temporary.
        macro_rules! in_other {
            ($variant:ident) => {{
                *other = const { Other::$variant(Tracker::unstarted()) };
                let Other::$variant(t) = other else {
                    unreachable!()
                };
                measure(t, frame, counter, config, scale)
            }};
        }
        match n {
            25 => in_other!(N25),
            50 => in_other!(N50),
            200 => in_other!(N200),
            400 => in_other!(N400),
            _ => measure(t100, frame, counter, config, scale),
        }
    }

    /// The defaults of `variant` with the target times `scale` (the RBPF's ground-plane
    /// slope scaled with it).
    fn scaled_config(variant: Variant, scale: Q16) -> Config {
        let mut config = run::config(variant);
        config.scale_per_row = config.scale_per_row * scale;
        config
    }

    #[entry]
    fn main() -> ! {
        let Some(mut cp) = cortex_m::Peripherals::take() else {
            panic!("peripherals taken twice");
        };
        let (Some((frame, t100)), Some(other)) = (board::statics(), OTHER.try_take()) else {
            panic!("statics taken twice");
        };
        SysTick::start(&mut cp.SYST);
        let (instructions, ticks) = board::calibrate(1_000_000);
        let mut counter = SysTick::counter((instructions + ticks / 2) / ticks.max(1));
        let variants = [Variant::Rbpf, Variant::ColourPf];

        hprintln!("N    cap  points   rbpf mean    rbpf max     pf mean      pf max  (instructions per frame)");
        for (n, cap, points) in CONFIGS {
            let row = variants.map(|variant| {
                let mut config = run::config(variant);
                config.pixels_per_window = cap;
                config.gradient_points = points;
                let f = &mut frame[..];
                measure_n(n, t100, other, f, &mut counter, config, Q16::ONE).total
            });
            hprintln!(
                "{:<4} {:>3} {:>7} {:>11} {:>11} {:>11} {:>11}",
                n,
                cap,
                points,
                row[0].0,
                row[0].1,
                row[1].0,
                row[1].1
            );
        }

        for variant in variants {
            hprintln!("");
            hprintln!(
                "{:?} at the defaults, mean instructions per frame by stage:",
                variant
            );
            hprintln!(
                "N    propagate      weigh     update   estimate   resample      total        max"
            );
            for n in COUNTS {
                let f = &mut frame[..];
                let c = measure_n(
                    n,
                    t100,
                    other,
                    f,
                    &mut counter,
                    run::config(variant),
                    Q16::ONE,
                );
                let [p, w, u, e, r] = c.stages;
                hprintln!(
                    "{:<4} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
                    n,
                    p,
                    w,
                    u,
                    e,
                    r,
                    c.total.0,
                    c.total.1
                );
            }
        }

        hprintln!("");
        hprintln!("target size, N = 100, defaults (mean target height, px):");
        hprintln!(
            "height   rbpf mean    rbpf max  rbpf pixels     pf mean      pf max    pf pixels"
        );
        for eighths in SCALES_EIGHTHS {
            let scale = Q16::from_int(eighths) / Q16::from_int(8);
            let [rbpf, pf] = variants.map(|variant| {
                let f = &mut frame[..];
                let config = scaled_config(variant, scale);
                measure_n(100, t100, other, f, &mut counter, config, scale)
            });
            hprintln!(
                "{:>6} {:>11} {:>11} {:>12} {:>11} {:>11} {:>12}",
                rbpf.height,
                rbpf.total.0,
                rbpf.total.1,
                rbpf.pixels,
                pf.total.0,
                pf.total.1,
                pf.pixels
            );
        }
        let full = scene::truth(FRAMES);
        hprintln!(
            "(the scene's own target, scale 1, grows to {} px tall)",
            (2 * full.hy.to_bits()) >> 16
        );

        // The controller, on the last estimate moved a little every step and tracked (a `Lost`
        // one would only hold the head).
        let fov = (Q16::from_int(60), Q16::from_int(45));
        let Ok(mut head) = PanTilt::new(PanTiltConfig::new(320, 240, fov.0, fov.1)) else {
            panic!("pan/tilt configuration");
        };
        let mut estimate = t100.estimate();
        estimate.status = Status::Tracking;
        const STEPS: u32 = 1000;
        let start = counter.now();
        for k in 0..STEPS {
            estimate.ellipse.cx = Q16::from_int(100 + (k % 120) as i32);
            core::hint::black_box(head.step(core::hint::black_box(&estimate)));
        }
        let spent = counter.now().wrapping_sub(start);
        hprintln!("");
        hprintln!(
            "pan/tilt step: {} instructions (mean of {})",
            spent / STEPS,
            STEPS
        );
        let shift = CameraMotion::shift(Q16::from_f64(-3.5), Q16::from_f64(1.25));
        let zoom = CameraMotion {
            zoom: Q16::from_f64(1.01),
            centre_x: Q16::from_int(160),
            centre_y: Q16::from_int(120),
            ..shift
        };
        for (name, motion) in [("shift", shift), ("shift and zoom", zoom)] {
            let start = counter.now();
            t100.camera_moved(core::hint::black_box(&motion));
            hprintln!(
                "camera motion ({}), N = 100: {} instructions",
                name,
                counter.now().wrapping_sub(start)
            );
        }

        let Some(grid) = FFT_GRID.try_take() else {
            panic!("statics taken twice");
        };
        let mut rng = Rng::new(1);
        for v in grid.as_flattened_mut() {
            *v = Complex::new(rng.next_u32() as i32, rng.next_u32() as i32);
        }
        let start = counter.now();
        let exponent = fft::forward_2d(core::hint::black_box(grid));
        hprintln!(
            "2-D forward FFT, 32 x 32, Q31: {} instructions (block exponent {})",
            counter.now().wrapping_sub(start),
            exponent
        );
        // The correlation filter's: Q16 features, and the scale filter's Q21 ones.
        let mut small = [[Complex::ZERO; 16]; 16];
        for v in small.as_flattened_mut() {
            *v = Complex::new((rng.next_u32() as i32) >> 15, (rng.next_u32() as i32) >> 15);
        }
        let start = counter.now();
        let exponent = fft::forward_2d(core::hint::black_box(&mut small));
        hprintln!(
            "2-D forward FFT, 16 x 16, Q16: {} instructions (block exponent {})",
            counter.now().wrapping_sub(start),
            exponent
        );
        // The scale filter's 4-point rows: 256 of them in the 32 x 32 grid's memory.
        for v in grid.as_flattened_mut() {
            *v = Complex::new((rng.next_u32() as i32) >> 11, (rng.next_u32() as i32) >> 11);
        }
        let start = counter.now();
        for row in grid.as_flattened_mut().chunks_exact_mut(4) {
            if let Ok(row) = <&mut [Complex; 4]>::try_from(row) {
                fft::forward_direct(core::hint::black_box(row));
            }
        }
        hprintln!(
            "direct transform, 4 points, Q21: {} instructions (mean of 256)",
            counter.now().wrapping_sub(start) / 256
        );

        hprintln!("");
        hprintln!("correlation-filter tracker, instructions per frame by stage (mean), total (mean, max):");
        hprintln!(
            " G  S cell area ring  size_of B  features   filter   colour    scale    learn     total       max      lost redetect  box h"
        );
        for (g, s, cell, area, ring) in CF_CONFIGS {
            let defaults = CfConfig::default();
            let config = CfConfig {
                cell,
                redetect: ring,
                scale: ScaleSettings {
                    area,
                    ..defaults.scale
                },
                ..defaults
            };
            let f = &mut frame[..];
            let (size, c, [_, box_h]) =
                measure_cf_in((g, s), other, f, &mut counter, config, Q16::ONE);
            hprintln!(
                "{:>2} {:>2} {:>4} {:>4} {:>4} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9} {:>8} {:>6}",
                g,
                s,
                cell,
                area,
                ring,
                size,
                c[0],
                c[1],
                c[2],
                c[3],
                c[4],
                c[5],
                c[6],
                c[7],
                c[8],
                box_h
            );
        }
        hprintln!(
            "32  8    4  512    2 {:>9}  not run: with the {} B frame buffer and the {} B stack \
             budget it exceeds the board's 320 KiB of RAM",
            core::mem::size_of::<Cf<32, 8>>(),
            scene::FRAME_BYTES,
            STACK_BUDGET_BYTES
        );
        hprintln!("");
        hprintln!(
            "correlation-filter tracker against target size, defaults (mean target height and \
             box height, px):"
        );
        hprintln!("height  box h  features    scale     total       max");
        for eighths in SCALES_EIGHTHS {
            let scale = Q16::from_int(eighths) / Q16::from_int(8);
            let f = &mut frame[..];
            let config = CfConfig::default();
            let (_, c, [height, box_h]) =
                measure_cf_in((16, 4), other, f, &mut counter, config, scale);
            hprintln!(
                "{:>6} {:>6} {:>9} {:>8} {:>9} {:>9}",
                height,
                box_h,
                c[0],
                c[3],
                c[5],
                c[6]
            );
        }

        // A tracker made in place must not have passed through the stack.
        let stack = board::stack_use();
        hprintln!(
            "stack high-water mark: {} of {} bytes (budget {})",
            stack.used,
            stack.size,
            STACK_BUDGET_BYTES
        );
        if stack.used > STACK_BUDGET_BYTES {
            panic!("stack over budget");
        }
        board::exit(debug::EXIT_SUCCESS)
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        board::report_panic(info)
    }
}
