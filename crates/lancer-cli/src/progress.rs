//! Progress of a render on stderr: a bar with an ETA when stderr is a terminal; otherwise (a
//! log file under Slurm or nohup) plain lines, one at every tenth of the work and at least one
//! every `--log-every` seconds, without control characters; or, with `--progress json`, the
//! same lines as JSON objects for a program to read.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Longest silence of the plain progress lines by default (`--log-every`).
pub const LINE_INTERVAL: Duration = Duration::from_secs(30);

/// How progress is shown (`--progress`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ProgressMode {
    /// A bar on a terminal, plain lines otherwise.
    #[default]
    Auto,
    /// Always the bar.
    Bar,
    /// Always plain lines.
    Lines,
    /// One JSON object per line: `{"percent", "done", "total", "elapsed_s", "samples_per_s",
    /// "eta_s"}`.
    Json,
}

/// How a render shows its progress.
pub enum Progress {
    /// The bar on a terminal (hidden when quiet).
    Bar(ProgressBar),
    /// Plain lines, for a stderr that is not a terminal.
    Lines(Lines),
}

impl Progress {
    /// Progress over `total` units (pixel samples): nothing when `quiet`; else as `mode`
    /// says (`auto`: a bar when stderr is a terminal, plain lines otherwise), lines at least
    /// every `interval`.
    pub fn new(total: u64, quiet: bool, mode: ProgressMode, interval: Duration) -> Progress {
        if quiet {
            return Progress::Bar(ProgressBar::with_draw_target(
                Some(total),
                ProgressDrawTarget::hidden(),
            ));
        }
        let lines = match mode {
            ProgressMode::Auto => !std::io::stderr().is_terminal(),
            ProgressMode::Bar => false,
            ProgressMode::Lines | ProgressMode::Json => true,
        };
        if lines {
            return Progress::Lines(Lines::new(total, interval, mode == ProgressMode::Json));
        }
        let pb = ProgressBar::new(total);
        pb.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}%  ETA {eta}",
            )
            .expect("valid template"),
        );
        Progress::Bar(pb)
    }

    /// Counts `n` more units done.
    pub fn inc(&self, n: u64) {
        match self {
            Progress::Bar(b) => b.inc(n),
            Progress::Lines(l) => l.inc(n, Instant::now(), |line| eprintln!("{line}")),
        }
    }

    /// Runs `f` with the bar out of the way (it prints or writes).
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match self {
            Progress::Bar(b) => b.suspend(f),
            Progress::Lines(_) => f(),
        }
    }

    /// Removes the bar (the plain lines need no clearing).
    pub fn finish_and_clear(&self) {
        if let Progress::Bar(b) = self {
            b.finish_and_clear();
        }
    }
}

/// The plain progress lines: `progress: P% (DONE of TOTAL pixel samples), E s elapsed, S
/// samples/s, about R s left`, with `S = DONE/E` and `R = (TOTAL − DONE)/S`; or the same
/// figures as one JSON object per line.
pub struct Lines {
    total: u64,
    start: Instant,
    /// Longest silence between two lines.
    interval: Duration,
    json: bool,
    /// Units done, the tenth last reported (0–10) and when the last line was printed: one
    /// lock, so that each line reports the count of its own increment and they come in order.
    state: Mutex<LinesState>,
}

struct LinesState {
    done: u64,
    tenth: u64,
    printed: Instant,
}

impl Lines {
    /// Lines over `total` units, at least one every `interval`, the clock starting now.
    pub fn new(total: u64, interval: Duration, json: bool) -> Lines {
        let now = Instant::now();
        Lines {
            total,
            start: now,
            interval,
            json,
            state: Mutex::new(LinesState {
                done: 0,
                tenth: 0,
                printed: now,
            }),
        }
    }

    /// Counts `n` more units done at `now` and hands the line to `print` if one is due: the
    /// work crossed a tenth (one line for the highest crossed), or the interval passed.
    /// `print` runs under the lock, so that lines from several threads come out in order.
    pub fn inc(&self, n: u64, now: Instant, print: impl FnOnce(String)) {
        let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        st.done = (st.done + n).min(self.total);
        let tenth = (st.done * 10).checked_div(self.total).unwrap_or(10);
        let due = tenth > st.tenth || now.duration_since(st.printed) >= self.interval;
        if !due || st.tenth == 10 {
            return;
        }
        st.tenth = tenth.max(st.tenth);
        st.printed = now;
        print(self.line(st.done, now));
    }

    fn line(&self, done: u64, now: Instant) -> String {
        let elapsed = now.duration_since(self.start).as_secs_f64();
        let percent = (done * 100).checked_div(self.total).unwrap_or(100);
        let rate = if elapsed > 0.0 {
            done as f64 / elapsed
        } else {
            0.0
        };
        // ETA = samples left / samples per second, unknown before the first sample.
        let eta = (done > 0 && done < self.total)
            .then(|| elapsed * (self.total - done) as f64 / done as f64);
        if self.json {
            return serde_json::json!({
                "percent": percent,
                "done": done,
                "total": self.total,
                "elapsed_s": round1(elapsed),
                "samples_per_s": rate.round(),
                "eta_s": eta.map(round1),
            })
            .to_string();
        }
        let mut s = format!(
            "progress: {percent}% ({done} of {} pixel samples), {elapsed:.1} s elapsed",
            self.total
        );
        if done > 0 && elapsed > 0.0 {
            s.push_str(&format!(", {} samples/s", si(rate)));
        }
        if let Some(left) = eta {
            s.push_str(&format!(", about {left:.1} s left"));
        }
        s
    }
}

fn round1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

/// A rate with an SI prefix: 950, 12.3 k, 4.56 M.
fn si(x: f64) -> String {
    if x >= 1e6 {
        format!("{:.2} M", x / 1e6)
    } else if x >= 1e3 {
        format!("{:.1} k", x / 1e3)
    } else {
        format!("{x:.0}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line `inc` prints, if any.
    fn inc(l: &Lines, n: u64, now: Instant) -> Option<String> {
        let mut out = None;
        l.inc(n, now, |s| out = Some(s));
        out
    }

    #[test]
    fn lines_come_at_each_tenth_and_once_a_minute() {
        let l = &Lines::new(200, Duration::from_secs(60), false);
        let t = l.start;
        // 5 %: no tenth crossed yet.
        assert_eq!(inc(l, 10, t), None);
        // 25 %: one line for the 20 % mark (10 % was crossed too, but only one line).
        let s = inc(l, 40, t + Duration::from_secs(5)).unwrap();
        assert_eq!(
            s,
            "progress: 25% (50 of 200 pixel samples), 5.0 s elapsed, 10 samples/s, about 15.0 s left"
        );
        // 29.5 %: still in the same tenth, less than a minute later: nothing.
        assert_eq!(inc(l, 9, t + Duration::from_secs(30)), None);
        // A minute after the last line, a line even without a new tenth.
        let s = inc(l, 0, t + Duration::from_secs(65)).unwrap();
        assert!(s.starts_with("progress: 29% (59 of 200"), "{s}");
        // The end: 100 %, no time left to announce, and only once.
        let s = inc(l, 141, t + Duration::from_secs(70)).unwrap();
        assert_eq!(
            s,
            "progress: 100% (200 of 200 pixel samples), 70.0 s elapsed, 3 samples/s"
        );
        assert_eq!(inc(l, 0, t + Duration::from_secs(200)), None);
    }

    #[test]
    fn the_interval_sets_the_longest_silence() {
        let l = &Lines::new(1000, Duration::from_secs(2), false);
        let t = l.start;
        assert_eq!(inc(l, 1, t + Duration::from_secs(1)), None);
        let s = inc(l, 1, t + Duration::from_secs(2)).unwrap();
        assert_eq!(
            s,
            "progress: 0% (2 of 1000 pixel samples), 2.0 s elapsed, 1 samples/s, about 998.0 s left"
        );
        assert_eq!(inc(l, 1, t + Duration::from_secs(3)), None);
        assert!(inc(l, 1, t + Duration::from_secs(4)).is_some());
    }

    #[test]
    fn json_lines_carry_the_same_figures() {
        let l = &Lines::new(4000, Duration::from_secs(60), true);
        let s = inc(l, 1000, l.start + Duration::from_millis(500)).unwrap();
        let v: serde_json::Value = serde_json::from_str(&s).unwrap();
        assert_eq!(v["percent"], 25);
        assert_eq!(v["done"], 1000);
        assert_eq!(v["total"], 4000);
        assert_eq!(v["elapsed_s"], 0.5);
        assert_eq!(v["samples_per_s"], 2000.0);
        assert_eq!(v["eta_s"], 1.5);
        let end = inc(l, 3000, l.start + Duration::from_secs(2)).unwrap();
        let v: serde_json::Value = serde_json::from_str(&end).unwrap();
        assert_eq!(v["percent"], 100);
        assert!(v["eta_s"].is_null());
    }

    #[test]
    fn rates_get_si_prefixes() {
        assert_eq!(si(950.0), "950");
        assert_eq!(si(12_345.0), "12.3 k");
        assert_eq!(si(4_560_000.0), "4.56 M");
    }
}
