//! Known camera motion: how the picture moved since the last frame, from the commanded
//! pan/tilt or an IMU, applied to the filter's state before the next step.
//!
//! A turning head moves every pixel, and a motion model that sees the target jump by the
//! head's turn has to find it again by noise alone. Told the shift (and zoom), the tracker
//! moves its particles, estimate and velocities with the picture, so its motion model
//! only has to explain the target's own motion.

use super::{Estimate, Tracker};
use crate::fixed::Q16;
use crate::image::Binning;
use crate::window::Ellipse;

/// Smallest zoom factor applied, Q16.16: 1/8 (smaller ones are raised to it).
const MIN_ZOOM: Q16 = Q16::from_bits(Q16::ONE.to_bits() >> 3);
/// Largest zoom factor applied, Q16.16: 8 (larger ones are lowered to it).
const MAX_ZOOM: Q16 = Q16::from_bits(Q16::ONE.to_bits() << 3);

/// How the picture moved between two frames: the scene point seen at `p` in the last
/// frame is seen at `centre + zoom (p - centre) + (dx, dy)` in the next one (px, Q16.16).
///
/// A camera panning right moves the picture left (`dx < 0`); for a head turned by `a`
/// degrees with a horizontal field of view of `fov` degrees over `width` px, `dx` is
/// about `-a width / fov`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CameraMotion {
    /// Horizontal shift of the picture, px, Q16.16.
    pub dx: Q16,
    /// Vertical shift of the picture, px, Q16.16.
    pub dy: Q16,
    /// Zoom factor, Q16.16 (1 = none; applied within `[1/8, 8]`).
    pub zoom: Q16,
    /// The point the zoom keeps in place (before the shift), px, Q16.16: usually the
    /// frame's centre.
    pub centre_x: Q16,
    /// Its row, px, Q16.16.
    pub centre_y: Q16,
}

impl CameraMotion {
    /// No motion.
    pub const STILL: Self = Self::shift(Q16::ZERO, Q16::ZERO);

    /// The picture shifted by `(dx, dy)` px, no zoom.
    pub const fn shift(dx: Q16, dy: Q16) -> Self {
        Self {
            dx,
            dy,
            zoom: Q16::ONE,
            centre_x: Q16::ZERO,
            centre_y: Q16::ZERO,
        }
    }

    /// The zoom factor applied: [`CameraMotion::zoom`] within `[1/8, 8]`.
    fn applied_zoom(&self) -> Q16 {
        self.zoom.clamp(MIN_ZOOM, MAX_ZOOM)
    }

    /// Where the point `(x, y)` of the last frame is in the next one, px, Q16.16
    /// (saturating).
    pub fn point(&self, x: Q16, y: Q16) -> (Q16, Q16) {
        let zoom = self.applied_zoom();
        (
            self.centre_x + zoom * (x - self.centre_x) + self.dx,
            self.centre_y + zoom * (y - self.centre_y) + self.dy,
        )
    }

    /// A length of the last frame in the next one (a half-axis, a velocity), px, Q16.16.
    pub fn length(&self, v: Q16) -> Q16 {
        self.applied_zoom() * v
    }

    /// The ellipse `e` of the last frame in the next one.
    pub fn ellipse(&self, e: &Ellipse) -> Ellipse {
        let (cx, cy) = self.point(e.cx, e.cy);
        Ellipse {
            cx,
            cy,
            hx: self.length(e.hx),
            hy: self.length(e.hy),
        }
    }
}

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Tells the tracker that the picture moved by `motion` since the last frame; call it
    /// before the [`Tracker::step`] on the new frame. Every particle, the last estimate and
    /// the last confident one move with the picture; sizes, size rates and velocities
    /// scale with the zoom; the ground plane's samples move with the rows. Weights, the
    /// colour model and the size covariance stay. The moved estimate may lie outside
    /// the frame until the step, which brings every particle back inside. An unstarted
    /// tracker ignores it. `N` particles of work, no pixels read.
    pub fn camera_moved(&mut self, motion: &CameraMotion) {
        if self.state.rng.is_none() {
            return;
        }
        if motion.applied_zoom() == Q16::ONE {
            // A shift alone moves the centres and nothing else.
            for p in self.state.particles.iter_mut() {
                (p.x, p.y) = (p.x + motion.dx, p.y + motion.dy);
            }
        } else {
            for p in self.state.particles.iter_mut() {
                (p.x, p.y) = motion.point(p.x, p.y);
                p.vx = motion.length(p.vx);
                p.vy = motion.length(p.vy);
                p.size.hx = motion.length(p.size.hx);
                p.size.hy = motion.length(p.size.hy);
                p.size.dhx = motion.length(p.size.dhx);
                p.size.dhy = motion.length(p.size.dhy);
            }
        }
        let last = self.state.estimate;
        self.state.estimate = Estimate {
            ellipse: motion.ellipse(&last.ellipse),
            vx: motion.length(last.vx),
            vy: motion.length(last.vy),
            ..last
        };
        self.state.last_confident = motion.ellipse(&self.state.last_confident);
        let row_offset = motion.point(Q16::ZERO, Q16::ZERO).1;
        self.state
            .ground
            .move_rows(motion.applied_zoom(), row_offset);
        self.state.motion_spread = self.state.motion_spread.map(|s| motion.length(s));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, ImageView, Luma64};
    use crate::tracker::{Config, Status, Variant};

    /// A bright 16x16 square with its top-left corner at `(x, y)` on a dark 96x64 frame.
    fn square_at(x: usize, y: usize) -> [u8; 96 * 64] {
        let mut buf = [30u8; 96 * 64];
        for row in y..y + 16 {
            buf[row * 96 + x..row * 96 + x + 16].fill(230);
        }
        buf
    }

    fn start(variant: Variant, buf: &[u8]) -> Tracker<Luma64, 64, 64> {
        let frame = ImageView::<Gray8>::new(buf, 96, 64, 96).unwrap();
        let init = Ellipse::new(
            Q16::from_f64(27.5),
            Q16::from_f64(31.5),
            Q16::from_int(8),
            Q16::from_int(8),
        );
        let mut config = Config::new(variant);
        config.position_noise = Q16::ONE;
        config.relative_position_noise = Q16::ZERO;
        Tracker::new(config, &frame, init).unwrap()
    }

    #[test]
    fn a_shift_moves_every_particle_and_the_estimate_exactly() {
        let buf = square_at(20, 24);
        let mut t = start(Variant::Rbpf, &buf);
        let frame = ImageView::<Gray8>::new(&buf, 96, 64, 96).unwrap();
        t.step(&frame);
        let (before, estimate) = (*t.particles(), t.estimate());
        let motion = CameraMotion::shift(Q16::from_int(-30), Q16::from_f64(2.5));
        t.camera_moved(&motion);
        for (p, q) in before.iter().zip(t.particles()) {
            assert_eq!(q.x, p.x - Q16::from_int(30));
            assert_eq!(q.y, p.y + Q16::from_f64(2.5));
            assert_eq!((q.vx, q.vy, q.size), (p.vx, p.vy, p.size));
        }
        let moved = t.estimate();
        assert_eq!(moved.ellipse.cx, estimate.ellipse.cx - Q16::from_int(30));
        assert_eq!(
            (moved.ellipse.hx, moved.confidence),
            (estimate.ellipse.hx, estimate.confidence)
        );
    }

    #[test]
    fn a_zoom_scales_about_its_centre() {
        let motion = CameraMotion {
            zoom: Q16::from_int(2),
            centre_x: Q16::from_int(48),
            centre_y: Q16::from_int(32),
            ..CameraMotion::shift(Q16::ONE, Q16::ZERO)
        };
        assert_eq!(
            motion.point(Q16::from_int(48), Q16::from_int(32)),
            (Q16::from_int(49), Q16::from_int(32))
        );
        assert_eq!(
            motion.point(Q16::from_int(40), Q16::from_int(40)),
            (Q16::from_int(33), Q16::from_int(48))
        );
        assert_eq!(motion.length(Q16::from_int(5)), Q16::from_int(10));
        // Out-of-range zooms are held to [1/8, 8]; extreme shifts saturate.
        let wild = CameraMotion {
            zoom: Q16::MIN,
            ..CameraMotion::shift(Q16::MAX, Q16::MIN)
        };
        assert_eq!(wild.length(Q16::from_int(8)), Q16::ONE);
        assert_eq!(
            wild.point(Q16::from_int(3), -Q16::from_int(3)),
            (Q16::MAX, Q16::MIN)
        );
    }

    /// The square jumps 40 px left with the picture between two frames: told of the
    /// shift, both trackers stay on it; not told, they lose it.
    #[test]
    fn a_told_jump_is_followed_and_an_untold_one_is_not() {
        let (before, after) = (square_at(60, 24), square_at(20, 24));
        let shift = CameraMotion::shift(Q16::from_int(-40), Q16::ZERO);
        for variant in [Variant::ColourPf, Variant::Rbpf] {
            for told in [true, false] {
                let mut t = start(variant, &before);
                let first = ImageView::<Gray8>::new(&before, 96, 64, 96).unwrap();
                let init = Ellipse::new(
                    Q16::from_f64(67.5),
                    Q16::from_f64(31.5),
                    Q16::from_int(8),
                    Q16::from_int(8),
                );
                t.reset(&first, init).unwrap();
                t.step(&first);
                if told {
                    t.camera_moved(&shift);
                }
                let next = ImageView::<Gray8>::new(&after, 96, 64, 96).unwrap();
                let e = t.step(&next);
                let error = (e.ellipse.cx.to_f64() - 27.5).abs();
                if told {
                    assert!(error < 2.0, "{variant:?}: {error} px off");
                    assert_eq!(e.status, Status::Tracking, "{variant:?}");
                } else {
                    assert!(error > 20.0, "{variant:?}: found without being told");
                }
            }
        }
    }

    #[test]
    fn an_unstarted_tracker_ignores_it() {
        let mut t = Tracker::<Luma64, 8, 64>::unstarted();
        t.camera_moved(&CameraMotion::shift(Q16::ONE, Q16::ONE));
        assert_eq!(t.particles()[0].x, Q16::ZERO);
    }
}
