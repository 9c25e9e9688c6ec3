//! rbtrack on the OpenMV Cam H7: the OV7725's QVGA RGB565 frames, captured by the DCMI with
//! DMA into two static buffers, tracked in place by the correlation-filter tracker; the
//! estimate and the cycles of each stage go out over defmt (RTT) for every frame.
//!
//! - **Clocks**: 12 MHz crystal (HSE), PLL1 to 400 MHz core, 200 MHz AXI/AHB, 100 MHz APB.
//!   The sensor's XCLK is the HSE itself on MCO1 (PA8), 12 MHz.
//! - **Sensor** ([`ov7725`]): SCCB on I2C1 (PB8 SCL, PB9 SDA) at 100 kHz, power-down on
//!   PD7, reset on PA10; QVGA RGB565, high byte first.
//! - **Capture**: DCMI, 8 bits (D0..D7 on PC6 PC7 PE0 PE1 PE4 PB6 PE5 PE6, HSYNC PA4, VSYNC
//!   PB7, PIXCLK PA6), DMA2 stream 1, into two 32-byte aligned frame buffers in AXI SRAM.
//!   embassy's driver captures one frame per call (snapshot mode), so the next frame's
//!   capture is started just before the tracker steps on the last one and runs beside it:
//!   frame k + 1 is captured while the tracker reads frame k.
//! - **Cache**: the I- and D-caches are on; after each capture the buffer's lines are
//!   invalidated, so the core reads what the DMA wrote.
//! - **Tracker**: the correlation-filter tracker at its defaults ([`RgbCfTracker`]: 16 x 16
//!   cells, 4 scales, 512 RGB bins), on an [`ImageView`] over the DMA buffer (no copy),
//!   started on a fixed 48 x 64 px box in the centre of the first frame. A product would
//!   take the box from a detector or a host command. For a particle filter instead (fewer
//!   cycles, less accurate), make [`Tracker`] an `rbtrack::RgbTracker<100>`, start it with
//!   `Config::new(Variant::Rbpf)` and log its `StageCycles`.
//! - **Output**: per frame, the estimate (centre, half-axes, velocity, confidence, status)
//!   and the DWT cycle counts of features, filter, colour, scale and learn; and the
//!   pan/tilt head's commands ([`rbtrack::pantilt`]) as servo pulses on P7 (pan, PD12,
//!   TIM4 channel 1) and P8 (tilt, PD13, TIM4 channel 2), 50 Hz, 1,500 us at 0 degrees and
//!   100/9 us per degree (a hobby servo's 500-2,500 us for 180 degrees); the head holds
//!   still while the status is `Lost`. [`FOV_X`] and [`FOV_Y`] must be the lens's
//!   field of view: the values here are placeholders to measure.

#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod ov7725;

use cortex_m::peripheral::{DWT, SCB};
use defmt::{error, info, warn};
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_futures::join::join;
use embassy_stm32::dcmi::{self, Dcmi};
use embassy_stm32::gpio::{Level, Output, OutputType, Speed};
use embassy_stm32::i2c::{self, I2c};
use embassy_stm32::peripherals::DCMI;
use embassy_stm32::rcc::{Mco, Mco1Source, McoConfig, McoPrescaler};
use embassy_stm32::time::Hertz;
use embassy_stm32::timer::low_level::CountingMode;
use embassy_stm32::timer::simple_pwm::{PwmPin, SimplePwm, SimplePwmChannel};
use embassy_stm32::{bind_interrupts, dma, peripherals};
use panic_probe as _;
use rbtrack::fixed::Q16;
use rbtrack::image::{ImageError, ImageView, Rgb565Be};
use rbtrack::pantilt::{PanTilt, PanTiltConfig};
use rbtrack::profile::{CfStageCycles, CycleCounter};
use rbtrack::rect::Rect;
use rbtrack::tracker::{CfConfig, ConfigError, Estimate, RgbCfTracker};
use static_cell::ConstStaticCell;

/// Frame width and height, px (QVGA).
const WIDTH: usize = 320;
const HEIGHT: usize = 240;
/// 32-bit words of one RGB565 frame: two pixels per word.
const FRAME_WORDS: usize = WIDTH * HEIGHT / 2;
/// The lens's field of view, degrees: placeholders, to be measured for the lens fitted.
const FOV_X: Q16 = Q16::from_int(70);
const FOV_Y: Q16 = Q16::from_int(53);
/// Servo pulse period (50 Hz) and the pulse at 0 degrees, us.
const SERVO_PERIOD_US: u32 = 20_000;
const SERVO_CENTRE_US: i32 = 1_500;

/// The tracker, on RGB 8x8x8 bins over the sensor's big-endian RGB565.
type Tracker = RgbCfTracker;
type Pixel = Rgb565Be;

/// One frame as the DMA writes it: 153,600 bytes, a whole number of the Cortex-M7's 32-byte
/// cache lines and aligned to them, so invalidating it touches nothing else.
#[repr(C, align(32))]
struct Frame([u32; FRAME_WORDS]);

/// The two capture buffers, in `.bss` (AXI SRAM, which DMA2 reaches; see `memory.x`).
static FRAME_A: ConstStaticCell<Frame> = ConstStaticCell::new(Frame([0; FRAME_WORDS]));
static FRAME_B: ConstStaticCell<Frame> = ConstStaticCell::new(Frame([0; FRAME_WORDS]));
static TRACKER: ConstStaticCell<Tracker> = ConstStaticCell::new(Tracker::unstarted());

bind_interrupts!(struct Irqs {
    DCMI => dcmi::InterruptHandler<peripherals::DCMI>;
    DMA2_STREAM1 => dma::InterruptHandler<peripherals::DMA2_CH1>;
});

/// The DWT cycle counter `CYCCNT`: core clock cycles (400 MHz).
struct Cycles;

impl Cycles {
    /// Enables the trace unit and the counter (the Cortex-M7 locks the DWT until unlocked).
    fn start(dcb: &mut cortex_m::peripheral::DCB, dwt: &mut DWT) -> Self {
        dcb.enable_trace();
        DWT::unlock();
        dwt.enable_cycle_counter();
        Self
    }
}

impl CycleCounter for Cycles {
    fn now(&mut self) -> u32 {
        DWT::cycle_count()
    }
}

/// HSE 12 MHz -> PLL1 (/3, x200, /2) 400 MHz core; AXI/AHB 200 MHz; APB1..4 100 MHz.
fn clocks() -> embassy_stm32::Config {
    use embassy_stm32::rcc::*;
    use embassy_stm32::time::Hertz;
    let mut config = embassy_stm32::Config::default();
    config.rcc.hse = Some(Hse {
        freq: Hertz::mhz(12),
        mode: HseMode::Oscillator,
    });
    config.rcc.pll1 = Some(Pll {
        source: PllSource::HSE,
        prediv: PllPreDiv::DIV3,
        mul: PllMul::MUL200,
        fracn: None,
        divp: Some(PllDiv::DIV2),
        divq: None,
        divr: None,
    });
    config.rcc.sys = Sysclk::PLL1_P;
    config.rcc.ahb_pre = AHBPrescaler::DIV2;
    config.rcc.apb1_pre = APBPrescaler::DIV2;
    config.rcc.apb2_pre = APBPrescaler::DIV2;
    config.rcc.apb3_pre = APBPrescaler::DIV2;
    config.rcc.apb4_pre = APBPrescaler::DIV2;
    config.rcc.voltage_scale = VoltageScale::Scale1;
    config
}

/// The frame in `words`, borrowed: no copy.
fn view(words: &[u32]) -> Result<ImageView<'_, Pixel>, ImageError> {
    ImageView::from_words(words, WIDTH, HEIGHT, WIDTH)
}

/// Starts `tracker` in place (a static: the tracker never lives on the stack) with the
/// defaults on a 48 x 64 px box in the centre of `frame`.
fn start_tracker(tracker: &mut Tracker, frame: &ImageView<'_, Pixel>) -> Result<(), ConfigError> {
    let (w, h) = (48, 64);
    let centre = Rect::new((WIDTH as i32 - w) / 2, (HEIGHT as i32 - h) / 2, w, h);
    tracker.start(CfConfig::default(), frame, centre)
}

/// Repeats a failed capture into `frame` until one succeeds, then invalidates the
/// D-cache lines of `frame` so that the core reads what the DMA wrote.
async fn finish_capture(
    dcmi: &mut Dcmi<'_, DCMI>,
    scb: &mut SCB,
    frame: &mut [u32; FRAME_WORDS],
    mut captured: Result<(), dcmi::Error>,
) {
    while let Err(e) = captured {
        warn!("capture failed ({}), capturing again", e);
        captured = dcmi.capture(frame).await;
    }
    // SAFETY: `frame` is 32-byte aligned and a whole number of 32-byte lines long, so the
    // invalidation discards no other data; the core never writes it (cortex-m-rt zeroed
    // `.bss` before the D-cache was on), so no dirty line of it is lost; the DMA transfer
    // into it has completed.
    #[allow(unsafe_code)]
    unsafe {
        scb.invalidate_dcache_by_slice(frame)
    };
}

/// A Q16.16 value as `f32`, for the log.
fn f32_of(q: Q16) -> f32 {
    q.to_bits() as f32 / 65536.0
}

/// Logs frame `frame`'s estimate and the core cycles of each stage of its step.
fn report(frame: u32, e: &Estimate, c: &CfStageCycles) {
    let el = e.ellipse;
    info!(
        "frame {=u32}: {} conf {=f32} cx {=f32} cy {=f32} hx {=f32} hy {=f32} vx {=f32} vy {=f32} | cycles {} total {=u32}",
        frame,
        e.status,
        f32_of(e.confidence),
        f32_of(el.cx),
        f32_of(el.cy),
        f32_of(el.hx),
        f32_of(el.hy),
        f32_of(e.vx),
        f32_of(e.vy),
        c,
        c.total()
    );
}

/// Sets `servo` to the pulse of `degrees` (Q16.16): 1,500 us at 0, 100/9 us per degree.
fn set_angle(servo: &mut SimplePwmChannel<'_, peripherals::TIM4>, degrees: Q16) {
    let offset_us = (degrees.to_bits() as i64 * 100 / 9) >> Q16::FRAC_BITS;
    let pulse_us = (SERVO_CENTRE_US as i64 + offset_us).clamp(500, 2_500) as u32;
    servo.set_duty_cycle_fraction(pulse_us, SERVO_PERIOD_US);
}

/// Stops the core after an error was logged (the probe keeps the log).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

#[embassy_executor::main]
async fn main(_spawner: Spawner) {
    let p = embassy_stm32::init(clocks());
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        error!("core peripherals already taken");
        halt()
    };
    cp.SCB.enable_icache();
    cp.SCB.enable_dcache(&mut cp.CPUID);
    let mut cycles = Cycles::start(&mut cp.DCB, &mut cp.DWT);
    info!(
        "rbtrack on the OpenMV Cam H7: {=usize}x{=usize} RGB565, correlation-filter tracker, tracker {=usize} B",
        WIDTH,
        HEIGHT,
        core::mem::size_of::<Tracker>()
    );

    let mut xclk_config = McoConfig::default();
    xclk_config.prescaler = McoPrescaler::DIV1;
    let _xclk = Mco::new(p.MCO1, p.PA8, Mco1Source::HSE, xclk_config);
    let sccb = I2c::new_blocking(p.I2C1, p.PB8, p.PB9, i2c::Config::default());
    let mut sensor = ov7725::Ov7725::new(
        sccb,
        Output::new(p.PD7, Level::High, Speed::Low),
        Output::new(p.PA10, Level::Low, Speed::Low),
    );
    match sensor.init_qvga_rgb565().await {
        Ok((pid, version)) => info!(
            "OV7725 (PID {=u8:#x}, VER {=u8:#x}) in QVGA RGB565",
            pid, version
        ),
        Err(e) => {
            error!("camera: {}", e);
            halt()
        }
    }

    let mut dcmi = Dcmi::new_8bit(
        p.DCMI,
        p.DMA2_CH1,
        Irqs,
        p.PC6,
        p.PC7,
        p.PE0,
        p.PE1,
        p.PE4,
        p.PB6,
        p.PE5,
        p.PE6,
        p.PB7,
        p.PA4,
        p.PA6,
        // VSYNC high and HSYNC low while data is invalid, sampled on PIXCLK's rising edge.
        dcmi::Config::default(),
    );
    let (Some(a), Some(b)) = (FRAME_A.try_take(), FRAME_B.try_take()) else {
        error!("frame buffers already taken");
        halt()
    };
    // `ready` holds the last complete frame, `next` receives the one after it.
    let (mut ready, mut next) = (&mut a.0, &mut b.0);

    let captured = dcmi.capture(ready).await;
    finish_capture(&mut dcmi, &mut cp.SCB, ready, captured).await;
    let Some(tracker) = TRACKER.try_take() else {
        error!("tracker already taken");
        halt()
    };
    match view(ready).map(|frame| start_tracker(tracker, &frame)) {
        Ok(Ok(())) => {}
        Ok(Err(e)) => {
            error!("tracker: {}", e);
            halt()
        }
        Err(e) => {
            error!("frame: {}", e);
            halt()
        }
    }

    let head = PanTiltConfig::new(WIDTH as u32, HEIGHT as u32, FOV_X, FOV_Y);
    let Ok(mut head) = PanTilt::new(head) else {
        error!("pan/tilt settings refused");
        halt()
    };
    let servos = SimplePwm::new(
        p.TIM4,
        Some(PwmPin::new(p.PD12, OutputType::PushPull)),
        Some(PwmPin::new(p.PD13, OutputType::PushPull)),
        None,
        None,
        Hertz(1_000_000 / SERVO_PERIOD_US),
        CountingMode::EdgeAlignedUp,
    );
    let mut servos = servos.split();
    for servo in [&mut servos.ch1, &mut servos.ch2] {
        set_angle(servo, Q16::ZERO);
        servo.enable();
    }

    let mut frame = 0u32;
    loop {
        frame = frame.wrapping_add(1);
        // `join` polls the capture first, which starts the DMA into `next`, then runs the
        // step on `ready` while the DCMI fills `next`.
        let (captured, stepped) = join(dcmi.capture(next), async {
            view(ready).map(|view| tracker.step_profiled(&view, &mut cycles))
        })
        .await;
        match stepped {
            Ok((estimate, stages)) => {
                report(frame, &estimate, &stages);
                let command = head.step(&estimate);
                set_angle(&mut servos.ch1, command.pan);
                set_angle(&mut servos.ch2, command.tilt);
            }
            Err(e) => warn!("frame {=u32}: {}", frame, e),
        }
        finish_capture(&mut dcmi, &mut cp.SCB, next, captured).await;
        core::mem::swap(&mut ready, &mut next);
    }
}
