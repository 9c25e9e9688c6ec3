//! The correlation-filter tracker relocated onto a detector's box on real video, its
//! filter, colour and scale models kept, against the same tracker left alone and one
//! started afresh on the box.

use rbtrack::image::Rgb888;
use rbtrack::tracker::CfConfig;
use rbtrack::{ImageView, Rect, RgbCfTracker};
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::{Format, Frame};
use rbtrack_host::run::{bbox_of, ellipse_of};
use rbtrack_host::sequence::{shared_data_dir, GtOrigin, Sequence};

/// Frames after the relocation that are scored.
const AFTER: usize = 20;

fn view(frame: &Frame) -> ImageView<'_, Rgb888> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    ImageView::new(&frame.bytes, w, h, w).expect("an RGB888 frame")
}

/// On the frames after `name` loses the target from its first box (the ground truth's
/// shifted by `shift`, px) (IoU below 0.1 for 5 frames in a row), how many of the next
/// [`AFTER`] frames are on the target (IoU at least 0.5): relocated there onto the
/// ground-truth box, left alone, started afresh on the box; `None` if it never loses the
/// target.
fn after_the_loss(
    data: &std::path::Path,
    name: &str,
    shift: (f64, f64),
) -> Option<(usize, [usize; 3])> {
    let seq = Sequence::open(data.join(name), GtOrigin::of_shared(name)).expect("opens");
    let frames: Vec<Frame> = seq.frames().map(|f| f.expect("decodes")).collect();
    assert!(frames.iter().all(|f| f.format == Format::Rgb888));
    let truth = &seq.groundtruth;
    let rect = |k: usize| Rect::from(ellipse_of(&truth[k]));
    let config = CfConfig::default();

    let mut tracker = Box::new(RgbCfTracker::unstarted());
    let first = BBox {
        x: truth[0].x + shift.0,
        y: truth[0].y + shift.1,
        ..truth[0]
    };
    tracker
        .start(config, &view(&frames[0]), Rect::from(ellipse_of(&first)))
        .expect("starts");
    let mut off = 0;
    let lost_at = (1..frames.len()).find(|&k| {
        let e = tracker.step(&view(&frames[k]));
        off = match bbox_of(&e).iou(&truth[k]) < 0.1 {
            true => off + 1,
            false => 0,
        };
        off == 5
    })?;
    assert!(lost_at + AFTER < frames.len(), "{name}: lost at {lost_at}");

    let mut alone = tracker.clone();
    tracker
        .relocate(&view(&frames[lost_at]), rect(lost_at))
        .expect("relocates");
    let mut fresh = Box::new(RgbCfTracker::unstarted());
    fresh
        .start(config, &view(&frames[lost_at]), rect(lost_at))
        .expect("starts");
    let on = |t: &mut RgbCfTracker| {
        (lost_at + 1..=lost_at + AFTER)
            .filter(|&k| bbox_of(&t.step(&view(&frames[k]))).iou(&truth[k]) >= 0.5)
            .count()
    };
    let counts = [on(&mut tracker), on(&mut alone), on(&mut fresh)];
    println!(
        "{name}: lost at frame {}; on the target in the next {AFTER} frames: relocated {}, \
         left alone {}, started afresh {}",
        lost_at + 1,
        counts[0],
        counts[1],
        counts[2]
    );
    Some((lost_at, counts))
}

/// On `KiteSurf` the surfer is lost from some first box, the ground truth's shifted 2 px
/// (the 7-start protocol's `left2`, `right2`, `up2`, `down2`, the first that loses him);
/// relocated onto the ground-truth box, the tracker is on him on at least 15 of the next
/// 20 frames, where left alone it is on at most 5 (skipped without ../shared/data).
/// `Girl`'s figures are printed too:
/// there the tracker lost her to a man's face it went on learning, and the relocated
/// tracker, whose models hold that face, does worse than one started afresh.
#[test]
fn a_detectors_box_brings_the_lost_target_back() {
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED: no ../shared/data folder with the real sequences");
        return;
    };
    let (_, [relocated, alone, _]) = [(-2.0, 0.0), (2.0, 0.0), (0.0, -2.0), (0.0, 2.0)]
        .into_iter()
        .find_map(|shift| after_the_loss(&data, "KiteSurf", shift))
        .expect("KiteSurf's surfer is lost from one of the shifted boxes");
    assert!(relocated >= 15 && alone <= 5, "{relocated} {alone}");
    after_the_loss(&data, "Girl", (0.0, 0.0));
}
