//! The per-frame memo of squared gradient magnitudes, and the sampler that reads the
//! gradient cue's samples through it.

use super::gradient::{gradient_sq, interior_gradient_sq};
use super::{GradientCue, Sampler};
use crate::image::{Crosses, ImageView, PixelFormat};

/// Slots of a [`GradientMemo`].
pub const MEMO_SLOTS: usize = 1024;

/// A per-frame memo of squared gradient magnitudes for [`GradientCue::evaluate_memo`] and
/// [`GradientCue::evaluate_each`]: [`MEMO_SLOTS`] direct-mapped slots keyed by pixel
/// (slot `(x + 32 y) mod 1024`: any 32 x 32 block of pixels, such as the samples of one
/// boundary point across a particle cloud, maps to distinct slots), each holding the
/// pixel's index in the frame tagged with an 8-bit frame generation and
/// `min(gx^2 + gy^2, 65535)` (exact for the cue whenever the saturation is at most 255,
/// whose square fits: larger squares all score the saturation). A look-up is a hash, a
/// load and a compare; a miss computes the gradient and replaces the slot's entry. Values
/// are only ever read back for the same pixel of the same generation, so results never
/// depend on the memo. 6 KiB; frames of `2^24` pixels or more, and saturations above 255,
/// bypass it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GradientMemo {
    /// `generation << 24 | (y width + x)`; never matches while the slot is empty (tags
    /// start at generation 1).
    keys: [u32; MEMO_SLOTS],
    values: [u16; MEMO_SLOTS],
    /// The current generation in the top 8 bits (`1..=255`).
    tag: u32,
}

#[cfg(feature = "defmt")]
impl defmt::Format for GradientMemo {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(f, "GradientMemo {{ generation: {} }}", self.tag >> 24)
    }
}

impl Default for GradientMemo {
    fn default() -> Self {
        Self::new()
    }
}

impl GradientMemo {
    /// An empty memo.
    pub const fn new() -> Self {
        Self {
            keys: [0; MEMO_SLOTS],
            values: [0; MEMO_SLOTS],
            tag: 1 << 24,
        }
    }

    /// Every bit zero: a memo that holds nothing valid until [`GradientMemo::clear`] (an
    /// unstarted tracker's, so that the tracker can sit in `.bss`).
    pub(crate) const UNSTARTED: Self = Self {
        keys: [0; MEMO_SLOTS],
        values: [0; MEMO_SLOTS],
        tag: 0,
    };

    /// Empties the memo in place: what [`GradientMemo::new`] gives.
    pub fn clear(&mut self) {
        self.keys.fill(0);
        self.values.fill(0);
        self.tag = 1 << 24;
    }

    /// Forgets every entry (in constant time, by moving to the next generation; every
    /// 255 frames the slots are cleared). Call it whenever the frame changes.
    pub fn start_frame(&mut self) {
        self.tag = self.tag.wrapping_add(1 << 24);
        if self.tag == 0 {
            self.keys = [0; MEMO_SLOTS];
            self.tag = 1 << 24;
        }
    }

    /// Whether frames of this size fit the 24-bit pixel index.
    fn serves<P: PixelFormat>(&self, img: &ImageView<'_, P>) -> bool {
        img.width() * img.height() < 1 << 24
    }
}

impl GradientCue {
    /// Whether `memo` can serve this cue on `img` (frame below `2^24` pixels, saturation
    /// squared below `2^16`).
    pub(super) fn memo_serves<P: PixelFormat>(
        &self,
        memo: &GradientMemo,
        img: &ImageView<'_, P>,
    ) -> bool {
        memo.serves(img) && self.saturation <= 255
    }
}

/// Reads gradients through a [`GradientMemo`].
pub(super) struct Memoised<'m> {
    memo: &'m mut GradientMemo,
    width: u32,
}

impl<'m> Memoised<'m> {
    pub(super) fn new<P: PixelFormat>(memo: &'m mut GradientMemo, img: &ImageView<'_, P>) -> Self {
        Self {
            memo,
            width: img.width() as u32,
        }
    }

    /// The slot of in-frame pixel `(x, y)` and its key.
    #[inline(always)]
    fn slot(&self, x: i32, y: i32) -> (usize, u32) {
        let (x, y) = (x as u32, y as u32);
        // y width + x < 2^24 for the frames the memo serves: no bit reaches the tag.
        let key = self.memo.tag | y.wrapping_mul(self.width).wrapping_add(x);
        let slot = (x.wrapping_add(y << 5) as usize) & (MEMO_SLOTS - 1);
        (slot, key)
    }

    /// The memo's value in `slot` if it is `key`'s.
    #[inline(always)]
    fn hit(&self, slot: usize, key: u32) -> Option<u32> {
        let slot = slot & (MEMO_SLOTS - 1);
        (self.memo.keys[slot] == key).then(|| self.memo.values[slot] as u32)
    }

    /// Stores `value`, saturated to 16 bits, for `key` in `slot`; returns the stored value.
    #[inline(always)]
    fn store(&mut self, slot: usize, key: u32, value: u32) -> u32 {
        let slot = slot & (MEMO_SLOTS - 1);
        let value = value.min(u16::MAX as u32);
        self.memo.keys[slot] = key;
        self.memo.values[slot] = value as u16;
        value
    }
}

/// [`interior_gradient_sq`] out of line: the memo's miss path, kept out of the look-up
/// loop so that its registers stay free.
#[inline(never)]
fn interior_miss<P: PixelFormat>(crosses: &Crosses<'_, P>, x: i32, y: i32) -> u32 {
    interior_gradient_sq(crosses, x, y)
}

/// [`gradient_sq`] out of line (the memo's miss path at the frame border).
#[inline(never)]
fn clamped_miss<P: PixelFormat>(img: &ImageView<'_, P>, x: i32, y: i32) -> u32 {
    gradient_sq(img, x, y)
}

impl<P: PixelFormat> Sampler<P> for Memoised<'_> {
    #[inline(always)]
    fn interior(&mut self, crosses: &Crosses<'_, P>, x: i32, y: i32) -> u32 {
        let (slot, key) = self.slot(x, y);
        match self.hit(slot, key) {
            Some(value) => value,
            None => self.store(slot, key, interior_miss(crosses, x, y)),
        }
    }
    #[inline(always)]
    fn clamped(&mut self, img: &ImageView<'_, P>, x: i32, y: i32) -> u32 {
        let (slot, key) = self.slot(x, y);
        match self.hit(slot, key) {
            Some(value) => value,
            None => self.store(slot, key, clamped_miss(img, x, y)),
        }
    }
}
