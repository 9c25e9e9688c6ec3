//! Histograms and models: `Histogram::fill`, `add` (one by one, or every pixel of a
//! window as `window::visit` gives them), `clear`,
//! `bhattacharyya`, `probability`, `Model::set` and `Model::update`, on frames of any
//! size, stride, pixel format and content, windows anywhere and any cap.
//!
//! Oracles: no panic; a window never visits more than `min(cap, MAX_CAP)` pixels; the
//! mass is the (saturating) sum of the counts; the touched list holds each non-zero bin
//! once; `rho` and `p_u` stay in `[0, 1]`; model entries stay in `[0, 1]` and, unless a
//! saturated histogram went in, sum to at most 1 plus one unit per bin and update.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::fixed::{sqrt_q8, Q16};
use rbtrack::hist::{Histogram, Model, PROB_ONE};
use rbtrack::image::{Binning, ImageView, Luma64, PixelFormat, Rgb8x8x8, Yuv8x8x4};
use rbtrack::window::{visit, MAX_CAP};
use rbtrack_fuzz::{with_format, EllipseSpec, Format, FrameSpec, Q};

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Bins {
    Rgb8x8x8,
    Yuv8x8x4,
    Luma64,
}

#[derive(Arbitrary, Debug, Clone)]
enum Op {
    Fill(EllipseSpec, u32),
    Accumulate(EllipseSpec, u32),
    Add(u16, u32),
    Clear,
    SetModel,
    UpdateModel(Q),
    Compare,
    Sqrt(u32),
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    bins: Bins,
    format: Format,
    frame: FrameSpec,
    ops: Vec<Op>,
}

const MAX_OPS: usize = 24;

/// What the model was built from: whether any histogram it took in had a saturated mass
/// (then `sum_u q_u` is not bounded: each `p_u` is at most 1 but they need not sum to 1),
/// and how many adaptive updates it took since `set` (each may round up by at most
/// one unit per bin).
#[derive(Default)]
struct ModelHistory {
    saturated: bool,
    updates: u64,
}

fn check<const B: usize>(h: &Histogram<B>, m: &Model<B>, history: &ModelHistory) {
    let sum: u64 = h.counts().iter().map(|&c| c as u64).sum();
    assert_eq!(
        h.mass() as u64,
        sum.min(u32::MAX as u64),
        "mass is the saturating sum"
    );
    let nonzero = h.counts().iter().filter(|&&c| c > 0).count();
    assert_eq!(h.touched().len(), nonzero);
    for &u in h.touched() {
        assert!(h.count(u as usize) > 0);
        assert!(h.probability(u as usize) <= PROB_ONE);
    }
    let rho = h.bhattacharyya(m);
    assert!(rho >= Q16::ZERO && rho <= Q16::ONE, "rho {rho:?}");
    let total: u64 = (0..B).map(|u| m.q(u) as u64).sum();
    if !history.saturated {
        let slack = (history.updates + 1) * B as u64;
        assert!(total <= PROB_ONE as u64 + slack, "model sums to {total}");
    }
    for u in 0..B {
        assert!(m.q(u) <= PROB_ONE && m.sqrt_q(u) <= 1 << 23);
    }
}

fn run<Bn: Binning, const B: usize, P: PixelFormat>(input: &Input) {
    let f = input.frame.build(input.format.bytes_per_pixel());
    let Ok(img) = ImageView::<P>::new(&f.buf, f.width, f.height, f.stride) else {
        return;
    };
    let mut h = Histogram::<B>::new();
    let mut m = Model::<B>::new();
    let mut history = ModelHistory::default();
    for op in input.ops.iter().take(MAX_OPS) {
        match op {
            Op::Fill(e, cap) => {
                let n = h.fill::<Bn, P>(&img, &e.get(img.width(), img.height()), *cap);
                assert!(n <= (*cap).min(MAX_CAP));
            }
            Op::Accumulate(e, cap) => {
                let e = e.get(img.width(), img.height());
                let n = visit(&img, &e, *cap, |row, x, w| h.add(row.bin::<Bn>(x), w));
                assert!(n <= (*cap).min(MAX_CAP));
            }
            Op::Add(bin, w) => h.add(*bin, *w),
            Op::Clear => {
                h.clear();
                assert!(h.is_empty() && h.touched().is_empty());
            }
            Op::SetModel => {
                m.set(&h);
                history = ModelHistory {
                    saturated: h.mass() == u32::MAX,
                    updates: 0,
                };
            }
            Op::UpdateModel(a) => {
                m.update(&h, a.get());
                history.saturated |= h.mass() == u32::MAX;
                history.updates += 1;
            }
            Op::Compare => {}
            Op::Sqrt(n) => {
                let s = sqrt_q8(*n) as u64;
                assert!(s * s <= (*n as u64) << 16);
            }
        }
        check(&h, &m, &history);
    }
}

fuzz_target!(|input: Input| {
    with_format!(input.format, P => match input.bins {
        Bins::Rgb8x8x8 => run::<Rgb8x8x8, 512, P>(&input),
        Bins::Yuv8x8x4 => run::<Yuv8x8x4, 256, P>(&input),
        Bins::Luma64 => run::<Luma64, 64, P>(&input),
    });
});
