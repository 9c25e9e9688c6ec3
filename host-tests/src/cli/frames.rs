//! `rbtrack frames`: one sequence folder's frames, decoded as `eval` and `track` decode
//! them, written as one raw RGB888 dump, so that other programs (e.g.
//! `benches/compare_opencv.py`) see exactly the pixels rbtrack tracks.

use super::args::FramesArgs;
use super::runs::create_parent;
use super::{emit, fail, Failure};
use crate::sequence::{GtOrigin, Sequence};
use std::io::Write;

/// Runs `rbtrack frames`: writes every frame of `args.sequence` to `args.out`, RGB888 rows
/// top to bottom, frames back to back, and prints `WIDTHxHEIGHT:rgb888 FRAMES` (the
/// layout `track --raw` reads).
pub fn frames(args: &FramesArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let seq =
        Sequence::open_optional_groundtruth(&args.sequence, GtOrigin::OneBased).map_err(fail)?;
    create_parent(&args.out)?;
    let file = std::fs::File::create(&args.out)
        .map_err(|e| fail(format!("cannot write {}: {e}", args.out.display())))?;
    let mut dump = std::io::BufWriter::new(file);
    let mut count = 0usize;
    for (i, frame) in seq.frames().enumerate() {
        let frame = frame.map_err(|e| fail(format!("frame {}: {e}", i + 1)))?;
        dump.write_all(&frame.to_rgb888())
            .map_err(|e| fail(format!("cannot write {}: {e}", args.out.display())))?;
        count += 1;
    }
    dump.flush()
        .map_err(|e| fail(format!("cannot write {}: {e}", args.out.display())))?;
    emit(
        out,
        &format!("{}x{}:rgb888 {count}\n", seq.width, seq.height),
    )
}
