//! Boxes, and where a tracker puts the target.

use super::rbt_error::{self, *};
use super::rbt_q16;
use rbtrack::tracker::{Estimate, Status};
use rbtrack::{Ellipse, Rect, Q16};

/// A box: top-left corner `(x, y)` and size `w x h`, px, Q16.16, 0-based (a box of whole
/// pixels covers columns `x..=x+w-1`). A tracker works on its inscribed ellipse.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_rect {
    /// Left edge (the centre of the leftmost pixel column), px, Q16.16.
    pub x: rbt_q16,
    /// Top edge (the centre of the top pixel row), px, Q16.16.
    pub y: rbt_q16,
    /// Width, px, Q16.16.
    pub w: rbt_q16,
    /// Height, px, Q16.16.
    pub h: rbt_q16,
}

impl rbt_rect {
    /// The box's inscribed ellipse.
    fn ellipse(&self) -> Ellipse {
        let q = Q16::from_bits;
        Rect::from_q16(q(self.x), q(self.y), q(self.w), q(self.h)).into()
    }
}

/// The box at `rect`.
///
/// # Safety
/// `rect` is null or points to an `rbt_rect`.
pub(super) unsafe fn ellipse(rect: *const rbt_rect) -> Result<Ellipse, rbt_error> {
    // SAFETY: null (refused) or an `rbt_rect` (the caller's promise).
    unsafe { rect.as_ref() }
        .map(rbt_rect::ellipse)
        .ok_or(RBT_ERR_NULL)
}

/// How sure the tracker is of its estimate, numbered from least to most sure.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_status {
    /// Confidence below `lost_below`: the target is hidden, gone or confused with another.
    RBT_STATUS_LOST = 0,
    /// Confidence in `[lost_below, uncertain_below)`.
    RBT_STATUS_UNCERTAIN = 1,
    /// Confidence at or above `uncertain_below`.
    RBT_STATUS_TRACKING = 2,
}

/// Where the target is after a step.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_estimate {
    /// The box: the ellipse's bounding box, px, Q16.16.
    pub rect: rbt_rect,
    /// The ellipse's centre column, px, Q16.16; always inside the frame.
    pub cx: rbt_q16,
    /// The ellipse's centre row, px, Q16.16.
    pub cy: rbt_q16,
    /// Horizontal half-axis, px, Q16.16.
    pub hx: rbt_q16,
    /// Vertical half-axis, px, Q16.16.
    pub hy: rbt_q16,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: rbt_q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: rbt_q16,
    /// The tracker's own score, Q16.16 in [0, 1]: a particle filter's colour coefficient
    /// less the particles' spread, the correlation filter's merged response margin (its
    /// peak less the best move beyond the peak's lobe).
    pub score: rbt_q16,
    /// The score through the tracker's calibration: about the chance that the box
    /// overlaps the target's by an IoU of at least 0.5, alike for every tracker; it sets
    /// the status. Q16.16 in [0, 1].
    pub confidence: rbt_q16,
    /// An `rbt_status`.
    pub status: u32,
}

impl From<Estimate> for rbt_estimate {
    fn from(e: Estimate) -> Self {
        let r = e.rect();
        let el = e.ellipse;
        Self {
            rect: rbt_rect {
                x: r.x.to_bits(),
                y: r.y.to_bits(),
                w: r.w.to_bits(),
                h: r.h.to_bits(),
            },
            cx: el.cx.to_bits(),
            cy: el.cy.to_bits(),
            hx: el.hx.to_bits(),
            hy: el.hy.to_bits(),
            vx: e.vx.to_bits(),
            vy: e.vy.to_bits(),
            score: e.score.to_bits(),
            confidence: e.confidence.to_bits(),
            status: match e.status {
                Status::Lost => rbt_status::RBT_STATUS_LOST,
                Status::Uncertain => rbt_status::RBT_STATUS_UNCERTAIN,
                Status::Tracking => rbt_status::RBT_STATUS_TRACKING,
            } as u32,
        }
    }
}

impl rbt_estimate {
    /// The core's estimate of these fields (the ellipse, not `rect`).
    pub(super) fn estimate(&self) -> Result<Estimate, rbt_error> {
        let status = match self.status {
            0 => Status::Lost,
            1 => Status::Uncertain,
            2 => Status::Tracking,
            _ => return Err(RBT_ERR_STATUS),
        };
        let q = Q16::from_bits;
        Ok(Estimate {
            ellipse: Ellipse::new(q(self.cx), q(self.cy), q(self.hx), q(self.hy)),
            vx: q(self.vx),
            vy: q(self.vy),
            score: q(self.score),
            confidence: q(self.confidence),
            status,
        })
    }
}
