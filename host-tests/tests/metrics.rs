//! OTB metrics against hand-computed cases.

use rbtrack_host::metrics::*;

const EPS: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < EPS
}

#[test]
fn identical_boxes() {
    let a = BBox::new(10.0, 20.0, 30.0, 40.0);
    assert_eq!(a.iou(&a), 1.0);
    assert_eq!(a.centre_error(&a), 0.0);
    assert_eq!(a.area(), 1200.0);
}

#[test]
fn disjoint_boxes() {
    let a = BBox::new(0.0, 0.0, 10.0, 10.0);
    let b = BBox::new(30.0, 40.0, 10.0, 10.0);
    assert_eq!(a.iou(&b), 0.0);
    assert!(close(a.centre_error(&b), 50.0));
    // Touching edges share no pixel.
    let c = BBox::new(10.0, 0.0, 10.0, 10.0);
    assert_eq!(a.iou(&c), 0.0);
}

#[test]
fn partial_overlaps() {
    let a = BBox::new(0.0, 0.0, 10.0, 10.0);
    // Shifted by half its width: overlap 50, union 150.
    let b = BBox::new(5.0, 0.0, 10.0, 10.0);
    assert!(close(a.iou(&b), 1.0 / 3.0));
    assert!(close(b.iou(&a), 1.0 / 3.0));
    assert!(close(a.centre_error(&b), 5.0));
    // Top half of the same box.
    let c = BBox::new(0.0, 0.0, 10.0, 5.0);
    assert!(close(a.iou(&c), 0.5));
    // Contained quarter.
    let d = BBox::new(2.0, 2.0, 5.0, 5.0);
    assert!(close(a.iou(&d), 0.25));
}

#[test]
fn empty_and_non_finite_boxes_never_nan() {
    let a = BBox::new(0.0, 0.0, 10.0, 10.0);
    let zero = BBox::new(5.0, 5.0, 0.0, 0.0);
    let negative = BBox::new(5.0, 5.0, -3.0, 4.0);
    let nan = BBox::new(f64::NAN, 0.0, 10.0, 10.0);
    let inf = BBox::new(0.0, 0.0, f64::INFINITY, 10.0);
    for b in [zero, negative, nan, inf] {
        assert!(!b.is_valid());
        assert_eq!(b.area(), 0.0);
        assert_eq!(a.iou(&b), 0.0);
        assert_eq!(b.iou(&a), 0.0);
        assert_eq!(b.iou(&b), 0.0);
    }
    assert_eq!(zero.centre_error(&zero), 0.0);
    assert_eq!(a.centre_error(&nan), f64::INFINITY);
    assert_eq!(nan.centre_error(&a), f64::INFINITY);
    let far = BBox::new(f64::MAX, f64::MAX, 1.0, 1.0);
    assert_eq!(
        far.centre_error(&BBox::new(-f64::MAX, 0.0, 1.0, 1.0)),
        f64::INFINITY
    );
}

#[test]
fn otb_centre_and_ellipse_round_trip() {
    // A 5-px-wide box at x = 10 covers pixels 10..=14: centre pixel 12.
    let b = BBox::new(10.0, 20.0, 5.0, 7.0);
    assert_eq!(b.centre(), (12.0, 23.0));
    let (cx, cy, hx, hy) = b.to_ellipse_f64();
    assert_eq!((cx, cy, hx, hy), (12.0, 23.0, 2.5, 3.5));
    assert_eq!(BBox::from_ellipse(cx, cy, hx, hy), b);
    let e = BBox::from_ellipse(100.0, 50.0, 8.0, 20.0);
    assert_eq!(e, BBox::new(92.5, 30.5, 16.0, 40.0));
    assert_eq!(e.centre(), (100.0, 50.0));
}

#[test]
fn one_based_conversion_and_clip() {
    let b = BBox::new(1.0, 1.0, 4.0, 3.0);
    assert_eq!(b.from_one_based(), BBox::new(0.0, 0.0, 4.0, 3.0));
    assert_eq!(b.from_one_based().to_one_based(), b);
    let c = BBox::new(-5.0, 8.0, 10.0, 10.0).clip(20.0, 12.0);
    assert_eq!(c, BBox::new(0.0, 8.0, 5.0, 4.0));
    let outside = BBox::new(30.0, 0.0, 5.0, 5.0).clip(20.0, 12.0);
    assert_eq!(outside.w, 0.0);
    assert!(!outside.is_valid());
}

#[test]
fn success_curve_and_auc() {
    let t = success_thresholds();
    assert_eq!(t.len(), 21);
    assert_eq!(t[0], 0.0);
    assert!(close(t[1], 0.05));
    assert_eq!(t[20], 1.0);

    let ious = [1.0, 0.5, 0.0, 0.75];
    let curve = success_curve(&ious);
    assert_eq!(curve[0], 0.75); // > 0: three of four
    assert_eq!(curve[10], 0.5); // > 0.5 (strict): 1.0 and 0.75
    assert_eq!(curve[15], 0.25); // > 0.75 (strict): 1.0 only
    assert_eq!(curve[20], 0.0); // nothing exceeds 1
                                // 1.0 passes 20 thresholds, 0.75 passes 15, 0.5 passes 10, 0 none: 45 / 4 / 21.
    assert!(close(success_auc(&ious), 45.0 / 4.0 / 21.0));
    assert_eq!(success_rate(&ious), 0.5);
    // Perfect tracking: 20 of 21 thresholds.
    assert!(close(success_auc(&[1.0; 7]), 20.0 / 21.0));
}

#[test]
fn precision() {
    let errors = [0.0, 20.0, 20.0001, f64::INFINITY];
    assert_eq!(precision_at(&errors, 20.0), 0.5);
    assert_eq!(precision_at(&errors, 0.0), 0.25);
    let curve = precision_curve(&errors, PRECISION_MAX_PX);
    assert_eq!(curve.len(), 51);
    assert_eq!(curve[19], 0.25);
    assert_eq!(curve[20], 0.5);
    assert_eq!(curve[21], 0.75);
    assert_eq!(curve[50], 0.75);
}

#[test]
fn empty_inputs_are_zero_not_nan() {
    assert_eq!(success_curve(&[]), [0.0; 21]);
    assert_eq!(success_auc(&[]), 0.0);
    assert_eq!(success_rate(&[]), 0.0);
    assert_eq!(precision_at(&[], 20.0), 0.0);
    assert_eq!(mean(&[]), 0.0);
    assert_eq!(mean(&[f64::NAN]), 0.0);
    assert_eq!(mean(&[1.0, f64::INFINITY]), f64::INFINITY);
    assert_eq!(mean(&[1.0, 2.0, f64::NAN]), 1.5);
    let e = Evaluation::new(&[], &[]);
    assert_eq!(e.frames, 0);
    assert_eq!(e.mean_iou, 0.0);
    assert_eq!(e.success_auc, 0.0);
    assert_eq!(e.precision_20, 0.0);
    assert_eq!(e.mean_centre_error, 0.0);
}

#[test]
fn evaluation_skips_invalid_truth() {
    let gt = [
        BBox::new(0.0, 0.0, 10.0, 10.0),
        BBox::new(f64::NAN, 0.0, 10.0, 10.0), // skipped
        BBox::new(0.0, 0.0, 10.0, 10.0),
        BBox::new(0.0, 0.0, 0.0, 10.0), // skipped
        BBox::new(0.0, 0.0, 10.0, 10.0),
    ];
    let est = [
        BBox::new(0.0, 0.0, 10.0, 10.0), // IoU 1, error 0
        BBox::new(0.0, 0.0, 10.0, 10.0), // (skipped)
        BBox::new(5.0, 0.0, 10.0, 10.0), // IoU 1/3, error 5
        BBox::new(0.0, 0.0, 10.0, 10.0), // (skipped)
        BBox::new(30.0, 40.0, 0.0, 0.0), // lost: IoU 0, error of centres
    ];
    let e = Evaluation::new(&gt, &est);
    assert_eq!(e.frames, 3);
    assert_eq!(e.skipped, 2);
    assert!(close(e.mean_iou, (1.0 + 1.0 / 3.0) / 3.0));
    assert!(close(e.success_rate, 1.0 / 3.0));
    // Centre of the empty box is (29.5, 39.5); truth centre (4.5, 4.5).
    let lost = (25.0f64).hypot(35.0);
    assert!(close(e.mean_centre_error, (0.0 + 5.0 + lost) / 3.0));
    assert!(close(e.precision_20, 2.0 / 3.0));
    assert_eq!(e.success_curve, success_curve(&e.ious));
    assert_eq!(e.precision_curve.len(), 51);
    // Shorter estimate list: scored over the common frames only.
    assert_eq!(Evaluation::new(&gt, &est[..1]).frames, 1);
}
