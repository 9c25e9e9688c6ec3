//! The shared Kalman filter with any noise, covariance, measurement and `dt`.
//!
//! Oracles: no panic; `SharedCovariance::new` accepts exactly positive semidefinite
//! noise and covariances; the filter keeps `P` block-diagonal with both blocks positive
//! semidefinite (exactly, in integers) after every operation.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::kalman::{predict_mean, BlockNoise, SharedCovariance, Size, Sym2};
use rbtrack_fuzz::Q;

#[derive(Arbitrary, Debug, Clone, Copy)]
struct S2([Q; 3]);

impl S2 {
    fn get(self) -> Sym2 {
        Sym2 {
            a00: self.0[0].get(),
            a01: self.0[1].get(),
            a11: self.0[2].get(),
        }
    }
}

#[derive(Arbitrary, Debug, Clone)]
enum Op {
    Predict(Q),
    Update([Q; 2]),
    PredictMean(Q),
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    q_x: S2,
    q_y: S2,
    r: [Q; 2],
    p_x: S2,
    p_y: S2,
    sizes: Vec<[Q; 4]>,
    ops: Vec<Op>,
}

fuzz_target!(|input: Input| {
    let noise = BlockNoise {
        q_x: input.q_x.get(),
        q_y: input.q_y.get(),
        r_x: input.r[0].get(),
        r_y: input.r[1].get(),
    };
    let (p_x, p_y) = (input.p_x.get(), input.p_y.get());
    let mut sizes: Vec<Size> = input
        .sizes
        .iter()
        .take(16)
        .map(|&[hx, dhx, hy, dhy]| Size {
            hx: hx.get(),
            dhx: dhx.get(),
            hy: hy.get(),
            dhy: dhy.get(),
        })
        .collect();
    let shared = SharedCovariance::new(p_x, p_y, noise);
    let valid = noise.check().is_ok() && p_x.is_psd() && p_y.is_psd();
    assert_eq!(shared.is_ok(), valid);
    let Ok(mut shared) = shared else {
        return;
    };
    for op in input.ops.iter().take(32) {
        match op {
            Op::Predict(dt) => shared.predict(dt.get()),
            Op::Update([hx, hy]) => {
                let g = shared.update(&mut sizes, hx.get(), hy.get());
                let _ = g.innovation_cov();
            }
            Op::PredictMean(dt) => {
                for s in sizes.iter_mut() {
                    predict_mean(s, dt.get());
                }
            }
        }
        let p = shared.cov();
        assert!(p.is_block_diagonal());
        assert!(p.x_block().is_psd() && p.y_block().is_psd(), "{p:?}");
    }
});
