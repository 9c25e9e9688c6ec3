//! Real image sequences in OTB layout: `<dir>/img/0001.jpg`, ... and
//! `<dir>/groundtruth_rect.txt`.
//!
//! Frames (JPEG or PNG, sorted by the number in their name, then by name) are decoded
//! lazily, one at a time, into RGB888 [`Frame`]s.
//!
//! Ground truth has one `x,y,w,h` line per frame, separated by commas, spaces or tabs
//! (blank lines are skipped; `NaN` is accepted and marks a frame without a valid box).
//! Whether a file counts pixels from 1 (OTB, UAV123, LaSOT, MOT as published:
//! [`GtOrigin::OneBased`], the default) or from 0 (VOT-derived boxes:
//! [`GtOrigin::ZeroBased`]) is stated by the caller, never guessed; boxes in memory are
//! 0-based.
//!
//! No function here panics on bad input: every failure is a [`SequenceError`].

use crate::metrics::BBox;
use crate::pixels::Frame;
use std::fmt;
use std::path::{Path, PathBuf};

/// Name of the ground-truth file inside a sequence folder.
pub const GROUNDTRUTH_FILE: &str = "groundtruth_rect.txt";

/// Environment variable that overrides where [`shared_data_dir`] looks for sequences.
pub const DATA_ENV: &str = "RBTRACK_DATA";

/// Environment variable naming the validation sequences' folder.
pub const VALSET_ENV: &str = "RBTRACK_VALSET";

/// The sequences of the shared development data ([`shared_data_dir`]) whose ground truth
/// is 0-based, as that folder's README states; the others there are 1-based.
pub const SHARED_ZERO_BASED: [&str; 1] = ["ball1_vot15"];

/// Why a sequence, frame, box or `--init` string could not be read.
#[derive(Debug)]
pub enum SequenceError {
    /// The sequence folder or its `img/` subfolder does not exist.
    MissingFolder(PathBuf),
    /// A file or folder could not be read.
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A frame could not be decoded.
    Image {
        /// The image file.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
    /// A frame's size differs from the first frame's.
    FrameSize {
        /// The image file.
        path: PathBuf,
        /// Size of the first frame, px.
        expected: (u32, u32),
        /// Size of this frame, px.
        found: (u32, u32),
    },
    /// A ground-truth line is not four numbers.
    GroundTruth {
        /// The ground-truth file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// The folder holds no JPEG or PNG frame.
    Empty(PathBuf),
    /// A frame index past the end of the sequence.
    FrameIndex {
        /// The requested 0-based index.
        index: usize,
        /// Number of frames.
        len: usize,
    },
    /// A box string (e.g. `--init x,y,w,h`) is malformed.
    BoxParse {
        /// The text given.
        text: String,
        /// What is wrong with it.
        message: String,
    },
}

impl fmt::Display for SequenceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::MissingFolder(p) => write!(f, "sequence folder not found: {}", p.display()),
            Self::Io { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            Self::Image { path, message } => {
                write!(f, "cannot decode image {}: {message}", path.display())
            }
            Self::FrameSize {
                path,
                expected,
                found,
            } => write!(
                f,
                "frame {} is {}x{} px, the first frame is {}x{} px",
                path.display(),
                found.0,
                found.1,
                expected.0,
                expected.1
            ),
            Self::GroundTruth {
                path,
                line,
                message,
            } => write!(f, "{}:{line}: {message}", path.display()),
            Self::Empty(p) => write!(f, "no .jpg or .png frames in {}", p.display()),
            Self::FrameIndex { index, len } => {
                write!(
                    f,
                    "frame index {index} out of range (sequence has {len} frames)"
                )
            }
            Self::BoxParse { text, message } => {
                write!(f, "bad box {text:?}: {message} (expected x,y,w,h)")
            }
        }
    }
}

impl std::error::Error for SequenceError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Whether a ground-truth file counts pixels from 1 (OTB) or from 0 (VOT).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GtOrigin {
    /// 1-based (OTB, UAV123, PETS as published): 1 is subtracted from `x` and `y`.
    #[default]
    OneBased,
    /// Already 0-based (VOT-derived boxes such as `ball1_vot15`): kept as is.
    ZeroBased,
}

impl GtOrigin {
    /// The origin of the shared development sequence `name` ([`SHARED_ZERO_BASED`]).
    pub fn of_shared(name: &str) -> Self {
        if SHARED_ZERO_BASED.contains(&name) {
            Self::ZeroBased
        } else {
            Self::OneBased
        }
    }

    /// `one-based` or `zero-based`.
    pub fn name(self) -> &'static str {
        match self {
            Self::OneBased => "one-based",
            Self::ZeroBased => "zero-based",
        }
    }

    /// What this origin adds to a 0-based coordinate: 1 or 0 px.
    pub fn offset(self) -> f64 {
        match self {
            Self::OneBased => 1.0,
            Self::ZeroBased => 0.0,
        }
    }

    /// Converts a box read from a file with this origin to 0-based.
    pub fn to_zero_based(self, b: BBox) -> BBox {
        BBox::new(b.x - self.offset(), b.y - self.offset(), b.w, b.h)
    }

    /// Converts a 0-based box to this origin, for writing a file in the same convention:
    /// inverse of [`GtOrigin::to_zero_based`].
    pub fn from_zero_based(self, b: BBox) -> BBox {
        BBox::new(b.x + self.offset(), b.y + self.offset(), b.w, b.h)
    }
}

/// An OTB-layout sequence: frame paths and 0-based ground truth; frames decode on demand.
#[derive(Clone, Debug)]
pub struct Sequence {
    /// Folder name (e.g. `Crossing`).
    pub name: String,
    /// The sequence folder.
    pub dir: PathBuf,
    /// Frame files, in order.
    pub frame_paths: Vec<PathBuf>,
    /// Ground truth per frame, 0-based (may be shorter or longer than the frame list).
    pub groundtruth: Vec<BBox>,
    /// Origin the ground-truth file was read with.
    pub origin: GtOrigin,
    /// Frame width, px (from the first frame's header).
    pub width: u32,
    /// Frame height, px.
    pub height: u32,
}

impl Sequence {
    /// Opens `dir` whose ground-truth file counts from `origin`. Lists the frames, reads
    /// the first frame's size and parses the ground truth; decodes no pixels.
    pub fn open(dir: impl AsRef<Path>, origin: GtOrigin) -> Result<Self, SequenceError> {
        Self::open_inner(dir.as_ref(), origin, true)
    }

    /// As [`Sequence::open`], but a missing ground-truth file is not an error: the
    /// sequence then has no ground truth (`groundtruth` empty). A ground-truth file that
    /// exists but cannot be read or parsed is still an error.
    pub fn open_optional_groundtruth(
        dir: impl AsRef<Path>,
        origin: GtOrigin,
    ) -> Result<Self, SequenceError> {
        Self::open_inner(dir.as_ref(), origin, false)
    }

    /// True when the sequence has ground truth for at least one frame.
    pub fn has_groundtruth(&self) -> bool {
        !self.groundtruth.is_empty()
    }

    fn open_inner(dir: &Path, origin: GtOrigin, require_gt: bool) -> Result<Self, SequenceError> {
        let dir = dir.to_path_buf();
        if !dir.is_dir() {
            return Err(SequenceError::MissingFolder(dir));
        }
        let img = dir.join("img");
        if !img.is_dir() {
            return Err(SequenceError::MissingFolder(img));
        }
        let frame_paths = list_frames(&img)?;
        let first = &frame_paths[0];
        let (width, height) = image::image_dimensions(first).map_err(|e| image_error(first, e))?;
        let gt_path = dir.join(GROUNDTRUTH_FILE);
        let groundtruth = if require_gt || gt_path.exists() {
            read_groundtruth(gt_path, origin)?
        } else {
            Vec::new()
        };
        Ok(Self {
            name: folder_name(&dir),
            dir,
            frame_paths,
            groundtruth,
            origin,
            width,
            height,
        })
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.frame_paths.len()
    }

    /// True when there are no frames (never, for a sequence that opened).
    pub fn is_empty(&self) -> bool {
        self.frame_paths.is_empty()
    }

    /// The first frame's ground truth (what initialises a tracker), 0-based.
    pub fn init_box(&self) -> Option<BBox> {
        self.groundtruth.first().copied()
    }

    /// Decodes frame `index` (0-based) to RGB888.
    pub fn frame(&self, index: usize) -> Result<Frame, SequenceError> {
        let path = self
            .frame_paths
            .get(index)
            .ok_or(SequenceError::FrameIndex {
                index,
                len: self.len(),
            })?;
        let rgb = image::open(path)
            .map_err(|e| image_error(path, e))?
            .into_rgb8();
        let found = rgb.dimensions();
        if found != (self.width, self.height) {
            return Err(SequenceError::FrameSize {
                path: path.clone(),
                expected: (self.width, self.height),
                found,
            });
        }
        Frame::rgb888(found.0, found.1, rgb.into_raw()).map_err(|e| SequenceError::Image {
            path: path.clone(),
            message: e.to_string(),
        })
    }

    /// Iterator that decodes the frames one by one, in order.
    pub fn frames(&self) -> Frames<'_> {
        Frames { seq: self, next: 0 }
    }
}

/// Lazy frame iterator of a [`Sequence`]; yields `Err` for a frame that fails to decode
/// and goes on with the next.
#[derive(Debug)]
pub struct Frames<'a> {
    seq: &'a Sequence,
    next: usize,
}

impl Iterator for Frames<'_> {
    type Item = Result<Frame, SequenceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.next >= self.seq.len() {
            return None;
        }
        self.next += 1;
        Some(self.seq.frame(self.next - 1))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.seq.len() - self.next;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Frames<'_> {}

/// The last component of `dir` (a sequence's name), or empty.
pub fn folder_name(dir: &Path) -> String {
    dir.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn image_error(path: &Path, e: image::ImageError) -> SequenceError {
    match e {
        image::ImageError::IoError(source) => SequenceError::Io {
            path: path.to_path_buf(),
            source,
        },
        e => SequenceError::Image {
            path: path.to_path_buf(),
            message: e.to_string(),
        },
    }
}

/// The `.jpg`/`.jpeg`/`.png` files of `img`, sorted by the number their name starts with,
/// then by name.
pub fn list_frames(img: &Path) -> Result<Vec<PathBuf>, SequenceError> {
    let io = |source| SequenceError::Io {
        path: img.to_path_buf(),
        source,
    };
    let mut frames = Vec::new();
    for entry in std::fs::read_dir(img).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if matches!(ext.as_deref(), Some("jpg" | "jpeg" | "png")) && path.is_file() {
            frames.push(path);
        }
    }
    if frames.is_empty() {
        return Err(SequenceError::Empty(img.to_path_buf()));
    }
    frames.sort_by_cached_key(|p| {
        let name = folder_name(p);
        let digits: String = name.chars().take_while(|c| c.is_ascii_digit()).collect();
        (digits.parse::<u64>().unwrap_or(u64::MAX), name)
    });
    Ok(frames)
}

/// Reads a ground-truth file and converts its boxes to 0-based with `origin`.
pub fn read_groundtruth(
    path: impl AsRef<Path>,
    origin: GtOrigin,
) -> Result<Vec<BBox>, SequenceError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| SequenceError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_groundtruth(&text)
        .map(|boxes| boxes.into_iter().map(|b| origin.to_zero_based(b)).collect())
        .map_err(|(line, message)| SequenceError::GroundTruth {
            path: path.to_path_buf(),
            line,
            message,
        })
}

/// Parses ground-truth text as written (no origin conversion): one box per non-blank line.
/// On error returns the 1-based line number and a message.
pub fn parse_groundtruth(text: &str) -> Result<Vec<BBox>, (usize, String)> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| parse_fields(l).map_err(|m| (i + 1, m)))
        .collect()
}

/// Parses `x,y,w,h` (commas, spaces or tabs) as a 0-based box, e.g. a `--init` argument.
/// Width and height must be positive.
pub fn parse_bbox(text: &str) -> Result<BBox, SequenceError> {
    let err = |message: String| SequenceError::BoxParse {
        text: text.to_string(),
        message,
    };
    let b = parse_fields(text).map_err(err)?;
    if !b.is_valid() {
        return Err(err("width and height must be positive and finite".into()));
    }
    Ok(b)
}

fn parse_fields(line: &str) -> Result<BBox, String> {
    let fields: Vec<&str> = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|f| !f.is_empty())
        .collect();
    if fields.len() != 4 {
        return Err(format!(
            "expected 4 numbers x,y,w,h, found {}",
            fields.len()
        ));
    }
    let mut v = [0.0; 4];
    for (slot, field) in v.iter_mut().zip(&fields) {
        *slot = field
            .parse::<f64>()
            .map_err(|_| format!("{field:?} is not a number"))?;
        if slot.is_infinite() {
            return Err(format!("{field:?} is not finite"));
        }
    }
    Ok(BBox::new(v[0], v[1], v[2], v[3]))
}

/// The sequence folders (those with an `img` folder) in `data`, sorted by name; none if
/// it cannot be read.
pub fn sequence_names(data: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(data)
        .map(|dir| {
            dir.filter_map(|e| e.ok())
                .filter(|e| e.path().join("img").is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Where the shared real sequences are: `$RBTRACK_DATA` if set, else `shared/data` beside
/// the repository (`<repo>/../shared/data`). `None` when that folder does not exist.
pub fn shared_data_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os(DATA_ENV) {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
    };
    dir.is_dir().then_some(dir)
}

/// Where the validation sequences are (built by `../shared/tools/valset/`):
/// `$RBTRACK_VALSET` if set, else `valset` beside the repository (`<repo>/../valset`).
/// `None` when that folder does not exist.
pub fn validation_data_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os(VALSET_ENV) {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../valset"),
    };
    dir.is_dir().then_some(dir)
}
