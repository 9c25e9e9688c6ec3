//! Instructions per frame against configuration, in QEMU (`thumbv7em-none-eabihf`,
//! Cortex-M4F, the example firmware's scene and counter): the cost half of the
//! accuracy-against-cost table in the README. For each particle count, pixel cap and
//! number of gradient points it runs both trackers over the scene's 60 frames and prints
//! the mean and largest instructions per frame.
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
    use rbtrack::image::Rgb8x8x8;
    use rbtrack::tracker::{Tracker, Variant};
    use rbtrack_firmware::board::{self, SysTick};
    use rbtrack_firmware::run::{self, BINS};
    use rbtrack_firmware::scene::FRAMES;
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

    // The frame buffer and the tracker of N = 100 are the board's; these the smaller ones.
    static T50: ConstStaticCell<Tracker<Rgb8x8x8, 50, BINS>> =
        ConstStaticCell::new(Tracker::unstarted());
    static T25: ConstStaticCell<Tracker<Rgb8x8x8, 25, BINS>> =
        ConstStaticCell::new(Tracker::unstarted());

    /// Mean and largest instructions per frame of `variant` with `cap` and `points` in
    /// `tracker`.
    fn measure<const N: usize>(
        tracker: &mut Tracker<Rgb8x8x8, N, BINS>,
        frame: &mut [u8],
        counter: &mut SysTick,
        variant: Variant,
        cap: u32,
        points: u8,
    ) -> (u64, u32) {
        let mut config = run::config(variant);
        config.pixels_per_window = cap;
        config.gradient_points = points;
        let (mut total, mut most) = (0u64, 0u32);
        let result = run::run_config(config, tracker, FRAMES, frame, counter, |r| {
            let units = r.cycles.total();
            total += units as u64;
            most = most.max(units);
        });
        if let Err(e) = result {
            panic!("configuration: {e}");
        }
        (total / FRAMES as u64, most)
    }

    #[entry]
    fn main() -> ! {
        let Some(mut cp) = cortex_m::Peripherals::take() else {
            panic!("peripherals taken twice");
        };
        let (Some((frame, t100)), Some(t50), Some(t25)) =
            (board::statics(), T50.try_take(), T25.try_take())
        else {
            panic!("statics taken twice");
        };
        SysTick::start(&mut cp.SYST);
        let (instructions, ticks) = board::calibrate(1_000_000);
        let mut counter = SysTick::counter((instructions + ticks / 2) / ticks.max(1));
        hprintln!("N    cap  points   rbpf mean    rbpf max     pf mean      pf max  (instructions per frame)");
        for (n, cap, points) in CONFIGS {
            let mut row = [(0u64, 0u32); 2];
            for (slot, variant) in row.iter_mut().zip([Variant::Rbpf, Variant::ColourPf]) {
                let f = &mut frame[..];
                *slot = match n {
                    100 => measure(t100, f, &mut counter, variant, cap, points),
                    50 => measure(t50, f, &mut counter, variant, cap, points),
                    _ => measure(t25, f, &mut counter, variant, cap, points),
                };
            }
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
        board::exit(debug::EXIT_SUCCESS)
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        board::report_panic(info)
    }
}
