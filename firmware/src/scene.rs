//! The example firmware's scene: a QVGA RGB565 (little-endian) frame of a two-coloured
//! target walking down and across a textured floor, growing as it comes nearer.
//!
//! Integer arithmetic only (32-bit hashes, no floats), so a Cortex-M and an x86 host
//! render the same bytes from the same seed.
//!
//! # The scene
//! - Floor: smooth colour blotches (bilinear between hashed colours on a 32 px grid,
//!   muted greens, browns and greys) with a fixed fine luma texture (±12 levels).
//! - Target: an ellipse, red ([`TOP`]) above its centre row and blue ([`BOTTOM`]) from
//!   it down, shaded darker towards its left and right edges. Its centre moves linearly
//!   from [`START`] to [`END`] (px) over frames `0..=FRAMES`; its half-height follows
//!   the ground plane, `hy = (cy - HORIZON_Y) * SCALE_PER_ROW`, from 13 to 41 px (3.2x),
//!   and its half-width is `hx = hy * 7 / 16`.
//! - Camera noise: ±6 levels per channel, hashed from the pixel, the frame and the seed.

use rbtrack::fixed::Q16;
use rbtrack::image::rgb888_to_rgb565;
use rbtrack::window::Ellipse;

/// Frame width, px.
pub const WIDTH: usize = 320;
/// Frame height, px.
pub const HEIGHT: usize = 240;
/// Bytes per frame (RGB565, 2 bytes per pixel, stride = width).
pub const FRAME_BYTES: usize = WIDTH * HEIGHT * 2;
/// Frames the trackers step through; frame 0 initialises them, frames `1..=FRAMES` are
/// tracked.
pub const FRAMES: usize = 60;
/// The scene's seed.
pub const SEED: u32 = 1;
/// Row of the horizon, px: the target's half-height is zero there.
pub const HORIZON_Y: i32 = 12;
/// Ground-plane slope: px of half-height per px the target moves down the image,
/// Q16.16 (0.25 exactly).
pub const SCALE_PER_ROW: Q16 = Q16::from_bits(1 << 14);
/// Centre at frame 0, px.
pub const START: (i32, i32) = (70, 64);
/// Centre at frame [`FRAMES`], px.
pub const END: (i32, i32) = (230, 176);
/// Upper half of the target, RGB888.
pub const TOP: [u8; 3] = [200, 45, 40];
/// Lower half of the target, RGB888.
pub const BOTTOM: [u8; 3] = [45, 65, 185];

/// Floor colour grid spacing, px (log2).
const GRID_LOG2: u32 = 5;
/// Fine texture amplitude, grey levels each side of zero.
const TEXTURE: i32 = 12;
/// Camera noise amplitude, grey levels each side of zero.
const NOISE: i32 = 6;

/// A 32-bit integer hash of three coordinates and a seed (a murmur3-style finaliser over
/// a multiplicative mix).
#[inline(always)]
fn hash(a: u32, b: u32, c: u32, seed: u32) -> u32 {
    let mut h = a.wrapping_mul(0x9E37_79B1)
        ^ b.wrapping_mul(0x85EB_CA77)
        ^ c.wrapping_mul(0xC2B2_AE3D)
        ^ seed.wrapping_mul(0x27D4_EB2F);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846C_A68B);
    h ^ (h >> 16)
}

/// A signed value in `-amp..=amp` from 8 bits of `h`.
#[inline(always)]
fn spread(h: u32, amp: i32) -> i32 {
    (((h & 0xFF) as i32 * (2 * amp + 1)) >> 8) - amp
}

/// The floor colour at grid node `(gx, gy)`: muted, each channel in 70..=165, biased
/// green-brown (no strong red or blue, which the target owns).
#[inline(always)]
fn node_colour(gx: u32, gy: u32, seed: u32) -> [i32; 3] {
    let h = hash(gx, gy, 0xF100_4000, seed);
    let base = 90 + (h & 0x3F) as i32; // 90..=153
    let r = base + spread(h >> 6, 12);
    let g = base + 8 + spread(h >> 14, 12);
    let b = base - 12 + spread(h >> 22, 10);
    [r, g, b]
}

/// The target's ellipse at `frame` (`0..=FRAMES`; later frames continue the line), px,
/// Q16.16.
pub fn truth(frame: usize) -> Ellipse {
    truth_scaled(frame, Q16::ONE)
}

/// [`truth`] with both half-axes times `scale` (Q16.16), the centre unchanged: the
/// scene's target made smaller or larger, for measuring cost against target size.
pub fn truth_scaled(frame: usize, scale: Q16) -> Ellipse {
    let t = frame as i64;
    let n = FRAMES as i64;
    let lerp = |a: i32, b: i32| {
        Q16::from_bits((((a as i64) << 16) + (((b - a) as i64 * t) << 16) / n) as i32)
    };
    let cx = lerp(START.0, END.0);
    let cy = lerp(START.1, END.1);
    let hy = (cy - Q16::from_int(HORIZON_Y)) * SCALE_PER_ROW * scale;
    let hx = Q16::from_bits(((hy.to_bits() as i64 * 7) >> 4) as i32);
    Ellipse { cx, cy, hx, hy }
}

/// Renders `frame` of the scene of `seed` into `buf` (`FRAME_BYTES` or more bytes; the
/// rest is left alone): RGB565 little-endian, stride [`WIDTH`].
///
/// # Panics
/// If `buf` is shorter than [`FRAME_BYTES`].
pub fn render(seed: u32, frame: usize, buf: &mut [u8]) {
    render_scaled(seed, frame, Q16::ONE, buf);
}

/// [`render`] with the target of [`truth_scaled`]`(frame, scale)`.
///
/// # Panics
/// If `buf` is shorter than [`FRAME_BYTES`].
pub fn render_scaled(seed: u32, frame: usize, scale: Q16, buf: &mut [u8]) {
    let e = truth_scaled(frame, scale);
    let (cx, cy) = (e.cx.to_bits() as i64, e.cy.to_bits() as i64);
    let (hx, hy) = (e.hx.to_bits() as i64, e.hy.to_bits() as i64);
    // Inside when (dx hy)^2 + (dy hx)^2 <= (hx hy)^2, all in Q16 px; dx, dy, hx, hy < 2^25,
    // so each product is below 2^50 and each square below 2^100: compare in u128.
    let limit = (hx * hy) as u128 * (hx * hy) as u128;
    let grid = 1u32 << GRID_LOG2;
    let (frame_u, pixels) = (frame as u32, &mut buf[..FRAME_BYTES]);
    for (y, row) in pixels.chunks_exact_mut(WIDTH * 2).enumerate() {
        let (yu, gy, fy) = (
            y as u32,
            y as u32 >> GRID_LOG2,
            y as i32 & (grid as i32 - 1),
        );
        let dy = ((y as i64) << 16) - cy;
        let dy_hx = (dy * hx).unsigned_abs() as u128;
        for (x, px) in row.chunks_exact_mut(2).enumerate() {
            let xu = x as u32;
            let dx = ((x as i64) << 16) - cx;
            let inside = (dx * hy).unsigned_abs() as u128 * (dx * hy).unsigned_abs() as u128
                + dy_hx * dy_hx
                <= limit;
            let mut rgb = if inside {
                let base = if dy < 0 { TOP } else { BOTTOM };
                // Shade 1 - 0.4 (dx / hx)^2, in 1/256.
                let t = ((dx << 8) / hx.max(1)) as i32; // -256..=256
                let shade = 256 - ((t * t) >> 8) * 2 / 5;
                base.map(|c| (c as i32 * shade) >> 8)
            } else {
                let (gx, fx) = (xu >> GRID_LOG2, x as i32 & (grid as i32 - 1));
                let c00 = node_colour(gx, gy, seed);
                let c10 = node_colour(gx + 1, gy, seed);
                let c01 = node_colour(gx, gy + 1, seed);
                let c11 = node_colour(gx + 1, gy + 1, seed);
                let texture = spread(hash(xu, yu, 0x7E27_0000, seed), TEXTURE);
                let g = grid as i32;
                core::array::from_fn(|k| {
                    let top = c00[k] * (g - fx) + c10[k] * fx;
                    let bottom = c01[k] * (g - fx) + c11[k] * fx;
                    ((top * (g - fy) + bottom * fy) >> (2 * GRID_LOG2)) + texture
                })
            };
            let noise = hash(xu, yu, frame_u, seed);
            for (k, c) in rgb.iter_mut().enumerate() {
                *c = (*c + spread(noise >> (8 * k), NOISE)).clamp(0, 255);
            }
            let [r, g, b] = rgb.map(|c| c as u8);
            px.copy_from_slice(&rgb888_to_rgb565(r, g, b).to_le_bytes());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truth_follows_the_ground_plane() {
        let first = truth(0);
        let last = truth(FRAMES);
        assert_eq!((first.cx, first.cy), (Q16::from_int(70), Q16::from_int(64)));
        assert_eq!((last.cx, last.cy), (Q16::from_int(230), Q16::from_int(176)));
        assert_eq!(first.hy, Q16::from_int(13));
        assert_eq!(last.hy, Q16::from_int(41));
        assert!(last.hx > Q16::from_int(17) && last.hx < Q16::from_int(18));
    }

    #[test]
    fn target_pixels_have_the_target_colours() {
        let mut buf = [0u8; FRAME_BYTES];
        render(SEED, 30, &mut buf);
        let e = truth(30);
        let at = |x: i32, y: i32| {
            let i = (y as usize * WIDTH + x as usize) * 2;
            let v = u16::from_le_bytes([buf[i], buf[i + 1]]);
            ((v >> 11) << 3, ((v >> 5) & 0x3F) << 2, (v & 0x1F) << 3)
        };
        let (cx, cy, hy) = (e.cx.round_int(), e.cy.round_int(), e.hy.round_int());
        let (r, _, b) = at(cx, cy - hy / 2);
        assert!(r > 160 && b < 80, "top {r} {b}");
        let (r, _, b) = at(cx, cy + hy / 2);
        assert!(b > 150 && r < 80, "bottom {r} {b}");
        let (r, g, b) = at(5, 230);
        assert!((60..=190).contains(&r) && (60..=190).contains(&g) && (50..=190).contains(&b));
    }

    #[test]
    fn frames_differ_by_noise_and_motion_only() {
        let mut a = [0u8; FRAME_BYTES];
        let mut b = [0u8; FRAME_BYTES];
        render(SEED, 3, &mut a);
        render(SEED, 3, &mut b);
        assert_eq!(a, b);
        render(SEED + 1, 3, &mut b);
        assert_ne!(a, b);
    }
}
