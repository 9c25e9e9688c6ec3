//! Cortex-M board support for the example firmware: cycle and instruction counters for
//! [`rbtrack::profile::CycleCounter`], the SysTick calibration, the static frame buffer,
//! the stack high-water mark, the examples' exit and panic report ([`exit`],
//! [`report_panic`]) and the no-panic proof's panic handler ([`unlinkable`]).
//!
//! # Counting
//! On a real Cortex-M4/M7 the DWT cycle counter `CYCCNT` counts core clock cycles:
//! [`Dwt::start`] enables it and [`Dwt`] reads it. QEMU does not model it (it reads 0).
//! There, SysTick, clocked from the core clock of the `mps2-an386` board (25 MHz), under
//! `-icount shift=0,sleep=off` advances one tick per 40 executed instructions (1 ns of
//! virtual time per instruction, 40 ns per tick), exactly reproducibly;
//! [`calibrate`] measures that ratio on a loop of known length, and [`SysTick`] turns
//! ticks into instructions with it.

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{DCB, DWT, SYST};
use cortex_m_semihosting::{debug, hprintln};
use rbtrack::profile::CycleCounter;

use crate::run::FirmwareTracker;
use crate::scene::FRAME_BYTES;
use static_cell::ConstStaticCell;

/// SysTick's reload value: the full 24-bit range.
const SYST_RELOAD: u32 = 0x00FF_FFFF;

/// The 24-bit SysTick down-counter, extended in software to a 32-bit up-count and scaled
/// to instructions. Reads must come less than 2^24 ticks apart (671 million instructions
/// in QEMU), which every stage of a step does.
pub struct SysTick {
    last: u32,
    ticks: u32,
    instructions_per_tick: u32,
}

impl SysTick {
    /// Starts SysTick free-running on the core clock over its full 24-bit range, without
    /// interrupts.
    pub fn start(syst: &mut SYST) {
        syst.disable_interrupt();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(SYST_RELOAD);
        syst.clear_current();
        syst.enable_counter();
    }

    /// A counter over the running SysTick, `instructions_per_tick` (from [`calibrate`])
    /// instructions per tick.
    pub fn counter(instructions_per_tick: u32) -> Self {
        Self {
            last: SYST::get_current(),
            ticks: 0,
            instructions_per_tick,
        }
    }
}

impl CycleCounter for SysTick {
    fn now(&mut self) -> u32 {
        let current = SYST::get_current();
        self.ticks = self
            .ticks
            .wrapping_add(self.last.wrapping_sub(current) & SYST_RELOAD);
        self.last = current;
        self.ticks.wrapping_mul(self.instructions_per_tick)
    }
}

/// The DWT cycle counter `CYCCNT`: core clock cycles on a real Cortex-M3/M4/M7.
pub struct Dwt;

/// The counter the examples time the trackers with: DWT cycles where the cycle counter
/// runs (a board), else instructions from the calibrated SysTick (QEMU).
pub enum Counter {
    /// Core cycles.
    Dwt(Dwt),
    /// Instructions.
    SysTick(SysTick),
}

impl CycleCounter for Counter {
    fn now(&mut self) -> u32 {
        match self {
            Counter::Dwt(c) => c.now(),
            Counter::SysTick(c) => c.now(),
        }
    }
}

impl Dwt {
    /// Enables the trace unit and the cycle counter; returns whether `CYCCNT` advances
    /// (it does not under QEMU).
    pub fn start(dcb: &mut DCB, dwt: &mut DWT) -> bool {
        dcb.enable_trace();
        DWT::unlock(); // Cortex-M7 locks the DWT until written with the key
        dwt.enable_cycle_counter();
        let before = DWT::cycle_count();
        let after = core::hint::black_box(spin(100));
        after != 0 && DWT::cycle_count() != before
    }
}

impl CycleCounter for Dwt {
    fn now(&mut self) -> u32 {
        DWT::cycle_count()
    }
}

/// Runs `2 * iterations + 1` instructions (`subs`/`bne` pairs and a `movs`), returns
/// `iterations`.
#[inline(never)]
fn spin(iterations: u32) -> u32 {
    let mut n = iterations;
    // SAFETY: touches only the register it is given; no memory, no stack.
    #[allow(unsafe_code)]
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, #1",
            "bne 2b",
            n = inout(reg) n,
            options(nomem, nostack),
        );
    }
    iterations + n // n is 0 afterwards
}

/// SysTick ticks for a loop of exactly `2 * iterations` instructions more than an empty
/// one, from the running SysTick ([`SysTick::start`]). Returns
/// `(instructions, ticks)`; under QEMU with `-icount shift=0` on the `mps2-an386`,
/// `instructions / ticks` is 40.
pub fn calibrate(iterations: u32) -> (u32, u32) {
    let mut counter = SysTick::counter(1);
    let t0 = counter.now();
    spin(1);
    let t1 = counter.now();
    spin(iterations + 1);
    let t2 = counter.now();
    let ticks = (t2.wrapping_sub(t1)).wrapping_sub(t1.wrapping_sub(t0));
    (2 * iterations, ticks)
}

/// The frame buffer and the tracker, built at compile time in `.bss`/`.data` (never on
/// the stack): handed out once, `None` afterwards.
pub fn statics() -> Option<(&'static mut [u8; FRAME_BYTES], &'static mut FirmwareTracker)> {
    static FRAME: ConstStaticCell<[u8; FRAME_BYTES]> = ConstStaticCell::new([0; FRAME_BYTES]);
    static TRACKER: ConstStaticCell<FirmwareTracker> =
        ConstStaticCell::new(FirmwareTracker::unstarted());
    Some((FRAME.try_take()?, TRACKER.try_take()?))
}

/// The stack's extent and its high-water mark.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StackUse {
    /// Bytes between the stack's lowest address (`_stack_end`, the end of `.bss`) and its
    /// top (`_stack_start`, the end of RAM).
    pub size: u32,
    /// Bytes from the top down to the lowest word that no longer holds the paint.
    pub used: u32,
}

/// The stack's high-water mark since reset. `cortex-m-rt`'s `paint-stack` feature fills
/// the whole stack with [`cortex_m_rt::STACK_PAINT_VALUE`] before `main`; this scans up
/// from the bottom to the first word that lost it.
pub fn stack_use() -> StackUse {
    extern "C" {
        static _stack_end: u32;
        static _stack_start: u32;
    }
    let bottom = core::ptr::addr_of!(_stack_end) as usize;
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let mut addr = bottom;
    while addr < top {
        // SAFETY: `bottom..top` is the stack region of the linker script, word-aligned
        // (`_stack_end` is 4-aligned, `_stack_start` 8-aligned) and always mapped; the
        // words below the stack pointer are not Rust objects, only the paint.
        #[allow(unsafe_code)]
        let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
        if word != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        addr += 4;
    }
    StackUse {
        size: (top - bottom) as u32,
        used: (top - addr) as u32,
    }
}

/// Ends the program through semihosting with `status` ([`debug::EXIT_SUCCESS`] or
/// [`debug::EXIT_FAILURE`]: QEMU exits with 0 or 1), then, where nothing ends it (a board
/// without a debugger), sleeps.
pub fn exit(status: debug::ExitStatus) -> ! {
    debug::exit(status);
    loop {
        cortex_m::asm::wfi();
    }
}

/// The examples' panic handler: prints the panic through semihosting and exits with
/// failure.
pub fn report_panic(info: &core::panic::PanicInfo<'_>) -> ! {
    hprintln!("panic: {}", info);
    exit(debug::EXIT_FAILURE)
}

/// Never returns, and never links: it calls `rbtrack_panic_path_is_reachable`, a function
/// defined nowhere. The panic handler of the no-panic proof (`examples/no_panic.rs`), which
/// therefore links only if the optimiser removed every call to it.
pub fn unlinkable() -> ! {
    extern "C" {
        fn rbtrack_panic_path_is_reachable() -> !;
    }
    // SAFETY: a program in which this call survives optimisation fails to link (undefined
    // symbol), so it never runs.
    #[allow(unsafe_code)]
    unsafe {
        rbtrack_panic_path_is_reachable()
    }
}
