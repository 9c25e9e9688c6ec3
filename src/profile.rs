//! Profiling: the cycle-counter hook a board supplies and the per-stage counts of a
//! tracker step.
//!
//! The caller supplies the clock: DWT `CYCCNT` on a Cortex-M board, SysTick under QEMU,
//! a monotonic clock on the host. [`CycleCounter`] is one method, with a blanket impl for
//! `&mut T` so a counter can be lent without giving it away.
//!
//! # Examples
//! ```
//! use rbtrack::profile::CycleCounter;
//! struct Ticks(u32);
//! impl CycleCounter for Ticks {
//!     fn now(&mut self) -> u32 {
//!         self.0 += 10;
//!         self.0
//!     }
//! }
//! let mut t = Ticks(0);
//! let a = t.now();
//! assert_eq!((&mut t).now().wrapping_sub(a), 10);
//! ```

/// A free-running counter, read at stage boundaries. Only differences are used, so
/// wrap-around is harmless as long as one stage takes fewer than 2^32 counts.
pub trait CycleCounter {
    /// The counter's current value (cycles or any other fixed tick).
    fn now(&mut self) -> u32;
}

impl<T: CycleCounter + ?Sized> CycleCounter for &mut T {
    fn now(&mut self) -> u32 {
        T::now(self)
    }
}

/// A counter that always reads zero: profiling off, at no cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoCounter;

impl CycleCounter for NoCounter {
    fn now(&mut self) -> u32 {
        0
    }
}

/// Counts spent in each stage of one step, in the caller's counter units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StageCycles {
    /// Drawing the particles' motion and predicting their leaves.
    pub propagate: u32,
    /// Colour histograms, Bhattacharyya coefficients and gradient cues of all particles.
    pub weigh: u32,
    /// Effective sample size and, when it is low, resampling.
    pub resample: u32,
    /// Scale measurement and Kalman update (RBPF), model adaptation (both).
    pub update: u32,
    /// Read-out of the estimate and its confidence.
    pub estimate: u32,
}

impl StageCycles {
    /// Sum of all stages.
    pub fn total(&self) -> u32 {
        self.propagate
            .saturating_add(self.weigh)
            .saturating_add(self.resample)
            .saturating_add(self.update)
            .saturating_add(self.estimate)
    }
}

/// Counts spent in each stage of one step of the correlation-filter tracker
/// ([`crate::tracker::CfTracker`]), in the caller's counter units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CfStageCycles {
    /// Resampling the search region and its cells' features.
    pub features: u32,
    /// The translation filter's response.
    pub filter: u32,
    /// The colour map and the merged response's peak and margin.
    pub colour: u32,
    /// The scale filter's samples and response.
    pub scale: u32,
    /// The three models' learning.
    pub learn: u32,
    /// The searches of other regions while the target is lost (their features, filter and
    /// colour responses).
    pub redetect: u32,
}

impl CfStageCycles {
    /// Sum of all stages.
    pub fn total(&self) -> u32 {
        self.search()
            .saturating_add(self.scale)
            .saturating_add(self.learn)
            .saturating_add(self.redetect)
    }

    /// One region's search: its features, filter and colour responses.
    pub(crate) fn search(&self) -> u32 {
        self.features
            .saturating_add(self.filter)
            .saturating_add(self.colour)
    }
}

/// Times consecutive stages: each [`Stopwatch::lap`] returns the counts since the last.
pub(crate) struct Stopwatch<C: CycleCounter> {
    counter: C,
    last: u32,
}

impl<C: CycleCounter> Stopwatch<C> {
    pub(crate) fn start(mut counter: C) -> Self {
        let last = counter.now();
        Self { counter, last }
    }

    pub(crate) fn lap(&mut self) -> u32 {
        let now = self.counter.now();
        let spent = now.wrapping_sub(self.last);
        self.last = now;
        spent
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Wrapping(u32);
    impl CycleCounter for Wrapping {
        fn now(&mut self) -> u32 {
            self.0 = self.0.wrapping_add(7);
            self.0
        }
    }

    #[test]
    fn laps_survive_wrap_around() {
        let mut w = Stopwatch::start(Wrapping(u32::MAX - 3));
        assert_eq!(w.lap(), 7);
        assert_eq!(w.lap(), 7);
        assert_eq!(Stopwatch::start(NoCounter).lap(), 0);
    }

    #[test]
    fn total_saturates() {
        let s = StageCycles {
            propagate: u32::MAX,
            weigh: 1,
            ..StageCycles::default()
        };
        assert_eq!(s.total(), u32::MAX);
    }
}
