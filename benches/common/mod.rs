//! Frames and warmed-up trackers shared by the Criterion and iai-callgrind benches.
//!
//! Two deterministic synthetic frames of the example firmware's scene
//! (`rbtrack_firmware::scene`: a red-and-blue walker on a textured floor, camera noise):
//! - QVGA RGB565 little-endian, as the firmware renders it;
//! - 1280x720 RGB888, the same picture scaled 4x across and 3x down (nearest pixel), so
//!   the target covers 12 times as many pixels in a 12 times larger frame.
//!
//! A step's work is bounded by the particle count and the per-window pixel cap, so both
//! frames should cost about the same per step; the benches show it.
#![allow(dead_code)] // each bench binary uses a part

use rbtrack::fixed::Q16;
use rbtrack::image::{ImageView, PixelFormat, Rgb565Le, Rgb888, Rgb8x8x8};
use rbtrack::tracker::{Config, Tracker, Variant};
use rbtrack::window::Ellipse;
use rbtrack_firmware::scene;

/// Histogram bins of every bench tracker (8x8x8 RGB).
pub const BINS: usize = 512;

/// The frame of the scene a bench steps on (the walker mid-way).
pub const FRAME: usize = 30;

/// Frames stepped before the measured step, so that the particle cloud has spread.
pub const WARM_UP: usize = 5;

/// The 720p frame: 4x the QVGA width, 3x its height.
pub const HD: (usize, usize) = (1280, 720);

/// Scene frame `k`, QVGA RGB565 LE.
pub fn qvga(k: usize) -> Vec<u8> {
    let mut buf = vec![0u8; scene::FRAME_BYTES];
    scene::render(scene::SEED, k, &mut buf);
    buf
}

/// Scene frame `k`, 1280x720 RGB888 (nearest-pixel scaling of the QVGA frame).
pub fn hd(k: usize) -> Vec<u8> {
    let small = qvga(k);
    let (w, h) = HD;
    let mut out = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        let sy = y / 3;
        for x in 0..w {
            let sx = x / 4;
            let i = 2 * (sy * scene::WIDTH + sx);
            let (r, g, b) =
                rbtrack::image::rgb565_to_rgb888(u16::from_le_bytes([small[i], small[i + 1]]));
            out.extend_from_slice(&[r, g, b]);
        }
    }
    out
}

/// The true ellipse of frame `k` in QVGA coordinates.
pub fn truth_qvga(k: usize) -> Ellipse {
    scene::truth(k)
}

/// The true ellipse of frame `k` in 720p coordinates.
pub fn truth_hd(k: usize) -> Ellipse {
    let e = scene::truth(k);
    let (sx, sy) = (Q16::from_int(4), Q16::from_int(3));
    Ellipse {
        cx: e.cx * sx + Q16::from_f64(1.5),
        cy: e.cy * sy + Q16::ONE,
        hx: e.hx * sx,
        hy: e.hy * sy,
    }
}

/// The bench configuration of `variant`: the firmware's (defaults, seed 1 and, for the
/// RBPF, the scene's ground-plane slope; the 720p frame stretches half-heights and rows
/// alike, 3x, so the slope holds there too).
pub fn config(variant: Variant) -> Config {
    rbtrack_firmware::run::config(variant)
}

/// A frame format and size with its frames.
pub struct Scene<P: PixelFormat> {
    /// Frames `FRAME - WARM_UP ..= FRAME + 1`, bytes.
    pub frames: Vec<Vec<u8>>,
    /// Width, height, px.
    pub size: (usize, usize),
    /// The true ellipse at `FRAME - WARM_UP`.
    pub start: Ellipse,
    _format: core::marker::PhantomData<P>,
}

impl<P: PixelFormat> Scene<P> {
    /// Frame `i` of [`Scene::frames`] as a view.
    pub fn view(&self, i: usize) -> ImageView<'_, P> {
        let (w, h) = self.size;
        ImageView::new(&self.frames[i], w, h, w).expect("bench frames are well-formed")
    }

    /// The frame the measured step runs on.
    pub fn measured(&self) -> ImageView<'_, P> {
        self.view(WARM_UP + 1)
    }

    /// A tracker started on the first frame and stepped over the warm-up frames.
    pub fn tracker<const N: usize>(&self, variant: Variant) -> Tracker<Rgb8x8x8, N, BINS> {
        let mut t = Tracker::new(config(variant), &self.view(0), self.start)
            .expect("bench configuration is valid");
        for i in 1..=WARM_UP {
            t.step(&self.view(i));
        }
        t
    }
}

/// The QVGA RGB565 scene around [`FRAME`].
pub fn qvga_scene() -> Scene<Rgb565Le> {
    Scene {
        frames: (FRAME - WARM_UP..=FRAME + 1).map(qvga).collect(),
        size: (scene::WIDTH, scene::HEIGHT),
        start: truth_qvga(FRAME - WARM_UP),
        _format: core::marker::PhantomData,
    }
}

/// The 720p RGB888 scene around [`FRAME`].
pub fn hd_scene() -> Scene<Rgb888> {
    Scene {
        frames: (FRAME - WARM_UP..=FRAME + 1).map(hd).collect(),
        size: HD,
        start: truth_hd(FRAME - WARM_UP),
        _format: core::marker::PhantomData,
    }
}
