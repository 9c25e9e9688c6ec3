//! A firmware that tracks with rbtrack: a QVGA RGB565 frame in a static buffer (here a
//! drawn target that moves 2 px a frame; on a board, the camera's DMA buffer), the
//! correlation-filter tracker at its defaults in a static, and per frame the estimate and
//! the cycles of the step and of its features.
//!
//! For a particle filter instead (cheaper, less accurate: rbtrack's README says when), make
//! `TRACKER` an `rbtrack::RgbTracker<100>`, start it with
//! `rbtrack::Config::new(rbtrack::Variant::ColourPf)` and print `cycles.weigh`.
//!
//! `cargo run --release` runs it in QEMU, where the cycle counter does not run (the cycles
//! print as 0); on a board the DWT counts core cycles.
#![no_std]
#![no_main]

use cortex_m::peripheral::DWT;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use rbtrack::profile::CycleCounter;
use rbtrack::{CfConfig, ImageView, Rect, Rgb565Le, RgbCfTracker};
use static_cell::ConstStaticCell;

/// Frame size, px.
const WIDTH: usize = 320;
const HEIGHT: usize = 240;
/// Frames tracked.
const FRAMES: u32 = 30;

/// The frame buffer, RGB565 little-endian: 153,600 B of `.bss`.
static FRAME: ConstStaticCell<[u8; WIDTH * HEIGHT * 2]> =
    ConstStaticCell::new([0; WIDTH * HEIGHT * 2]);
/// The tracker, 16 x 16 cells, 4 scales and 512 colour bins: 82 KB of `.bss`, never on the
/// stack.
static TRACKER: ConstStaticCell<RgbCfTracker> = ConstStaticCell::new(RgbCfTracker::unstarted());

/// The core's cycle counter (DWT CYCCNT).
struct Cycles;

impl CycleCounter for Cycles {
    fn now(&mut self) -> u32 {
        DWT::cycle_count()
    }
}

/// The target's box `(x, y, w, h)` at frame `k`, px: 24 x 40, moving 2 px right and 1 px
/// down a frame.
fn target(k: u32) -> (i32, i32, i32, i32) {
    (100 + 2 * k as i32, 80 + k as i32, 24, 40)
}

/// Draws frame `k` into `frame`: a grey floor with a check pattern, and the target, red
/// above its middle and blue below.
fn draw(frame: &mut [u8], k: u32) {
    let (tx, ty, tw, th) = target(k);
    for (y, row) in frame.chunks_exact_mut(WIDTH * 2).enumerate() {
        for (x, px) in row.chunks_exact_mut(2).enumerate() {
            let (x, y) = (x as i32, y as i32);
            let inside = (tx..tx + tw).contains(&x) && (ty..ty + th).contains(&y);
            let (r, g, b) = match (inside, y < ty + th / 2) {
                (true, true) => (200, 40, 40),
                (true, false) => (40, 60, 190),
                _ if (x / 16 + y / 16) % 2 == 0 => (110, 120, 100),
                _ => (90, 100, 85),
            };
            let rgb565: u16 = ((r >> 3) << 11) | ((g >> 2) << 5) | (b >> 3);
            px.copy_from_slice(&rgb565.to_le_bytes());
        }
    }
}

#[entry]
fn main() -> ! {
    // `try_take` hands each static out once: no panic path.
    let (Some(mut cp), Some(frame), Some(tracker)) = (
        cortex_m::Peripherals::take(),
        FRAME.try_take(),
        TRACKER.try_take(),
    ) else {
        exit(debug::EXIT_FAILURE);
    };
    cp.DCB.enable_trace();
    cp.DWT.enable_cycle_counter();

    draw(frame, 0);
    let started = ImageView::<Rgb565Le>::new(&frame[..], WIDTH, HEIGHT, WIDTH)
        .map_err(rbtrack::Error::from)
        .and_then(|view| {
            let (x, y, w, h) = target(0);
            Ok(tracker.start(CfConfig::default(), &view, Rect::new(x, y, w, h))?)
        });
    if let Err(e) = started {
        hprintln!("cannot start: {}", e);
        exit(debug::EXIT_FAILURE);
    }
    hprintln!("frame      x      y      w      h  status    conf %  cycles: features    total");
    let mut off = 0;
    for k in 1..=FRAMES {
        draw(frame, k);
        let Ok(view) = ImageView::<Rgb565Le>::new(&frame[..], WIDTH, HEIGHT, WIDTH) else {
            exit(debug::EXIT_FAILURE);
        };
        let (estimate, cycles) = tracker.step_profiled(&view, &mut Cycles);
        let (x, y, w, h) = estimate.rect().px();
        // Integer formatting only: float formatting would add some 20 KB of flash.
        let percent = (estimate.confidence.to_bits() * 100) >> 16;
        hprintln!(
            "{:>5} {:>6} {:>6} {:>6} {:>6}  {:?}  {:>6}  {:>16} {:>8}",
            k,
            x,
            y,
            w,
            h,
            estimate.status,
            percent,
            cycles.features,
            cycles.total()
        );
        let (tx, ty, _, _) = target(k);
        off = off.max((x - tx).abs().max((y - ty).abs()));
    }
    hprintln!("largest corner error: {} px", off);
    exit(if off <= 8 {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    })
}

/// Ends the program through semihosting (QEMU exits with 0 or 1), then sleeps where
/// nothing ends it.
fn exit(status: debug::ExitStatus) -> ! {
    debug::exit(status);
    loop {
        cortex_m::asm::wfi();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    exit(debug::EXIT_FAILURE)
}
