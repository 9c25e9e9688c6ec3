//! Faulty camera streams built on the synthetic scenes ([`crate::scene`]): black frames,
//! frames of pure noise, a frozen frame repeated, torn frames (the lower rows still from
//! the previous frame, as when a frame buffer is read while the camera writes it) and
//! sudden illumination changes, each over a range of frame indices. A target that leaves
//! the frame comes from the scene itself ([`crate::scene::Variant::LeaveAndReturn`]; with
//! 250 frames it is wholly outside for 50).
//!
//! The scene's own frames and ground truth are unchanged; a [`FaultyScene`] only rewrites
//! the frames it renders, deterministically from the scene's seed.
//!
//! # Example
//! ```
//! use rbtrack_host::faults::{Fault, FaultyScene};
//! use rbtrack_host::scene::{Scene, SceneConfig, Variant};
//! let scene = Scene::new(SceneConfig::new(Variant::Perspective, 1)).unwrap();
//! let faulty = FaultyScene::new(scene, vec![(Fault::Black, 10..20)]);
//! assert!(faulty.render(12).unwrap().iter().all(|&b| b == 0));
//! assert!(faulty.target_hidden(12));
//! assert!(faulty.plainly_visible(25));
//! ```

use crate::scene::{Scene, SceneError, Truth};
use std::ops::Range;

/// What goes wrong with a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// All bytes zero.
    Black,
    /// Uniform random bytes, different in every frame.
    Noise,
    /// The last good frame before the fault, repeated.
    Frozen,
    /// Rows from `split` (share of the height, `0..=1`) down come from the scene's previous
    /// frame.
    Torn {
        /// First row taken from the previous frame, as a share of the height.
        split: f64,
    },
    /// Every channel multiplied by `gain` (rounded, saturating at 255).
    Illumination {
        /// Brightness gain, `>= 0`.
        gain: f64,
    },
}

impl Fault {
    /// Whether the fault hides the target from view (black and noise frames do).
    pub fn hides_target(self) -> bool {
        matches!(self, Fault::Black | Fault::Noise)
    }
}

/// A scene whose frames in given ranges suffer given faults.
#[derive(Clone, Debug)]
pub struct FaultyScene {
    scene: Scene,
    faults: Vec<(Fault, Range<usize>)>,
}

impl FaultyScene {
    /// `scene` with `faults`, each over a range of frame indices (the first one listed
    /// wins where ranges overlap).
    pub fn new(scene: Scene, faults: Vec<(Fault, Range<usize>)>) -> Self {
        Self { scene, faults }
    }

    /// The underlying scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.scene.len()
    }

    /// Always false: a scene has at least 10 frames.
    pub fn is_empty(&self) -> bool {
        self.scene.is_empty()
    }

    /// The fault of frame `index`, if any.
    pub fn fault(&self, index: usize) -> Option<Fault> {
        self.faults
            .iter()
            .find(|(_, range)| range.contains(&index))
            .map(|(fault, _)| *fault)
    }

    /// The first frame of the fault covering `index` (or `index` itself).
    fn fault_start(&self, index: usize) -> usize {
        self.faults
            .iter()
            .find(|(_, range)| range.contains(&index))
            .map_or(index, |(_, range)| range.start)
    }

    /// Ground truth of frame `index`, as the scene draws it (a frozen frame still shows
    /// the target where it was when the stream froze: see [`FaultyScene::shown_truth`]).
    pub fn truth(&self, index: usize) -> Option<&Truth> {
        self.scene.truth(index)
    }

    /// Where the target appears in frame `index` of the faulty stream: for a frozen frame
    /// the truth of the frame that is repeated, else the scene's.
    pub fn shown_truth(&self, index: usize) -> Option<&Truth> {
        match self.fault(index) {
            Some(Fault::Frozen) => self.scene.truth(self.fault_start(index).saturating_sub(1)),
            _ => self.scene.truth(index),
        }
    }

    /// Whether none of the target can be seen in frame `index`: it is wholly out of view
    /// (or hidden), or a black or noise frame hides it.
    pub fn target_hidden(&self, index: usize) -> bool {
        self.shown_truth(index)
            .is_none_or(|t| t.visible_fraction == 0.0)
            || self.fault(index).is_some_and(Fault::hides_target)
    }

    /// Whether the target is plainly visible in frame `index`: wholly in view and the
    /// frame is not faulty.
    pub fn plainly_visible(&self, index: usize) -> bool {
        self.fault(index).is_none()
            && self
                .scene
                .truth(index)
                .is_some_and(|t| t.visible_fraction >= 1.0)
    }

    /// Renders frame `index` of the faulty stream as RGB888.
    pub fn render(&self, index: usize) -> Result<Vec<u8>, SceneError> {
        let (w, h) = (self.scene.width() as usize, self.scene.height() as usize);
        let Some(fault) = self.fault(index) else {
            return self.scene.render(index);
        };
        Ok(match fault {
            Fault::Black => {
                self.scene.render(index)?; // checks the index
                vec![0; w * h * 3]
            }
            Fault::Noise => {
                self.scene.render(index)?;
                let mut state =
                    self.scene.config().seed ^ (index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                (0..w * h * 3)
                    .map(|_| (splitmix(&mut state) >> 56) as u8)
                    .collect()
            }
            Fault::Frozen => {
                self.scene.render(index)?;
                self.render(self.fault_start(index).saturating_sub(1))?
            }
            Fault::Torn { split } => {
                let mut frame = self.scene.render(index)?;
                if index > 0 {
                    let previous = self.scene.render(index - 1)?;
                    let row = ((split.clamp(0.0, 1.0) * h as f64).round() as usize).min(h);
                    frame[row * w * 3..].copy_from_slice(&previous[row * w * 3..]);
                }
                frame
            }
            Fault::Illumination { gain } => {
                let gain = gain.max(0.0);
                self.scene
                    .render(index)?
                    .into_iter()
                    .map(|v| (v as f64 * gain).round().min(255.0) as u8)
                    .collect()
            }
        })
    }
}

/// One SplitMix64 step: advances `state` and returns the next output.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
