//! Pan/tilt output: head commands that keep a tracked target in the middle of the picture,
//! for a camera on a pan/tilt head. Integer only, Q16.16 throughout.
//!
//! Units: the error of an axis is the target's angle off the optical axis, degrees: its
//! centre's offset from the frame's centre, px, times the field of view over the frame's
//! size (degrees per px, the pinhole camera near its axis). Commands are head angles,
//! degrees, positive to the right (pan) and down (tilt); a hobby servo takes them as pulse
//! widths through its own microseconds per degree.
//!
//! Each axis is an incremental PID: every frame the command moves by
//! `kp e + ki sum(e) + kd (e - e_prev)`, limited to `max_rate` degrees, the command to
//! `min..=max`. Within the dead band the head holds still (the sum kept, the previous
//! error taken as zero). The sum stops growing while the command sits at a limit it pushes
//! against (anti-windup). While the status is [`Status::Lost`] the head holds still and keeps
//! its sum; an `Uncertain` estimate is still followed (on the dev set nearly every frame
//! off the target is `Lost`, and many on it are only `Uncertain`).
//!
//! A head that turns by the commanded angle within a frame sees a still target's error
//! fall by the share `kp` each frame: `kp = 1` centres it in one frame, `kp` in `(0, 2)`
//! converges, and smaller values ride out the tracker's jitter; `ki` removes the lag
//! behind a target that keeps moving.
//!
//! # Examples
//! ```
//! use rbtrack::pantilt::{PanTilt, PanTiltConfig};
//! use rbtrack::{Ellipse, Estimate, Q16, Status};
//! // A 320x240 camera with a 60 x 45 degree field of view: 0.1875 degree per px.
//! let mut head = PanTilt::new(PanTiltConfig::new(320, 240, Q16::from_int(60), Q16::from_int(45)))?;
//! let target = Ellipse::new(Q16::from_int(239), Q16::from_int(119), Q16::from_int(10), Q16::from_int(20));
//! let (vx, vy, score, confidence) = (Q16::ZERO, Q16::ZERO, Q16::ONE, Q16::ONE);
//! let status = Status::Tracking;
//! let estimate = Estimate { ellipse: target, vx, vy, score, confidence, status };
//! let command = head.step(&estimate);
//! // 80 px right of centre is 15 degrees: the head turns right, by at most 5 a frame.
//! assert_eq!(command.pan, Q16::from_int(5));
//! assert_eq!(command.tilt, Q16::ZERO);
//! # Ok::<(), rbtrack::pantilt::PanTiltError>(())
//! ```

use crate::fixed::Q16;
use crate::tracker::{Estimate, Status};

/// Largest gain, per frame.
const MAX_GAIN: Q16 = Q16::from_int(4);

/// Largest field of view, degrees.
const MAX_FIELD_OF_VIEW: Q16 = Q16::from_int(360);

/// One axis's controller settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisConfig {
    /// Share of the error moved per frame, Q16.16 in `[0, 4]`.
    pub kp: Q16,
    /// Share of the summed error moved per frame, Q16.16 in `[0, 4]`.
    pub ki: Q16,
    /// Share of the error's change moved per frame, Q16.16 in `[0, 4]`.
    pub kd: Q16,
    /// Errors this small count as zero, degrees, Q16.16, `>= 0`.
    pub dead_band: Q16,
    /// Largest move per frame, degrees, Q16.16, `> 0`.
    pub max_rate: Q16,
    /// Smallest command, degrees, Q16.16.
    pub min: Q16,
    /// Largest command, degrees, Q16.16, `>= min`.
    pub max: Q16,
    /// Command at the start, degrees, Q16.16, in `min..=max`.
    pub home: Q16,
}

impl AxisConfig {
    /// `kp` 0.5, `ki` 0.02, `kd` 0, dead band 0.5 degree, at most 5 degrees a frame,
    /// range -90..=90 degrees, home 0.
    pub const fn new() -> Self {
        Self {
            kp: Q16::from_ratio(1, 2),
            ki: Q16::from_ratio(1, 50),
            kd: Q16::ZERO,
            dead_band: Q16::from_ratio(1, 2),
            max_rate: Q16::from_int(5),
            min: Q16::from_int(-90),
            max: Q16::from_int(90),
            home: Q16::ZERO,
        }
    }
}

impl Default for AxisConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// The head and the camera on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PanTiltConfig {
    /// Frame width, px, `> 0`.
    pub width: u32,
    /// Frame height, px, `> 0`.
    pub height: u32,
    /// Horizontal field of view, degrees, Q16.16 in `(0, 360]`.
    pub fov_x: Q16,
    /// Vertical field of view, degrees, Q16.16 in `(0, 360]`.
    pub fov_y: Q16,
    /// The pan axis.
    pub pan: AxisConfig,
    /// The tilt axis.
    pub tilt: AxisConfig,
}

impl PanTiltConfig {
    /// A camera of `width x height` px and `fov_x x fov_y` degrees, both axes at
    /// [`AxisConfig::new`].
    pub const fn new(width: u32, height: u32, fov_x: Q16, fov_y: Q16) -> Self {
        Self {
            width,
            height,
            fov_x,
            fov_y,
            pan: AxisConfig::new(),
            tilt: AxisConfig::new(),
        }
    }
}

/// A setting [`PanTilt::new`] refuses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PanTiltError {
    /// A frame side of 0 px.
    FrameSize,
    /// A field of view outside `(0, 360]` degrees.
    FieldOfView,
    /// A gain outside `[0, 4]`.
    Gain,
    /// A negative dead band or a rate limit that is not positive.
    Limit,
    /// `min > max`, or home outside `min..=max`.
    Range,
}

impl core::fmt::Display for PanTiltError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::FrameSize => "frame width and height must be positive",
            Self::FieldOfView => "field of view must be in (0, 360] degrees",
            Self::Gain => "gains must be in [0, 4]",
            Self::Limit => "dead band must be >= 0 and the rate limit > 0",
            Self::Range => "min must be <= max, with home between them",
        })
    }
}

/// The head's commands after a step, degrees, Q16.16.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Command {
    /// Pan angle, positive to the right.
    pub pan: Q16,
    /// Tilt angle, positive down.
    pub tilt: Q16,
}

/// One axis's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct Axis {
    config: AxisConfig,
    /// Degrees per px.
    scale: Q16,
    /// The frame's centre on this axis, px.
    centre: Q16,
    command: Q16,
    sum: Q16,
    last: Q16,
}

impl Axis {
    fn new(config: AxisConfig, side: u32, fov: Q16) -> Result<Self, PanTiltError> {
        let side = i32::try_from(side)
            .ok()
            .filter(|&s| s > 0)
            .ok_or(PanTiltError::FrameSize)?;
        if fov <= Q16::ZERO || fov > MAX_FIELD_OF_VIEW {
            return Err(PanTiltError::FieldOfView);
        }
        let gains = [config.kp, config.ki, config.kd];
        if gains.iter().any(|&g| g < Q16::ZERO || g > MAX_GAIN) {
            return Err(PanTiltError::Gain);
        }
        if config.dead_band < Q16::ZERO || config.max_rate <= Q16::ZERO {
            return Err(PanTiltError::Limit);
        }
        if config.min > config.max || config.home < config.min || config.home > config.max {
            return Err(PanTiltError::Range);
        }
        Ok(Self {
            config,
            scale: Q16::from_ratio(
                fov.to_bits() as i64,
                side as i64 * Q16::ONE.to_bits() as i64,
            ),
            centre: Q16::from_ratio(side as i64 - 1, 2),
            command: config.home,
            sum: Q16::ZERO,
            last: Q16::ZERO,
        })
    }

    /// The command after the target's centre is seen at `at` px.
    fn step(&mut self, at: Q16) -> Q16 {
        let c = &self.config;
        let error = (at - self.centre) * self.scale;
        if error.abs() <= c.dead_band {
            self.last = Q16::ZERO;
            return self.command;
        }
        let sum = self.sum + error;
        let change = error - self.last;
        self.last = error;
        let step = (c.kp * error + c.ki * sum + c.kd * change).clamp(-c.max_rate, c.max_rate);
        let command = (self.command + step).clamp(c.min, c.max);
        let pushing =
            (command == c.max && error > Q16::ZERO) || (command == c.min && error < Q16::ZERO);
        if !pushing {
            self.sum = sum;
        }
        self.command = command;
        command
    }
}

/// The pan/tilt controller: one [`PanTilt::step`] per tracker estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PanTilt {
    pan: Axis,
    tilt: Axis,
}

impl PanTilt {
    /// A controller with the head at home.
    ///
    /// # Errors
    /// The first setting of `config` out of range ([`PanTiltError`]).
    pub fn new(config: PanTiltConfig) -> Result<Self, PanTiltError> {
        Ok(Self {
            pan: Axis::new(config.pan, config.width, config.fov_x)?,
            tilt: Axis::new(config.tilt, config.height, config.fov_y)?,
        })
    }

    /// The commands that follow `estimate`, taken on a frame seen at the current
    /// commands; the current commands, unchanged, when its status is `Lost`.
    pub fn step(&mut self, estimate: &Estimate) -> Command {
        if estimate.status != Status::Lost {
            self.pan.step(estimate.ellipse.cx);
            self.tilt.step(estimate.ellipse.cy);
        }
        self.command()
    }

    /// The current commands.
    pub fn command(&self) -> Command {
        Command {
            pan: self.pan.command,
            tilt: self.tilt.command,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window::Ellipse;

    const W: u32 = 320;
    const H: u32 = 240;

    fn config() -> PanTiltConfig {
        PanTiltConfig::new(W, H, Q16::from_int(60), Q16::from_int(45))
    }

    fn at(cx: Q16, cy: Q16, status: Status) -> Estimate {
        Estimate {
            ellipse: Ellipse::new(cx, cy, Q16::from_int(8), Q16::from_int(16)),
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            score: Q16::ONE,
            confidence: Q16::ONE,
            status,
        }
    }

    fn seen(cx: f64, cy: f64, status: Status) -> Estimate {
        at(Q16::from_f64(cx), Q16::from_f64(cy), status)
    }

    /// Where a target at world angles `(pan, tilt)` degrees is seen by a head at
    /// `command`, px (the pinhole camera's linear approximation).
    fn project(pan: f64, tilt: f64, command: Command) -> (f64, f64) {
        let (sx, sy) = (60.0 / W as f64, 45.0 / H as f64);
        let cx = (W as f64 - 1.0) / 2.0 + (pan - command.pan.to_f64()) / sx;
        let cy = (H as f64 - 1.0) / 2.0 + (tilt - command.tilt.to_f64()) / sy;
        (cx, cy)
    }

    /// Closed loop over `frames` frames: the target at `path(k)` degrees, seen at the
    /// commands of the frame before; the commands of every frame.
    fn close_loop(
        head: &mut PanTilt,
        frames: usize,
        path: impl Fn(usize) -> (f64, f64),
    ) -> std::vec::Vec<Command> {
        let mut commands = std::vec::Vec::new();
        for k in 0..frames {
            let (pan, tilt) = path(k);
            let (cx, cy) = project(pan, tilt, head.command());
            commands.push(head.step(&seen(cx, cy, Status::Tracking)));
        }
        commands
    }

    #[test]
    fn centres_a_still_target_without_overshoot() {
        let mut head = PanTilt::new(config()).unwrap();
        let commands = close_loop(&mut head, 40, |_| (12.0, -7.0));
        let last = commands[commands.len() - 1];
        assert!((last.pan.to_f64() - 12.0).abs() <= 0.5, "{last:?}");
        assert!((last.tilt.to_f64() + 7.0).abs() <= 0.5, "{last:?}");
        // Monotonic approach: never beyond the target by more than the dead band.
        assert!(
            commands.iter().all(|c| c.pan.to_f64() <= 12.5),
            "{commands:?}"
        );
        assert!(
            commands.iter().all(|c| c.tilt.to_f64() >= -7.5),
            "{commands:?}"
        );
        // At most 5 degrees a frame.
        let mut before = Command::default();
        for c in &commands {
            assert!((c.pan - before.pan).abs() <= Q16::from_int(5));
            assert!((c.tilt - before.tilt).abs() <= Q16::from_int(5));
            before = *c;
        }
    }

    #[test]
    fn the_sum_removes_the_lag_behind_a_moving_target() {
        let path = |k: usize| (0.3 * k as f64, 0.0);
        // The error the head sees: the target against the command of the frame before.
        let lag = |ki: Q16| {
            let mut c = config();
            (c.pan.ki, c.pan.dead_band) = (ki, Q16::ZERO);
            let mut head = PanTilt::new(c).unwrap();
            let commands = close_loop(&mut head, 200, path);
            (path(199).0 - commands[198].pan.to_f64()).abs()
        };
        // Proportional alone trails by speed / kp = 0.6 degree; the sum takes it to
        // nothing.
        assert!(lag(Q16::ZERO) > 0.55, "{}", lag(Q16::ZERO));
        assert!(
            lag(Q16::from_ratio(1, 50)) < 0.05,
            "{}",
            lag(Q16::from_ratio(1, 50))
        );
    }

    #[test]
    fn limits_hold_and_the_sum_does_not_wind_up() {
        let mut c = config();
        (c.pan.min, c.pan.max) = (Q16::from_int(-20), Q16::from_int(20));
        let mut head = PanTilt::new(c).unwrap();
        // Out of reach at 40 degrees for 100 frames, then back at 10.
        let mut sums = std::vec::Vec::new();
        let commands = close_loop(&mut head, 100, |_| (40.0, 0.0));
        sums.push(head.pan.sum);
        assert!(commands.iter().all(|c| c.pan <= Q16::from_int(20)));
        assert_eq!(commands[99].pan, Q16::from_int(20));
        // At the limit the sum stopped growing: from the fifth frame on it stayed.
        let mut again = PanTilt::new(c).unwrap();
        close_loop(&mut again, 5, |_| (40.0, 0.0));
        assert_eq!(again.pan.sum, sums[0]);
        // Back in reach, the head leaves the limit on the first frame and settles.
        let back = close_loop(&mut head, 60, |_| (10.0, 0.0));
        assert!(back[0].pan < Q16::from_int(20), "{:?}", back[0]);
        assert!(
            (back[59].pan.to_f64() - 10.0).abs() <= 0.6,
            "{:?}",
            back[59]
        );
    }

    #[test]
    fn holds_when_lost_and_ignores_the_dead_band() {
        let mut head = PanTilt::new(config()).unwrap();
        let (cx, cy) = project(10.0, 5.0, head.command());
        assert_eq!(head.step(&seen(cx, cy, Status::Lost)), Command::default());
        let mut uncertain = head;
        assert_ne!(
            uncertain.step(&seen(cx, cy, Status::Uncertain)),
            Command::default(),
            "an uncertain estimate is followed"
        );
        // 0.4 degree off (2 px): inside the dead band, no move.
        let (cx, cy) = project(0.4, -0.4, head.command());
        assert_eq!(
            head.step(&seen(cx, cy, Status::Tracking)),
            Command::default()
        );
    }

    #[test]
    fn matches_an_f64_controller() {
        let mut head = PanTilt::new(config()).unwrap();
        let (kp, ki, band, rate) = (0.5, 0.02, 0.5, 5.0);
        let (mut command, mut sum) = (0.0f64, 0.0f64);
        for k in 0..300 {
            let target = 30.0 * (k as f64 / 23.0).sin() + 8.0 * (k as f64 / 5.0).cos();
            let cx = (W as f64 - 1.0) / 2.0 + (target - command) * W as f64 / 60.0;
            let got = head.step(&seen(cx, 120.0, Status::Tracking)).pan.to_f64();
            let e = target - command;
            if e.abs() > band {
                let s = sum + e;
                let next = (command + (kp * e + ki * s).clamp(-rate, rate)).clamp(-90.0, 90.0);
                if !((next == 90.0 && e > 0.0) || (next == -90.0 && e < 0.0)) {
                    sum = s;
                }
                command = next;
            }
            // Q16.16 rounding of the centre, the scale and each product: 0.01 degree.
            assert!(
                (got - command).abs() < 0.01,
                "frame {k}: {got} against {command}"
            );
            command = got;
        }
    }

    #[test]
    fn bad_settings_are_refused() {
        let bad = |edit: fn(&mut PanTiltConfig)| {
            let mut c = config();
            edit(&mut c);
            PanTilt::new(c).err()
        };
        assert_eq!(bad(|c| c.width = 0), Some(PanTiltError::FrameSize));
        assert_eq!(bad(|c| c.height = u32::MAX), Some(PanTiltError::FrameSize));
        assert_eq!(
            bad(|c| c.fov_x = Q16::ZERO),
            Some(PanTiltError::FieldOfView)
        );
        assert_eq!(
            bad(|c| c.fov_y = Q16::from_int(361)),
            Some(PanTiltError::FieldOfView)
        );
        assert_eq!(bad(|c| c.pan.kp = -Q16::ONE), Some(PanTiltError::Gain));
        assert_eq!(
            bad(|c| c.tilt.kd = Q16::from_int(5)),
            Some(PanTiltError::Gain)
        );
        assert_eq!(
            bad(|c| c.pan.max_rate = Q16::ZERO),
            Some(PanTiltError::Limit)
        );
        assert_eq!(
            bad(|c| c.tilt.dead_band = -Q16::ONE),
            Some(PanTiltError::Limit)
        );
        assert_eq!(
            bad(|c| c.pan.min = Q16::from_int(91)),
            Some(PanTiltError::Range)
        );
        assert_eq!(
            bad(|c| c.tilt.home = Q16::from_int(95)),
            Some(PanTiltError::Range)
        );
        assert!(bad(|_| ()).is_none());
    }

    #[test]
    fn extreme_estimates_saturate() {
        let mut head = PanTilt::new(config()).unwrap();
        for q in [Q16::MAX, Q16::MIN, Q16::ZERO] {
            let c = head.step(&at(q, q, Status::Tracking));
            assert!(c.pan.abs() <= Q16::from_int(90) && c.tilt.abs() <= Q16::from_int(90));
        }
    }
}
