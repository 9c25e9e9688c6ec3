//! Property tests of the core's primitives (proptest), each over random inputs
//! that include the extremes:
//! - histogram mass equals the kernel sum of the window's pixels, bin by bin;
//! - the Bhattacharyya coefficient stays in `[0, 1]` (and a window against its own model
//!   is within 2e-3 of 1);
//! - resampling returns exactly the requested number of valid indices whatever the
//!   weights (all zero, one non-zero, saturated, mixed), never one of zero weight;
//!   `normalise` is exact and the effective sample size bounded;
//! - a clipped window never reads outside the frame and never more than its cap;
//! - `Q16` arithmetic saturates at the rails instead of wrapping.
//!
//! Case counts are proptest's default (256) unless a test says otherwise; set
//! `PROPTEST_CASES` to run more.

use proptest::prelude::*;
use rbtrack::fixed::Q16;
use rbtrack::hist::{Histogram, Model};
use rbtrack::image::{
    Binning, Gray8, ImageView, Luma64, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Rgb8x8x8, Uyvy,
    Yuv8x8x4, Yuyv,
};
use rbtrack::resample::{
    effective_sample_size, normalise, resample, Normalised, Scheme, WEIGHT_TOTAL,
};
use rbtrack::rng::Rng;
use rbtrack::window::{visit, Ellipse, MAX_CAP, WEIGHT_ONE};

// ---------------------------------------------------------------------------------------
// Strategies.

/// A Q16.16 value: anything, the rails, or a plausible number of pixels.
fn any_q16() -> impl Strategy<Value = Q16> {
    prop_oneof![
        any::<i32>().prop_map(Q16::from_bits),
        Just(Q16::MAX),
        Just(Q16::MIN),
        Just(Q16::ZERO),
        (-300i32..300, 0i32..65536).prop_map(|(i, f)| Q16::from_bits((i << 16) | f)),
    ]
}

/// A frame: pixel format index, width, height, stride padding and bytes.
#[derive(Debug, Clone)]
struct FrameCase {
    format: usize,
    width: usize,
    height: usize,
    stride: usize,
    bytes: Vec<u8>,
}

fn frame_case() -> impl Strategy<Value = FrameCase> {
    (0usize..6, 1usize..=48, 1usize..=40, 0usize..6, any::<u64>()).prop_map(
        |(format, width, height, pad, seed)| {
            // YUV 4:2:2 needs even widths and strides.
            let (width, pad) = if format >= 4 {
                (width.next_multiple_of(2), pad & !1)
            } else {
                (width, pad)
            };
            let stride = width + pad;
            let bpp = [1, 2, 2, 3, 2, 2][format];
            let mut rng = Rng::new(seed);
            let bytes = (0..stride * height * bpp)
                .map(|_| rng.next_u32() as u8)
                .collect();
            FrameCase {
                format,
                width,
                height,
                stride,
                bytes,
            }
        },
    )
}

/// An ellipse around (and beyond) a frame of up to 48 x 40 px, any size from nothing to
/// far larger than the frame; or anything at all.
fn ellipse_case() -> impl Strategy<Value = Ellipse> {
    prop_oneof![
        4 => (-60.0f64..110.0, -60.0f64..100.0, 0.0f64..120.0, 0.0f64..120.0).prop_map(
            |(cx, cy, hx, hy)| Ellipse::new(
                Q16::from_f64(cx),
                Q16::from_f64(cy),
                Q16::from_f64(hx),
                Q16::from_f64(hy)
            )
        ),
        1 => (any_q16(), any_q16(), any_q16(), any_q16())
            .prop_map(|(cx, cy, hx, hy)| Ellipse::new(cx, cy, hx, hy)),
    ]
}

fn cap_case() -> impl Strategy<Value = u32> {
    prop_oneof![
        0u32..64,
        64u32..4096,
        Just(MAX_CAP),
        Just(MAX_CAP + 1),
        any::<u32>()
    ]
}

/// Calls `$body` with the type `$p` bound to pixel format number `$format`.
macro_rules! with_format {
    ($format:expr, $p:ident => $body:expr) => {
        match $format {
            0 => {
                type $p = Gray8;
                $body
            }
            1 => {
                type $p = Rgb565Le;
                $body
            }
            2 => {
                type $p = Rgb565Be;
                $body
            }
            3 => {
                type $p = Rgb888;
                $body
            }
            4 => {
                type $p = Yuyv;
                $body
            }
            _ => {
                type $p = Uyvy;
                $body
            }
        }
    };
}

// ---------------------------------------------------------------------------------------
// Histograms.

fn mass_equals_kernel_sum<P: PixelFormat, Bn: Binning, const B: usize>(
    f: &FrameCase,
    e: &Ellipse,
    cap: u32,
) -> Result<(), TestCaseError> {
    let img = ImageView::<P>::new(&f.bytes, f.width, f.height, f.stride).expect("valid frame");
    let mut kernel = 0u64;
    let mut per_bin = vec![0u64; B];
    visit(&img, e, cap, |row, x, w| {
        kernel += w as u64;
        per_bin[row.bin::<Bn>(x) as usize] += w as u64;
    });
    let mut h = Histogram::<B>::new();
    let n = h.fill::<Bn, P>(&img, e, cap);
    prop_assert!(n <= cap.min(MAX_CAP));
    prop_assert_eq!(h.mass() as u64, kernel);
    for (u, &c) in per_bin.iter().enumerate() {
        prop_assert_eq!(h.count(u) as u64, c);
    }
    let mut touched = h.touched().to_vec();
    touched.sort_unstable();
    touched.dedup();
    prop_assert_eq!(touched.len(), h.touched().len());
    prop_assert_eq!(touched.len(), per_bin.iter().filter(|&&c| c > 0).count());
    Ok(())
}

proptest! {
    #[test]
    fn histogram_mass_equals_kernel_sum(f in frame_case(), e in ellipse_case(), cap in cap_case()) {
        with_format!(f.format, P => {
            mass_equals_kernel_sum::<P, Rgb8x8x8, 512>(&f, &e, cap)?;
            mass_equals_kernel_sum::<P, Yuv8x8x4, 256>(&f, &e, cap)?;
            mass_equals_kernel_sum::<P, Luma64, 64>(&f, &e, cap)?;
        });
    }

    /// `0 <= rho <= 1` for windows against models of other windows, adapted models and
    /// hand-made histograms with saturated bins; a non-empty window against its own model
    /// is within 2e-3 of 1.
    #[test]
    fn bhattacharyya_in_unit_interval(
        f in frame_case(),
        a in ellipse_case(),
        b in ellipse_case(),
        alpha in any_q16(),
        adds in prop::collection::vec((0u16..600, any::<u32>()), 0..20),
    ) {
        with_format!(f.format, P => {
            let img = ImageView::<P>::new(&f.bytes, f.width, f.height, f.stride).expect("frame");
            let mut ha = Histogram::<512>::new();
            let mut hb = Histogram::<512>::new();
            ha.fill::<Rgb8x8x8, P>(&img, &a, 300);
            hb.fill::<Rgb8x8x8, P>(&img, &b, 300);
            let own = Model::from_histogram(&ha);
            let rho = ha.bhattacharyya(&own);
            if !ha.is_empty() {
                prop_assert!(rho.to_f64() >= 1.0 - 2e-3 && rho <= Q16::ONE, "self rho {}", rho);
            } else {
                prop_assert_eq!(rho, Q16::ZERO);
            }
            let mut model = Model::from_histogram(&hb);
            for h in [&ha, &hb] {
                let rho = h.bhattacharyya(&model);
                prop_assert!(rho >= Q16::ZERO && rho <= Q16::ONE);
            }
            model.update(&ha, alpha);
            for &(bin, w) in &adds {
                hb.add(bin, w);
            }
            for h in [&ha, &hb] {
                let rho = h.bhattacharyya(&model);
                prop_assert!(rho >= Q16::ZERO && rho <= Q16::ONE, "rho {}", rho);
            }
            let from_adds = Model::from_histogram(&hb);
            let rho = ha.bhattacharyya(&from_adds);
            prop_assert!(rho >= Q16::ZERO && rho <= Q16::ONE);
        });
    }

    /// A clipped window never reads outside the frame (nor the stride padding) and never
    /// visits more than its cap, whatever the ellipse and cap.
    #[test]
    fn clipped_window_never_leaves_the_frame(f in frame_case(), e in ellipse_case(), cap in cap_case()) {
        with_format!(f.format, P => {
            let img = ImageView::<P>::new(&f.bytes, f.width, f.height, f.stride).expect("frame");
            let mut seen = 0u32;
            let mut inside = true;
            let n = visit(&img, &e, cap, |row, x, w| {
                seen += 1;
                inside &= x < f.width
                    && row.y() < f.height
                    && row.bytes().len() == f.width * P::BYTES_PER_PIXEL
                    && w <= WEIGHT_ONE;
            });
            prop_assert!(inside, "{:?} read outside {}x{}", e, f.width, f.height);
            prop_assert_eq!(n, seen);
            prop_assert!(n <= cap.min(MAX_CAP));
        });
    }
}

// ---------------------------------------------------------------------------------------
// Resampling.

/// Weights of one of the kinds the tracker can produce, and worse.
fn weights_case() -> impl Strategy<Value = Vec<u32>> {
    (1usize..=400, 0usize..6, any::<u64>()).prop_map(|(n, kind, seed)| {
        let mut rng = Rng::new(seed);
        let one = rng.below(n as u32) as usize;
        (0..n)
            .map(|i| match kind {
                0 => 0,                                         // all zero
                1 => (i == one) as u32 * rng.next_u32().max(1), // one non-zero
                2 => u32::MAX,                                  // saturated
                3 => rng.next_u32(),                            // random
                4 => rng.next_u32() >> rng.below(32),           // wide dynamic range
                _ => [0, 1, u32::MAX][rng.below(3) as usize],   // mixed extremes
            })
            .collect()
    })
}

fn scheme_case() -> impl Strategy<Value = Scheme> {
    prop_oneof![
        Just(Scheme::Multinomial),
        Just(Scheme::Systematic),
        Just(Scheme::Stratified),
        Just(Scheme::Residual),
    ]
}

proptest! {
    /// Exactly M valid indices for any weights and scheme (M = N, and M != N), never one
    /// whose normalised weight is zero unless every weight is zero.
    #[test]
    fn resampling_returns_n_valid_indices(
        weights in weights_case(),
        scheme in scheme_case(),
        other_m in 0usize..500,
        seed in any::<u64>(),
    ) {
        let n = weights.len();
        let all_zero = weights.iter().all(|&w| w == 0);
        let mut normalised = weights.clone();
        normalise(&mut normalised);
        let mut rng = Rng::new(seed);
        for m in [n, other_m] {
            let mut scratch = weights.clone();
            let mut out = vec![u16::MAX; m];
            let found = resample(scheme, &mut scratch, &mut rng, &mut out).expect("serviceable");
            prop_assert_eq!(found == Normalised::AllZero, all_zero);
            prop_assert_eq!(out.len(), m);
            for &i in &out {
                prop_assert!((i as usize) < n, "index {} of {}", i, n);
                prop_assert!(all_zero || normalised[i as usize] > 0, "drew a zero weight");
            }
            if scheme == Scheme::Systematic && m == n {
                // Each particle gets floor or ceil of its expected number of copies.
                for (i, &w) in normalised.iter().enumerate() {
                    let copies = out.iter().filter(|&&j| j as usize == i).count() as u64;
                    let expected = m as u64 * w as u64;
                    let total = WEIGHT_TOTAL as u64;
                    prop_assert!(copies >= expected / total && copies <= expected.div_ceil(total));
                }
            }
        }
    }

    /// `normalise` sums to exactly `WEIGHT_TOTAL`, keeps zeros zero (unless all are) and
    /// each weight within one unit of its share; the effective sample size lies in
    /// `[1, non-zero count]`, 0 when all are zero.
    #[test]
    fn normalise_and_effective_sample_size(weights in weights_case()) {
        let mut w = weights.clone();
        let found = normalise(&mut w);
        let sum: u64 = weights.iter().map(|&x| x as u64).sum();
        prop_assert_eq!(found == Normalised::AllZero, sum == 0);
        prop_assert_eq!(w.iter().map(|&x| x as u64).sum::<u64>(), WEIGHT_TOTAL as u64);
        if sum > 0 {
            for (&a, &b) in w.iter().zip(weights.iter()) {
                let ideal = b as f64 / sum as f64 * WEIGHT_TOTAL as f64;
                prop_assert!((a as f64 - ideal).abs() <= 1.0);
                prop_assert!(b > 0 || a == 0);
            }
        }
        let nonzero = weights.iter().filter(|&&x| x > 0).count();
        let ess = effective_sample_size(&weights);
        if nonzero == 0 {
            prop_assert_eq!(ess, Q16::ZERO);
        } else {
            prop_assert!(ess.to_f64() >= 1.0 - 1e-4 && ess <= Q16::from_int(nonzero as i32), "ess {}", ess);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Q16 saturation.

fn clamp_i32(v: i128) -> i32 {
    v.clamp(i32::MIN as i128, i32::MAX as i128) as i32
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// Every operator gives the exact result clamped to the rails (never a wrapped one):
    /// add, sub, mul (rounded to nearest), div (toward zero; by zero to the dividend's
    /// rail), neg, abs, mul_int, from_int, from_ratio; sqrt is the floor of the root.
    #[test]
    fn q16_operations_saturate(
        a in prop_oneof![any::<i32>(), Just(i32::MAX), Just(i32::MIN), -70_000i32..70_000],
        b in prop_oneof![any::<i32>(), Just(i32::MAX), Just(i32::MIN), -70_000i32..70_000, Just(0)],
        n in any::<i32>(),
        num in any::<i64>(),
        den in any::<i64>(),
    ) {
        let (x, y) = (Q16::from_bits(a), Q16::from_bits(b));
        let (a, b) = (a as i128, b as i128);
        prop_assert_eq!((x + y).to_bits(), clamp_i32(a + b));
        prop_assert_eq!((x - y).to_bits(), clamp_i32(a - b));
        prop_assert_eq!((x * y).to_bits(), clamp_i32((a * b + 0x8000) >> 16));
        let quotient = if b == 0 {
            match a.signum() { 1 => i32::MAX, -1 => i32::MIN, _ => 0 }
        } else {
            clamp_i32((a << 16) / b)
        };
        prop_assert_eq!((x / y).to_bits(), quotient);
        prop_assert_eq!((-x).to_bits(), clamp_i32(-a));
        prop_assert_eq!(x.abs().to_bits(), clamp_i32(a.abs()));
        prop_assert_eq!(x.mul_int(n).to_bits(), clamp_i32(a * n as i128));
        prop_assert_eq!(Q16::from_int(n).to_bits(), clamp_i32((n as i128) << 16));
        let ratio = if den == 0 { 0 } else { clamp_i32(num as i128 * 65536 / den as i128) };
        prop_assert_eq!(Q16::from_ratio(num, den).to_bits(), ratio);
        // Saturation never flips a sign: same-signed operands give a same-signed sum.
        if a > 0 && b > 0 {
            prop_assert!(x + y > Q16::ZERO && x * y >= Q16::ZERO);
        }
        if a < 0 && b < 0 {
            prop_assert!(x + y < Q16::ZERO && x * y >= Q16::ZERO);
        }
        let s = x.sqrt().to_bits() as i128;
        if a <= 0 {
            prop_assert_eq!(s, 0);
        } else {
            // s = floor(sqrt(a * 2^16)), raw.
            prop_assert!(s * s <= a << 16 && (s + 1) * (s + 1) > a << 16);
        }
        prop_assert_eq!(x.floor_int() as i128, a >> 16);
        prop_assert_eq!(x.round_int() as i128, (a + 0x8000) >> 16);
        prop_assert_eq!(x.saturating_add(y), x + y);
        prop_assert_eq!(x.saturating_mul(y), x * y);
    }
}

// ---------------------------------------------------------------------------------------
// Entry points the fuzz targets cannot vary: the const generic particle count.

/// `N = 0` is refused with `ConfigError::ParticleCount`, not a panic (`N` above 65535 is
/// refused the same way; such a tracker is too large to build on a test's stack).
#[test]
fn zero_particles_is_an_error() {
    use rbtrack::tracker::{Config, ConfigError, Tracker, Variant};
    let buf = [0u8; 16 * 16];
    let img = ImageView::<Gray8>::new(&buf, 16, 16, 16).expect("frame");
    let init = Ellipse::new(
        Q16::from_int(8),
        Q16::from_int(8),
        Q16::from_int(3),
        Q16::from_int(3),
    );
    for variant in [Variant::Rbpf, Variant::ColourPf] {
        let r = Tracker::<Luma64, 0, 64>::new(Config::new(variant), &img, init);
        assert_eq!(r.err(), Some(ConfigError::ParticleCount));
    }
}
