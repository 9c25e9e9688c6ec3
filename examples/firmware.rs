//! Example firmware: both trackers on a rendered QVGA scene, profiled per stage.
//!
//! ```sh
//! cargo run --release --example firmware --target thumbv7em-none-eabihf
//! ```
//!
//! runs it in QEMU's `mps2-an386` (Cortex-M4F; the runner is in `.cargo/config.toml`,
//! the memory map in `memory.x`). It renders a deterministic 320x240 RGB565 scene (a
//! two-coloured target walking nearer over a textured floor, `rbtrack_firmware::scene`)
//! into a static frame buffer, runs the RBPF and then the colour PF, 100 particles each,
//! over 60 frames, and prints per frame the counts spent in each stage, the pixels read,
//! the pixel-visit bound and the estimate; then per tracker the mean and maximum, the
//! checksum over all estimates (which `host-tests/tests/firmware.rs` reproduces on the
//! host), the tracker's RAM and the stack high-water mark. It exits through semihosting:
//! 0 on success, 1 on a panic.
//!
//! Counts are core cycles where the DWT cycle counter runs (a real board), and
//! instructions from the calibrated SysTick where it does not (QEMU).
//!
//! On a hosted target this example is an empty program.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("firmware: build with --target thumbv7em-none-eabihf (see examples/firmware.rs)");
}

#[cfg(target_os = "none")]
mod firmware {
    use core::fmt;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use rbtrack::cue::{self, GradientCue};
    use rbtrack::fixed::Q16;
    use rbtrack::hist::{Histogram, Model};
    use rbtrack::image::{ImageView, Rgb565Le, Rgb8x8x8};
    use rbtrack::profile::{CycleCounter, StageCycles};
    use rbtrack::tracker::{Status, Tracker, Variant};
    use rbtrack::window;
    use rbtrack_firmware::board::{self, Counter, Dwt, SysTick};
    use rbtrack_firmware::run::{self, Checksum, FrameReport, BINS, PARTICLES};
    use rbtrack_firmware::scene::{self, FRAMES};
    use static_cell::ConstStaticCell;

    /// Iterations of the SysTick calibration loop (2 instructions each).
    const CALIBRATION_ITERATIONS: u32 = 5_000_000;

    /// A Q16.16 value with `D` decimals, right-aligned in `W` columns.
    struct Fixed<const W: usize, const D: u32>(Q16);

    impl<const W: usize, const D: u32> fmt::Display for Fixed<W, D> {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            let scale = 10i64.pow(D);
            let v = (self.0.to_bits() as i64 * scale + (1 << 15)) >> 16;
            let (int, frac) = (v.div_euclid(scale), v.rem_euclid(scale));
            let int_width = W.saturating_sub(D as usize + 1);
            write!(f, "{int:>int_width$}.{frac:0d$}", d = D as usize)
        }
    }

    /// `num / den` with two decimals, right-aligned in 6 columns.
    struct Ratio(u64, u64);

    impl fmt::Display for Ratio {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            let hundredths = (self.0 * 100 + self.1 / 2).checked_div(self.1).unwrap_or(0);
            write!(f, "{:>3}.{:02}", hundredths / 100, hundredths % 100)
        }
    }

    /// The cost of the tightest pixel-to-bin loop: `units` counts for `pixels` pixels.
    #[derive(Clone, Copy)]
    struct PixelCost {
        units: u64,
        pixels: u64,
    }

    impl PixelCost {
        fn bound(&self, pixels: u32) -> u64 {
            (pixels as u64 * self.units + self.pixels / 2) / self.pixels.max(1)
        }
    }

    /// Per-stage sums and maxima over the frames of one run.
    #[derive(Default)]
    struct Totals {
        sum: [u64; 6],
        max: [u32; 6],
        bound: u64,
        pixels: u64,
    }

    fn stages(c: &StageCycles) -> [u32; 6] {
        [
            c.propagate,
            c.weigh,
            c.update,
            c.estimate,
            c.resample,
            c.total(),
        ]
    }

    fn status(s: Status) -> &'static str {
        match s {
            Status::Tracking => "tracking",
            Status::Uncertain => "uncertain",
            Status::Lost => "lost",
        }
    }

    fn print_header() {
        hprintln!(
            "frame propagate   weigh  update estimate resample   total  pixels   bound  ratio |     cx     cy     hx     hy  conf status    err"
        );
    }

    fn print_frame(r: &FrameReport, cost: &PixelCost) {
        let [p, w, u, e, s, total] = stages(&r.cycles);
        let bound = cost.bound(r.pixels);
        let el = r.estimate.ellipse;
        let (dx, dy) = (
            (el.cx - r.truth.cx).to_bits() as i64,
            (el.cy - r.truth.cy).to_bits() as i64,
        );
        let err = Q16::from_bits(((dx * dx + dy * dy) as u64).isqrt() as i32);
        hprintln!(
            "{:>5} {:>9} {:>7} {:>7} {:>8} {:>8} {:>7} {:>7} {:>7} {} | {} {} {} {} {} {:<9} {}",
            r.frame,
            p,
            w,
            u,
            e,
            s,
            total,
            r.pixels,
            bound,
            Ratio(total as u64, bound),
            Fixed::<6, 2>(el.cx),
            Fixed::<6, 2>(el.cy),
            Fixed::<6, 2>(el.hx),
            Fixed::<6, 2>(el.hy),
            Fixed::<5, 3>(r.estimate.confidence),
            status(r.estimate.status),
            Fixed::<6, 2>(err),
        );
    }

    /// Prints each frame of a run and, after its last frame, the run's summary.
    struct Table<'a> {
        cost: PixelCost,
        unit: &'a str,
        checksum: Checksum,
        totals: Totals,
    }

    impl Table<'_> {
        fn frame(&mut self, variant: Variant, r: &FrameReport) {
            let name = match variant {
                Variant::Rbpf => "rbpf",
                Variant::ColourPf => "pf",
            };
            if r.frame == 1 {
                hprintln!("\n{} (N = {}), {} per stage:", name, PARTICLES, self.unit);
                print_header();
                self.checksum = Checksum::new();
                self.totals = Totals::default();
            }
            print_frame(r, &self.cost);
            self.checksum.add(&r.estimate);
            let t = &mut self.totals;
            for (k, v) in stages(&r.cycles).into_iter().enumerate() {
                t.sum[k] += v as u64;
                t.max[k] = t.max[k].max(v);
            }
            if r.pixels > run::pixel_bound(variant) {
                panic!(
                    "frame {}: {} pixels read, above the bound {}",
                    r.frame,
                    r.pixels,
                    run::pixel_bound(variant)
                );
            }
            t.bound += self.cost.bound(r.pixels);
            t.pixels += r.pixels as u64;
            if r.frame == FRAMES {
                self.summary(name);
            }
        }

        fn summary(&self, name: &str) {
            let t = &self.totals;
            let frames = FRAMES as u64;
            let mean = t.sum.map(|s| (s + frames / 2) / frames);
            let [p, w, u, e, s, total] = mean;
            hprintln!(
                " mean {:>9} {:>7} {:>7} {:>8} {:>8} {:>7} {:>7} {:>7} {}",
                p,
                w,
                u,
                e,
                s,
                total,
                (t.pixels + frames / 2) / frames,
                (t.bound + frames / 2) / frames,
                Ratio(t.sum[5], t.bound),
            );
            let [p, w, u, e, s, total] = t.max;
            hprintln!(
                "  max {:>9} {:>7} {:>7} {:>8} {:>8} {:>7}",
                p,
                w,
                u,
                e,
                s,
                total
            );
            hprintln!(
                "{}: {} {} per frame on average, {} at most; {} x the pixel-visit bound; checksum {:#018x}",
                name,
                mean[5],
                self.unit,
                t.max[5],
                Ratio(t.sum[5], t.bound),
                self.checksum.value()
            );
        }
    }

    /// Counts spent in `f`, the last of three calls (two warm-ups).
    fn time<T>(counter: &mut Counter, mut f: impl FnMut() -> T) -> (u32, T) {
        let mut result = None;
        let mut spent = 0;
        for _ in 0..3 {
            let t0 = counter.now();
            result = Some(core::hint::black_box(f()));
            spent = counter.now().wrapping_sub(t0);
        }
        match result {
            Some(r) => (spent, r),
            None => unreachable!(),
        }
    }

    /// Costs of the primitives a particle's weight is made of, on the target's window in
    /// the rendered frame 0; the histogram and model are statics, like the tracker.
    #[inline(never)]
    fn primitives(frame: &[u8], counter: &mut Counter, unit: &str) {
        static HIST: ConstStaticCell<Histogram<BINS>> = ConstStaticCell::new(Histogram::new());
        static MODEL: ConstStaticCell<Model<BINS>> = ConstStaticCell::new(Model::new());
        let (Some(hist), Some(model)) = (HIST.try_take(), MODEL.try_take()) else {
            panic!("primitives measured twice");
        };
        let Ok(img) = ImageView::<Rgb565Le>::new(frame, scene::WIDTH, scene::HEIGHT, scene::WIDTH)
        else {
            panic!("frame buffer too short");
        };
        let config = run::config(Variant::Rbpf);
        let e = scene::truth(0);
        let cap = config.pixels_per_window;
        hprintln!(
            "primitives on the target's window at frame 0 (hx {}, hy {}, cap {} px), {}:",
            Fixed::<0, 2>(e.hx),
            Fixed::<0, 2>(e.hy),
            cap,
            unit
        );
        let (t, n) = time(counter, || window::visit(&img, &e, cap, |_, _, _| {}));
        hprintln!(
            "  window::visit, empty closure  {:>6}  {} px, {} per px",
            t,
            n,
            Ratio(t as u64, n as u64)
        );
        let (t, n) = time(counter, || hist.fill::<Rgb8x8x8, Rgb565Le>(&img, &e, cap));
        hprintln!(
            "  Histogram::fill               {:>6}  {} px, {} per px",
            t,
            n,
            Ratio(t as u64, n as u64)
        );
        model.set(hist);
        let (t, _) = time(counter, || hist.bhattacharyya(model));
        hprintln!(
            "  Histogram::bhattacharyya      {:>6}  {} bins",
            t,
            hist.touched().len()
        );
        let cue_config = config.gradient();
        let Ok(cue) = GradientCue::new(&cue_config) else {
            panic!("gradient cue configuration");
        };
        let gradients = cue_config.points as u64 * (2 * cue_config.search_px as u64 + 1);
        let (t, _) = time(counter, || cue.evaluate(&img, &e));
        hprintln!(
            "  GradientCue::evaluate         {:>6}  {} points x {} positions, {} per gradient",
            t,
            cue_config.points,
            2 * cue_config.search_px + 1,
            Ratio(t as u64, gradients)
        );
        let (cx, cy) = (e.cx.round_int(), e.cy.round_int());
        let (t, _) = time(counter, || cue::gradient_sq(&img, cx, cy));
        hprintln!(
            "  cue::gradient_sq              {:>6}  one 5-tap gradient, 8 luma reads",
            t
        );
    }

    #[entry]
    fn main() -> ! {
        let Some(mut cp) = cortex_m::Peripherals::take() else {
            panic!("peripherals taken twice");
        };
        let Some((frame, tracker)) = board::statics() else {
            panic!("frame buffer and tracker taken twice");
        };
        hprintln!(
            "rbtrack example firmware: {}x{} RGB565 scene, seed {}, {} frames; N = {}, {} bins",
            scene::WIDTH,
            scene::HEIGHT,
            scene::SEED,
            FRAMES,
            PARTICLES,
            BINS
        );

        SysTick::start(&mut cp.SYST);
        let (instructions, ticks) = board::calibrate(CALIBRATION_ITERATIONS);
        let per_tick = (instructions + ticks / 2) / ticks.max(1);
        hprintln!(
            "SysTick: {} instructions in {} ticks: {} instructions per tick",
            instructions,
            ticks,
            Ratio(instructions as u64, ticks as u64)
        );
        let (mut counter, unit) = if Dwt::start(&mut cp.DCB, &mut cp.DWT) {
            (Counter::Dwt(Dwt), "cycles")
        } else {
            hprintln!("DWT CYCCNT does not run (QEMU): counting instructions with SysTick");
            (Counter::SysTick(SysTick::counter(per_tick)), "instructions")
        };

        // The tightest pixel-to-bin loop, on the first frame: two warm-up passes, then
        // the timed one.
        scene::render(scene::SEED, 0, &mut frame[..]);
        let mut counts = [0u32; BINS];
        let mut pixels = 0;
        let mut units = 0;
        for _ in 0..3 {
            let t0 = counter.now();
            pixels = run::bin_pixels(&frame[..], &mut counts, 1);
            units = counter.now().wrapping_sub(t0);
        }
        let cost = PixelCost {
            units: units as u64,
            pixels: pixels as u64,
        };
        hprintln!(
            "pixel loop (read RGB565, bin, add): {} pixels in {} {}: {} per pixel (bins {})",
            pixels,
            units,
            unit,
            Ratio(cost.units, cost.pixels),
            counts.iter().filter(|&&c| c > 0).count()
        );
        primitives(&frame[..], &mut counter, unit);
        hprintln!(
            "tracker RAM (size_of, {} bins): N = 50: {} B, N = 100: {} B, N = 200: {} B",
            BINS,
            core::mem::size_of::<Tracker<Rgb8x8x8, 50, BINS>>(),
            core::mem::size_of::<Tracker<Rgb8x8x8, 100, BINS>>(),
            core::mem::size_of::<Tracker<Rgb8x8x8, 200, BINS>>()
        );

        let mut table = Table {
            cost,
            unit,
            checksum: Checksum::new(),
            totals: Totals::default(),
        };
        let checksum = match run::run_all(tracker, &mut frame[..], &mut counter, |v, r| {
            table.frame(v, r)
        }) {
            Ok(checksum) => checksum,
            Err(e) => panic!("tracker configuration: {e}"),
        };

        let stack = board::stack_use();
        hprintln!(
            "\nstack high-water mark: {} of {} bytes (budget {})",
            stack.used,
            stack.size,
            run::STACK_BUDGET_BYTES
        );
        if stack.used > run::STACK_BUDGET_BYTES {
            panic!("the stack outgrew its budget");
        }
        hprintln!("checksum {:#018x}", checksum.value());
        board::exit(debug::EXIT_SUCCESS)
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        board::report_panic(info)
    }
}
