//! Stage 1, propagate: every particle's motion and size drawn forward one frame, the
//! re-detection draws while searching, and the motion noise this frame.

use super::particle::{predict_size, scale_randomly, Bounds, Motion, Particle};
use super::{Estimate, Status, Tracker, Variant};
use crate::fixed::Q16;
use crate::image::Binning;
use crate::resample::WEIGHT_TOTAL;
use crate::window::Ellipse;

/// The innovation mean's smoothing: each step moves it `2^-SPREAD_SMOOTHING_LOG2` (1/8)
/// of the way to the new innovation.
const SPREAD_SMOOTHING_LOG2: u32 = 3;

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Draws every particle forward: re-detection first while searching, then the motion
    /// and the size (sampled, or predicted with the shared covariance, RBPF).
    pub(super) fn propagate(&mut self, bounds: &Bounds) {
        let searching = self.state.estimate.status != Status::Tracking;
        if searching {
            self.redetect(bounds);
        }
        // While searching, RBPF sizes follow the ground plane only (rates held at zero), so
        // they cannot drift away from what the rows predict before the target is found.
        let rate_noise = if searching {
            Q16::ZERO
        } else {
            self.config.scale_noise
        };
        let motion = Motion::new(&self.config, self.noise_scale(searching));
        let slope = self.scale_per_row();
        debug_assert!(self.state.rng.is_some(), "a step of an unstarted tracker");
        let Some(rng) = self.state.rng.as_mut() else {
            return;
        };
        for p in self.state.particles.iter_mut() {
            let y_before = p.y;
            motion.drift(p, rng, bounds);
            if self.config.freeze_size {
                // Frozen at the initial size, but never larger than this frame allows.
                (p.size.hx, p.size.hy) = bounds.halves(p.size.hx, p.size.hy);
                continue;
            }
            match self.config.variant {
                Variant::ColourPf => scale_randomly(p, self.config.scale_noise, rng, bounds),
                Variant::Rbpf => {
                    if searching {
                        (p.size.dhx, p.size.dhy) = (Q16::ZERO, Q16::ZERO);
                    }
                    let dy = p.y - y_before;
                    predict_size(p, dy, slope, rate_noise, rng, bounds)
                }
            }
        }
        if self.config.variant == Variant::Rbpf {
            self.state.size_cov.predict(Q16::ONE);
        }
    }

    /// The factor on the motion noise this frame: `clamp(noise_gain * s / sigma,
    /// noise_floor, 1)` while tracking with a known innovation `s`, else 1.
    pub(super) fn noise_scale(&self, searching: bool) -> Q16 {
        match self.state.motion_spread {
            Some(spread) if !searching && self.config.noise_gain > Q16::ZERO => {
                let sigma = self.nominal_noise(&self.state.estimate.ellipse);
                (self.config.noise_gain * spread / sigma).clamp(self.config.noise_floor, Q16::ONE)
            }
            _ => Q16::ONE,
        }
    }

    /// The innovation mean after `estimate`: the distance of its centre from the last
    /// estimate moved by its velocity, `(|dx| + |dy|) / 2` px, averaged with weight 1/8
    /// (starting from the unscaled noise, so the noise narrows gradually).
    pub(super) fn next_spread(&self, estimate: &Estimate) -> Q16 {
        let last = &self.state.estimate;
        let dx = estimate.ellipse.cx - (last.ellipse.cx + last.vx);
        let dy = estimate.ellipse.cy - (last.ellipse.cy + last.vy);
        let innovation = Q16::from_bits((dx.abs().to_bits() >> 1) + (dy.abs().to_bits() >> 1));
        let spread = self
            .state
            .motion_spread
            .unwrap_or_else(|| self.nominal_noise(&estimate.ellipse));
        spread + Q16::from_bits((innovation - spread).to_bits() >> SPREAD_SMOOTHING_LOG2)
    }

    /// The unscaled position noise of a particle on `e`, px.
    fn nominal_noise(&self, e: &Ellipse) -> Q16 {
        Motion::new(&self.config, Q16::ONE).position_sigma(e.hx, e.hy)
    }

    /// Re-draws `redetect_share` of the particles uniformly over the frame, at rest, sized
    /// as the last confident estimate moved along the ground-plane relation to their row,
    /// with weight `redetect_prior` against the others' 1.
    fn redetect(&mut self, bounds: &Bounds) {
        let share = self.config.redetect_share.to_bits() as u64;
        let count = ((share * N as u64) >> Q16::FRAC_BITS) as usize;
        let last = self.state.last_confident;
        let slope = self.scale_per_row();
        let width = bounds.max_x.floor_int() as u32 + 1;
        let height = bounds.max_y.floor_int() as u32 + 1;
        debug_assert!(self.state.rng.is_some(), "a step of an unstarted tracker");
        for p in self.state.particles.iter_mut().take(count) {
            let Some(rng) = self.state.rng.as_mut() else {
                return;
            };
            let x = Q16::from_int(rng.below(width) as i32);
            let y = Q16::from_int(rng.below(height) as i32);
            let hy = last.hy + slope * (y - last.cy);
            let (hx, hy) = bounds.halves(last.hx * (hy / last.hy), hy);
            *p = Particle::at(&Ellipse {
                cx: x,
                cy: y,
                hx,
                hy,
            });
        }
        let even = WEIGHT_TOTAL / N as u32;
        let prior = (self.config.redetect_prior * Q16::from_bits(even as i32)).to_bits() as u32;
        for (i, w) in self.state.weights.iter_mut().enumerate() {
            *w = if i < count { prior.max(1) } else { even };
        }
    }
}
