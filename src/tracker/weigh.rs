//! Stage 2, weigh: each particle's window scored by its cues, the costs turned into
//! likelihoods and the weights normalised; and, last in a step, resampling when the
//! weights have degenerated.

use super::{CueMix, Tracker, Variant};
use crate::colour::Match;
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::likelihood::{exp_neg, LIKELIHOOD_BITS};
use crate::resample::{
    effective_sample_size_at_least, normalise, replicate, resample, Normalised, WEIGHT_TOTAL,
    WEIGHT_TOTAL_LOG2,
};
use crate::window::Ellipse;

/// Bits dropped from a normalised weight (`<= 2^24`) times a likelihood (`< 2^16`) so
/// that the product fits a `u32`.
const WEIGHT_PRODUCT_SHIFT: u32 = WEIGHT_TOTAL_LOG2 + LIKELIHOOD_BITS - u32::BITS;

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Multiplies every particle's weight by the likelihood of its window and normalises
    /// the weights (uniform, and counted, if they all vanished).
    pub(super) fn weigh<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) {
        if self.derived.contrast_cost.is_some() {
            self.build_map(frame, &self.particle_region());
        }
        if self.config.variant == Variant::Rbpf {
            // Boundary point by boundary point across the particles: their samples of one
            // point lie close together, so the memo computes each pixel's gradient about
            // once (the values are those of `GradientCue::evaluate`).
            let particles = &self.state.particles;
            self.derived.cue.evaluate_each(
                frame,
                |i| {
                    debug_assert!(i < N, "window {i} of {N}");
                    particles.get(i).map(|p| p.ellipse()).unwrap_or_default()
                },
                &mut self.scratch.cues,
                &mut self.scratch.memo,
            );
        }
        // The frame's smallest cost, taken off every particle's before `exp`.
        let mut offset = Q16::MAX;
        for i in 0..N {
            let e = self.state.particles[i].ellipse();
            let score = self.colour_score(frame, &e);
            let colour = self.colour_cost(&e, score);
            self.scratch.colour_costs[i] = colour;
            offset = offset.min(colour + self.gradient_cost(self.scratch.cues[i]));
        }
        for i in 0..N {
            let gradient = self.gradient_cost(self.scratch.cues[i]);
            let likelihood = self.likelihood(self.scratch.colour_costs[i], gradient, offset);
            let weight = self.state.weights[i] as u64 * likelihood as u64;
            self.state.weights[i] = (weight >> WEIGHT_PRODUCT_SHIFT) as u32;
        }
        if normalise(&mut self.state.weights) == Normalised::AllZero {
            let recoveries = &mut self.report.weight_recoveries;
            *recoveries = recoveries.saturating_add(1);
        }
    }

    /// The colour score of window `e` ([`crate::colour::Match::score`]), its pixels
    /// counted.
    fn colour_score<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, e: &Ellipse) -> Q16 {
        let histograms = &mut self.scratch.histograms;
        let (score, pixels) = self.state.model.colour.score::<Bn, P>(frame, e, histograms);
        self.report.read(pixels);
        score
    }

    /// Window `e` compared with the colour model, its pixels counted.
    pub(super) fn compare<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        e: &Ellipse,
    ) -> Match {
        let histograms = &mut self.scratch.histograms;
        let m = self
            .state
            .model
            .colour
            .compare::<Bn, P>(frame, e, histograms);
        self.report.read(m.pixels);
        m
    }

    /// The colour cost of window `e` of colour score `score`, Q16.16: the score's, plus the
    /// contrast cue's when it is configured.
    pub(super) fn colour_cost(&self, e: &Ellipse, score: Q16) -> Q16 {
        let colour = self.derived.colour_cost.cost(Q16::ONE - score);
        match self.derived.contrast_cost {
            Some(scale) => colour + scale.cost(Q16::ONE - self.contrast(e)),
            None => colour,
        }
    }

    /// The gradient cost of a window of gradient cue `g` (RBPF; 0 for the colour PF),
    /// Q16.16: `(1 - g)^2 / (2 gradient_sigma^2)`.
    pub(super) fn gradient_cost(&self, g: Q16) -> Q16 {
        match self.config.variant {
            Variant::ColourPf => Q16::ZERO,
            Variant::Rbpf => {
                let miss = Q16::ONE - g;
                self.derived.gradient_cost.cost(miss * miss)
            }
        }
    }

    /// Likelihood, Q0.16 in `0..=65535`, of a window of colour cost `colour` and gradient
    /// cost `gradient`: `exp(-(colour + gradient - offset))`, `offset` the frame's
    /// smallest cost (so the best window has 65535 and sharp cues never underflow the
    /// table for every window at once); with [`CueMix::Average`], the RBPF paper's
    /// `a exp(-colour) + (1 - a) exp(-gradient)`, no offset.
    pub(super) fn likelihood(&self, colour: Q16, gradient: Q16, offset: Q16) -> u32 {
        match (self.config.variant, self.config.cue_mix) {
            (Variant::Rbpf, CueMix::Average(a)) => {
                let a = a.to_bits() as u64; // Q16.16 in 0..=1
                let rest = Q16::ONE.to_bits() as u64 - a;
                let mix = a * exp_neg(colour) as u64 + rest * exp_neg(gradient) as u64;
                (mix >> Q16::FRAC_BITS) as u32
            }
            _ => exp_neg(colour + gradient - offset),
        }
    }

    /// Resamples when the effective sample size is below `resample_below * N`; the
    /// weights are uniform afterwards either way.
    pub(super) fn resample_if_degenerate(&mut self) {
        let threshold = self.config.resample_below.mul_int(N as i32);
        self.scratch.resampled = false;
        if effective_sample_size_at_least(&self.state.weights, threshold) {
            return;
        }
        let scheme = self.config.resampling;
        debug_assert!(self.state.rng.is_some(), "a step of an unstarted tracker");
        let Some(rng) = self.state.rng.as_mut() else {
            return;
        };
        let (weights, indices) = (&mut self.state.weights, &mut self.scratch.indices);
        if resample(scheme, weights, rng, indices).is_ok() {
            replicate(&mut self.state.particles, indices, &mut self.scratch.counts);
            self.scratch.resampled = true;
        }
        self.state.weights = [WEIGHT_TOTAL / N as u32; N];
    }
}
