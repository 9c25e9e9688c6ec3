"""rbtrack: a visual object tracker (a correlation-filter tracker, a colour particle
filter and a Rao-Blackwellised particle filter) with OpenCV's tracker interface.

    import cv2, rbtrack
    video = cv2.VideoCapture("clip.mp4")
    ok, frame = video.read()
    tracker = rbtrack.Tracker()           # or rbtrack.TrackerCreate(variant="pf", particles=50)
    tracker.init(frame, (140, 90, 40, 60))
    ok, (x, y, w, h) = tracker.update(frame)   # ok is False while the target is lost

Frames are NumPy uint8 arrays: (H, W, 3) in B, G, R order (as OpenCV reads them) by
default, R, G, B with format="rgb", (H, W) or (H, W, 1) grey levels with format="gray".
A frame whose rows lie in one buffer with unit pixel and channel steps (any row stride,
so a crop of a larger frame too) is read in place; any other is copied first.
"""

from typing import Literal, Optional, Tuple

import numpy as np
import numpy.typing as npt

Box = Tuple[float, float, float, float]
"""A box (x, y, w, h): top-left corner and size, px, 0-based (a box of whole pixels
covers columns x..x+w-1). As an argument, any sequence of 4 numbers (a tuple, a list, a
NumPy array)."""

Variant = Literal["cf", "rbpf", "pf"]
Format = Literal["bgr", "rgb", "gray", "grey"]
Status = Literal["tracking", "uncertain", "lost"]

PARTICLES: list[int]
"""The particle counts offered: 25, 50, 100, 200."""

class Tracker:
    """One target, tracked frame by frame.

    variant: "cf" (the correlation-filter tracker: a shape template and a colour model,
        a scale filter; 16 x 16 cells, 4 scales, at its defaults; the default and the most
        accurate), "rbpf" (Rao-Blackwellised particle filter: colour and boundary cues,
        size by a Kalman filter) or "pf" (colour particle filter: cheaper).
    particles: a particle filter's, one of PARTICLES (default 100); none for "cf".
    seed: a particle filter's seed of the random draws (default 1); none for "cf", which
        draws none. The same variant, seed, frames and box give the same boxes as
        `rbtrack track` does.
    format: the frames' layout, "bgr" (default), "rgb" or "gray".

    Raises ValueError for a variant, particle count or format it does not offer, and for
    particles or a seed given to "cf".
    """

    def __init__(
        self,
        variant: Variant = "cf",
        particles: Optional[int] = None,
        seed: Optional[int] = None,
        format: Format = "bgr",
    ) -> None: ...
    def init(self, frame: npt.NDArray[np.uint8], bbox: Box) -> None:
        """Starts on the box `bbox` of `frame`, whatever the tracker did before.

        Raises TypeError for a frame that is not a uint8 array or a box that is not a
        sequence of numbers; ValueError for a shape the format does not take, a box of
        other than 4 numbers ("box must be 4 numbers x, y, w, h") or with one not finite,
        or a box the core refuses (the core's message: smaller than 4 px across, or
        centred outside the frame).
        """
    def update(self, frame: npt.NDArray[np.uint8]) -> Tuple[bool, Tuple[int, int, int, int]]:
        """Tracks one frame, with the GIL released: (ok, (x, y, w, h)), the box rounded to
        whole pixels (`box` has it exactly) and ok False while `status` is "lost".

        Raises RuntimeError before `init`; TypeError and ValueError as `init` does for
        the frame, and ValueError for a frame of another size than `init`'s.
        """
    def relocate(self, frame: npt.NDArray[np.uint8], bbox: Box) -> None:
        """Moves the tracker onto the box `bbox` of `frame` (a detector's, say), keeping
        what it learnt: a particle filter's colour model, the correlation filter's filter,
        colour model and scale filter. Raises as `init` does, RuntimeError before it, and
        ValueError for a frame of another size than `init`'s."""
    @property
    def box(self) -> Box:
        """The last box (x, y, w, h), px, exact (multiples of 1/65536): the initial box
        after `init`. RuntimeError before `init`."""
    @property
    def ellipse(self) -> Tuple[float, float, float, float]:
        """The last ellipse (cx, cy, hx, hy): centre and half-axes, px."""
    @property
    def status(self) -> Status:
        """"tracking", "uncertain" or "lost", by the confidence."""
    @property
    def confidence(self) -> float:
        """How sure the tracker is, 0..1: about the chance that the box overlaps the
        target's by an IoU of at least 0.5, the same for every variant (its score through
        a table fitted on 44 sequences). Below 0.5 "uncertain", below 0.2 "lost"."""
    @property
    def score(self) -> float:
        """The tracker's own score, 0..1, before calibration. "cf": how far the peak of its merged
        template and colour response stands above the rest of it; "rbpf" and "pf": how well the estimate's window
        matches the target's colours, less the particles' spread."""
    @property
    def variant(self) -> Variant: ...
    @property
    def particles(self) -> Optional[int]:
        """A particle filter's particles; None for "cf"."""
    @property
    def seed(self) -> Optional[int]:
        """A particle filter's seed; None for "cf"."""
    @property
    def format(self) -> Format: ...

def TrackerCreate(
    variant: Variant = "cf",
    particles: Optional[int] = None,
    seed: Optional[int] = None,
    format: Format = "bgr",
) -> Tracker:
    """Tracker(...), named as OpenCV names its factories (cv2.TrackerCSRT_create)."""

def frame_is_borrowed(frame: npt.NDArray[np.uint8], format: Format = "bgr") -> bool:
    """Whether `frame` would be read in place in `format` (True) or copied first."""
