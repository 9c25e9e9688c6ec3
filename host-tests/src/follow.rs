//! The closed loop of a camera on a pan/tilt head: recorded video is the scene, a virtual
//! camera sees a window of it where the head points, the tracker follows the target in
//! that view, and the controller (`rbtrack::pantilt`) turns the head to keep it in the
//! middle. The tracker is told each frame how the picture moved (the head's turn, as a
//! firmware knows it from its own commands or an IMU).
//!
//! Geometry: the view is half the scene's width and height; the lens's field of view is
//! [`FIELD_OF_VIEW_X`] degrees over the view's width, with square pixels, so a head angle
//! of `a` degrees puts the view's centre `a / degrees_per_px` px from the scene's centre.
//! The head's range is where the view stays inside the scene. The head reaches the
//! commanded angle within a frame.
//!
//! Two jumps test the settling: the run starts with the target [`JUMP_SHARE`] of the
//! view's width right of the centre, and halfway through the head is knocked by the same
//! amount (the controller is not told; the tracker is, as by an IMU). The pan's range is
//! widened by the knock so that the knocked head can still cover the scene.

use crate::camera::Window;
use crate::metrics::BBox;
use crate::pixels::Frame;
use crate::run::{self, Options};
use rbtrack::fixed::Q16;
use rbtrack::pantilt::{Command, PanTilt, PanTiltConfig};
use rbtrack::tracker::Estimate;

/// The lens's horizontal field of view over the view's width, degrees.
pub const FIELD_OF_VIEW_X: f64 = 60.0;

/// The size of each jump, as a share of the view's width.
pub const JUMP_SHARE: f64 = 0.25;

/// The centring band, as a share of the view's width: a frame is centred when the
/// target's centre is within it of the view's centre.
pub const BAND_SHARE: f64 = 0.1;

/// Frames after a jump over which an overshoot is looked for.
const OVERSHOOT_FRAMES: usize = 30;

/// One frame of the loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowFrame {
    /// The view's window in the scene.
    pub window: Window,
    /// The target's true box in the view, px (0-based).
    pub truth: BBox,
    /// The tracker's estimate in the view.
    pub estimate: Estimate,
    /// The head's command after the frame, degrees.
    pub command: Command,
    /// Whether some view within the scene has the target within the band of its centre
    /// (a target at the scene's edge is out of the head's reach).
    pub reachable: bool,
}

impl FollowFrame {
    /// The target's true centre minus the view's centre, px.
    pub fn error(&self) -> (f64, f64) {
        let (cx, cy) = self.truth.centre();
        let half = |side: u32| (side as f64 - 1.0) / 2.0;
        (cx - half(self.window.width), cy - half(self.window.height))
    }
}

/// A whole run of the loop.
#[derive(Clone, Debug, PartialEq)]
pub struct Follow {
    /// Every frame, the first included.
    pub frames: Vec<FollowFrame>,
    /// The frames at which the target jumped off-centre (the start, the knock).
    pub jumps: Vec<usize>,
}

/// What the loop achieved, px unless stated.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FollowSummary {
    /// The view's size.
    pub view: (u32, u32),
    /// The centring band's radius.
    pub band: f64,
    /// Per jump, frames until the target was first within the band (`None`: never).
    pub settling: Vec<Option<usize>>,
    /// Share of the settled frames (after the first settling, outside the knock's
    /// transient) with the target within the band.
    pub centred: f64,
    /// The same share over the settled frames whose target is within the head's reach.
    pub centred_in_reach: f64,
    /// Settled frames whose target is out of the head's reach.
    pub out_of_reach: usize,
    /// Mean centring error of the settled frames.
    pub mean_error: f64,
    /// Its 95th percentile.
    pub p95_error: f64,
    /// The largest overshoot past the centre after a jump, along the jump's axis, within
    /// 30 frames of settling (0 if none).
    pub overshoot: f64,
    /// Settled frames counted.
    pub settled_frames: usize,
}

impl Follow {
    /// The loop's figures.
    pub fn summary(&self) -> FollowSummary {
        let view = self
            .frames
            .first()
            .map_or((0, 0), |f| (f.window.width, f.window.height));
        let band = BAND_SHARE * view.0 as f64;
        let distance = |f: &FollowFrame| {
            let (ex, ey) = f.error();
            ex.hypot(ey)
        };
        let mut settling = Vec::new();
        let mut transient = vec![false; self.frames.len()];
        let mut overshoot: f64 = 0.0;
        for (k, &jump) in self.jumps.iter().enumerate() {
            let end = self.jumps.get(k + 1).copied().unwrap_or(self.frames.len());
            let settle = (jump..end).find(|&i| distance(&self.frames[i]) <= band);
            settling.push(settle.map(|i| i - jump));
            for t in &mut transient[jump..settle.unwrap_or(end)] {
                *t = true;
            }
            if let (Some(s), Some(first)) = (settle, self.frames.get(jump)) {
                let side = first.error().0.signum();
                let later = &self.frames[s..(s + OVERSHOOT_FRAMES).min(end)];
                for f in later {
                    overshoot = overshoot.max(-side * f.error().0);
                }
            }
        }
        let settled_frames: Vec<&FollowFrame> = self
            .frames
            .iter()
            .zip(&transient)
            .filter(|(_, &t)| !t)
            .map(|(f, _)| f)
            .collect();
        let share_centred = |frames: &[&FollowFrame]| {
            let centred = frames.iter().filter(|f| distance(f) <= band).count();
            centred as f64 / frames.len().max(1) as f64
        };
        let in_reach: Vec<&FollowFrame> = settled_frames
            .iter()
            .copied()
            .filter(|f| f.reachable)
            .collect();
        let mut errors: Vec<f64> = settled_frames.iter().map(|f| distance(f)).collect();
        let settled = errors.len();
        let centred = share_centred(&settled_frames);
        let mean_error = errors.iter().sum::<f64>() / settled.max(1) as f64;
        errors.sort_by(f64::total_cmp);
        let p95_error = match settled {
            0 => 0.0,
            n => errors[((n as f64 * 0.95).ceil() as usize).clamp(1, n) - 1],
        };
        FollowSummary {
            view,
            band,
            settling,
            centred,
            centred_in_reach: share_centred(&in_reach),
            out_of_reach: settled - in_reach.len(),
            mean_error,
            p95_error,
            overshoot,
            settled_frames: settled,
        }
    }
}

/// The head and the view over a `width x height` scene.
struct Rig {
    scene: (u32, u32),
    view: (u32, u32),
    /// Degrees per px of the view.
    degrees_per_px: f64,
}

impl Rig {
    fn new(width: u32, height: u32) -> Self {
        let view = (width / 2, height / 2);
        Self {
            scene: (width, height),
            view,
            degrees_per_px: FIELD_OF_VIEW_X / view.0 as f64,
        }
    }

    /// The head angle, degrees, that puts the view's centre at scene px `centre` on an
    /// axis (0: pan, 1: tilt).
    fn angle(&self, axis: usize, centre: f64) -> f64 {
        let scene = [self.scene.0, self.scene.1][axis] as f64;
        (centre - (scene - 1.0) / 2.0) * self.degrees_per_px
    }

    /// The view's window for head angles `(pan, tilt)`, degrees, within the scene.
    fn window(&self, pan: f64, tilt: f64) -> Window {
        let place = |angle: f64, scene: u32, view: u32| {
            let left = (scene as f64 - 1.0) / 2.0 + angle / self.degrees_per_px
                - (view as f64 - 1.0) / 2.0;
            left.round().clamp(0.0, (scene - view) as f64) as u32
        };
        Window {
            x: place(pan, self.scene.0, self.view.0),
            y: place(tilt, self.scene.1, self.view.1),
            width: self.view.0,
            height: self.view.1,
        }
    }

    /// Whether some view has the scene point `(x, y)` within `band` px of its centre.
    fn reaches(&self, (x, y): (f64, f64), band: f64) -> bool {
        let off = |v: f64, scene: u32, view: u32| {
            let (low, high) = (
                (view as f64 - 1.0) / 2.0,
                scene as f64 - (view as f64 + 1.0) / 2.0,
            );
            v - v.clamp(low, high)
        };
        let (dx, dy) = (
            off(x, self.scene.0, self.view.0),
            off(y, self.scene.1, self.view.1),
        );
        dx.hypot(dy) <= band
    }

    /// The controller: the view's size and field of view, each axis's range where the
    /// view stays inside the scene (the pan's widened by `slack` degrees each way, so
    /// that a knocked head can still reach it all), starting at `home` degrees.
    fn controller(&self, home: (f64, f64), slack: f64) -> Result<PanTilt, String> {
        let (w, h) = self.view;
        let fov_y = self.degrees_per_px * h as f64;
        let mut config = PanTiltConfig::new(w, h, Q16::from_f64(FIELD_OF_VIEW_X), q(fov_y));
        let reach = |scene: u32, view: u32| (scene - view) as f64 / 2.0 * self.degrees_per_px;
        for (axis, reach, home) in [
            (&mut config.pan, reach(self.scene.0, w) + slack, home.0),
            (&mut config.tilt, reach(self.scene.1, h), home.1),
        ] {
            axis.min = q(-reach);
            axis.max = q(reach);
            axis.home = q(home.clamp(-reach, reach));
        }
        PanTilt::new(config).map_err(|e| e.to_string())
    }
}

fn q(v: f64) -> Q16 {
    Q16::from_f64(v)
}

/// Runs the loop over `scene` (RGB888 frames of `width x height` px) whose target's true
/// box in each frame is `truth` (0-based, scene px), tracked with `options`; frames past
/// the ground truth's end are not run. `on_frame(index, view, frame)` sees each frame's
/// view and what happened in it, e.g. to draw it. An error names the frame.
pub fn follow<E: std::fmt::Display>(
    scene: impl IntoIterator<Item = Result<Frame, E>>,
    truth: &[BBox],
    width: u32,
    height: u32,
    options: &Options,
    mut on_frame: impl FnMut(usize, &Frame, &FollowFrame) -> Result<(), String>,
) -> Result<Follow, String> {
    if width < 4 || height < 4 {
        return Err(format!("a {width}x{height} scene is too small to pan over"));
    }
    let rig = Rig::new(width, height);
    let first = truth.first().ok_or("no ground truth")?;
    let (cx, cy) = first.centre();
    // The target starts JUMP_SHARE of the view's width right of the centre.
    let start_pan = rig.angle(0, cx - JUMP_SHARE * rig.view.0 as f64);
    let knock_at = truth.len() / 2;
    let knock = JUMP_SHARE * rig.view.0 as f64 * rig.degrees_per_px;
    let mut head = rig.controller((start_pan, rig.angle(1, cy)), knock)?;
    let band = BAND_SHARE * rig.view.0 as f64;
    let mut frames: Vec<FollowFrame> = Vec::with_capacity(truth.len());
    let mut tracker = None;
    for (index, scene_frame) in scene.into_iter().take(truth.len()).enumerate() {
        let scene_frame = scene_frame.map_err(|e| format!("frame {}: {e}", index + 1))?;
        let command = head.command();
        let offset = if index >= knock_at && index > 0 {
            knock
        } else {
            0.0
        };
        let window = rig.window(command.pan.to_f64() - offset, command.tilt.to_f64());
        let view = window
            .crop(&scene_frame)
            .ok_or_else(|| format!("frame {}: not an RGB888 frame of the scene", index + 1))?;
        let seen = window.to_view(&truth[index]);
        let estimate = match &mut tracker {
            None => {
                let started = run::start(options, &view, &seen).map_err(|e| e.to_string())?;
                let estimate = started.estimate();
                tracker = Some(started);
                estimate
            }
            Some(t) => {
                let last = frames.last().map_or(window, |f| f.window);
                t.camera_moved(&last.motion_to(&window));
                t.step(&view).map_err(|e| e.to_string())?.estimate
            }
        };
        let frame = FollowFrame {
            window,
            truth: seen,
            estimate,
            command: head.step(&estimate),
            reachable: rig.reaches(truth[index].centre(), band),
        };
        on_frame(index, &view, &frame)?;
        frames.push(frame);
    }
    let jumps = if frames.len() > knock_at && knock_at > 0 {
        vec![0, knock_at]
    } else {
        vec![0]
    };
    Ok(Follow { frames, jumps })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rig_maps_angles_to_windows_within_the_scene() {
        let rig = Rig::new(320, 240);
        assert_eq!(rig.view, (160, 120));
        let centre = rig.window(0.0, 0.0);
        assert_eq!((centre.x, centre.y), (80, 60));
        // 60 degrees over 160 px: 30 degrees is 80 px, as far as the view goes.
        assert_eq!(rig.window(30.0, 0.0).x, 160);
        assert_eq!(rig.window(90.0, -90.0).x, 160);
        assert_eq!(rig.window(90.0, -90.0).y, 0);
        assert!((rig.angle(0, 239.5) - 30.0).abs() < 1e-9);
        let head = rig.controller((45.0, 0.0), 5.0).unwrap();
        assert_eq!(
            head.command().pan,
            Q16::from_int(35),
            "home held to the range"
        );
        // Views centre on columns 79.5..=239.5 and rows 59.5..=179.5.
        assert!(rig.reaches((100.0, 70.0), 0.0));
        assert!(rig.reaches((64.5, 59.5), 15.0) && !rig.reaches((64.5, 59.5), 14.0));
    }

    #[test]
    fn the_summary_counts_settling_overshoot_and_centring() {
        let window = Window {
            x: 0,
            y: 0,
            width: 100,
            height: 100,
        };
        // The target's centre x at 49.5 + e: errors 30, 20, 5, -3 (overshoot), 0...
        let frame = |e: f64| FollowFrame {
            window,
            truth: BBox::new(45.0 + e, 45.0, 10.0, 10.0),
            estimate: Estimate {
                ellipse: rbtrack::Ellipse::new(Q16::ZERO, Q16::ZERO, Q16::ONE, Q16::ONE),
                vx: Q16::ZERO,
                vy: Q16::ZERO,
                score: Q16::ONE,
                confidence: Q16::ONE,
                status: rbtrack::Status::Tracking,
            },
            command: Command::default(),
            reachable: e != 12.0,
        };
        let errors = [30.0, 20.0, 5.0, -3.0, 0.0, 12.0, 0.0, 25.0, 8.0, 1.0];
        let follow = Follow {
            frames: errors.iter().map(|&e| frame(e)).collect(),
            jumps: vec![0, 7],
        };
        let s = follow.summary();
        assert_eq!(s.band, 10.0);
        assert_eq!(s.settling, [Some(2), Some(1)]);
        assert_eq!(s.settled_frames, 7);
        assert!((s.centred - 6.0 / 7.0).abs() < 1e-12, "{}", s.centred);
        assert_eq!(
            (s.centred_in_reach, s.out_of_reach),
            (1.0, 1),
            "12 px is out of reach"
        );
        assert_eq!(s.overshoot, 3.0);
        assert_eq!(s.p95_error, 12.0);
        assert!((s.mean_error - 29.0 / 7.0).abs() < 1e-12);
    }
}
