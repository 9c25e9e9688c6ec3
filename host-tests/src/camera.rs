//! A virtual camera over recorded video: each frame of a sequence is the scene, and the
//! camera sees a smaller window of it whose place changes from frame to frame, as a
//! camera on a pan/tilt head would. Its ground truth moves with the window, and the
//! picture's shift between two frames is the [`CameraMotion`] a tracker can be told.
//!
//! The window is 3/4 of the scene's width and height, first centred on the target (as far
//! as the scene allows). [`Camera::Still`] keeps it there, [`Camera::Pan`] sweeps it back
//! and forth (a triangle wave, horizontally at a fifth of the margin per frame, vertically
//! at half that), so the same sequence can be tracked with and without the camera moving.

use crate::metrics::BBox;
use crate::pixels::Frame;
use rbtrack::fixed::Q16;
use rbtrack::tracker::CameraMotion;

/// A window of the scene: top-left corner and size, px (0-based, inside the scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    /// Left edge in the scene, px.
    pub x: u32,
    /// Top edge in the scene, px.
    pub y: u32,
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
}

impl Window {
    /// The window's view of an RGB888 scene frame, RGB888; `None` if the frame is not
    /// RGB888 or the window does not fit in it.
    pub fn crop(&self, scene: &Frame) -> Option<Frame> {
        let fits = self.x + self.width <= scene.width && self.y + self.height <= scene.height;
        if scene.format != crate::pixels::Format::Rgb888 || !fits {
            return None;
        }
        let row = scene.width as usize * 3;
        let (left, len) = (self.x as usize * 3, self.width as usize * 3);
        let mut bytes = Vec::with_capacity(len * self.height as usize);
        for y in self.y as usize..(self.y + self.height) as usize {
            bytes.extend_from_slice(&scene.bytes[y * row + left..][..len]);
        }
        Frame::rgb888(self.width, self.height, bytes).ok()
    }

    /// A box of the scene as the window sees it, px.
    pub fn to_view(&self, b: &BBox) -> BBox {
        BBox {
            x: b.x - self.x as f64,
            y: b.y - self.y as f64,
            ..*b
        }
    }

    /// How the picture moved from this window's view to `next`'s: the scene moves
    /// opposite to the window.
    pub fn motion_to(&self, next: &Window) -> CameraMotion {
        let shift = |from: u32, to: u32| Q16::from_int(from as i32 - to as i32);
        CameraMotion::shift(shift(self.x, next.x), shift(self.y, next.y))
    }
}

/// How the virtual camera moves over a sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Camera {
    /// The window stays where it starts.
    Still,
    /// The window pans and tilts; the tracker is not told.
    Pan,
    /// The window pans and tilts; the tracker is told each frame's shift.
    PanKnown,
}

impl Camera {
    /// Share of each scene side the window leaves out, on each side: 1/8 (the window is
    /// 3/4 of the scene's width and height).
    pub const MARGIN_DIVISOR: u32 = 8;
}

/// A [`Camera`] over one sequence: pointed at the target in the first frame (the window
/// centred on its box as far as the scene allows), then still, or sweeping from there
/// while keeping the target's centre at least 1/8 of the window inside its edges (as far
/// as the scene allows): a pan that never loses the target from view, so that what it
/// changes is the motion, not what is seen.
#[derive(Clone, Debug, PartialEq)]
pub struct VirtualCamera {
    camera: Camera,
    /// The scene's size, px.
    scene: (u32, u32),
    /// The first window's top-left corner, px.
    start: (u32, u32),
    /// The target's centre in each frame (`None` without a valid box), scene px.
    centres: Vec<Option<(f64, f64)>>,
}

impl VirtualCamera {
    /// `camera` over a scene of `width x height` px whose target's box in each frame is
    /// `truth` (0-based, scene px; the first places the first window).
    pub fn new(camera: Camera, width: u32, height: u32, truth: &[BBox]) -> Self {
        let (mx, my) = margins(width, height);
        let (cx, cy) = truth.first().map_or(
            ((width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0),
            BBox::centre,
        );
        let aim = |centre: f64, side: u32, margin: u32| {
            let left = centre - (side - 2 * margin) as f64 / 2.0;
            left.round().clamp(0.0, (2 * margin) as f64) as u32
        };
        Self {
            camera,
            scene: (width, height),
            start: (aim(cx, width, mx), aim(cy, height, my)),
            centres: truth
                .iter()
                .map(|b| b.is_valid().then(|| b.centre()))
                .collect(),
        }
    }

    /// The window of frame `index`.
    pub fn window(&self, index: usize) -> Window {
        let (width, height) = self.scene;
        let (mx, my) = margins(width, height);
        let (vw, vh) = (width - 2 * mx, height - 2 * my);
        let (x, y) = match self.camera {
            Camera::Still => self.start,
            Camera::Pan | Camera::PanKnown => {
                let x = sweep(index, self.start.0, mx, (mx / 5).max(1));
                let y = sweep(index, self.start.1, my, (my / 10).max(1));
                match self.centres.get(index).copied().flatten() {
                    Some((cx, cy)) => (keep(x, cx, vw, 2 * mx), keep(y, cy, vh, 2 * my)),
                    None => (x, y),
                }
            }
        };
        Window {
            x,
            y,
            width: vw,
            height: vh,
        }
    }

    /// The motion the tracker is told before frame `index`: the picture's shift since
    /// the frame before for [`Camera::PanKnown`], none otherwise (and before frame 0).
    pub fn told(&self, index: usize) -> CameraMotion {
        match (self.camera, index) {
            (Camera::PanKnown, 1..) => self.window(index - 1).motion_to(&self.window(index)),
            _ => CameraMotion::STILL,
        }
    }
}

/// The window edge `left` moved as little as needed to keep `centre` at least `view / 8`
/// inside a window of `view` px, within `0..=reach`, px.
fn keep(left: u32, centre: f64, view: u32, reach: u32) -> u32 {
    let inset = (view / 8) as f64;
    let (low, high) = (centre - (view as f64 - inset), centre - inset);
    (left as f64)
        .clamp(low.min(high), high)
        .round()
        .clamp(0.0, reach as f64) as u32
}

/// The window's margin on each side of a `width x height` scene, px.
fn margins(width: u32, height: u32) -> (u32, u32) {
    (
        width / Camera::MARGIN_DIVISOR,
        height / Camera::MARGIN_DIVISOR,
    )
}

/// Reads a camera-motion file: a CSV line `frame,dx,dy[,zoom]` per frame whose picture
/// moved since the frame before (frames numbered from 1 as in `--per-frame`; `dx`, `dy` in
/// px, positive right and down; zoom about the frame's centre, 1 when left out). A first
/// line of names (`frame,dx,dy,zoom`), blank lines and `#` comments are skipped; frames not listed did
/// not move. Returns the motion before each frame, indexed from 0, for frames of
/// `width x height` px; an error names the line.
pub fn parse_motions(text: &str, width: u32, height: u32) -> Result<Vec<CameraMotion>, String> {
    let centre = |side: u32| Q16::from_f64((side as f64 - 1.0) / 2.0);
    let mut motions = Vec::new();
    for (number, line) in (1..).zip(text.lines()) {
        let line = line.trim();
        let header = number == 1 && line.starts_with("frame,");
        if line.is_empty() || line.starts_with('#') || header {
            continue;
        }
        let bad = |why: &str| format!("line {number}: {why}: {line:?}");
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if !(3..=4).contains(&fields.len()) {
            return Err(bad("expected frame,dx,dy[,zoom]"));
        }
        let frame: usize =
            fields[0].parse().ok().filter(|&f| f >= 2).ok_or_else(|| {
                bad("the frame must be a number from 2 (the first has no motion)")
            })?;
        let number_at = |i: usize| -> Result<f64, String> {
            fields[i]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && v.abs() < 32_768.0)
                .ok_or_else(|| bad("dx, dy and zoom must be numbers within +-32768"))
        };
        let zoom = match fields.get(3) {
            Some(_) => number_at(3)?,
            None => 1.0,
        };
        if !(0.125..=8.0).contains(&zoom) {
            return Err(bad("the zoom must be in [0.125, 8]"));
        }
        if frame > motions.len() {
            motions.resize(frame, CameraMotion::STILL);
        }
        motions[frame - 1] = CameraMotion {
            zoom: Q16::from_f64(zoom),
            centre_x: centre(width),
            centre_y: centre(height),
            ..CameraMotion::shift(Q16::from_f64(number_at(1)?), Q16::from_f64(number_at(2)?))
        };
    }
    Ok(motions)
}

/// A triangle wave over `0..=2 margin` starting at `start` and moving `speed` px a
/// frame, at frame `index`, px.
fn sweep(index: usize, start: u32, margin: u32, speed: u32) -> u32 {
    let span = 2 * margin as u64;
    if span == 0 {
        return 0;
    }
    let travelled = (start as u64 + index as u64 * speed as u64) % (2 * span);
    (if travelled <= span {
        travelled
    } else {
        2 * span - travelled
    }) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweep_starts_centred_and_turns_at_the_margins() {
        let path: Vec<u32> = (0..12).map(|i| sweep(i, 10, 10, 4)).collect();
        assert_eq!(path, [10, 14, 18, 18, 14, 10, 6, 2, 2, 6, 10, 14]);
        assert_eq!(sweep(5, 0, 0, 1), 0);
    }

    #[test]
    fn windows_aim_at_the_target_stay_in_the_scene_and_the_told_shift_undoes_the_pan() {
        let (w, h) = (320, 240);
        let truth = vec![BBox::new(150.0, 100.0, 21.0, 41.0); 200];
        let camera = |c| VirtualCamera::new(c, w, h, &truth);
        // Centred on the box's centre (160, 120) is the middle window.
        let middle = Window {
            x: 40,
            y: 30,
            width: 240,
            height: 180,
        };
        assert_eq!(camera(Camera::Still).window(7), middle);
        // A target near the corner gets the window as far as it goes.
        let corner = VirtualCamera::new(Camera::Still, w, h, &[BBox::new(2.0, 300.0, 8.0, 8.0)]);
        assert_eq!((corner.window(0).x, corner.window(0).y), (0, 60));
        let (pan, known) = (camera(Camera::Pan), camera(Camera::PanKnown));
        assert_eq!(pan.window(0), middle);
        for i in 1..200 {
            let (a, b) = (pan.window(i - 1), pan.window(i));
            assert_eq!(known.window(i), b);
            assert!(b.x + b.width <= w && b.y + b.height <= h);
            let told = known.told(i);
            // A scene point at view column c moves to c + dx in the next view.
            assert_eq!(told.dx.to_f64(), a.x as f64 - b.x as f64);
            assert_eq!(told.dy.to_f64(), a.y as f64 - b.y as f64);
            assert_eq!(pan.told(i), CameraMotion::STILL);
        }
        assert_eq!(known.told(0), CameraMotion::STILL);
        // The pan keeps the target 1/8 of the window (30 px) inside: a target at column 300
        // holds the window's left edge at 80 (its centre at 300 - 80 = 220 = 240 - 30).
        let right = vec![BBox::new(290.0, 100.0, 21.0, 41.0); 50];
        let pan = VirtualCamera::new(Camera::Pan, w, h, &right);
        assert!((0..50).all(|i| pan.window(i).x >= 80), "never loses it");
        assert_eq!(keep(10, 300.0, 240, 80), 80);
        assert_eq!(keep(70, 150.0, 240, 80), 70, "already inside");
        assert_eq!(
            keep(70, 400.0, 240, 80),
            80,
            "out of reach: as far as it goes"
        );
    }

    #[test]
    fn motion_files_parse_and_name_their_bad_lines() {
        let text = "frame,dx,dy,zoom\n# head turned\n3,-4.5,2\n\n5, 1, 0, 1.25\n";
        let m = parse_motions(text, 11, 9).unwrap();
        assert_eq!(m.len(), 5);
        assert_eq!(m[0], CameraMotion::STILL);
        assert_eq!((m[2].dx.to_f64(), m[2].dy.to_f64()), (-4.5, 2.0));
        assert_eq!((m[4].zoom.to_f64(), m[4].centre_x.to_f64()), (1.25, 5.0));
        assert_eq!(m[4].centre_y, Q16::from_int(4));
        for (bad, says) in [
            ("1,2,3", "line 1: the frame must be a number from 2"),
            ("2,x,3", "line 1: dx, dy and zoom must be numbers"),
            ("2,1", "line 1: expected frame,dx,dy[,zoom]"),
            ("2,1,1,0", "line 1: the zoom must be in"),
            ("2,1,1e9", "line 1: dx, dy and zoom must be numbers"),
        ] {
            let e = parse_motions(bad, 10, 10).unwrap_err();
            assert!(e.starts_with(says), "{bad}: {e}");
        }
    }

    #[test]
    fn a_crop_is_the_scene_window_and_boxes_follow_it() {
        let (w, h) = (8u32, 6u32);
        let bytes: Vec<u8> = (0..w * h * 3).map(|i| i as u8).collect();
        let scene = Frame::rgb888(w, h, bytes.clone()).unwrap();
        let win = Window {
            x: 2,
            y: 1,
            width: 4,
            height: 3,
        };
        let view = win.crop(&scene).unwrap();
        assert_eq!((view.width, view.height), (4, 3));
        assert_eq!(&view.bytes[..3], &bytes[(8 + 2) * 3..][..3]);
        assert_eq!(
            &view.bytes[view.bytes.len() - 3..],
            &bytes[(3 * 8 + 5) * 3..][..3]
        );
        let too_big = Window { x: 5, ..win };
        assert!(too_big.crop(&scene).is_none());
        let b = win.to_view(&BBox::new(3.0, 2.5, 2.0, 2.0));
        assert_eq!(b, BBox::new(1.0, 1.5, 2.0, 2.0));
    }
}
