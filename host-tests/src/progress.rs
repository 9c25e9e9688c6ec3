//! A dependency-free progress bar on stderr for long runs (e.g. evaluating sequences).
//!
//! On a terminal it redraws one line at most ten times a second:
//! `label [#########.........] 45/100 12.3/s ETA 4s`. When stderr is not a terminal (CI
//! logs, pipes) it prints only the final summary line from [`Progress::finish`].

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Width of the bar, characters.
const BAR: usize = 30;
/// Shortest time between two redraws.
const REDRAW: Duration = Duration::from_millis(100);

/// Progress of `total` steps, drawn on stderr.
#[derive(Debug)]
pub struct Progress {
    label: String,
    total: u64,
    done: u64,
    start: Instant,
    last_draw: Option<Instant>,
    live: bool,
}

impl Progress {
    /// A bar for `total` steps; draws only when stderr is a terminal.
    pub fn new(label: impl Into<String>, total: u64) -> Self {
        Self::with_live(label, total, std::io::stderr().is_terminal())
    }

    /// A bar that never redraws (only [`Progress::finish`] prints).
    pub fn hidden(label: impl Into<String>, total: u64) -> Self {
        Self::with_live(label, total, false)
    }

    fn with_live(label: impl Into<String>, total: u64, live: bool) -> Self {
        Self {
            label: label.into(),
            total,
            done: 0,
            start: Instant::now(),
            last_draw: None,
            live,
        }
    }

    /// Steps done so far.
    pub fn done(&self) -> u64 {
        self.done
    }

    /// Records `n` more steps done and redraws if due.
    pub fn inc(&mut self, n: u64) {
        self.done = self.done.saturating_add(n);
        if self.live && self.last_draw.is_none_or(|t| t.elapsed() >= REDRAW) {
            self.last_draw = Some(Instant::now());
            let line = self.line();
            let mut err = std::io::stderr().lock();
            // A failed write to stderr is not worth stopping the run for.
            let _ = write!(err, "\r{line}\x1b[K");
            let _ = err.flush();
        }
    }

    /// The progress line as drawn (without the carriage return).
    pub fn line(&self) -> String {
        let elapsed = self.start.elapsed().as_secs_f64();
        let rate = if elapsed > 0.0 {
            self.done as f64 / elapsed
        } else {
            0.0
        };
        let fill = if self.total == 0 {
            BAR
        } else {
            (self.done.min(self.total) as f64 / self.total as f64 * BAR as f64) as usize
        };
        let eta = if rate > 0.0 && self.total > self.done {
            format!(" ETA {:.0}s", (self.total - self.done) as f64 / rate)
        } else {
            String::new()
        };
        format!(
            "{} [{}{}] {}/{} {rate:.1}/s{eta}",
            self.label,
            "#".repeat(fill),
            ".".repeat(BAR - fill),
            self.done,
            self.total
        )
    }

    /// Ends the bar: prints `label: done/total in T s (rate/s)` on its own line.
    pub fn finish(self) {
        let secs = self.start.elapsed().as_secs_f64();
        let rate = if secs > 0.0 {
            self.done as f64 / secs
        } else {
            0.0
        };
        let mut err = std::io::stderr().lock();
        let clear = if self.live { "\r\x1b[K" } else { "" };
        let _ = writeln!(
            err,
            "{clear}{}: {}/{} in {secs:.1} s ({rate:.1}/s)",
            self.label, self.done, self.total
        );
    }
}
