"""rbtrack: a visual object tracker (colour particle filter and Rao-Blackwellised
particle filter) with OpenCV's tracker interface.

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

from typing import Literal, Tuple

import numpy as np
import numpy.typing as npt

Box = Tuple[float, float, float, float]
"""A box (x, y, w, h): top-left corner and size, px, 0-based (a box of whole pixels
covers columns x..x+w-1)."""

Variant = Literal["rbpf", "pf"]
Format = Literal["bgr", "rgb", "gray", "grey"]
Status = Literal["tracking", "uncertain", "lost"]

PARTICLES: list[int]
"""The particle counts offered: 25, 50, 100, 200."""

class Tracker:
    """One target, tracked frame by frame.

    variant: "rbpf" (Rao-Blackwellised particle filter: colour and boundary cues, size by
        a Kalman filter; the default) or "pf" (colour particle filter: cheaper).
    particles: one of PARTICLES (default 100).
    seed: seed of the random draws (default 1): the same seed, frames and box give the
        same boxes as `rbtrack track` does.
    format: the frames' layout, "bgr" (default), "rgb" or "gray".

    Raises ValueError for a variant, particle count or format it does not offer.
    """

    def __init__(
        self,
        variant: Variant = "rbpf",
        particles: int = 100,
        seed: int = 1,
        format: Format = "bgr",
    ) -> None: ...
    def init(self, frame: npt.NDArray[np.uint8], bbox: Box) -> None:
        """Starts on the box `bbox` of `frame`, whatever the tracker did before.

        Raises TypeError for a frame that is not a uint8 array; ValueError for a shape
        the format does not take, a box that is not four finite numbers, or one the core
        refuses (the core's message: smaller than 4 px across, or centred outside the
        frame).
        """
    def update(self, frame: npt.NDArray[np.uint8]) -> Tuple[bool, Tuple[int, int, int, int]]:
        """Tracks one frame, with the GIL released: (ok, (x, y, w, h)), the box rounded to
        whole pixels (`box` has it exactly) and ok False while `status` is "lost".

        Raises RuntimeError before `init`; TypeError and ValueError as `init` does for
        the frame.
        """
    def relocate(self, frame: npt.NDArray[np.uint8], bbox: Box) -> None:
        """Moves the tracker onto the box `bbox` of `frame` (a detector's, say), keeping the
        colour model it learnt. Raises as `init` does, and RuntimeError before it."""
    @property
    def box(self) -> Box:
        """The last box (x, y, w, h), px, exact (multiples of 1/65536): the initial box
        after `init`. RuntimeError before `init`."""
    @property
    def ellipse(self) -> Tuple[float, float, float, float]:
        """The last ellipse (cx, cy, hx, hy): centre and half-axes, px."""
    @property
    def status(self) -> Status:
        """"tracking", "uncertain" (the tracker searches too) or "lost"."""
    @property
    def confidence(self) -> float:
        """How well the estimate's window matches the target's colours, less the
        particles' spread, 0..1: below 0.75 "uncertain", below 0.4 "lost"."""
    @property
    def variant(self) -> Variant: ...
    @property
    def particles(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def format(self) -> Format: ...

def TrackerCreate(
    variant: Variant = "rbpf",
    particles: int = 100,
    seed: int = 1,
    format: Format = "bgr",
) -> Tracker:
    """Tracker(...), named as OpenCV names its factories (cv2.TrackerCSRT_create)."""

def frame_is_borrowed(frame: npt.NDArray[np.uint8], format: Format = "bgr") -> bool:
    """Whether `frame` would be read in place in `format` (True) or copied first."""
