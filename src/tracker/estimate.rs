//! Stage 4, estimate: where the particles put the target, how well that window matches
//! the colour model (the confidence, which sets the status), and the model's adaptation.

use super::particle::Particle;
use super::{Readout, Tracker};
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::rect::Rect;
use crate::window::Ellipse;

/// How sure the tracker is of its estimate.
///
/// `Lost` is 0, so that an unstarted tracker ([`Tracker::unstarted`]) is all zero bits and
/// a `static` of one takes no flash.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Status {
    /// Confidence at or above `uncertain_below`.
    Tracking = 1,
    /// Confidence in `[lost_below, uncertain_below)`; like `Lost`, the tracker searches
    /// the whole frame with part of its particles.
    Uncertain = 2,
    /// Confidence below `lost_below`.
    Lost = 0,
}

/// Where the target is after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Estimate {
    /// Centre and half-axes, px, Q16.16; the centre is always inside the frame.
    pub ellipse: Ellipse,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: Q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: Q16,
    /// Bhattacharyya coefficient of the estimate's window against the model, Q16.16 in
    /// `[0, 1]`.
    pub confidence: Q16,
    /// Tracking, uncertain or lost.
    pub status: Status,
}

impl Estimate {
    /// The estimate's box: its ellipse's bounding box, px ([`crate::rect`] gives the
    /// convention).
    pub fn rect(&self) -> Rect {
        self.ellipse.into()
    }

    /// A target at rest on `ellipse`.
    pub(super) const fn at_rest(ellipse: Ellipse, confidence: Q16, status: Status) -> Self {
        Self {
            ellipse,
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            confidence,
            status,
        }
    }
}

/// Where the particles put the target, before its window is judged: a window and a
/// velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Location {
    /// Centre and half-axes, px, Q16.16.
    pub ellipse: Ellipse,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: Q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: Q16,
}

impl Location {
    /// Where particle `p` is.
    fn of(p: &Particle) -> Self {
        Self {
            ellipse: p.ellipse(),
            vx: p.vx,
            vy: p.vy,
        }
    }
}

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// The step's estimate: the particles' location by the configured read-out, its
    /// window's coefficient against the model as the confidence, the status that gives;
    /// the motion innovation followed while tracking, and the model adapted when the
    /// confidence is high.
    pub(super) fn read_out<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> Estimate {
        let location = self.locate();
        let confidence = self.compare(frame, &location.ellipse).rho;
        let estimate = Estimate {
            ellipse: location.ellipse,
            vx: location.vx,
            vy: location.vy,
            confidence,
            status: self.status(confidence),
        };
        self.follow(&estimate);
        self.adapt(frame, &estimate);
        estimate
    }

    /// Where the particles put the target, by the configured [`Readout`].
    fn locate(&self) -> Location {
        match self.config.readout {
            Readout::Mean => self.weighted_mean(|_| true),
            Readout::Best => Location::of(&self.best_particle()),
            Readout::RobustMean(radius) => {
                let best = self.best_particle();
                self.weighted_mean(|p| {
                    (p.x - best.x).abs() <= radius && (p.y - best.y).abs() <= radius
                })
            }
        }
    }

    /// The status a window of coefficient `confidence` gives the estimate.
    fn status(&self, confidence: Q16) -> Status {
        if confidence < self.config.lost_below {
            Status::Lost
        } else if confidence < self.config.uncertain_below {
            Status::Uncertain
        } else {
            Status::Tracking
        }
    }

    /// While tracking, `estimate` is the last confident one and moves the innovation mean
    /// on; otherwise the innovation is unknown.
    fn follow(&mut self, estimate: &Estimate) {
        if estimate.status == Status::Tracking {
            self.state.last_confident = estimate.ellipse;
            self.state.motion_spread = Some(self.next_spread(estimate));
        } else {
            self.state.motion_spread = None;
        }
    }

    /// Blends `estimate`'s window into the colour model at `adapt_rate`, when its
    /// confidence is at least `adapt_above`.
    fn adapt<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, estimate: &Estimate) {
        let rate = self.config.adapt_rate;
        if estimate.confidence < self.config.adapt_above || rate <= Q16::ZERO {
            return;
        }
        let (colour, histograms) = (&mut self.state.model.colour, &mut self.scratch.histograms);
        let pixels = colour.adapt::<Bn, P>(frame, &estimate.ellipse, histograms, rate);
        self.report.read(pixels);
    }

    /// Weighted mean of the particles that `keep` accepts (all weights normalised).
    pub(super) fn weighted_mean(&self, keep: impl Fn(&Particle) -> bool) -> Location {
        let mut sums = [0i64; 6];
        let mut total = 0i64;
        for (p, &w) in self.state.particles.iter().zip(self.state.weights.iter()) {
            if !keep(p) {
                continue;
            }
            let w = w as i64;
            total += w;
            for (s, v) in sums
                .iter_mut()
                .zip([p.x, p.y, p.vx, p.vy, p.size.hx, p.size.hy])
            {
                *s += w * v.to_bits() as i64;
            }
        }
        let [cx, cy, vx, vy, hx, hy] = sums.map(|s| Q16::saturate(s / total.max(1)));
        Location {
            ellipse: Ellipse { cx, cy, hx, hy },
            vx,
            vy,
        }
    }

    /// The particle of largest weight (the last of equal ones).
    fn best_particle(&self) -> Particle {
        let (mut best, mut best_weight) = (Particle::default(), 0u32);
        for (p, &w) in self.state.particles.iter().zip(self.state.weights.iter()) {
            if w >= best_weight {
                (best, best_weight) = (*p, w);
            }
        }
        best
    }
}
