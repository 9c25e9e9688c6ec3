//! A short run for the instruction-level Cortex-M4 cycle model
//! (`../shared/tools/m4-cycle-model/ucount.py`): the example firmware's scene, frames 1-5,
//! for the defaults of both trackers (N = 100) and for the configurations that fit a
//! 1 M instruction budget (RBPF N = 50, 150 px, 12 gradient points; colour PF N = 50),
//! each step between `step_begins` and `step_ends`.
//!
//! ```sh
//! cargo build --release --example cycles --target thumbv7em-none-eabihf
//! python3 ../shared/tools/m4-cycle-model/ucount.py \
//!     target/thumbv7em-none-eabihf/release/examples/cycles --start step_begins --end step_ends
//! ```
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("the cycles example runs on thumbv7em-none-eabihf: see its doc comment");
}

#[cfg(target_os = "none")]
mod cycles {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use rbtrack::fixed::Q16;
    use rbtrack::image::Rgb8x8x8;
    use rbtrack::profile::NoCounter;
    use rbtrack::tracker::{Config, Tracker, Variant};
    use rbtrack_firmware::board;
    use rbtrack_firmware::run::{self, BINS};
    use static_cell::ConstStaticCell;

    /// Frames stepped per configuration.
    const FRAMES: usize = 5;

    // The frame buffer and the tracker of N = 100 are the board's; this the smaller one.
    static T50: ConstStaticCell<Tracker<Rgb8x8x8, 50, BINS>> =
        ConstStaticCell::new(Tracker::unstarted());

    /// Steps `tracker` of `config` over frames `1..=FRAMES`.
    fn steps<const N: usize>(
        label: &str,
        config: Config,
        tracker: &mut Tracker<Rgb8x8x8, N, BINS>,
        frame: &mut [u8],
    ) {
        let mut stepped = 0;
        let result = run::run_config(config, tracker, FRAMES, Q16::ONE, frame, NoCounter, |r| {
            stepped = r.frame;
            if r.frame == FRAMES {
                hprintln!("{}: {} steps", label, stepped);
            }
        });
        if let Err(e) = result {
            panic!("configuration: {e}");
        }
    }

    #[entry]
    fn main() -> ! {
        let (Some((frame, t100)), Some(t50)) = (board::statics(), T50.try_take()) else {
            panic!("statics taken twice");
        };
        let budget = |variant: Variant| {
            let mut c = run::config(variant);
            if variant == Variant::Rbpf {
                (c.pixels_per_window, c.gradient_points) = (150, 12);
            }
            c
        };
        steps(
            "rbpf, N = 100",
            run::config(Variant::Rbpf),
            t100,
            &mut frame[..],
        );
        steps(
            "pf, N = 100",
            run::config(Variant::ColourPf),
            t100,
            &mut frame[..],
        );
        steps(
            "rbpf, N = 50, 150 px, 12 points",
            budget(Variant::Rbpf),
            t50,
            &mut frame[..],
        );
        steps("pf, N = 50", budget(Variant::ColourPf), t50, &mut frame[..]);
        board::exit(debug::EXIT_SUCCESS)
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        board::report_panic(info)
    }
}
