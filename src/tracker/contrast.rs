//! The contrast cue on the object map: how much more a window's box holds the target's
//! colours than the ring around it, the map it is read from, and the box scale calibrated
//! on the first frame.

use super::particle::Particle;
use super::{SizeMeasurement, Tracker, Variant};
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::map::Span;
use crate::window::Ellipse;

/// Steps of the calibration search, at most.
const CALIBRATION_STEPS: usize = 20;

/// Rings the calibration's map reaches, in contrast rings: a coarser map than the
/// per-frame measurement's, measured to hold the sizes better on the real sequences.
const CALIBRATION_RINGS: i32 = 3;

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Mean object probability inside window `e`'s contrast box minus that in the ring
    /// around it, on this frame's map (see [`crate::map::ObjectMap::contrast`]).
    pub(super) fn contrast(&self, e: &Ellipse) -> Q16 {
        let inner = self.contrast_span(e, Q16::ONE);
        let outer = self.contrast_span(e, self.config.contrast_ring);
        self.scratch.map.contrast(&inner, &outer)
    }

    /// The contrast box of window `e` (its bounding box times the calibration), scaled by
    /// `k` about its centre.
    pub(super) fn contrast_span(&self, e: &Ellipse, k: Q16) -> Span {
        let k = self.state.model.calibration.saturating_mul(k);
        let (hx, hy) = (e.hx.saturating_mul(k), e.hy.saturating_mul(k));
        Span {
            x0: e.cx - hx,
            y0: e.cy - hy,
            x1: e.cx + hx,
            y1: e.cy + hy,
        }
    }

    /// Whether the RBPF measures sizes on the object map.
    fn measures_size_by_contrast(&self) -> bool {
        self.config.variant == Variant::Rbpf
            && self.config.size_measurement == SizeMeasurement::Contrast
            && !self.config.freeze_size
    }

    /// The region every particle's contrast ring covers.
    pub(super) fn particle_region(&self) -> Span {
        let outer = |p: &Particle| self.contrast_span(&p.ellipse(), self.config.contrast_ring);
        debug_assert!(N >= 1, "a started tracker has particles");
        let mut region = self.state.particles.first().map(outer).unwrap_or_default();
        for s in self.state.particles.iter().map(outer) {
            region = Span {
                x0: region.x0.min(s.x0),
                y0: region.y0.min(s.y0),
                x1: region.x1.max(s.x1),
                y1: region.y1.max(s.y1),
            };
        }
        region
    }

    /// Builds this frame's object map over `region`.
    pub(super) fn build_map<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, region: &Span) {
        let prob = self.state.model.colour.object_prob();
        let n = self.scratch.map.build::<Bn, P, B>(frame, region, prob);
        self.report.read(n);
    }

    /// The contrast box scale at which `init` has the highest contrast on `frame`, by
    /// steps of `scale_step` from 1 (at most [`CALIBRATION_STEPS`], within `[1/2, 2]`): the
    /// measured sizes are then relative to the box the user gave, whatever the target's
    /// share of it.
    pub(super) fn calibrate<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        init: &Ellipse,
    ) -> Q16 {
        self.state.model.calibration = Q16::ONE;
        if !self.measures_size_by_contrast() && self.derived.contrast_cost.is_none() {
            return Q16::ONE;
        }
        let reach = Q16::from_int(CALIBRATION_RINGS) * self.config.contrast_ring;
        self.build_map(frame, &self.contrast_span(init, reach));
        let step = self.config.scale_step;
        for _ in 0..CALIBRATION_STEPS {
            // The best of one step down, none and one step up (no step on a tie).
            let mut best_contrast = self.contrast(init);
            let mut best_factor = Q16::ONE;
            for factor in [Q16::ONE - step, Q16::ONE + step] {
                let c = self.contrast(&Ellipse {
                    hx: init.hx * factor,
                    hy: init.hy * factor,
                    ..*init
                });
                if c > best_contrast {
                    (best_contrast, best_factor) = (c, factor);
                }
            }
            if best_factor == Q16::ONE {
                break;
            }
            let calibration = self.state.model.calibration * best_factor;
            self.state.model.calibration = calibration.clamp(Q16::HALF, Q16::from_int(2));
        }
        self.state.model.calibration
    }
}
