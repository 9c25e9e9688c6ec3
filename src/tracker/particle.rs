//! A particle: its state, the bounds a frame sets on it, and its motion and size models.

use super::Config;
use crate::fixed::Q16;
use crate::kalman::Size;
use crate::rng::Rng;
use crate::window::Ellipse;

/// One hypothesis: the sampled motion (the RBPF's root) and the ellipse size (its leaf).
///
/// Colour PF: every field is sampled; the size's rates stay zero. RBPF: the size is the
/// mean of the particle's Kalman filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Particle {
    /// Centre column, px, Q16.16.
    pub x: Q16,
    /// Centre row, px, Q16.16.
    pub y: Q16,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: Q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: Q16,
    /// Half-axes, px, and their rates, px/frame, Q16.16.
    pub size: Size,
}

impl Particle {
    /// A particle at rest on `e`.
    pub const fn at(e: &Ellipse) -> Self {
        Self {
            x: e.cx,
            y: e.cy,
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            size: Size::at_rest(e.hx, e.hy),
        }
    }

    /// The particle's window.
    pub fn ellipse(&self) -> Ellipse {
        Ellipse {
            cx: self.x,
            cy: self.y,
            hx: self.size.hx,
            hy: self.size.hy,
        }
    }
}

/// The fastest motion along each axis, as a share of the frame's larger side: a quarter.
const MAX_SPEED_DIVISOR: i32 = 4;

/// Limits a propagated state must respect: the frame and the half-axis range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Bounds {
    /// Largest centre column and row, px, Q16.16 (`width - 1`, `height - 1`).
    pub max_x: Q16,
    pub max_y: Q16,
    /// Half-axis range, px, Q16.16.
    pub min_half: Q16,
    pub max_half: Q16,
    /// Largest speed along each axis, px/frame, Q16.16: a quarter of the larger side.
    pub max_speed: Q16,
}

impl Bounds {
    pub(crate) fn for_frame(width: usize, height: usize, min_half: Q16) -> Self {
        let max_x = Q16::from_int(width as i32 - 1);
        let max_y = Q16::from_int(height as i32 - 1);
        Self {
            max_x,
            max_y,
            min_half,
            max_half: max_x.max(max_y).max(min_half),
            max_speed: Q16::from_int(width.max(height) as i32 / MAX_SPEED_DIVISOR),
        }
    }

    /// Half-axes `(hx, hy)` brought into range keeping their ratio: a pair with an axis
    /// below `min_half` is scaled up until the smaller one equals it (a non-positive axis
    /// is set to `min_half`), then each is capped at `max_half`.
    pub(crate) fn halves(&self, hx: Q16, hy: Q16) -> (Q16, Q16) {
        let small = hx.min(hy);
        let (hx, hy) = if small <= Q16::ZERO {
            (hx.max(self.min_half), hy.max(self.min_half))
        } else if small < self.min_half {
            let grow = |h: Q16| {
                Q16::saturate(
                    h.to_bits() as i64 * self.min_half.to_bits() as i64 / small.to_bits() as i64,
                )
            };
            (grow(hx), grow(hy))
        } else {
            (hx, hy)
        };
        (hx.min(self.max_half), hy.min(self.max_half))
    }
}

/// Noise levels of the motion model (Q16.16; see [`super::Config`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Motion {
    pub position_noise: Q16,
    pub relative_noise: Q16,
    pub velocity_noise: Q16,
    pub velocity_keep: Q16,
}

impl Motion {
    /// The motion model of `config` with its three noise levels times `scale` (the
    /// frame's [`super::Config::noise_gain`] factor, 1 for none), Q16.16 in `(0, 1]`.
    pub(crate) fn new(config: &Config, scale: Q16) -> Self {
        Self {
            position_noise: config.position_noise * scale,
            relative_noise: config.relative_position_noise * scale,
            velocity_noise: config.velocity_noise * scale,
            velocity_keep: config.velocity_keep,
        }
    }

    /// Position noise of a particle with half-axes `hx`, `hy`: `position_noise +
    /// relative_noise * (Hx + Hy) / 2`, px, Q16.16.
    #[inline]
    pub(crate) fn position_sigma(&self, hx: Q16, hy: Q16) -> Q16 {
        let size = Q16::from_bits((hx.to_bits() >> 1) + (hy.to_bits() >> 1));
        self.position_noise + self.relative_noise * size
    }

    /// Constant-velocity drift with Gaussian noise:
    /// `v <- keep v + sigma_v n` (each axis limited to a quarter of the frame's larger side
    /// per frame), `x <- x + v + sigma n`, centre clamped to the frame, where `sigma` is
    /// [`Motion::position_sigma`], growing with the target.
    #[inline]
    pub(crate) fn drift(&self, p: &mut Particle, rng: &mut Rng, bounds: &Bounds) {
        let vmax = bounds.max_speed;
        p.vx = (self.velocity_keep * p.vx + rng.gaussian(self.velocity_noise)).clamp(-vmax, vmax);
        p.vy = (self.velocity_keep * p.vy + rng.gaussian(self.velocity_noise)).clamp(-vmax, vmax);
        let sigma = self.position_sigma(p.size.hx, p.size.hy);
        p.x = (p.x + p.vx + rng.gaussian(sigma)).clamp(Q16::ZERO, bounds.max_x);
        p.y = (p.y + p.vy + rng.gaussian(sigma)).clamp(Q16::ZERO, bounds.max_y);
    }
}

/// Colour PF size step: both half-axes scaled by one factor `1 + sigma n`.
#[inline]
pub(crate) fn scale_randomly(p: &mut Particle, relative_noise: Q16, rng: &mut Rng, b: &Bounds) {
    let factor = Q16::ONE + rng.gaussian(relative_noise);
    (p.size.hx, p.size.hy) = b.halves(p.size.hx * factor, p.size.hy * factor);
}

/// RBPF size mean prediction (eq. 7 of the RBPF paper) for a particle that moved `dy` px
/// down the image: `Hy^- = Hy + dHy + k dy` (`k` = alpha/beta, px/px),
/// `Hx^- = Hx Hy^- / Hy` (aspect ratio kept), rates drawn around their previous values
/// with standard deviation `rate_noise` (px/frame), `dHy`'s first.
#[inline]
pub(crate) fn predict_size(
    p: &mut Particle,
    dy: Q16,
    scale_per_row: Q16,
    rate_noise: Q16,
    rng: &mut Rng,
    b: &Bounds,
) {
    let Size { hx, dhx, hy, dhy } = p.size;
    let hy_raw = hy + dhy + scale_per_row * dy;
    let hx_raw = Q16::saturate(
        (hx.to_bits() as i64 * hy_raw.to_bits() as i64) / (hy.to_bits().max(1) as i64),
    );
    let (hx, hy) = b.halves(hx_raw, hy_raw);
    let dhy = dhy + rng.gaussian(rate_noise);
    let dhx = dhx + rng.gaussian(rate_noise);
    p.size = Size { hx, dhx, hy, dhy };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_stays_in_frame() {
        let b = Bounds::for_frame(10, 8, Q16::ONE);
        let m = Motion {
            position_noise: Q16::from_int(50),
            relative_noise: Q16::ONE,
            velocity_noise: Q16::from_int(50),
            velocity_keep: Q16::ONE,
        };
        let mut rng = Rng::new(5);
        let mut p = Particle::default();
        for _ in 0..1000 {
            m.drift(&mut p, &mut rng, &b);
            assert!(p.x >= Q16::ZERO && p.x <= Q16::from_int(9));
            assert!(p.y >= Q16::ZERO && p.y <= Q16::from_int(7));
            // A quarter of the larger side: 2 px/frame.
            assert!(p.vx.abs() <= Q16::from_int(2) && p.vy.abs() <= Q16::from_int(2));
        }
    }

    #[test]
    fn size_prediction_follows_rows_and_keeps_aspect() {
        let b = Bounds::for_frame(320, 240, Q16::from_int(2));
        let mut p = Particle::at(&Ellipse {
            cx: Q16::from_int(100),
            cy: Q16::from_int(100),
            hx: Q16::from_int(10),
            hy: Q16::from_int(20),
        });
        let mut rng = Rng::new(1);
        // 10 px down with 0.5 px of half-height per px: Hy 20 -> 25, Hx 10 -> 12.5.
        predict_size(
            &mut p,
            Q16::from_int(10),
            Q16::HALF,
            Q16::ZERO,
            &mut rng,
            &b,
        );
        assert_eq!(p.size.hy, Q16::from_int(25));
        assert_eq!(p.size.hx, Q16::from_f64(12.5));
        // Shrinking below the smallest half-axis keeps the aspect ratio: Hy 4 -> 1 would
        // give (1, 0.5); it becomes (4, 2) scaled to (min 2): (4, 2).
        p.size = Size::at_rest(Q16::from_int(2), Q16::from_int(4));
        predict_size(
            &mut p,
            Q16::from_int(-6),
            Q16::HALF,
            Q16::ZERO,
            &mut rng,
            &b,
        );
        assert_eq!((p.size.hy, p.size.hx), (Q16::from_int(4), Q16::from_int(2)));
        // Degenerate input stays within bounds.
        p.size = Size {
            hx: Q16::MAX,
            dhx: Q16::MAX,
            hy: Q16::ZERO,
            dhy: Q16::MIN,
        };
        predict_size(&mut p, Q16::MAX, Q16::from_int(4), Q16::ONE, &mut rng, &b);
        assert!(p.size.hy >= b.min_half && p.size.hy <= b.max_half);
        assert!(p.size.hx >= b.min_half && p.size.hx <= b.max_half);
    }
}
