//! The shared filter's tests, and the proof that it equals the general per-particle filter
//! ([`super::general`]) bit for bit.

use super::general::{Filter, Noise};
use super::*;
use crate::rng::Rng;

fn q(v: f64) -> Q16 {
    Q16::from_f64(v)
}

fn paper_filter() -> (Filter, Noise) {
    let f = Filter::new(
        Size {
            hx: q(25.0),
            dhx: q(-0.25),
            hy: q(40.0),
            dhy: q(0.5),
        },
        Sym4::diagonal([q(10.0); 4]),
    );
    (f, BlockNoise::PAPER.general())
}

/// The shared filter == the general per-particle filter, bit for bit: 32 particles, 300
/// steps, random means, measurements and dt, diagonal and correlated block noise.
#[test]
fn shared_path_is_bit_exact_with_per_particle_filters() {
    let noises = [
        BlockNoise::PAPER,
        BlockNoise {
            q_y: Sym2 {
                a00: q(0.25),
                a01: q(0.5),
                a11: q(1.0),
            },
            q_x: Sym2 {
                a00: q(1.0 / 3.0),
                a01: q(0.5),
                a11: q(1.0),
            },
            r_y: q(3.0),
            r_x: q(0.7),
        },
    ];
    for (case, noise) in noises.iter().enumerate() {
        let mut rng = Rng::new(100 + case as u64);
        let p0y = Sym2 {
            a00: q(9.0),
            a01: q(1.5),
            a11: q(4.0),
        };
        let p0x = Sym2::diagonal(q(16.0), q(2.0));
        let mut shared = SharedCovariance::new(p0x, p0y, *noise).unwrap();
        let general = noise.general();
        let mut means = [Size::default(); 32];
        for m in means.iter_mut() {
            *m = Size {
                hy: q(50.0) + rng.gaussian(q(5.0)),
                dhy: rng.normal(),
                hx: q(30.0) + rng.gaussian(q(5.0)),
                dhx: rng.normal(),
            };
        }
        let mut filters = means.map(|m| Filter::new(m, shared.cov()));
        for step in 0..300 {
            let dt = if step % 7 == 0 {
                Q16::from_bits(rng.below(3 << 16) as i32)
            } else {
                Q16::ONE
            };
            shared.predict(dt);
            for m in means.iter_mut() {
                predict_mean(m, dt);
            }
            for f in filters.iter_mut() {
                f.predict(dt, &general);
            }
            let hy = q(50.0) + rng.gaussian(q(8.0));
            let hx = q(30.0) + rng.gaussian(q(8.0));
            let g = shared.update(&mut means, hx, hy);
            for f in filters.iter_mut() {
                let gf = f.update([hx, hy], &general.r);
                assert_eq!(gf.s, g.innovation_cov());
                assert_eq!(gf.k[0], [g.x.k[0], 0]);
                assert_eq!(gf.k[1], [g.x.k[1], 0]);
                assert_eq!(gf.k[2], [0, g.y.k[0]]);
                assert_eq!(gf.k[3], [0, g.y.k[1]]);
            }
            for (f, m) in filters.iter().zip(means.iter()) {
                assert_eq!(f.mean, *m, "case {case} step {step}");
                assert_eq!(f.cov, shared.cov(), "case {case} step {step}");
            }
        }
    }
}

/// One step by hand: P = 10 I, Q = 4 I, R = 2 I, dt = 1.
#[test]
fn one_step_matches_hand_computation() {
    let (mut f, noise) = paper_filter();
    f.predict(Q16::ONE, &noise);
    // P^- y block: [[10 + 10 + 4, 10], [10, 14]] = [[24, 10], [10, 14]].
    assert_eq!(f.cov.a00, q(24.0));
    assert_eq!(f.cov.a01, q(10.0));
    assert_eq!(f.cov.a11, q(14.0));
    assert_eq!(
        f.mean,
        Size {
            hx: q(24.75),
            dhx: q(-0.25),
            hy: q(40.5),
            dhy: q(0.5)
        }
    );
    let g = f.update([q(24.75), q(41.5)], &noise.r);
    // S = 26, K = (24/26, 10/26); mean += K * 1.
    assert_eq!(g.s.a00, q(26.0));
    let k0 = g.k[0][0] as f64 / (1u64 << 24) as f64;
    assert!((k0 - 24.0 / 26.0).abs() < 1e-7);
    assert!((f.mean.hy.to_f64() - (40.5 + 24.0 / 26.0)).abs() < 2e-5);
    assert!((f.mean.dhy.to_f64() - (0.5 + 10.0 / 26.0)).abs() < 2e-5);
    // P = P^- - c c^T / S, c = (24, 10).
    assert!((f.cov.a00.to_f64() - (24.0 - 576.0 / 26.0)).abs() < 1e-5);
    assert!((f.cov.a01.to_f64() - (10.0 - 240.0 / 26.0)).abs() < 1e-5);
    assert!((f.cov.a11.to_f64() - (14.0 - 100.0 / 26.0)).abs() < 1e-5);
    assert!(f.cov.is_psd());
}

/// A measurement near the Q16.16 rails saturates instead of wrapping.
#[test]
fn huge_measurements_saturate() {
    let (mut f, noise) = paper_filter();
    for _ in 0..50 {
        f.predict(Q16::ONE, &noise);
        f.update([Q16::MIN, Q16::MAX], &noise.r);
    }
    assert!(f.mean.hy > q(30_000.0));
    assert!(f.mean.hx < q(-30_000.0));
    assert!(f.cov.is_psd());
    // And back: no stuck state.
    for _ in 0..200 {
        f.predict(Q16::ONE, &noise);
        f.update([q(10.0), q(10.0)], &noise.r);
    }
    assert!((f.mean.hy.to_f64() - 10.0).abs() < 1.0, "{:?}", f.mean);
    assert!((f.mean.hx.to_f64() - 10.0).abs() < 1.0, "{:?}", f.mean);
    // Shared path, same abuse.
    let mut s = SharedCovariance::new(
        Sym2::diagonal(q(10.0), q(10.0)),
        Sym2::diagonal(q(10.0), q(10.0)),
        BlockNoise::PAPER,
    )
    .unwrap();
    let mut means = [Size {
        hx: Q16::MAX,
        dhx: Q16::MIN,
        hy: Q16::MIN,
        dhy: Q16::MAX,
    }; 3];
    for _ in 0..20 {
        for m in means.iter_mut() {
            predict_mean(m, Q16::MAX);
        }
        s.predict(Q16::MAX);
        s.update(&mut means, Q16::MIN, Q16::MAX);
    }
    assert!(s.cov().is_psd());
}

/// Zero Q and R: the measured positions are taken exactly; P stays PSD.
#[test]
fn zero_noise() {
    let noise = Noise {
        q: Sym4::ZERO,
        r: Sym2::ZERO,
    };
    let mut f = Filter::new(
        Size {
            hx: q(7.0),
            dhx: q(0.0),
            hy: q(5.0),
            dhy: q(1.0),
        },
        Sym4::diagonal([q(1.0); 4]),
    );
    f.predict(Q16::ONE, &noise);
    f.update([q(9.0), q(8.0)], &noise.r);
    assert_eq!(f.mean.hy, q(8.0));
    assert_eq!(f.mean.hx, q(9.0));
    assert_eq!(f.cov.a00, Q16::ZERO);
    assert_eq!(f.cov.a22, Q16::ZERO);
    assert!(f.cov.is_psd());
    // Second step: the rate is learnt from the two exact positions.
    f.predict(Q16::ONE, &noise);
    f.update([q(9.0), q(10.0)], &noise.r);
    assert_eq!(f.mean.hy, q(10.0));
    assert!((f.mean.dhy.to_f64() - 2.0).abs() < 1e-4, "{:?}", f.mean);
    // With P = 0 as well, S is singular: no update, no panic.
    let ones = Size {
        hx: q(1.0),
        dhx: q(1.0),
        hy: q(1.0),
        dhy: q(1.0),
    };
    let mut g = Filter::new(ones, Sym4::ZERO);
    g.predict(Q16::ONE, &noise);
    let gain = g.update([q(100.0), q(100.0)], &noise.r);
    assert_eq!(gain.k, [[0; 2]; 4]);
    assert_eq!(
        g.mean,
        Size {
            hx: q(2.0),
            hy: q(2.0),
            ..ones
        }
    );
    let mut b = Block { cov: Sym2::ZERO };
    assert_eq!(b.gain(Q16::ZERO).k, [0, 0]);
    b.update(Q16::ZERO);
    assert_eq!(b.cov, Sym2::ZERO);
}

/// Huge R: the measurement is ignored; huge Q: it is followed.
#[test]
fn huge_noise() {
    let big = q(30_000.0);
    let (f0, _) = paper_filter();
    let mut f = f0;
    let noise = Noise {
        q: Sym4::diagonal([q(0.01); 4]),
        r: Sym2::diagonal(big, big),
    };
    f.predict(Q16::ONE, &noise);
    f.update([q(1000.0), q(1000.0)], &noise.r);
    assert!((f.mean.hy.to_f64() - 40.5).abs() < 1.0, "{:?}", f.mean);
    let mut f = f0;
    let noise = Noise {
        q: Sym4::diagonal([big; 4]),
        r: Sym2::diagonal(q(0.01), q(0.01)),
    };
    for _ in 0..5 {
        f.predict(Q16::ONE, &noise);
        f.update([q(-1000.0), q(1000.0)], &noise.r);
        assert!(f.cov.is_psd());
    }
    assert!((f.mean.hy.to_f64() - 1000.0).abs() < 0.1, "{:?}", f.mean);
    assert!((f.mean.hx.to_f64() + 1000.0).abs() < 0.1, "{:?}", f.mean);
}

/// Arbitrary bit patterns everywhere (covariances not PSD, negative noise, any dt):
/// no overflow panic (tests run with overflow checks) in either path.
#[test]
fn arbitrary_inputs_never_panic() {
    let mut rng = Rng::new(77);
    let mut any = || {
        let w = rng.next_u32() as i32;
        match w & 3 {
            0 => Q16::from_bits(w),
            1 => Q16::MAX,
            2 => Q16::MIN,
            _ => Q16::from_bits(w >> 12),
        }
    };
    for _ in 0..20_000 {
        let mut sym4 = || Sym4 {
            a00: any(),
            a01: any(),
            a02: any(),
            a03: any(),
            a11: any(),
            a12: any(),
            a13: any(),
            a22: any(),
            a23: any(),
            a33: any(),
        };
        let (cov, q4) = (sym4(), sym4());
        let mut sym2 = || Sym2 {
            a00: any(),
            a01: any(),
            a11: any(),
        };
        let (r2, by, bx) = (sym2(), sym2(), sym2());
        let mut f = Filter::new(
            Size {
                hx: any(),
                dhx: any(),
                hy: any(),
                dhy: any(),
            },
            cov,
        );
        let dt = any();
        let y = [any(), any()];
        f.predict(dt, &Noise { q: q4, r: r2 });
        let _ = f.update(y, &r2);
        let mut b = Block { cov: by };
        b.predict(dt, &bx);
        let g = b.gain(any());
        let (mut p, mut v) = (any(), any());
        g.update_mean(&mut p, &mut v, any());
        b.update(any());
    }
}

/// Regression (found by the `kalman` fuzz target): with no measurement for 31 steps
/// (`Q = 4 I`), `P00` stuck at the rail while `P01` kept growing and `P` became
/// indefinite; a negative `dt` made a variance negative. Both filters now stay positive
/// semidefinite, and the shared one still equals the general one bit for bit.
#[test]
fn rails_keep_the_covariance_psd() {
    let noise = BlockNoise::PAPER;
    let p0 = Sym2::diagonal(q(2.0), q(4.0));
    let mut shared = SharedCovariance::new(p0, p0, noise).unwrap();
    let mut f = Filter::new(Size::default(), Sym4::from_blocks(p0, p0));
    let mut means = [Size::at_rest(q(10.0), q(10.0))];
    let mut step = |dt: Q16, update: bool| {
        shared.predict(dt);
        f.predict_cov(dt, &noise.general().q);
        if update {
            shared.update(&mut means, q(10.0), q(10.0));
            f.update([q(10.0), q(10.0)], &noise.general().r);
        }
        assert!(shared.cov().y_block().is_psd() && shared.cov().x_block().is_psd());
        assert_eq!(shared.cov(), f.cov);
        shared.cov()
    };
    let mut p = Sym4::ZERO;
    for _ in 0..2000 {
        p = step(Q16::ONE, false);
    }
    assert_eq!(p.a00, Q16::MAX);
    for _ in 0..50 {
        p = step(Q16::ONE, true);
    }
    // Back at the steady state of the paper's noise.
    assert!((p.a00.to_f64() - 1.7643).abs() < 1e-3, "{p:?}");
    for dt in [Q16::MIN, Q16::MAX, q(-3.0), q(700.0)] {
        step(dt, false);
        step(dt, true);
    }
}

/// dt = 0: A = I, so predict only adds Q and leaves the mean.
#[test]
fn dt_zero() {
    let (mut f, noise) = paper_filter();
    let before = f;
    f.predict(Q16::ZERO, &noise);
    assert_eq!(f.mean, before.mean);
    assert_eq!(f.cov, Sym4::diagonal([q(14.0); 4]));
}

/// Correlated measurement noise: general path still symmetric, PSD, and close to a
/// float computation.
#[test]
fn correlated_noise_matches_float() {
    let mut f = Filter::new(
        Size::at_rest(q(10.0), q(20.0)),
        Sym4 {
            a02: q(2.0),
            a13: q(0.5),
            ..Sym4::diagonal([q(5.0), q(1.0), q(6.0), q(2.0)])
        },
    );
    let r = Sym2 {
        a00: q(2.0),
        a01: q(1.0),
        a11: q(3.0),
    };
    let y = [q(12.0), q(17.0)];
    // Float reference of the gain.
    let p0 = f.cov;
    let p = |i, j| p0.get(i, j).to_f64();
    let (s00, s01, s11) = (p(0, 0) + 2.0, p(0, 2) + 1.0, p(2, 2) + 3.0);
    let det = s00 * s11 - s01 * s01;
    let k = |i| {
        let (a, b) = (p(i, 0), p(i, 2));
        [(a * s11 - b * s01) / det, (b * s00 - a * s01) / det]
    };
    let g = f.update(y, &r);
    for i in 0..4 {
        for m in 0..2 {
            let got = g.k[i][m] as f64 / (1u64 << 24) as f64;
            assert!((got - k(i)[m]).abs() < 1e-7, "{i} {m} {got} {:?}", k(i));
        }
    }
    assert!(f.cov.is_psd());
}

#[test]
fn config_checks() {
    assert!(BlockNoise::PAPER.check().is_ok());
    assert!(BlockNoise::PAPER.general().check().is_ok());
    let bad = BlockNoise {
        r_x: q(-1.0),
        ..BlockNoise::PAPER
    };
    assert_eq!(
        bad.check(),
        Err(KalmanError::NotPositiveSemidefinite("r_x"))
    );
    let bad = BlockNoise {
        q_y: Sym2 {
            a00: q(1.0),
            a01: q(2.0),
            a11: q(1.0),
        },
        ..BlockNoise::PAPER
    };
    assert_eq!(
        bad.check(),
        Err(KalmanError::NotPositiveSemidefinite("q_y"))
    );
    let err = SharedCovariance::new(
        Sym2::ZERO,
        Sym2::diagonal(q(-1.0), q(1.0)),
        BlockNoise::PAPER,
    );
    assert_eq!(err, Err(KalmanError::NotPositiveSemidefinite("cov_y")));
    let indefinite = Sym4 {
        a03: q(3.0),
        ..Sym4::diagonal([q(1.0); 4])
    };
    assert!(!indefinite.is_psd());
    assert!(Sym4::ZERO.is_psd());
    let semidefinite = Sym4 {
        a02: q(1.0),
        ..Sym4::diagonal([q(1.0), q(0.0), q(1.0), q(2.0)])
    };
    assert!(semidefinite.is_psd());
    extern crate std;
    use std::string::ToString;
    assert_eq!(
        KalmanError::NotPositiveSemidefinite("q").to_string(),
        "covariance `q` is not positive semidefinite"
    );
    assert_eq!(Sym4::ZERO.get(7, 1), Q16::ZERO);
}
