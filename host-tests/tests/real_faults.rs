//! Faults on real video: the first 70 frames of `Crossing` (a man walking across a road),
//! with, from frame 21, an occluder pasted over the man for 10 frames, the man cut out and
//! pasted 60 px away (the ground truth moves with him), 10 frames dropped, or one frame of
//! noise. For each fault and tracker (defaults, N = 100, seed 1) it measures the frames
//! from the fault's start until the status is first `Lost`, and the frames from the
//! fault's end until the estimate is back on the man (IoU >= 0.5 with the ground truth),
//! prints them (`cargo test -p rbtrack-host --test real_faults -- --nocapture`, the
//! table in docs/guarantees.md) and asserts them. The runs are deterministic: the bounds
//! are today's figures, so that a change that makes one worse fails; "never" bounds nothing.

use rbtrack::tracker::{Status, Variant};
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::Frame;
use rbtrack_host::run::{self, Options};
use rbtrack_host::sequence::{shared_data_dir, GtOrigin, Sequence};

/// Frames of the sequence used.
const FRAMES: usize = 70;
/// The first faulty frame (0-based; frame 21 counted from 1).
const START: usize = 20;
/// Frames an occlusion or a gap lasts.
const LENGTH: usize = 10;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Fault {
    Occluder,
    CutAndPaste,
    Dropped,
    Noise,
}

/// The frames and ground truth as the tracker sees them with `fault`, and the first frame
/// after the fault (index into the returned frames).
fn faulty(fault: Fault, frames: &[Frame], truth: &[BBox]) -> (Vec<Frame>, Vec<BBox>, usize) {
    let mut frames = frames.to_vec();
    let mut truth = truth.to_vec();
    match fault {
        Fault::Occluder => {
            for (f, t) in frames.iter_mut().zip(&truth).skip(START).take(LENGTH) {
                let grown = BBox::new(t.x - 4.0, t.y - 4.0, t.w + 8.0, t.h + 8.0);
                fill(f, &grown, |_, _| [128, 128, 128]);
            }
            (frames, truth, START + LENGTH)
        }
        Fault::CutAndPaste => {
            for (f, t) in frames.iter_mut().zip(truth.iter_mut()).skip(START) {
                let from = *t;
                let to = BBox::new(from.x - 60.0, from.y, from.w, from.h);
                let original = f.clone();
                // The man's pixels to the new place, the new place's to his.
                fill(f, &to, |x, y| pixel(&original, x + 60, y));
                fill(f, &from, |x, y| pixel(&original, x - 60, y));
                *t = to;
            }
            (frames, truth, START)
        }
        Fault::Dropped => {
            frames.drain(START..START + LENGTH);
            truth.drain(START..START + LENGTH);
            (frames, truth, START)
        }
        Fault::Noise => {
            let mut state = 0x2545_f491_4f6c_dd1du64;
            for b in frames[START].bytes.iter_mut() {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                *b = state as u8;
            }
            (frames, truth, START + 1)
        }
    }
}

fn pixel(f: &Frame, x: i64, y: i64) -> [u8; 3] {
    let (w, h) = (f.width as i64, f.height as i64);
    let (x, y) = (x.clamp(0, w - 1), y.clamp(0, h - 1));
    let i = ((y * w + x) * 3) as usize;
    [f.bytes[i], f.bytes[i + 1], f.bytes[i + 2]]
}

/// Sets every pixel of `b` (clipped to the frame) to `colour(x, y)`.
fn fill(f: &mut Frame, b: &BBox, colour: impl Fn(i64, i64) -> [u8; 3]) {
    let (w, h) = (f.width as i64, f.height as i64);
    let (x0, y0) = (b.x.round().max(0.0) as i64, b.y.round().max(0.0) as i64);
    let (x1, y1) = (
        ((b.x + b.w).round() as i64).min(w),
        ((b.y + b.h).round() as i64).min(h),
    );
    for y in y0..y1 {
        for x in x0..x1 {
            let i = ((y * w + x) * 3) as usize;
            f.bytes[i..i + 3].copy_from_slice(&colour(x, y));
        }
    }
}

/// Frames from the fault's start until `Lost`, and from its end until the estimate is on
/// the target again (`None`: not within the sequence).
fn measure(
    variant: Variant,
    fault: Fault,
    frames: &[Frame],
    truth: &[BBox],
) -> (Option<usize>, Option<usize>) {
    let (frames, truth, end) = faulty(fault, frames, truth);
    let options = Options::new(variant);
    let mut tracker = run::start(&options, &frames[0], &truth[0]).unwrap();
    let mut lost = None;
    let mut back = None;
    for (i, f) in frames.iter().enumerate().skip(1) {
        let step = tracker.step(f).unwrap();
        if i >= START && lost.is_none() && step.estimate.status == Status::Lost {
            lost = Some(i - START);
        }
        if i >= end && back.is_none() && truth[i].iou(&step.bbox) >= 0.5 {
            back = Some(i - end);
        }
    }
    (lost, back)
}

#[test]
fn faults_on_real_frames() {
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED: no ../shared/data folder with the real sequences");
        return;
    };
    let seq = Sequence::open(data.join("Crossing"), GtOrigin::of_shared("Crossing")).unwrap();
    let frames: Vec<Frame> = (0..FRAMES).map(|i| seq.frame(i).unwrap()).collect();
    let truth = &seq.groundtruth[..FRAMES];
    let show = |v: Option<usize>| v.map_or("never".to_owned(), |n| n.to_string());
    println!("| fault | tracker | frames until Lost | frames until back on the target |");
    println!("|---|---|---|---|");
    let mut figures = Vec::new();
    for fault in [
        Fault::Occluder,
        Fault::CutAndPaste,
        Fault::Dropped,
        Fault::Noise,
    ] {
        for variant in [Variant::ColourPf, Variant::Rbpf] {
            let (lost, back) = measure(variant, fault, &frames, truth);
            println!(
                "| {fault:?} | {variant:?} | {} | {} |",
                show(lost),
                show(back)
            );
            figures.push(((fault, variant), (lost, back)));
        }
    }
    for (case, (lost, back)) in figures {
        let (lost_bound, back_bound) = bounds(case);
        for (what, got, bound) in [("Lost", lost, lost_bound), ("back", back, back_bound)] {
            if let Some(bound) = bound {
                assert!(
                    got.is_some_and(|n| n <= bound),
                    "{case:?}: frames until {what} {got:?}, at most {bound} expected"
                );
            }
        }
    }
}

/// docs/guarantees.md's figures for a fault and tracker: frames until `Lost` and until back on
/// the target, as upper bounds (`None`: never, which bounds nothing).
fn bounds(case: (Fault, Variant)) -> (Option<usize>, Option<usize>) {
    match case {
        (Fault::Occluder, Variant::ColourPf) => (Some(0), None),
        (Fault::Occluder, Variant::Rbpf) => (Some(0), Some(4)),
        (Fault::CutAndPaste, Variant::ColourPf) => (None, Some(15)),
        (Fault::CutAndPaste, Variant::Rbpf) => (None, Some(16)),
        (Fault::Dropped, Variant::ColourPf) => (None, Some(1)),
        (Fault::Dropped, Variant::Rbpf) => (None, Some(0)),
        (Fault::Noise, _) => (Some(0), Some(0)),
    }
}
