//! Example firmware of the correlation-filter tracker alone, profiled per stage.
//!
//! ```sh
//! cargo run --release --example cf_firmware --target thumbv7em-none-eabihf
//! ```
//!
//! runs it in QEMU's `mps2-an386` (Cortex-M4F), like `examples/firmware.rs`, over the same
//! rendered QVGA RGB565 scene: `CfTracker<Rgb8x8x8, 512, 16, 4>` at its defaults, in a
//! static started in place, over 60 frames. It prints per frame the counts spent in each
//! stage and the estimate; then the mean and the largest per stage, the tracker's RAM, the
//! stack high-water mark (it fails above the budget), the mean intersection over union of
//! the estimate's and the truth's bounding boxes, and the checksum over all estimates (which
//! `host-tests/tests/cf_firmware.rs` reproduces on the host). It links no particle filter,
//! so its flash is what a firmware of this tracker alone takes. It exits through
//! semihosting: 0 on success, 1 on a panic.
//!
//! Counts are core cycles where the DWT cycle counter runs (a real board), and
//! instructions from the calibrated SysTick where it does not (QEMU).
//!
//! On a hosted target this example is an empty program.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "cf_firmware: build with --target thumbv7em-none-eabihf (see examples/cf_firmware.rs)"
    );
}

#[cfg(target_os = "none")]
mod firmware {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use rbtrack::fixed::Q16;
    use rbtrack::profile::CfStageCycles;
    use rbtrack::tracker::{CfConfig, Status};
    use rbtrack_firmware::board::{self, Counter, Dwt, SysTick};
    use rbtrack_firmware::cf::{
        iou_permille, run_cf, CfFrameReport, FirmwareCfTracker, CF_GRID, CF_SCALES,
    };
    use rbtrack_firmware::run::STACK_BUDGET_BYTES;
    use rbtrack_firmware::scene::{self, FRAMES, FRAME_BYTES};
    use static_cell::ConstStaticCell;

    /// Iterations of the SysTick calibration loop (2 instructions each).
    const CALIBRATION_ITERATIONS: u32 = 5_000_000;

    /// The frame buffer and the tracker, built at compile time (never on the stack).
    static FRAME: ConstStaticCell<[u8; FRAME_BYTES]> = ConstStaticCell::new([0; FRAME_BYTES]);
    static TRACKER: ConstStaticCell<FirmwareCfTracker> =
        ConstStaticCell::new(FirmwareCfTracker::unstarted());

    fn stages(c: &CfStageCycles) -> [u32; 7] {
        [
            c.features,
            c.filter,
            c.colour,
            c.scale,
            c.learn,
            c.redetect,
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

    /// Whole pixels of a Q16.16 value, rounded.
    fn px(v: rbtrack::fixed::Q16) -> i32 {
        v.round_int()
    }

    #[entry]
    fn main() -> ! {
        let Some(mut cp) = cortex_m::Peripherals::take() else {
            panic!("peripherals taken twice");
        };
        let (Some(frame), Some(tracker)) = (FRAME.try_take(), TRACKER.try_take()) else {
            panic!("frame buffer and tracker taken twice");
        };
        hprintln!(
            "rbtrack correlation-filter firmware: {}x{} RGB565 scene, seed {}, {} frames; {} x {} cells, {} scales",
            scene::WIDTH,
            scene::HEIGHT,
            scene::SEED,
            FRAMES,
            CF_GRID,
            CF_GRID,
            CF_SCALES
        );
        SysTick::start(&mut cp.SYST);
        let (instructions, ticks) = board::calibrate(CALIBRATION_ITERATIONS);
        let per_tick = (instructions + ticks / 2) / ticks.max(1);
        let (mut counter, unit) = if Dwt::start(&mut cp.DCB, &mut cp.DWT) {
            (Counter::Dwt(Dwt), "cycles")
        } else {
            hprintln!("DWT CYCCNT does not run (QEMU): counting instructions with SysTick");
            (Counter::SysTick(SysTick::counter(per_tick)), "instructions")
        };
        hprintln!(
            "tracker RAM (size_of): {} B",
            core::mem::size_of::<FirmwareCfTracker>()
        );
        hprintln!(
            "frame features  filter  colour   scale   learn redetect    total |    cx    cy    hx    hy  conf status"
        );
        let (mut sum, mut max, mut iou) = ([0u64; 7], [0u32; 7], 0u32);
        let mut report = |r: &CfFrameReport| {
            iou += iou_permille(&r.estimate.ellipse, &r.truth);
            let s = stages(&r.cycles);
            for ((total, top), v) in sum.iter_mut().zip(max.iter_mut()).zip(s) {
                *total += v as u64;
                *top = (*top).max(v);
            }
            let e = r.estimate;
            hprintln!(
                "{:>5} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8} {:>8} | {:>5} {:>5} {:>5} {:>5} {:>5} {}",
                r.frame,
                s[0],
                s[1],
                s[2],
                s[3],
                s[4],
                s[5],
                s[6],
                px(e.ellipse.cx),
                px(e.ellipse.cy),
                px(e.ellipse.hx),
                px(e.ellipse.hy),
                (e.confidence.to_bits() as i64 * 100 + (1 << 15)) >> 16,
                status(e.status)
            );
        };
        let checksum = match run_cf(
            CfConfig::default(),
            tracker,
            Q16::ONE,
            &mut frame[..],
            &mut counter,
            &mut report,
        ) {
            Ok(checksum) => checksum,
            Err(e) => panic!("tracker configuration: {e}"),
        };
        let mean = sum.map(|v| v / FRAMES as u64);
        for (what, v) in [("mean", mean.map(|m| m as u32)), ("largest", max)] {
            hprintln!(
                "cf ({}) {}: features {} filter {} colour {} scale {} learn {} redetect {} total {}",
                unit,
                what,
                v[0],
                v[1],
                v[2],
                v[3],
                v[4],
                v[5],
                v[6]
            );
        }
        let iou = iou / FRAMES as u32;
        hprintln!("cf mean IoU: 0.{:03}", iou);
        let stack = board::stack_use();
        hprintln!(
            "stack high-water mark: {} of {} bytes (budget {})",
            stack.used,
            stack.size,
            STACK_BUDGET_BYTES
        );
        if stack.used > STACK_BUDGET_BYTES {
            panic!("the stack outgrew its budget");
        }
        hprintln!("cf checksum {:#018x}", checksum.value());
        board::exit(debug::EXIT_SUCCESS)
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        board::report_panic(info)
    }
}
