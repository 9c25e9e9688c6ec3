//! Both fixed-point Kalman filters (shared and general) against a plain `f64` filter over
//! 1,000 steps.
//!
//! Scenario: a target whose half-axes follow a slow oscillation plus a drift (`Hy` between
//! roughly 20 and 90 px, `Hx = 0.6 Hy`), measured with noise of variance 2 (the paper's R),
//! filtered with the paper's `Q = 4 I4`, `R = 2 I2`, `dt = 1`, `P0 = 10 I4`. The f64 filter
//! gets the same (Q16.16-quantised) measurements.
//!
//! Error measure: for every mean and covariance entry and every step,
//! `|fixed - f64| / max(|f64|, 1)` (relative, with values below 1 compared absolutely, so
//! that a rate near zero does not blow the ratio up). Required: below `1e-3`. Also required:
//! `P` symmetric (by construction) and positive definite at every step.

#![allow(clippy::needless_range_loop)] // plain textbook matrix loops, on purpose

use super::general::Filter;
use super::{predict_mean, BlockNoise, SharedCovariance, Size, Sym2, Sym4};
use crate::fixed::Q16;
use crate::rng::Rng;
use std::string::String;
use std::{format, println};

/// Plain f64 Kalman filter, 4 states (Hx, dHx, Hy, dHy), 2 measurements (Hx, Hy).
struct F64Kalman {
    mu: [f64; 4],
    p: [[f64; 4]; 4],
}

impl F64Kalman {
    fn predict(&mut self, dt: f64, q: f64) {
        let a = [
            [1.0, dt, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, dt],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let mut mu = [0.0; 4];
        for i in 0..4 {
            for j in 0..4 {
                mu[i] += a[i][j] * self.mu[j];
            }
        }
        let mut ap = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    ap[i][j] += a[i][k] * self.p[k][j];
                }
            }
        }
        let mut p = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    p[i][j] += ap[i][k] * a[j][k];
                }
            }
            p[i][i] += q;
        }
        self.mu = mu;
        self.p = p;
    }

    fn update(&mut self, y: [f64; 2], r: f64) {
        let h = [0usize, 2usize];
        let mut s = [[0.0; 2]; 2];
        for m in 0..2 {
            for n in 0..2 {
                s[m][n] = self.p[h[m]][h[n]] + if m == n { r } else { 0.0 };
            }
        }
        let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
        let si = [
            [s[1][1] / det, -s[0][1] / det],
            [-s[1][0] / det, s[0][0] / det],
        ];
        let mut k = [[0.0; 2]; 4];
        for i in 0..4 {
            for m in 0..2 {
                for n in 0..2 {
                    k[i][m] += self.p[i][h[n]] * si[n][m];
                }
            }
        }
        let e = [y[0] - self.mu[0], y[1] - self.mu[2]];
        for i in 0..4 {
            self.mu[i] += k[i][0] * e[0] + k[i][1] * e[1];
        }
        let mut p = self.p;
        for i in 0..4 {
            for j in 0..4 {
                p[i][j] -= k[i][0] * self.p[h[0]][j] + k[i][1] * self.p[h[1]][j];
            }
        }
        self.p = p;
    }
}

fn rel(fixed: Q16, reference: f64) -> f64 {
    (fixed.to_f64() - reference).abs() / reference.abs().max(1.0)
}

/// The entries of a size in the state's order.
fn entries(s: &Size) -> [Q16; 4] {
    [s.hx, s.dhx, s.hy, s.dhy]
}

/// Positive definite by Cholesky.
fn is_pd(p: &Sym4) -> bool {
    let mut m = [[0.0f64; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = p.get(i, j).to_f64();
        }
    }
    for j in 0..4 {
        let mut d = m[j][j];
        for k in 0..j {
            d -= m[j][k] * m[j][k];
        }
        if d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        m[j][j] = d;
        for i in (j + 1)..4 {
            let mut v = m[i][j];
            for k in 0..j {
                v -= m[i][k] * m[j][k];
            }
            m[i][j] = v / d;
        }
    }
    true
}

#[test]
fn fixed_point_kalman_tracks_f64_reference() {
    const STEPS: usize = 1000;
    let noise = BlockNoise::PAPER;
    let general = noise.general();
    let p0 = 10.0;
    let mut reference = F64Kalman {
        mu: [30.0, 0.0, 50.0, 0.0],
        p: [[0.0; 4]; 4],
    };
    for i in 0..4 {
        reference.p[i][i] = p0;
    }
    let mean0 = Size::at_rest(Q16::from_f64(30.0), Q16::from_f64(50.0));
    let mut filter = Filter::new(mean0, Sym4::diagonal([Q16::from_f64(p0); 4]));
    let p0_block = Sym2::diagonal(Q16::from_f64(p0), Q16::from_f64(p0));
    let mut shared = SharedCovariance::new(p0_block, p0_block, noise).unwrap();
    let mut shared_mean = [mean0];

    let mut rng = Rng::new(0x5ca1e);
    let (mut max_mean, mut max_cov, mut max_shared) = (0f64, 0f64, 0f64);
    let mut worst_entry = String::new();
    for t in 0..STEPS {
        let tf = t as f64;
        let hy = 55.0 + 30.0 * (tf / 80.0).sin() + 5.0 * (tf / 500.0);
        let hx = 0.6 * hy;
        // Measurements with variance 2, quantised once and fed to both filters.
        let measured_hy = Q16::from_f64(hy) + rng.gaussian(Q16::from_f64(2f64.sqrt()));
        let measured_hx = Q16::from_f64(hx) + rng.gaussian(Q16::from_f64(2f64.sqrt()));
        let y = [measured_hx, measured_hy];

        reference.predict(1.0, 4.0);
        filter.predict(Q16::ONE, &general);
        predict_mean(&mut shared_mean[0], Q16::ONE);
        shared.predict(Q16::ONE);

        reference.update([y[0].to_f64(), y[1].to_f64()], 2.0);
        filter.update(y, &general.r);
        shared.update(&mut shared_mean, measured_hx, measured_hy);

        let (mean, shared_mean_entries) = (entries(&filter.mean), entries(&shared_mean[0]));
        for i in 0..4 {
            let e = rel(mean[i], reference.mu[i]);
            if e > max_mean {
                max_mean = e;
            }
            for j in 0..4 {
                let e = rel(filter.cov.get(i, j), reference.p[i][j]);
                if e > max_cov {
                    max_cov = e;
                    worst_entry = format!("P[{i}][{j}] at step {t}");
                }
                let e = rel(shared.cov().get(i, j), reference.p[i][j]);
                max_shared = max_shared.max(e);
            }
            max_shared = max_shared.max(rel(shared_mean_entries[i], reference.mu[i]));
        }
        assert!(is_pd(&filter.cov), "P not PD at step {t}: {:?}", filter.cov);
        assert!(is_pd(&shared.cov()), "shared P not PD at step {t}");
        assert!(
            (reference.p[0][1] - reference.p[1][0]).abs() < 1e-9,
            "reference lost symmetry"
        );
    }
    println!(
        "kalman vs f64 over {STEPS} steps: max relative error mean {max_mean:.3e}, \
         covariance {max_cov:.3e} ({worst_entry}), shared path {max_shared:.3e}"
    );
    println!(
        "final P (fixed): Hx {:.6} dHx {:.6} cross {:.6}; f64: {:.6} {:.6} {:.6}",
        filter.cov.a00.to_f64(),
        filter.cov.a11.to_f64(),
        filter.cov.a01.to_f64(),
        reference.p[0][0],
        reference.p[1][1],
        reference.p[0][1]
    );
    assert!(max_mean < 1e-3, "mean error {max_mean}");
    assert!(max_cov < 1e-3, "covariance error {max_cov}");
    assert!(max_shared < 1e-3, "shared path error {max_shared}");
    assert_eq!(shared.cov(), filter.cov, "shared and general paths differ");
    assert_eq!(
        shared_mean[0], filter.mean,
        "shared and general means differ"
    );
}
