//! How a tracker comes through the part of a synthetic scene where its target is not fully
//! visible: an occlusion, a look-alike crossing in front, leaving the frame.
//!
//! # Example
//! ```
//! use rbtrack::tracker::Variant;
//! use rbtrack_host::recovery::recovery;
//! use rbtrack_host::run::Options;
//! use rbtrack_host::scene::{Scene, SceneConfig, Variant as SceneVariant};
//! let mut config = SceneConfig::new(SceneVariant::Occlusion, 1);
//! config.frames = 40;
//! let scene = Scene::new(config).unwrap();
//! let mut options = Options::new(Variant::Rbpf);
//! scene.configure(&mut options.config);
//! let r = recovery(&scene, &options).unwrap();
//! assert!(r.hidden > 0 && r.after > 0);
//! ```

use crate::run::{start, Options, RunError};
use crate::scene::Scene;
use rbtrack::tracker::Status;

/// The outcome of one run over a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Recovery {
    /// Frames from the target being fully visible again (after it was partly or wholly
    /// hidden) until the estimate's IoU with the truth exceeds 0.5; `None` if it never
    /// does or the target is never hidden.
    pub delay: Option<usize>,
    /// Frames in which the target was not visible (`Truth::visible` false: under a quarter
    /// of it seen).
    pub hidden: u32,
    /// Of those, frames reported `Lost`.
    pub lost_while_hidden: u32,
    /// Of those, the frames before the first reported `Lost` (all of them if none is).
    pub hidden_until_lost: u32,
    /// Of those, the frames wholly covered (nothing of the target seen).
    pub covered_until_lost: u32,
    /// Frames from the target being fully visible again to the end.
    pub after: u32,
    /// Of those, frames whose estimated centre lies nearer the target's than the
    /// distractor's (all of them in scenes without one).
    pub nearer_target: u32,
}

impl Recovery {
    /// Whether the target was had again (IoU > 0.5) within `frames` frames.
    pub fn within(&self, frames: usize) -> bool {
        self.delay.is_some_and(|d| d <= frames)
    }
}

/// Runs a tracker with `options` over `scene` from the first frame's truth.
///
/// # Errors
/// The tracker rejects the configuration or the initial box.
pub fn recovery(scene: &Scene, options: &Options) -> Result<Recovery, RunError> {
    let mut frames = scene.frames();
    let Some(first) = frames.next() else {
        return Ok(Recovery::default());
    };
    let mut runner = start(options, &first, &scene.boxes()[0])?;
    let mut r = Recovery::default();
    let (mut was_covered, mut back) = (false, None);
    for (i, frame) in (1..).zip(frames) {
        let step = runner.step(&frame)?;
        let Some(truth) = scene.truth(i) else { break };
        was_covered |= truth.visible_fraction < 1.0;
        if !truth.visible {
            let lost = step.estimate.status == Status::Lost;
            r.hidden += 1;
            r.lost_while_hidden += lost as u32;
            let before = r.lost_while_hidden == 0;
            r.hidden_until_lost += before as u32;
            r.covered_until_lost += (before && truth.visible_fraction <= 0.0) as u32;
        }
        if was_covered && back.is_none() && truth.visible_fraction >= 1.0 {
            back = Some(i);
        }
        let Some(b) = back else { continue };
        if r.delay.is_none() && truth.bbox.iou(&step.bbox) > 0.5 {
            r.delay = Some(i - b);
        }
        let e = &step.estimate.ellipse;
        let (cx, cy) = (e.cx.to_f64(), e.cy.to_f64());
        let to_target = (cx - truth.cx).hypot(cy - truth.cy);
        let to_distractor = scene
            .distractor(i)
            .map_or(f64::INFINITY, |(dx, dy, _, _)| (cx - dx).hypot(cy - dy));
        r.after += 1;
        r.nearer_target += (to_target < to_distractor) as u32;
    }
    Ok(r)
}
