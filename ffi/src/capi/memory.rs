//! Trackers placed in memory their caller owns: the handle, the memory each configuration
//! needs, and the functions that place them.

use super::rbt_error::{self, *};
use super::MAGIC;
use crate::track::{CfTrack, Track};
use core::ffi::c_void;
use core::ptr::{self, NonNull};
use rbtrack::tracker::CfTracker;
use rbtrack::{Binning, LumaTracker, Rgb256Tracker, RgbCfTracker, RgbTracker, Tracker, YuvTracker};

/// A tracker, in memory its caller owns (`rbt_tracker_place_*` makes one).
pub struct rbt_tracker {
    _private: [u8; 0],
}

/// The start of a placed tracker's memory: the magic word, then how to reach the tracker.
#[repr(C)]
struct Header {
    magic: u32,
    open: unsafe fn(NonNull<Header>) -> Placed,
}

/// A placed tracker of either kind, as its header reaches it.
enum Placed {
    /// A particle filter.
    Particles(NonNull<dyn Track>),
    /// The correlation-filter tracker.
    Correlation(NonNull<dyn CfTrack>),
}

/// A placed tracker of either kind, borrowed.
pub(super) enum Engine<'a> {
    /// A particle filter.
    Particles(&'a mut dyn Track),
    /// The correlation-filter tracker.
    Correlation(&'a mut dyn CfTrack),
}

/// A placed tracker: the header, then the tracker.
#[repr(C)]
struct Slot<T> {
    header: Header,
    tracker: T,
}

/// The tracker of the slot of type `T` that `header` starts.
///
/// # Safety
/// `header` starts a live `Slot<T>`.
unsafe fn tracker_of<T>(header: NonNull<Header>) -> NonNull<T> {
    let slot = header.cast::<Slot<T>>().as_ptr();
    // SAFETY: `slot` is a live `Slot<T>` (the caller's promise), so the field's address is
    // in bounds and non-null.
    unsafe { NonNull::new_unchecked(ptr::addr_of_mut!((*slot).tracker)) }
}

/// A tracker that can be placed: its unstarted value is a constant, and its header
/// reaches it as its kind.
trait Placeable: Sized + 'static {
    /// The unstarted tracker (`unstarted()`: all zero bits).
    const UNSTARTED: Self;
    /// The tracker of the slot that `header` starts.
    ///
    /// # Safety
    /// `header` starts a live `Slot<Self>`.
    unsafe fn open(header: NonNull<Header>) -> Placed;
}

impl<Bn: Binning + 'static, const N: usize, const B: usize> Placeable for Tracker<Bn, N, B> {
    const UNSTARTED: Self = Self::unstarted();

    unsafe fn open(header: NonNull<Header>) -> Placed {
        // SAFETY: as this function's contract.
        Placed::Particles(unsafe { tracker_of::<Self>(header) })
    }
}

impl<Bn: Binning + 'static, const B: usize, const G: usize, const S: usize> Placeable
    for CfTracker<Bn, B, G, S>
{
    const UNSTARTED: Self = Self::unstarted();

    unsafe fn open(header: NonNull<Header>) -> Placed {
        // SAFETY: as this function's contract.
        Placed::Correlation(unsafe { tracker_of::<Self>(header) })
    }
}

/// Places an unstarted `T` at `memory` and writes its handle to `out`.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes, which the tracker then owns;
/// `out` is null or points to a writable pointer.
unsafe fn place<T: Placeable>(
    memory: *mut c_void,
    size: usize,
    out: *mut *mut rbt_tracker,
) -> rbt_error {
    if memory.is_null() || out.is_null() {
        return RBT_ERR_NULL;
    }
    if size < size_of::<Slot<T>>() {
        return RBT_ERR_MEMORY_SIZE;
    }
    let slot = memory.cast::<Slot<T>>();
    if !slot.is_aligned() {
        return RBT_ERR_MEMORY_ALIGN;
    }
    // SAFETY: `slot` is non-null, aligned and has room for a `Slot<T>` (checked above) in
    // memory the caller hands over; the value is a constant, written in place.
    unsafe {
        slot.write(Slot {
            header: Header {
                magic: MAGIC,
                open: T::open,
            },
            tracker: T::UNSTARTED,
        });
        out.write(slot.cast::<rbt_tracker>());
    }
    RBT_OK
}

/// The tracker behind `handle`.
///
/// # Safety
/// `handle` is null or a handle from an `rbt_tracker_place_*` function whose memory is
/// still the tracker's, not used elsewhere during the borrow `'a`; or other memory whose
/// first 4 bytes are readable and not `b"RBT1"`.
unsafe fn tracker<'a>(handle: *mut rbt_tracker) -> Result<Engine<'a>, rbt_error> {
    let header = NonNull::new(handle.cast::<Header>()).ok_or(RBT_ERR_NULL)?;
    if !header.as_ptr().is_aligned() {
        return Err(RBT_ERR_NOT_A_TRACKER);
    }
    // SAFETY: the first 4 bytes are readable (the caller's promise) and aligned (checked);
    // any bits are a `u32`.
    let magic = unsafe { ptr::addr_of!((*header.as_ptr()).magic).read() };
    if magic != MAGIC {
        return Err(RBT_ERR_NOT_A_TRACKER);
    }
    // SAFETY: the magic word says `place` wrote this header and its slot, which is live
    // and borrowed by no one else for `'a` (the caller's promise).
    unsafe {
        let open = ptr::addr_of!((*header.as_ptr()).open).read();
        Ok(match open(header) {
            Placed::Particles(t) => Engine::Particles(&mut *t.as_ptr()),
            Placed::Correlation(t) => Engine::Correlation(&mut *t.as_ptr()),
        })
    }
}

/// Runs `f` on the tracker behind `handle`, returning its code.
///
/// # Safety
/// As [`tracker`].
pub(super) unsafe fn with_tracker(
    handle: *mut rbt_tracker,
    f: impl FnOnce(Engine<'_>) -> rbt_error,
) -> rbt_error {
    // SAFETY: as this function's contract.
    match unsafe { tracker(handle) } {
        Ok(t) => f(t),
        Err(e) => e,
    }
}

/// Runs `f` on the particle filter behind `handle`, returning its code;
/// `RBT_ERR_TRACKER_KIND` for the correlation-filter tracker.
///
/// # Safety
/// As [`tracker`].
pub(super) unsafe fn with_particles(
    handle: *mut rbt_tracker,
    f: impl FnOnce(&mut dyn Track) -> rbt_error,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(handle, |t| match t {
            Engine::Particles(t) => f(t),
            Engine::Correlation(_) => RBT_ERR_TRACKER_KIND,
        })
    }
}

// Bytes of tracker memory of each configuration offered, on 32-bit targets (Cortex-M,
// RISC-V) and on 64-bit ones; each is checked against the tracker at compile time, and
// `place` checks the memory it is given against the size on the target it runs on.
/// Bytes of memory for a tracker of 25 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_25_SIZE: usize = 50848;
/// Bytes of memory for a tracker of 25 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_25_SIZE: usize = 50888;
/// Bytes of memory for a tracker of 50 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_50_SIZE: usize = 52048;
/// Bytes of memory for a tracker of 50 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_50_SIZE: usize = 52080;
/// Bytes of memory for a tracker of 100 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_100_SIZE: usize = 54448;
/// Bytes of memory for a tracker of 100 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_100_SIZE: usize = 54480;
/// Bytes of memory for a tracker of 200 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_200_SIZE: usize = 59248;
/// Bytes of memory for a tracker of 200 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_200_SIZE: usize = 59280;
/// Bytes of memory for a tracker of 100 particles on 256 RGB bins (8x8x4) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB256_100_SIZE: usize = 41648;
/// Bytes of memory for a tracker of 100 particles on 256 RGB bins (8x8x4) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB256_100_SIZE: usize = 41680;
/// Bytes of memory for a tracker of 100 particles on 256 YUV bins (8x8x4) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_YUV_100_SIZE: usize = 41648;
/// Bytes of memory for a tracker of 100 particles on 256 YUV bins (8x8x4) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_YUV_100_SIZE: usize = 41680;
/// Bytes of memory for a tracker of 100 particles on 64 grey levels (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_LUMA_100_SIZE: usize = 32048;
/// Bytes of memory for a tracker of 100 particles on 64 grey levels (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_LUMA_100_SIZE: usize = 32080;
/// Bytes of memory for the correlation-filter tracker at its defaults: 16 x 16 cells, 4
/// scales, 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_CF_SIZE: usize = 82048;
/// Bytes of memory for the correlation-filter tracker at its defaults: 16 x 16 cells, 4
/// scales, 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_CF_SIZE: usize = 82136;
/// Alignment of every tracker's memory, bytes.
pub const RBT_TRACKER_ALIGN: usize = 8;

/// Checks a configuration's memory constants at compile time.
macro_rules! check_memory {
    ($tracker:ty, $size:ident) => {
        const _: () = assert!(
            size_of::<Slot<$tracker>>() == $size
                && align_of::<Slot<$tracker>>() <= RBT_TRACKER_ALIGN,
            "the header's size or alignment is not the tracker's"
        );
    };
}
check_memory!(RgbTracker<25>, RBT_TRACKER_RGB_25_SIZE);
check_memory!(RgbTracker<50>, RBT_TRACKER_RGB_50_SIZE);
check_memory!(RgbTracker<100>, RBT_TRACKER_RGB_100_SIZE);
check_memory!(RgbTracker<200>, RBT_TRACKER_RGB_200_SIZE);
check_memory!(Rgb256Tracker<100>, RBT_TRACKER_RGB256_100_SIZE);
check_memory!(YuvTracker<100>, RBT_TRACKER_YUV_100_SIZE);
check_memory!(LumaTracker<100>, RBT_TRACKER_LUMA_100_SIZE);
check_memory!(RgbCfTracker, RBT_TRACKER_CF_SIZE);

/// Places an unstarted tracker of 25 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_25_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_25(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<25>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 50 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_50_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_50(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<50>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 512 RGB bins (8x8x8): the defaults of the example firmware and the host tool in `memory`
/// (`RBT_TRACKER_RGB_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 200 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_200_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_200(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<200>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 256 RGB bins (8x8x4) in `memory`
/// (`RBT_TRACKER_RGB256_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb256_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<Rgb256Tracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 256 YUV bins (8x8x4) in `memory`
/// (`RBT_TRACKER_YUV_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_yuv_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<YuvTracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 64 grey levels in `memory`
/// (`RBT_TRACKER_LUMA_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_luma_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<LumaTracker<100>>(memory, size, tracker) }
}

/// Places the unstarted correlation-filter tracker at its defaults (16 x 16 cells, 5
/// scales, 512 RGB bins (8x8x8): the core's `RgbCfTracker`) in `memory`
/// (`RBT_TRACKER_CF_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle to
/// `tracker`; `rbt_cf_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_cf(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbCfTracker>(memory, size, tracker) }
}
