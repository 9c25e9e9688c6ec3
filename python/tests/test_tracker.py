"""The Python module against the host tool, bad input, the GIL and memory.

    pip install ./python pytest && python3 -m pytest python/tests

The tests against `rbtrack track` need the shared sequences (../shared/data beside the
repository; they skip, saying so, without them) and the `rbtrack` binary: RBTRACK_BIN,
else target/release/rbtrack or target/debug/rbtrack, else `cargo build --release -p
rbtrack-host` makes it.
"""

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rbtrack

REPO = Path(__file__).resolve().parents[2]
CROSSING = REPO.parent / "shared" / "data" / "Crossing"
# Crossing's first ground-truth box (1-based in the file), 0-based.
CROSSING_BOX = (204.0, 150.0, 17.0, 50.0)


def rbtrack_binary():
    if os.environ.get("RBTRACK_BIN"):
        return Path(os.environ["RBTRACK_BIN"])
    for profile in ("release", "debug"):
        path = REPO / "target" / profile / "rbtrack"
        if path.is_file():
            return path
    subprocess.run(["cargo", "build", "-q", "--release", "-p", "rbtrack-host"], cwd=REPO, check=True)
    return REPO / "target" / "release" / "rbtrack"


@pytest.fixture(scope="module")
def crossing(tmp_path_factory):
    """Crossing decoded by `rbtrack frames`: the dump's path, its --raw layout and its
    frames as an (N, H, W, 3) RGB array."""
    if not CROSSING.is_dir():
        pytest.skip(f"no shared data at {CROSSING}: the tests against rbtrack track need it")
    binary = rbtrack_binary()
    dump = tmp_path_factory.mktemp("crossing") / "crossing.rgb"
    out = subprocess.run([binary, "frames", CROSSING, dump], capture_output=True, text=True, check=True)
    layout, count = out.stdout.split()
    width, height = (int(v) for v in layout.split(":")[0].split("x"))
    frames = np.fromfile(dump, dtype=np.uint8).reshape(int(count), height, width, 3)
    return binary, dump, (width, height), frames


def track_boxes(binary, dump, layout, variant, tmp_path):
    """The box lines `rbtrack track` writes for the dump (0-based, two decimals)."""
    boxes = tmp_path / f"{variant}.txt"
    init = ",".join(f"{v:g}" for v in CROSSING_BOX)
    subprocess.run(
        [binary, "track", dump, "--raw", layout, "--init", init, "--zero-based",
         "--tracker", variant, "--boxes", boxes],
        capture_output=True, check=True,
    )
    return boxes.read_text().splitlines()


def python_boxes(tracker, frames):
    """The box lines of `tracker` over `frames`, formatted as the host tool writes them."""
    tracker.init(frames[0], CROSSING_BOX)
    boxes = [tracker.box]
    for frame in frames[1:]:
        ok, whole = tracker.update(frame)
        assert ok == (tracker.status != "lost")
        assert whole == tuple(int(np.floor(v + 0.5)) for v in tracker.box)
        boxes.append(tracker.box)
    return [",".join(f"{v:.2f}" for v in b) for b in boxes]


@pytest.mark.parametrize("variant", ["cf", "rbpf", "pf"])
def test_boxes_equal_the_host_tools(crossing, variant, tmp_path):
    binary, dump, (width, height), frames = crossing
    want = track_boxes(binary, dump, f"{width}x{height}:rgb888", variant, tmp_path)
    assert len(want) == len(frames)
    bgr = np.ascontiguousarray(frames[..., ::-1])
    assert python_boxes(rbtrack.Tracker(variant=variant), bgr) == want
    assert python_boxes(rbtrack.TrackerCreate(variant=variant, format="rgb"), frames) == want


@pytest.mark.parametrize("variant", ["cf", "rbpf"])
def test_grey_frames_equal_the_host_tools(crossing, variant, tmp_path):
    binary, _, (width, height), frames = crossing
    grey = (frames.astype(np.uint32) @ np.array([77, 150, 29], np.uint32) + 128 >> 8).astype(np.uint8)
    dump = tmp_path / "grey.raw"
    grey.tofile(dump)
    want = track_boxes(binary, dump, f"{width}x{height}:gray8", variant, tmp_path)
    assert python_boxes(rbtrack.Tracker(variant=variant, format="gray"), grey) == want
    assert python_boxes(rbtrack.Tracker(variant=variant, format="gray"), grey[..., None]) == want


@pytest.mark.parametrize("variant", ["cf", "rbpf", "pf"])
def test_compare_opencv_in_process_gives_the_dump_paths_boxes(crossing, variant, tmp_path):
    """benches/compare_opencv.py --in-process tracks with this module; its boxes are the
    ones its default path reads from `rbtrack track` on the dump."""
    pytest.importorskip("cv2", reason="benches/compare_opencv.py needs OpenCV")
    import argparse
    import importlib.util

    spec = importlib.util.spec_from_file_location("compare_opencv", REPO / "benches" / "compare_opencv.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    binary = crossing[0]
    layout, frames = bench.decode(binary, CROSSING, tmp_path / "crossing.rgb")
    first = bench.read_boxes(CROSSING / "groundtruth_rect.txt")[0]
    start = bench.STARTS[5]  # scale0.95: a box with fractions
    _, dump_boxes = bench.run_rbtrack(
        binary, CROSSING, tmp_path / "crossing.rgb", layout, False, variant, 2, start,
        argparse.Namespace(particles=50),
    )
    init = bench.to_zero_based(bench.start_box(first, start), False)
    boxes, _ = bench.run_rbtrack_in_process(frames, init, variant, 2, 50)
    two_decimals = lambda bs: [",".join(f"{v:.2f}" for v in b) for b in bs]
    assert two_decimals(boxes) == two_decimals(dump_boxes)


def square(x0, shape=(48, 64)):
    """A red 16x16 square at column x0 on grey, BGR."""
    frame = np.full((*shape, 3), 90, np.uint8)
    frame[16:32, x0 : x0 + 16] = (40, 40, 230)
    return frame


def test_a_crop_is_read_in_place_and_tracked_as_its_copy():
    big = np.zeros((100, 160, 3), np.uint8)
    big[20:68, 30:94] = square(20)
    crop = big[20:68, 30:94]
    assert rbtrack.frame_is_borrowed(crop)
    assert not rbtrack.frame_is_borrowed(crop[:, ::-1])
    a, b = rbtrack.Tracker(variant="pf"), rbtrack.Tracker(variant="pf")
    a.init(crop, (20, 16, 16, 16))
    b.init(crop.copy(), (20, 16, 16, 16))
    for x0 in (22, 24, 26):
        big[20:68, 30:94] = square(x0)
        assert a.update(crop) == b.update(crop.copy())
        assert a.box == b.box


@pytest.mark.parametrize("make", [dict(), dict(variant="pf", particles=50)])
def test_ok_is_false_while_lost(make):
    # Every tracker shares the thresholds: "uncertain" below 0.5, "lost" below 0.2.
    tracker = rbtrack.Tracker(**make)
    tracker.init(square(20), (20, 16, 16, 16))
    assert tracker.update(square(21))[0] is True
    assert tracker.status == "tracking" and tracker.confidence >= 0.5
    assert 0.0 <= tracker.score <= 1.0
    empty = np.full((48, 64, 3), 90, np.uint8)
    seen = [tracker.update(empty)[0] for _ in range(5)]
    assert tracker.status == "lost" and tracker.confidence < 0.1
    assert seen[-1] is False


def test_the_defaults_and_what_each_variant_takes():
    cf = rbtrack.Tracker()
    assert (cf.variant, cf.particles, cf.seed, cf.format) == ("cf", None, None, "bgr")
    assert repr(cf) == 'rbtrack.Tracker(variant="cf", format="bgr")'
    pf = rbtrack.TrackerCreate(variant="pf")
    assert (pf.variant, pf.particles, pf.seed) == ("pf", 100, 1)
    assert repr(pf) == 'rbtrack.Tracker(variant="pf", particles=100, seed=1, format="bgr")'
    cf.init(square(20), (20, 16, 16, 16))
    cf.relocate(square(22), (22, 16, 16, 16))
    assert cf.box == (22.0, 16.0, 16.0, 16.0) and cf.status == "tracking"
    pf.init(square(20), (20, 16, 16, 16))
    pf.relocate(square(22), (22, 16, 16, 16))
    assert pf.box == (22.0, 16.0, 16.0, 16.0)


@pytest.mark.parametrize(
    "make, frame, box, error, message",
    [
        (dict(variant="csrt"), None, None, ValueError, "variant must be 'cf', 'rbpf' or 'pf'"),
        (dict(variant="rbpf", particles=30), None, None, ValueError, "particles must be one of [25, 50, 100, 200]"),
        (dict(particles=100), None, None, ValueError, "('cf') has no particles and no seed"),
        (dict(seed=2), None, None, ValueError, "('cf') has no particles and no seed"),
        (dict(format="yuv"), None, None, ValueError, "format must be 'bgr', 'rgb' or 'gray'"),
        ({}, square(20).astype(np.float32), (20, 16, 16, 16), TypeError, "must be a uint8 array, not float32"),
        ({}, [[1, 2], [3, 4]], (20, 16, 16, 16), TypeError, "must be a NumPy uint8 array, not list"),
        ({}, square(20)[..., :2], (20, 16, 16, 16), ValueError, "has shape (height, width, 3)"),
        ({}, square(20)[None], (20, 16, 16, 16), ValueError, "has shape (height, width, 3)"),
        (dict(format="gray"), square(20), (20, 16, 16, 16), ValueError, "has shape (height, width)"),
        ({}, np.zeros((0, 64, 3), np.uint8), (20, 16, 16, 16), ValueError, "image width or height is zero"),
        ({}, square(20), (200, 16, 16, 16), ValueError, "initial ellipse centred outside the frame"),
        ({}, square(20), (20, 16, 1, 16), ValueError, "initial ellipse below the smallest half-axis"),
        ({}, square(20), (20, 16, float("nan"), 16), ValueError, "box must be 4 finite numbers x, y, w, h"),
        ({}, square(20), (20, 16, 16), ValueError, "box must be 4 numbers x, y, w, h, not 3 ((20, 16, 16))"),
        ({}, square(20), [20, 16, 16, 16, 1], ValueError, "box must be 4 numbers x, y, w, h, not 5"),
        ({}, square(20), "20,16,16,16", TypeError, "box must be 4 numbers x, y, w, h, not '20,16,16,16'"),
        ({}, square(20), (20, 16, "16", 16), TypeError, "box must be 4 numbers x, y, w, h"),
        ({}, square(20), None, TypeError, "box must be 4 numbers x, y, w, h, not None"),
    ],
)
def test_bad_input_raises(make, frame, box, error, message):
    with pytest.raises(error) as raised:
        tracker = rbtrack.Tracker(**make)
        tracker.init(frame, box)
    assert message in str(raised.value)


def test_a_box_is_any_sequence_of_four_numbers():
    boxes = [(20, 16, 16, 16), [20, 16, 16, 16], np.array([20.0, 16.0, 16.0, 16.0]), np.arange(20, 24)]
    for box in boxes:
        tracker = rbtrack.Tracker(variant="pf")
        tracker.init(square(20), box)
        assert tracker.box == tuple(float(v) for v in box)
        tracker.relocate(square(22), box)


@pytest.mark.parametrize("variant", ["cf", "pf"])
def test_a_frame_of_another_size_than_inits_raises(variant):
    tracker = rbtrack.Tracker(variant=variant)
    tracker.init(square(20), (20, 16, 16, 16))
    wider = square(20, shape=(48, 80))
    with pytest.raises(ValueError, match=r"frame is 80 x 48 px, but init's was 64 x 48 px"):
        tracker.update(wider)
    with pytest.raises(ValueError, match=r"frame is 64 x 40 px, but init's was 64 x 48 px"):
        tracker.update(square(20)[:40])
    if variant == "pf":
        with pytest.raises(ValueError, match=r"frame is 80 x 48 px"):
            tracker.relocate(wider, (20, 16, 16, 16))
    assert tracker.update(square(21))[0] is True
    tracker.init(wider, (20, 16, 16, 16))
    assert tracker.update(square(21, shape=(48, 80)))[0] is True


def test_update_and_properties_before_init_raise():
    tracker = rbtrack.Tracker()
    for use in (lambda: tracker.update(square(20)), lambda: tracker.box, lambda: tracker.status):
        with pytest.raises(RuntimeError, match="call init first"):
            use()
    tracker.init(square(20), (20, 16, 16, 16))
    with pytest.raises(TypeError, match="uint8"):
        tracker.update(square(20).astype(np.int16))


def ticks_in_the_middle(work):
    """Timestamps another thread records, running Python code, in the middle half of the
    time `work()` takes."""
    ticks, stop = [], threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-3)
    thread = threading.Thread(target=tick)
    thread.start()
    try:
        time.sleep(0.01)
        t0 = time.perf_counter()
        work()
        t1 = time.perf_counter()
    finally:
        stop.set()
        thread.join()
        sys.setswitchinterval(interval)
    quarter = (t1 - t0) / 4
    return sum(t0 + quarter < t < t1 - quarter for t in ticks), t1 - t0


def test_update_releases_the_gil():
    """While 60 updates run back to back (`map` calls them from C: no bytecode between
    them, so no GIL hand-over but their own), another thread keeps running Python code;
    while a C loop of similar length that keeps the GIL runs, it cannot."""
    frame = np.random.default_rng(1).integers(0, 256, (480, 640, 3), np.uint8)
    tracker = rbtrack.Tracker(variant="rbpf", particles=200)
    tracker.init(frame, (200, 150, 120, 160))
    during_updates, took = ticks_in_the_middle(lambda: list(map(tracker.update, [frame] * 60)))
    assert during_updates > 0, f"no Python code ran in {took * 1e3:.1f} ms of updates"
    during_sum, took = ticks_in_the_middle(lambda: sum(range(3_000_000)))
    assert during_sum == 0, f"{during_sum} ticks in {took * 1e3:.1f} ms of sum(), which keeps the GIL"


def resident_kib():
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="reads /proc/self/statm (Linux)")
def test_memory_does_not_grow_over_a_long_loop():
    """20,000 updates after 1,000 warm-up ones add under 256 KiB of resident memory (no
    per-frame allocation is kept: a leak of even 16 bytes an update would show)."""
    frames = [square(x0) for x0 in (20, 22, 24, 22)]
    tracker = rbtrack.Tracker(variant="pf", particles=50)
    tracker.init(frames[0], (20, 16, 16, 16))
    for i in range(1_000):
        tracker.update(frames[i % 4])
    before = resident_kib()
    for i in range(20_000):
        tracker.update(frames[i % 4])
        tracker.box, tracker.status, tracker.confidence
    grown = resident_kib() - before
    print(f"resident memory grew {grown} KiB over 20,000 updates")
    assert grown < 256, f"{grown} KiB"
