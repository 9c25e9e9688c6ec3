//! Stage 4, estimate: where the particles put the target, how sure they are of it (the
//! score: how well that window matches the colour model, less how widely the particles
//! disagree; through the variant's table the confidence, which sets the status), and the
//! model's adaptation.

use super::calibration::Calibration;
use super::particle::Particle;
use super::{Readout, Tracker};
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::rect::Rect;
use crate::window::Ellipse;

/// How sure the tracker is of its estimate, numbered from least to most sure (the C
/// API's `rbt_status` numbers).
///
/// `Lost` is 0, so that an unstarted tracker ([`Tracker::unstarted`]) is all zero bits and
/// a `static` of one takes no flash.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Status {
    /// Confidence at or above `uncertain_below`.
    Tracking = 2,
    /// Confidence in `[lost_below, uncertain_below)`; like `Lost`, a particle filter
    /// searches the whole frame with part of its particles.
    Uncertain = 1,
    /// Confidence below `lost_below` (the correlation filter: and, once lost, while it
    /// searches, until `uncertain_below`).
    Lost = 0,
}

impl Status {
    /// The status of `confidence`: lost below `lost_below`, uncertain below
    /// `uncertain_below`, else tracking; the same rule for every tracker.
    pub const fn of(confidence: Q16, lost_below: Q16, uncertain_below: Q16) -> Self {
        if confidence.to_bits() < lost_below.to_bits() {
            Status::Lost
        } else if confidence.to_bits() < uncertain_below.to_bits() {
            Status::Uncertain
        } else {
            Status::Tracking
        }
    }
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
    /// The tracker's own score of the estimate, Q16.16 in `[0, 1]`: a particle filter's
    /// Bhattacharyya coefficient of the estimate's window against the model, less
    /// `spread_penalty` times the particles' spread ([`super::Config::spread_penalty`]);
    /// the correlation filter's merged response margin (its peak less the best value of
    /// the moves more than 2 cells from it, [`super::CfTracker`]).
    pub score: Q16,
    /// The score through the tracker's [`super::Calibration`]: about the chance that the
    /// estimate's box overlaps the target's by an IoU of at least 0.5, the same for every
    /// tracker at its defaults; it sets the status. Q16.16 in `[0, 1]`.
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

    /// The first box's estimate: at rest on `ellipse`, tracking, of score 1.
    pub(super) const fn first(ellipse: Ellipse, calibration: &Calibration) -> Self {
        Self {
            ellipse,
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            score: Q16::ONE,
            confidence: calibration.confidence(Q16::ONE),
            status: Status::Tracking,
        }
    }

    /// A lost target at rest on `ellipse`, of score and confidence 0.
    pub(super) const fn lost_at(ellipse: Ellipse) -> Self {
        Self {
            ellipse,
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            score: Q16::ZERO,
            confidence: Q16::ZERO,
            status: Status::Lost,
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
    /// window's coefficient against the model less the spread's penalty as the
    /// confidence, the status that gives; the motion innovation followed while tracking,
    /// and the model adapted when the confidence is high.
    pub(super) fn read_out<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> Estimate {
        let location = self.locate();
        let rho = self.compare(frame, &location.ellipse).rho;
        let penalty = self.config.spread_penalty * self.spread(&location.ellipse);
        let score = rho.saturating_sub(penalty).clamp(Q16::ZERO, Q16::ONE);
        let confidence = self.config.variant.calibration().confidence(score);
        let estimate = Estimate {
            ellipse: location.ellipse,
            vx: location.vx,
            vy: location.vy,
            score,
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
        Status::of(
            confidence,
            self.config.lost_below,
            self.config.uncertain_below,
        )
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
        if estimate.score < self.config.adapt_above || rate <= Q16::ZERO {
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

    /// The particles' weighted mean distance `|dx| + |dy|` from the centre of `e`, over
    /// its mean half-axis (at least 1 px), Q16.16: 0 when they agree, about 1 when they
    /// scatter over the target's size, more when they search the frame.
    fn spread(&self, e: &Ellipse) -> Q16 {
        let (mut sum, mut total) = (0i64, 0i64);
        for (p, &w) in self.state.particles.iter().zip(self.state.weights.iter()) {
            let dx = p.x.saturating_sub(e.cx).abs().to_bits() as i64;
            let dy = p.y.saturating_sub(e.cy).abs().to_bits() as i64;
            // Weights sum to 2^24 and distances are below 2^32: no overflow.
            sum += w as i64 * (dx + dy);
            total += w as i64;
        }
        let distance = Q16::saturate(sum / total.max(1));
        let half = Q16::saturate((e.hx.to_bits() as i64 + e.hy.to_bits() as i64) / 2);
        distance.saturating_div(half.max(Q16::ONE))
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

#[cfg(test)]
mod tests {
    use super::super::particle::Bounds;
    use super::super::{Config, Status, Tracker, Variant};
    use super::*;
    use crate::image::{Gray8, Luma64};

    #[test]
    fn the_status_is_the_confidence_against_the_two_thresholds() {
        let (lost, uncertain) = (Q16::from_ratio(1, 5), Q16::from_ratio(1, 2));
        let just_below = |q: Q16| Q16::from_bits(q.to_bits() - 1);
        let cases = [
            (Q16::ZERO, Status::Lost),
            (just_below(lost), Status::Lost),
            (lost, Status::Uncertain),
            (just_below(uncertain), Status::Uncertain),
            (uncertain, Status::Tracking),
            (Q16::ONE, Status::Tracking),
        ];
        for (confidence, want) in cases {
            assert_eq!(
                Status::of(confidence, lost, uncertain),
                want,
                "{confidence:?}"
            );
        }
    }

    /// A bright 20 px square on a dark 64x48 frame, and the ellipse on it.
    fn square() -> ([u8; 64 * 48], Ellipse) {
        let mut buf = [40u8; 64 * 48];
        for y in 14..34 {
            buf[y * 64 + 22..y * 64 + 42].fill(220);
        }
        let e = Ellipse::new(
            Q16::from_f64(31.5),
            Q16::from_f64(23.5),
            Q16::from_int(10),
            Q16::from_int(10),
        );
        (buf, e)
    }

    /// The spread by its definition, in f64: weighted mean `|dx| + |dy|` over the mean
    /// half-axis.
    fn spread_f64(particles: &[Particle], weights: &[u32], e: &Ellipse) -> f64 {
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        let distance: f64 = particles
            .iter()
            .zip(weights)
            .map(|(p, &w)| {
                let d = (p.x.to_f64() - e.cx.to_f64()).abs() + (p.y.to_f64() - e.cy.to_f64()).abs();
                w as f64 * d
            })
            .sum::<f64>()
            / total;
        distance / ((e.hx.to_f64() + e.hy.to_f64()) / 2.0)
    }

    #[test]
    fn the_confidence_is_the_coefficient_less_the_spread_penalty() {
        let (buf, init) = square();
        let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        for variant in [Variant::ColourPf, Variant::Rbpf] {
            let config = Config::new(variant);
            let mut t = Tracker::<Luma64, 50, 64>::new(config, &frame, init).unwrap();
            let bounds = Bounds::for_frame(64, 48, config.min_half_axis);
            t.propagate(&bounds);
            t.weigh(&frame);
            let location = t.locate();
            let want = spread_f64(&t.state.particles, &t.state.weights, &location.ellipse);
            let got = t.spread(&location.ellipse).to_f64();
            assert!(
                (got - want).abs() < 1e-3,
                "{variant:?}: {got} against {want}"
            );
            assert!(want > 0.01, "the particles moved: {want}");
            let rho = t.compare(&frame, &location.ellipse).rho;
            let e = t.read_out(&frame);
            let penalty = config.spread_penalty.to_f64() * want;
            assert!(
                (e.score.to_f64() - (rho.to_f64() - penalty)).abs() < 1e-3,
                "{variant:?}: {e:?}, rho {rho}, penalty {penalty}"
            );
        }
    }

    #[test]
    fn scattered_particles_are_not_tracking_on_a_matching_window() {
        let (buf, init) = square();
        let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        for penalty in [Q16::ZERO, Config::new(Variant::ColourPf).spread_penalty] {
            let mut config = Config::new(Variant::ColourPf);
            config.spread_penalty = penalty;
            let mut t = Tracker::<Luma64, 50, 64>::new(config, &frame, init).unwrap();
            // Half the particles on the square, half spread over the frame's corners: their
            // weighted mean is still near the square.
            for (i, p) in t.state.particles.iter_mut().enumerate() {
                if i % 2 == 1 {
                    let corner = [(2, 2), (61, 2), (2, 45), (61, 45)][i / 2 % 4];
                    p.x = Q16::from_int(corner.0);
                    p.y = Q16::from_int(corner.1);
                }
            }
            let e = t.read_out(&frame);
            if penalty == Q16::ZERO {
                assert_eq!(e.status, Status::Tracking, "{e:?}");
            } else {
                assert_eq!(e.status, Status::Lost, "{e:?}");
                assert!(t.spread(&e.ellipse) > Q16::from_int(2));
            }
        }
    }

    #[test]
    fn the_spread_saturates_on_extreme_positions() {
        let (buf, init) = square();
        let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        let mut t =
            Tracker::<Luma64, 4, 64>::new(Config::new(Variant::Rbpf), &frame, init).unwrap();
        t.state.particles[0].x = Q16::MAX;
        t.state.particles[1].y = Q16::MIN;
        let tiny = Ellipse::new(Q16::MIN, Q16::MAX, Q16::ZERO, Q16::ZERO);
        assert_eq!(t.spread(&tiny), Q16::MAX);
        assert!(t.spread(&init) > Q16::ONE);
    }
}
