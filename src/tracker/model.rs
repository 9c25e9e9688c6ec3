//! The learnt target model: saved, restored, and kept while the tracker moves onto a
//! window a detector found.

use super::{check_init, ConfigError, Tracker};
use crate::colour::ColourModel;
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::window::Ellipse;

/// What a tracker has learnt of its target on the first frame (and since, with
/// [`super::Config::adapt_rate`]): the colour model against its surroundings, and the
/// scale of the contrast boxes. About 19 KiB with 512 bins: read it in place with
/// [`Tracker::model`], and give it back by reference to [`Tracker::set_model`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TargetModel<const B: usize> {
    /// The target's colours against its surroundings.
    pub(super) colour: ColourModel<B>,
    /// Scale of the contrast boxes relative to the windows' bounding boxes, Q16.16: the
    /// scale at which the first window had the highest contrast.
    pub(super) calibration: Q16,
}

impl<const B: usize> TargetModel<B> {
    /// Nothing learnt, every bit zero: an unstarted tracker's model, and a place to save
    /// one into (a `static` of it lands in `.bss`); [`Tracker::set_model`] refuses it.
    pub const UNSET: Self = Self {
        colour: ColourModel::UNSET,
        calibration: Q16::ZERO,
    };
}

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// Moves the tracker onto `at` in `frame` (say a box a detector found) and keeps what
    /// it learnt: the target model and the ground plane. The particles, their velocities
    /// and size covariance start afresh as in [`Tracker::reset`], which learns a new
    /// model instead. An unstarted tracker, having no model to keep, is reset.
    ///
    /// # Errors
    /// [`ConfigError::InitialTooSmall`] or [`ConfigError::InitialOutside`] as for
    /// [`Tracker::start`]; the tracker is unchanged.
    pub fn relocate<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        at: impl Into<Ellipse>,
    ) -> Result<(), ConfigError> {
        if self.state.rng.is_none() {
            return self.reset(frame, at);
        }
        let at = at.into();
        check_init(&self.config, frame, &at)?;
        let size_cov = self.initial_size_cov()?;
        self.place(at, size_cov);
        Ok(())
    }

    /// The learnt target model, to save (`clone_from` into a [`TargetModel::UNSET`] of your
    /// own) and later give to [`Tracker::set_model`] of this or another tracker.
    pub fn model(&self) -> &TargetModel<B> {
        &self.state.model
    }

    /// Replaces the target model by `model`, learnt by a tracker of the same colour
    /// settings (the [`super::Config`] fields `split_halves`, `background_weighting`,
    /// `background_floor`, `ring_scale` and `pixels_per_window`); the particles stay where
    /// they are ([`Tracker::relocate`] moves them).
    ///
    /// # Errors
    /// [`ConfigError::ModelSettings`] if `model` was learnt under other colour settings
    /// (or this tracker has not started); the tracker is then unchanged.
    pub fn set_model(&mut self, model: &TargetModel<B>) -> Result<(), ConfigError> {
        let started = self.state.rng.is_some();
        if !started || *model.colour.settings() != self.config.colour() {
            return Err(ConfigError::ModelSettings);
        }
        self.state.model.clone_from(model);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Luma64};
    use crate::rect::Rect;
    use crate::tracker::{Config, Status, Variant};
    use std::vec;
    use std::vec::Vec;

    /// A 96x48 grey frame with a bright square at `x0` and a mid-grey one at `x1`.
    fn two_squares(x0: usize, x1: usize) -> Vec<u8> {
        let mut buf = vec![30u8; 96 * 48];
        for y in 14..34 {
            buf[y * 96 + x0..y * 96 + x0 + 20].fill(230);
            buf[y * 96 + x1..y * 96 + x1 + 20].fill(130);
        }
        buf
    }

    fn view(buf: &[u8]) -> ImageView<'_, Gray8> {
        ImageView::new(buf, 96, 48, 96).unwrap()
    }

    #[test]
    fn relocate_keeps_the_model_and_reset_learns_a_new_one() {
        let buf = two_squares(10, 60);
        let frame = view(&buf);
        let config = Config::new(Variant::Rbpf);
        let mut t =
            Tracker::<Luma64, 50, 64>::new(config, &frame, Rect::new(10, 14, 20, 20)).unwrap();
        t.step(&frame);
        let learnt = t.model().clone();
        // A box a detector found: the bright square, moved.
        let moved = two_squares(40, 70);
        let found = Rect::new(40, 14, 20, 20);
        t.relocate(&view(&moved), found).unwrap();
        assert_eq!(*t.model(), learnt);
        assert_eq!(t.estimate().ellipse, Ellipse::from(found));
        assert!(t.particles().iter().all(|p| p.x == Ellipse::from(found).cx));
        let e = t.step(&view(&moved));
        assert_eq!(e.status, Status::Tracking);
        assert!((e.rect().px().0 - 40).abs() <= 2, "{e:?}");
        // A box off the frame is refused and changes nothing.
        let before = t.clone();
        assert_eq!(
            t.relocate(&view(&moved), Rect::new(200, 14, 20, 20)),
            Err(ConfigError::InitialOutside)
        );
        assert_eq!(t.particles(), before.particles());
        assert_eq!(t.estimate(), before.estimate());
        // A reset on the other square learns its colours.
        t.reset(&view(&moved), Rect::new(70, 14, 20, 20)).unwrap();
        assert_ne!(*t.model(), learnt);
    }

    #[test]
    fn a_saved_model_restores_into_a_tracker_of_the_same_colour_settings() {
        let buf = two_squares(10, 60);
        let frame = view(&buf);
        let config = Config::new(Variant::ColourPf);
        let bright = Rect::new(10, 14, 20, 20);
        let saved = Tracker::<Luma64, 50, 64>::new(config, &frame, bright)
            .unwrap()
            .model()
            .clone();
        let mut other =
            Tracker::<Luma64, 50, 64>::new(config, &frame, Rect::new(60, 14, 20, 20)).unwrap();
        assert_ne!(*other.model(), saved);
        other.set_model(&saved).unwrap();
        assert_eq!(*other.model(), saved);
        // With the bright square's model, a relocation onto it tracks it.
        other.relocate(&frame, bright).unwrap();
        assert_eq!(other.step(&frame).status, Status::Tracking);

        let mut halves = config;
        halves.split_halves = !config.split_halves;
        let mut unlike =
            Tracker::<Luma64, 50, 64>::new(halves, &frame, Rect::new(60, 14, 20, 20)).unwrap();
        let kept = unlike.model().clone();
        assert_eq!(unlike.set_model(&saved), Err(ConfigError::ModelSettings));
        assert_eq!(*unlike.model(), kept);
        let mut unstarted = Tracker::<Luma64, 50, 64>::unstarted();
        assert_eq!(unstarted.set_model(&saved), Err(ConfigError::ModelSettings));
        let mut slot = TargetModel::UNSET;
        slot.clone_from(other.model());
        assert_eq!(slot, saved);
        assert_eq!(
            other.set_model(&TargetModel::UNSET),
            Err(ConfigError::ModelSettings)
        );
    }
}
