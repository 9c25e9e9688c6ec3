//! The OV7725 image sensor over SCCB (I2C): power-up, reset and a QVGA (320 x 240) RGB565
//! register table.
//!
//! SCCB is I2C without repeated start: a register write is `[register, value]`; a read is
//! a write of `[register]` followed by a separate one-byte read. The sensor's 7-bit address
//! is 0x21 (0x42 to write). In RGB565 it sends each pixel's high byte (`RRRRRGGG`) first,
//! which is [`rbtrack::image::Rgb565Be`] in the DCMI's buffer.

use defmt::Format;
use embassy_stm32::gpio::Output;
use embassy_stm32::i2c::{self, I2c, Master};
use embassy_stm32::mode::Blocking;
use embassy_time::Timer;

/// 7-bit SCCB address.
const ADDRESS: u8 = 0x21;
/// Product ID register (`PID`) and the OV7725's value in it.
const PID: u8 = 0x0A;
const PID_OV7725: u8 = 0x77;
/// Version register (`VER`).
const VER: u8 = 0x0B;
/// Common control 7: bit 7 resets every register, bit 6 selects QVGA, bits 3..2 the RGB
/// layout (01: RGB565), bits 1..0 the output (10: RGB).
const COM7: u8 = 0x12;
const COM7_RESET: u8 = 0x80;

/// Register writes after the reset, in order: the OV7725 implementation guide's settings
/// as the OpenMV firmware's `ov7725.c` applies them for QVGA RGB565 on this board (12 MHz
/// XCLK), with the VGA window it writes first and then replaces left out.
const QVGA_RGB565: &[(u8, u8)] = &[
    (0x3D, 0x03), // COM12: DC offset compensation
    // Clock: CLKRC uses XCLK undivided, COM4 PLL x4 and AEC over the full window.
    (0x11, 0xC0),
    (0x0D, 0x41),
    // Black level, analogue gain, AWB, DSP: scaling down (DCW and zoom) on, DSPAUTO on.
    (0x42, 0x7F), // TGT_B
    (0x4D, 0x09), // FIXGAIN
    (0x63, 0xE0), // AWB_CTRL0
    (0x64, 0xFF), // DSP_CTRL1
    (0x65, 0x2F), // DSP_CTRL2
    (0x66, 0x00), // DSP_CTRL3
    // Exposure and gain: COM6, COM9 (gain ceiling), banding filter, AEC/AGC windows,
    // dummy pixels and rows, AWB_CTRL3; COM8 enables fast AGC/AEC, banding, AGC, AWB,
    // AEC.
    (0x0F, 0xC5),
    (0x14, 0x11),
    (0x22, 0x7F),
    (0x23, 0x03),
    (0x24, 0x40),
    (0x25, 0x30),
    (0x26, 0xA1),
    (0x2B, 0x00),
    (0x33, 0x00),
    (0x6B, 0xAA),
    (0x13, 0xFF),
    // Sharpness and de-noise: EDGE1, DNSOFF, EDGE2, EDGE3.
    (0x90, 0x05),
    (0x91, 0x01),
    (0x92, 0x03),
    (0x93, 0x00),
    // Colour matrix MTX1..MTX6 and its signs (MTX_CTRL); brightness, contrast, auto UV
    // adjust; SDE: contrast, brightness and saturation on.
    (0x94, 0xB0),
    (0x95, 0x9D),
    (0x96, 0x13),
    (0x97, 0x16),
    (0x98, 0x7B),
    (0x99, 0x91),
    (0x9A, 0x1E),
    (0x9B, 0x08),
    (0x9C, 0x20),
    (0x9E, 0x81),
    (0xA6, 0x06),
    // Gamma curve GAM1..GAM15 and the slope above it (SLOP).
    (0x7E, 0x0C),
    (0x7F, 0x16),
    (0x80, 0x2A),
    (0x81, 0x4E),
    (0x82, 0x61),
    (0x83, 0x6F),
    (0x84, 0x7B),
    (0x85, 0x86),
    (0x86, 0x8E),
    (0x87, 0x97),
    (0x88, 0xA4),
    (0x89, 0xAF),
    (0x8A, 0xC5),
    (0x8B, 0xD7),
    (0x8C, 0xE8),
    (0x8D, 0x20),
    // Lens correction: LC_RADI, LC_COEF, LC_COEFB, LC_COEFR, LC_CTR.
    (0x4A, 0x10),
    (0x49, 0x10),
    (0x4B, 0x14),
    (0x4C, 0x17),
    (0x46, 0x01),
    // COM5: auto frame rate.
    (0x0E, 0xF5),
    // Output: DSP_CTRL4 YUV/RGB (not raw); output size HOUTSIZE 320 / 4, VOUTSIZE
    // 240 / 2, their low bits (EXHCH) 0, HREF 0; then COM7 QVGA, RGB565, RGB, and after it
    // (COM6 re-windows on a format change) the QVGA sensor window HSTART, HSIZE, VSTART,
    // VSIZE and DSPAUTO (automatic scaling factors).
    (0x67, 0x00),
    (0x29, 0x50),
    (0x2C, 0x78),
    (0x2A, 0x00),
    (0x32, 0x00),
    (COM7, 0x46),
    (0x17, 0x3F),
    (0x18, 0x50),
    (0x19, 0x03),
    (0x1A, 0x78),
    (0xAC, 0xFF),
];

/// Why the sensor could not be brought up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Format)]
pub enum Error {
    /// An SCCB transfer failed (no acknowledge: no sensor, or it is held in reset).
    Sccb(i2c::Error),
    /// A sensor answered with another product ID (`PID`).
    NotOv7725(u8),
}

impl From<i2c::Error> for Error {
    fn from(e: i2c::Error) -> Self {
        Self::Sccb(e)
    }
}

/// The sensor on its SCCB bus, with its power-down (`PWDN`, high powers down) and reset
/// pins.
pub struct Ov7725<'d> {
    sccb: I2c<'d, Blocking, Master>,
    power_down: Output<'d>,
    reset: Output<'d>,
}

impl<'d> Ov7725<'d> {
    /// Takes the bus and the two pins; nothing is sent yet.
    pub fn new(sccb: I2c<'d, Blocking, Master>, power_down: Output<'d>, reset: Output<'d>) -> Self {
        Self {
            sccb,
            power_down,
            reset,
        }
    }

    /// Powers the sensor up, resets it, checks its product ID and writes the QVGA RGB565
    /// table. XCLK must already run. Returns the product and version IDs (`PID`, `VER`).
    ///
    /// The reset pin's polarity is tried both ways, active low first (the OV7725's `RSTB`;
    /// the OpenMV firmware also probes both on this board), 10 ms per phase.
    pub async fn init_qvga_rgb565(&mut self) -> Result<(u8, u8), Error> {
        let mut found = Err(Error::NotOv7725(0));
        for reset_active_low in [true, false] {
            self.power_down.set_high();
            Timer::after_millis(10).await;
            self.power_down.set_low();
            Timer::after_millis(10).await;
            self.reset.set_level((!reset_active_low).into());
            Timer::after_millis(10).await;
            self.reset.set_level(reset_active_low.into());
            Timer::after_millis(10).await;
            found = self.read(PID);
            if found.is_ok() {
                break;
            }
        }
        let pid = found?;
        if pid != PID_OV7725 {
            return Err(Error::NotOv7725(pid));
        }
        let version = self.read(VER)?;
        self.write(COM7, COM7_RESET)?;
        Timer::after_millis(2).await;
        for &(register, value) in QVGA_RGB565 {
            self.write(register, value)?;
        }
        // Let exposure and white balance settle before the first frame is used.
        Timer::after_millis(300).await;
        Ok((pid, version))
    }

    fn write(&mut self, register: u8, value: u8) -> Result<(), Error> {
        Ok(self.sccb.blocking_write(ADDRESS, &[register, value])?)
    }

    fn read(&mut self, register: u8) -> Result<u8, Error> {
        let mut value = [0u8];
        self.sccb.blocking_write(ADDRESS, &[register])?;
        self.sccb.blocking_read(ADDRESS, &mut value)?;
        Ok(value[0])
    }
}
