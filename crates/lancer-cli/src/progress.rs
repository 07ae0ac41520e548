//! Progress of a render on stderr: a bar with an ETA when stderr is a terminal; otherwise (a
//! log file under Slurm or nohup) plain lines, one at every tenth of the work and at least one
//! a minute, without control characters.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Longest silence of the plain progress lines.
pub const LINE_INTERVAL: Duration = Duration::from_secs(60);

/// How a render shows its progress.
pub enum Progress {
    /// The bar on a terminal (hidden when quiet).
    Bar(ProgressBar),
    /// Plain lines, for a stderr that is not a terminal.
    Lines(Lines),
}

impl Progress {
    /// Progress over `total` units (pixel samples): nothing when `quiet`, a bar when stderr is
    /// a terminal, plain lines otherwise.
    pub fn new(total: u64, quiet: bool) -> Progress {
        if quiet {
            return Progress::Bar(ProgressBar::with_draw_target(
                Some(total),
                ProgressDrawTarget::hidden(),
            ));
        }
        if !std::io::stderr().is_terminal() {
            return Progress::Lines(Lines::new(total));
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

/// The plain progress lines: `progress: P% (DONE of TOTAL pixel samples), E s elapsed, about
/// R s left`, with `R = E·(TOTAL − DONE)/DONE`.
pub struct Lines {
    total: u64,
    start: Instant,
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
    /// Lines over `total` units, the clock starting now.
    pub fn new(total: u64) -> Lines {
        let now = Instant::now();
        Lines {
            total,
            start: now,
            state: Mutex::new(LinesState {
                done: 0,
                tenth: 0,
                printed: now,
            }),
        }
    }

    /// Counts `n` more units done at `now` and hands the line to `print` if one is due: the
    /// work crossed a tenth (one line for the highest crossed), or [`LINE_INTERVAL`] passed.
    /// `print` runs under the lock, so that lines from several threads come out in order.
    pub fn inc(&self, n: u64, now: Instant, print: impl FnOnce(String)) {
        let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        st.done = (st.done + n).min(self.total);
        let tenth = (st.done * 10).checked_div(self.total).unwrap_or(10);
        let due = tenth > st.tenth || now.duration_since(st.printed) >= LINE_INTERVAL;
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
        let mut s = format!(
            "progress: {percent}% ({done} of {} pixel samples), {elapsed:.1} s elapsed",
            self.total
        );
        if done > 0 && done < self.total {
            let left = elapsed * (self.total - done) as f64 / done as f64;
            s.push_str(&format!(", about {left:.1} s left"));
        }
        s
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
        let l = &Lines::new(200);
        let t = l.start;
        // 5 %: no tenth crossed yet.
        assert_eq!(inc(l, 10, t), None);
        // 25 %: one line for the 20 % mark (10 % was crossed too, but only one line).
        let s = inc(l, 40, t + Duration::from_secs(5)).unwrap();
        assert_eq!(
            s,
            "progress: 25% (50 of 200 pixel samples), 5.0 s elapsed, about 15.0 s left"
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
            "progress: 100% (200 of 200 pixel samples), 70.0 s elapsed"
        );
        assert_eq!(inc(l, 0, t + Duration::from_secs(200)), None);
    }
}
