//! A target colour model: the normalised histogram of the target's window and its square
//! roots, adapted by blending in later windows.

use super::{Histogram, PROB_ONE};
use crate::fixed::{sqrt_q8, Q16};

/// `v <- (1 - alpha) v + alpha p` bin by bin, `v` and `p` (the normalised counts of
/// `hist`) Q0.30, `alpha` Q16.16 clamped to `[0, 1]`; each bin rounded to nearest.
pub(crate) fn blend<const B: usize>(v: &mut [u32; B], hist: &Histogram<B>, alpha: Q16) {
    let (one, half) = (Q16::ONE.to_bits() as u64, Q16::HALF.to_bits() as u64);
    let a = alpha.clamp(Q16::ZERO, Q16::ONE).to_bits() as u64; // 0..=one
    for q in v.iter_mut() {
        *q = ((*q as u64 * (one - a) + half) >> Q16::FRAC_BITS) as u32;
    }
    for &u in hist.touched() {
        let u = u as usize;
        let p = hist.probability(u) as u64;
        if let Some(q) = v.get_mut(u) {
            *q = q
                .saturating_add(((p * a + half) >> Q16::FRAC_BITS) as u32)
                .min(PROB_ONE);
        }
    }
}

/// A target colour model: normalised histogram `q` and `sqrt(q)`, for `B` bins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Model<const B: usize> {
    /// `q_u`, Q0.30; sums to about `PROB_ONE` (0 for an empty model).
    q: [u32; B],
    /// `sqrt(q_u)`, Q0.23 (`sqrt_q8` of `q_u`).
    sqrt_q: [u32; B],
}

#[cfg(feature = "defmt")]
impl<const B: usize> defmt::Format for Model<B> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(f, "Model {{ bins: {} }}", B)
    }
}

impl<const B: usize> Default for Model<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const B: usize> Model<B> {
    /// The empty model: every coefficient against it is 0.
    pub const fn new() -> Self {
        Self {
            q: [0; B],
            sqrt_q: [0; B],
        }
    }

    /// The model of a histogram's normalised counts (empty if the histogram is).
    pub fn from_histogram(hist: &Histogram<B>) -> Self {
        let mut m = Self::new();
        m.set(hist);
        m
    }

    /// Empties the model in place.
    pub fn clear(&mut self) {
        self.q.fill(0);
        self.sqrt_q.fill(0);
    }

    /// Replaces the model with `hist`'s normalised counts.
    pub fn set(&mut self, hist: &Histogram<B>) {
        self.q = [0; B];
        self.sqrt_q = [0; B];
        for &u in hist.touched() {
            let u = u as usize;
            let p = hist.probability(u);
            if let (Some(q), Some(s)) = (self.q.get_mut(u), self.sqrt_q.get_mut(u)) {
                *q = p;
                *s = sqrt_q8(p);
            }
        }
    }

    /// The adaptive update `q <- (1 - alpha) q + alpha p`, `p` the normalised counts of
    /// `hist`, `alpha` Q16.16 clamped to `[0, 1]`; recomputes `sqrt(q)`. An empty `hist`
    /// leaves the model unchanged. Cost: `B` multiplies and square roots, one division per
    /// touched bin.
    pub fn update(&mut self, hist: &Histogram<B>, alpha: Q16) {
        if hist.is_empty() {
            return;
        }
        blend(&mut self.q, hist, alpha);
        for (s, &q) in self.sqrt_q.iter_mut().zip(self.q.iter()) {
            *s = sqrt_q8(q);
        }
    }

    /// `q_u` of `bin`, Q0.30 (`0..=PROB_ONE`); 0 for `bin >= B`.
    pub fn q(&self, bin: usize) -> u32 {
        self.q.get(bin).copied().unwrap_or(0)
    }

    /// `sqrt(q_u)` of `bin`, Q0.23 (`0..=2^23`); 0 for `bin >= B`.
    pub fn sqrt_q(&self, bin: usize) -> u32 {
        self.sqrt_q.get(bin).copied().unwrap_or(0)
    }

    /// Every `q_u`, Q0.30.
    pub fn probabilities(&self) -> &[u32; B] {
        &self.q
    }

    /// Every `sqrt(q_u)`, Q0.23.
    pub fn sqrt_table(&self) -> &[u32; B] {
        &self.sqrt_q
    }

    /// Whether the model has no mass.
    pub fn is_empty(&self) -> bool {
        self.q.iter().all(|&q| q == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adaptive_update_blends() {
        let mut a = Histogram::<64>::new();
        a.add(1, 3000);
        a.add(2, 1000);
        let mut b = Histogram::<64>::new();
        b.add(2, 500);
        b.add(3, 500);
        let mut m = Model::from_histogram(&a);
        let before = m.clone();
        m.update(&b, Q16::ZERO);
        assert_eq!(m, before);
        m.update(&b, Q16::from_f64(0.25));
        let f = |u| m.q(u) as f64 / PROB_ONE as f64;
        assert!((f(1) - 0.5625).abs() < 1e-6);
        assert!((f(2) - (0.1875 + 0.125)).abs() < 1e-6);
        assert!((f(3) - 0.125).abs() < 1e-6);
        let s = m.sqrt_q(3) as f64 / (1u32 << 23) as f64;
        assert!((s - 0.125f64.sqrt()).abs() < 1e-5);
        m.update(&b, Q16::from_int(3)); // clamped to 1
        assert_eq!(m, Model::from_histogram(&b));
        assert!((b.bhattacharyya(&m).to_f64() - 1.0).abs() < 1e-4);
    }
}
