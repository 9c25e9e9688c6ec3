//! Stage 3, update (RBPF): the target's size measured once around the weighted mean, and
//! every particle's size given the Kalman update with the shared gain.

use super::config::decimal;
use super::particle::Bounds;
use super::{CueMix, SizeMeasurement, Status, Tracker};
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::window::Ellipse;

/// The scales tried when measuring the size: `1 + k scale_step` for these `k`, the
/// unchanged size first (it wins a tie).
const SCALE_STEPS: [i32; 5] = [0, -1, 1, -2, 2];

/// How far beyond the largest scale's ring the measurement's object map reaches, as a
/// factor on the ring: a margin for the map's whole cells.
const MAP_MARGIN: Q16 = decimal(11, 10);

/// One scale the size measurement tried.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    /// How well the scale's window matches: larger is better.
    score: i64,
    /// The scale, `1 + k scale_step`, Q16.16.
    factor: Q16,
    /// Whether the window is on the target at all.
    usable: bool,
}

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Measures the size around the weighted mean and gives every particle's size the
    /// Kalman update. A measurement whose window is not on the target (see
    /// [`Tracker::measure_size`]) is dropped: the means keep their prediction, while the
    /// shared covariance takes its update regardless, so it stays at its data-independent
    /// steady state.
    pub(super) fn update_sizes<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        bounds: &Bounds,
    ) {
        let mean = self.weighted_mean(|_| true).ellipse;
        let measured = self.measure_size(frame, bounds, &mean);
        let gain = self.state.size_cov.gain();
        self.state.size_cov.update_cov();
        let Some(factor) = measured else {
            return;
        };
        self.report.scale_factor = Some(factor);
        let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
        // The slope is learnt from measured sizes (not from estimates, which already
        // follow the slope's own prediction), while tracking.
        if self.config.learn_scale_per_row && self.state.estimate.status == Status::Tracking {
            self.state.ground.observe(mean.cy, hy);
        }
        for p in self.state.particles.iter_mut() {
            gain.update_mean(&mut p.size, hx, hy);
            (p.size.hx, p.size.hy) = bounds.halves(p.size.hx, p.size.hy);
        }
    }

    /// The factor of the best-matching of the scales `1 + k scale_step` of `mean`
    /// ([`SCALE_STEPS`], the first on a tie; by contrast on the object map or by
    /// likelihood), or `None` if its window is not on the target.
    fn measure_size<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        bounds: &Bounds,
        mean: &Ellipse,
    ) -> Option<Q16> {
        let step = self.config.scale_step;
        let scaled = |k: i32| {
            let factor = Q16::ONE + step.mul_int(k);
            let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
            (factor, Ellipse { hx, hy, ..*mean })
        };
        if self.config.size_measurement == SizeMeasurement::Contrast {
            // The largest scale's ring, with a margin for the map's whole cells.
            let (_, largest) = scaled(SCALE_STEPS[SCALE_STEPS.len() - 1]);
            let reach = self.config.contrast_ring * MAP_MARGIN;
            self.build_map(frame, &self.contrast_span(&largest, reach));
        }
        let mut best = Candidate {
            score: i64::MIN,
            factor: Q16::ONE,
            usable: false,
        };
        for k in SCALE_STEPS {
            let (factor, e) = scaled(k);
            let candidate = self.candidate(frame, &e, factor);
            if candidate.score > best.score {
                best = candidate;
            }
        }
        best.usable.then_some(best.factor)
    }

    /// Scale `factor`'s window `e` judged by the configured measurement.
    fn candidate<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        e: &Ellipse,
        factor: Q16,
    ) -> Candidate {
        match self.config.size_measurement {
            // A window that does not stand out from its ring is not on the target.
            SizeMeasurement::Contrast => {
                let c = self.contrast(e);
                Candidate {
                    score: c.to_bits() as i64,
                    factor,
                    usable: c > Q16::ZERO,
                }
            }
            SizeMeasurement::Likelihood => {
                let m = self.compare(frame, e);
                let colour = self.colour_cost(e, m.score);
                let g = self
                    .derived
                    .cue
                    .evaluate_memo(frame, e, &mut self.scratch.memo);
                let gradient = self.gradient_cost(g);
                let score = match self.config.cue_mix {
                    CueMix::Average(_) => self.likelihood(colour, gradient, Q16::ZERO) as i64,
                    CueMix::Product => -((colour + gradient).to_bits() as i64),
                };
                // No target there, or (averaged likelihoods) nothing matches at all.
                let matched = matches!(self.config.cue_mix, CueMix::Product) || score > 0;
                Candidate {
                    score,
                    factor,
                    usable: self.config.variant.calibration().confidence(m.rho)
                        >= self.config.lost_below
                        && matched,
                }
            }
        }
    }
}
