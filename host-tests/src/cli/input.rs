//! What `rbtrack track` reads frames from: an image folder in OTB layout, any video
//! ffmpeg reads (decoded by an `ffmpeg` subprocess to RGB888 over a pipe, its size from
//! `ffprobe`), or a raw dump of frames from a board, back to back in one of the core's
//! pixel formats and handed to the tracker as they are.

use super::{fail, Failure};
use crate::metrics::BBox;
use crate::pixels::{Format, Frame};
use crate::sequence::{GtOrigin, Sequence};
use std::fs::File;
use std::io::{self, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::str::FromStr;
use std::thread::JoinHandle;

/// The layout of a raw dump: `WIDTHxHEIGHT:FORMAT`, e.g. `320x240:rgb565le`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawLayout {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// Pixel format of every frame.
    pub format: Format,
}

impl FromStr for RawLayout {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let formats = Format::ALL.map(Format::name).join(", ");
        let expected = || format!("expected WIDTHxHEIGHT:FORMAT with FORMAT one of {formats}");
        let (size, format) = s.split_once(':').ok_or_else(expected)?;
        let (w, h) = size.split_once(['x', 'X']).ok_or_else(expected)?;
        let (width, height) = match (w.trim().parse(), h.trim().parse()) {
            (Ok(w), Ok(h)) => (w, h),
            _ => return Err(expected()),
        };
        let format = Format::from_name(format.trim()).ok_or_else(expected)?;
        format
            .frame_bytes(width, height)
            .ok_or_else(|| format!("no {format} frame is {width}x{height} px"))?;
        Ok(Self {
            width,
            height,
            format,
        })
    }
}

/// Frames and their failures, in order.
pub type Frames<'a> = Box<dyn Iterator<Item = Result<Frame, Failure>> + 'a>;

/// A source of frames.
#[derive(Debug)]
pub enum Input {
    /// An OTB-layout image folder.
    Folder(Sequence),
    /// A video file.
    Video(Video),
    /// A raw dump.
    Raw(RawDump),
}

impl Input {
    /// Opens `path`: a raw dump when `raw` is given, else an image folder (whose
    /// ground-truth file counts from `origin`, and may be missing unless
    /// `need_groundtruth`), else a video file.
    pub fn open(
        path: &Path,
        raw: Option<RawLayout>,
        origin: GtOrigin,
        need_groundtruth: bool,
    ) -> Result<Self, Failure> {
        if !path.exists() {
            return Err(fail(format!("input not found: {}", path.display())));
        }
        if let Some(layout) = raw {
            return RawDump::open(path, layout).map(Self::Raw);
        }
        if path.is_dir() {
            let seq = if need_groundtruth {
                Sequence::open(path, origin)
            } else {
                Sequence::open_optional_groundtruth(path, origin)
            };
            return seq.map(Self::Folder).map_err(fail);
        }
        Video::open(path).map(Self::Video)
    }

    /// The sequence's name: the folder's, or the file's without its extension.
    pub fn name(&self) -> String {
        match self {
            Self::Folder(s) => s.name.clone(),
            Self::Video(v) => file_stem(&v.path),
            Self::Raw(r) => file_stem(&r.path),
        }
    }

    /// Frame size, px.
    pub fn size(&self) -> (u32, u32) {
        match self {
            Self::Folder(s) => (s.width, s.height),
            Self::Video(v) => (v.width, v.height),
            Self::Raw(r) => (r.layout.width, r.layout.height),
        }
    }

    /// Number of frames, when known before decoding.
    pub fn len(&self) -> Option<usize> {
        match self {
            Self::Folder(s) => Some(s.len()),
            Self::Video(v) => v.frames,
            Self::Raw(r) => Some(r.frames),
        }
    }

    /// The folder's ground truth (0-based), if any.
    pub fn groundtruth(&self) -> &[BBox] {
        match self {
            Self::Folder(s) => &s.groundtruth,
            _ => &[],
        }
    }

    /// The frames, decoded ones converted to `format`, raw ones as they are.
    pub fn frames(&self, format: Format) -> Result<Frames<'_>, Failure> {
        let convert = move |f: Frame| f.convert(format).map_err(fail);
        Ok(match self {
            Self::Folder(s) => Box::new(s.frames().map(move |f| f.map_err(fail).and_then(convert))),
            Self::Video(v) => Box::new(v.decode()?.map(move |f| f.and_then(convert))),
            Self::Raw(r) => Box::new(r.read()?),
        })
    }
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Reads one frame of `len` bytes; `None` at the end of the stream, an error for a
/// partial frame.
fn read_frame(reader: &mut impl Read, len: usize) -> io::Result<Option<Vec<u8>>> {
    let mut buf = vec![0u8; len];
    let mut filled = 0;
    while filled < len {
        match reader.read(&mut buf[filled..]) {
            Ok(0) if filled == 0 => return Ok(None),
            Ok(0) => {
                return Err(io::Error::new(
                    io::ErrorKind::UnexpectedEof,
                    format!("the last frame is cut short ({filled} of {len} bytes)"),
                ))
            }
            Ok(n) => filled += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(Some(buf))
}

/// A raw dump: frames of one layout back to back.
#[derive(Debug)]
pub struct RawDump {
    path: PathBuf,
    layout: RawLayout,
    frames: usize,
}

impl RawDump {
    fn open(path: &Path, layout: RawLayout) -> Result<Self, Failure> {
        let frame_bytes = layout
            .format
            .frame_bytes(layout.width, layout.height)
            .ok_or_else(|| fail("bad raw layout"))?;
        let size = std::fs::metadata(path)
            .map_err(|e| fail(format!("cannot read {}: {e}", path.display())))?
            .len();
        if size == 0 || size % frame_bytes as u64 != 0 {
            return Err(fail(format!(
                "{}: {size} bytes are not whole {}x{} {} frames of {frame_bytes} bytes",
                path.display(),
                layout.width,
                layout.height,
                layout.format
            )));
        }
        Ok(Self {
            path: path.to_path_buf(),
            layout,
            frames: (size / frame_bytes as u64) as usize,
        })
    }

    fn read(&self) -> Result<impl Iterator<Item = Result<Frame, Failure>>, Failure> {
        let file = File::open(&self.path)
            .map_err(|e| fail(format!("cannot read {}: {e}", self.path.display())))?;
        let mut reader = BufReader::new(file);
        let RawLayout {
            width,
            height,
            format,
        } = self.layout;
        let len = format.frame_bytes(width, height).unwrap_or(0);
        let path = self.path.clone();
        let mut done = false;
        Ok(std::iter::from_fn(move || {
            if done {
                return None;
            }
            let frame = match read_frame(&mut reader, len) {
                Ok(Some(bytes)) => Frame::new(format, width, height, bytes).map_err(fail),
                Ok(None) => return None,
                Err(e) => Err(fail(format!("cannot read {}: {e}", path.display()))),
            };
            done = frame.is_err();
            Some(frame)
        }))
    }
}

/// Bytes of an MPEG transport stream packet: a `.ts` file of another size is cut short.
const TS_PACKET_BYTES: u64 = 188;

/// A video file, decoded by `ffmpeg`.
#[derive(Debug)]
pub struct Video {
    path: PathBuf,
    width: u32,
    height: u32,
    /// The container's frame count, when it states one.
    frames: Option<usize>,
    /// An MPEG transport stream that ends inside a packet.
    cut_packet: bool,
}

/// Runs a tool; the error says how to get it when it is missing.
fn spawn(command: &mut Command, tool: &str) -> Result<Child, Failure> {
    command.spawn().map_err(|e| {
        let hint = if e.kind() == io::ErrorKind::NotFound {
            " (install ffmpeg, e.g. `apt-get install ffmpeg`, to read video files)"
        } else {
            ""
        };
        fail(format!("cannot run {tool}: {e}{hint}"))
    })
}

/// The last non-empty line of a tool's stderr.
fn last_line(stderr: &str) -> &str {
    stderr
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("no message")
}

impl Video {
    /// Reads the first video stream's size (turned by its rotation, as ffmpeg turns the
    /// frames) and frame count with `ffprobe`.
    fn open(path: &Path) -> Result<Self, Failure> {
        let child = spawn(
            Command::new("ffprobe")
                .args(["-v", "error", "-select_streams", "v:0", "-show_entries"])
                .arg("stream=width,height,nb_frames:stream_side_data=rotation:format=format_name")
                .args(["-of", "json"])
                .arg(path)
                .stdin(Stdio::null())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped()),
            "ffprobe",
        )?;
        let output = child
            .wait_with_output()
            .map_err(|e| fail(format!("ffprobe: {e}")))?;
        let cannot = |why: &str| fail(format!("cannot read video {}: {why}", path.display()));
        if !output.status.success() {
            return Err(cannot(last_line(&String::from_utf8_lossy(&output.stderr))));
        }
        let probe: serde_json::Value =
            serde_json::from_slice(&output.stdout).map_err(|e| cannot(&e.to_string()))?;
        let stream = &probe["streams"][0];
        let side = |key: &str| stream[key].as_u64().and_then(|v| u32::try_from(v).ok());
        let (Some(width), Some(height)) = (side("width"), side("height")) else {
            return Err(cannot("no video stream"));
        };
        let rotation = stream["side_data_list"]
            .as_array()
            .into_iter()
            .flatten()
            .find_map(|d| d["rotation"].as_i64())
            .unwrap_or(0);
        let (width, height) = if rotation.rem_euclid(180) == 90 {
            (height, width)
        } else {
            (width, height)
        };
        let frames = stream["nb_frames"].as_str().and_then(|n| n.parse().ok());
        let transport = probe["format"]["format_name"] == "mpegts";
        let size = std::fs::metadata(path).map_or(0, |m| m.len());
        Ok(Self {
            path: path.to_path_buf(),
            width,
            height,
            frames,
            cut_packet: transport && !size.is_multiple_of(TS_PACKET_BYTES),
        })
    }

    /// Starts `ffmpeg` decoding every frame of the first video stream to RGB888.
    fn decode(&self) -> Result<VideoFrames, Failure> {
        let mut child = spawn(
            Command::new("ffmpeg")
                .args(["-nostdin", "-v", "error", "-i"])
                .arg(&self.path)
                .args(["-map", "0:v:0", "-fps_mode", "passthrough"])
                .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "pipe:1"])
                .stdin(Stdio::null())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped()),
            "ffmpeg",
        )?;
        let stdout = child.stdout.take().map(BufReader::new);
        // Drained on its own thread, so a chatty decoder cannot stall the frames' pipe.
        let stderr = child.stderr.take().map(|mut err| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = err.read_to_string(&mut text);
                text
            })
        });
        Ok(VideoFrames {
            child,
            stdout,
            stderr,
            path: self.path.clone(),
            width: self.width,
            height: self.height,
            stated: self.frames,
            cut_packet: self.cut_packet,
            decoded: 0,
        })
    }
}

/// The frames coming out of an `ffmpeg` process; the process is ended when dropped.
struct VideoFrames {
    child: Child,
    stdout: Option<BufReader<ChildStdout>>,
    stderr: Option<JoinHandle<String>>,
    path: PathBuf,
    width: u32,
    height: u32,
    /// The container's frame count, when it states one.
    stated: Option<usize>,
    /// An MPEG transport stream that ends inside a packet.
    cut_packet: bool,
    /// Frames read so far.
    decoded: usize,
}

impl VideoFrames {
    /// Waits for `ffmpeg` at the end of its output: an error, naming the last frame read,
    /// if it failed, reported an error (a damaged stream it decoded around), gave fewer
    /// frames than the container states, or read a transport stream that ends inside a
    /// packet (files cut short).
    fn finish(&mut self) -> Result<(), Failure> {
        let status = self
            .child
            .wait()
            .map_err(|e| fail(format!("ffmpeg: {e}")))?;
        let stderr = self
            .stderr
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        let (path, decoded) = (self.path.display(), self.decoded);
        let first_error = stderr.lines().map(str::trim).find(|l| !l.is_empty());
        if !status.success() {
            return Err(fail(format!(
                "cannot decode video {path} after frame {decoded}: ffmpeg: {}",
                last_line(&stderr)
            )));
        }
        if let Some(stated) = self.stated.filter(|&n| decoded < n) {
            let why = first_error.map_or(String::new(), |e| format!(" (ffmpeg: {e})"));
            return Err(fail(format!(
                "video {path} ends after frame {decoded} of the {stated} its container \
                 states: the file is cut short or damaged{why}"
            )));
        }
        if let Some(e) = first_error {
            return Err(fail(format!(
                "video {path} is damaged: ffmpeg reported errors by frame {decoded}: {e}"
            )));
        }
        if self.cut_packet {
            return Err(fail(format!(
                "video {path} ends inside a {TS_PACKET_BYTES}-byte transport packet after \
                 frame {decoded}: the file is cut short"
            )));
        }
        Ok(())
    }
}

impl Iterator for VideoFrames {
    type Item = Result<Frame, Failure>;

    fn next(&mut self) -> Option<Self::Item> {
        let reader = self.stdout.as_mut()?;
        let len = Format::Rgb888.frame_bytes(self.width, self.height)?;
        let frame = match read_frame(reader, len) {
            Ok(Some(rgb)) => {
                self.decoded += 1;
                return Some(Frame::rgb888(self.width, self.height, rgb).map_err(fail));
            }
            Ok(None) => self.finish().err(),
            Err(e) => Some(self.finish().err().unwrap_or_else(|| {
                fail(format!("cannot decode video {}: {e}", self.path.display()))
            })),
        };
        self.stdout = None;
        frame.map(Err)
    }
}

impl Drop for VideoFrames {
    fn drop(&mut self) {
        if self.stdout.is_some() {
            // Stopped before the end (a failure downstream): end the decoder.
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_layouts() {
        let l: RawLayout = "320x240:rgb565le".parse().unwrap();
        assert_eq!((l.width, l.height, l.format), (320, 240, Format::Rgb565Le));
        let l: RawLayout = "8X6:yuyv".parse().unwrap();
        assert_eq!(l.format, Format::Yuyv);
        for bad in [
            "320x240",
            "320:rgb888",
            "ax2:gray8",
            "4x4:bgr",
            "3x3:yuyv",
            "0x4:gray8",
        ] {
            assert!(bad.parse::<RawLayout>().is_err(), "{bad}");
        }
    }

    #[test]
    fn frames_are_read_whole() {
        let bytes: Vec<u8> = (0..10).collect();
        let mut r = &bytes[..];
        assert_eq!(read_frame(&mut r, 4).unwrap(), Some(vec![0, 1, 2, 3]));
        assert_eq!(read_frame(&mut r, 4).unwrap(), Some(vec![4, 5, 6, 7]));
        let e = read_frame(&mut r, 4).unwrap_err();
        assert!(e.to_string().contains("2 of 4 bytes"), "{e}");
        assert_eq!(read_frame(&mut &[][..], 4).unwrap(), None);
    }
}
