//! Particles on the merged response: the particle filters' way of tracking, reading the
//! correlation-filter tracker's map instead of colour windows.
//!
//! Each particle is a position and a velocity, px. A step moves each by its velocity plus
//! Gaussian noise (the velocity itself drifts by a tenth of that noise), the search region
//! is centred on their mean, and each is weighed by `exp((m - m_max) / tau)`, `m` the merged
//! response read (bilinearly) where it stands and `m_max` the map's peak. The estimate is
//! their weighted mean; they are then resampled (systematic).

use rbtrack::rng::Rng;

/// One hypothesis: position and velocity, px and px a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Particle {
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
}

/// The particle set.
#[derive(Clone, Debug)]
pub struct Particles {
    particles: Vec<Particle>,
    weights: Vec<f64>,
    rng: Rng,
}

impl Particles {
    /// `n` particles at rest on `centre`, drawing from `seed`.
    pub fn new(n: usize, centre: (f64, f64), seed: u64) -> Self {
        let p = Particle {
            x: centre.0,
            y: centre.1,
            vx: 0.0,
            vy: 0.0,
        };
        Self {
            particles: vec![p; n.max(1)],
            weights: vec![1.0 / n.max(1) as f64; n.max(1)],
            rng: Rng::new(seed),
        }
    }

    /// Moves every particle by its velocity and noise of `sigma` px; returns their mean.
    pub fn predict(&mut self, sigma: f64) -> (f64, f64) {
        for p in &mut self.particles {
            p.vx += 0.1 * sigma * self.rng.normal().to_f64();
            p.vy += 0.1 * sigma * self.rng.normal().to_f64();
            p.x += p.vx + sigma * self.rng.normal().to_f64();
            p.y += p.vy + sigma * self.rng.normal().to_f64();
        }
        self.mean(|_| 1.0)
    }

    /// Moves every particle with the picture: `moved(x, y)` is where a point goes.
    pub fn shift(&mut self, moved: impl Fn(f64, f64) -> (f64, f64)) {
        for p in &mut self.particles {
            (p.x, p.y) = moved(p.x, p.y);
        }
    }

    /// Moves a `share` of the particles (the last ones) to `peak`, px, with the velocity
    /// that takes them there from `from`, spread by `sigma` px: the map's peak proposed as
    /// a hypothesis, so that a jump the motion model does not foresee is followed.
    pub fn propose(&mut self, peak: (f64, f64), from: (f64, f64), share: f64, sigma: f64) {
        let n = self.particles.len();
        let k = (share * n as f64).round() as usize;
        for i in n - k.min(n)..n {
            let x = peak.0 + sigma * self.rng.normal().to_f64();
            let y = peak.1 + sigma * self.rng.normal().to_f64();
            self.particles[i] = Particle {
                x,
                y,
                vx: x - from.0,
                vy: y - from.1,
            };
        }
    }

    /// Weighs the particles by `map` (the merged response at a position, px) with
    /// sharpness `tau`, returns their weighted mean, and resamples them.
    pub fn weigh(&mut self, map: impl Fn(f64, f64) -> f64, tau: f64) -> (f64, f64) {
        let values: Vec<f64> = self.particles.iter().map(|p| map(p.x, p.y)).collect();
        let top = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for (w, v) in self.weights.iter_mut().zip(&values) {
            *w = ((v - top) / tau).exp();
        }
        let total: f64 = self.weights.iter().sum();
        for w in &mut self.weights {
            *w /= total;
        }
        let mean = self.mean(|i| self.weights[i]);
        self.resample();
        mean
    }

    fn mean(&self, weight: impl Fn(usize) -> f64) -> (f64, f64) {
        let (mut x, mut y, mut total) = (0.0, 0.0, 0.0);
        for (i, p) in self.particles.iter().enumerate() {
            let w = weight(i);
            x += w * p.x;
            y += w * p.y;
            total += w;
        }
        (x / total, y / total)
    }

    /// Systematic resampling on the normalised weights.
    fn resample(&mut self) {
        let n = self.particles.len();
        let start = f64::from(self.rng.next_u32()) / 2f64.powi(32) / n as f64;
        let mut out = Vec::with_capacity(n);
        let (mut cumulative, mut j) = (self.weights[0], 0);
        for k in 0..n {
            let at = start + k as f64 / n as f64;
            while cumulative < at && j + 1 < n {
                j += 1;
                cumulative += self.weights[j];
            }
            out.push(self.particles[j]);
        }
        self.particles = out;
        self.weights.fill(1.0 / n as f64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn particles_gather_on_the_map_peak() {
        let mut p = Particles::new(200, (50.0, 50.0), 1);
        let peak = (56.0, 47.0);
        let map = |x: f64, y: f64| -((x - peak.0).powi(2) + (y - peak.1).powi(2)) / 50.0;
        let mut mean = (0.0, 0.0);
        for _ in 0..10 {
            p.predict(3.0);
            mean = p.weigh(map, 0.05);
        }
        assert!(
            (mean.0 - peak.0).abs() < 1.0 && (mean.1 - peak.1).abs() < 1.0,
            "{mean:?}"
        );
    }
}
