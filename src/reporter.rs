//! The command line's progress reporter (part of the binary, declared in `main.rs`; the
//! library only reports through [`rotorshunt::progress::Progress`]).
//!
//! On a terminal, standard error shows a bar: the command, the phase (and its place in
//! the run's phases), steps done of steps known, elapsed time and ETA. Elsewhere (a log
//! file, a pipe) a run prints nothing for its first [`LINE_INTERVAL`], then one line
//! every [`LINE_INTERVAL`] and one at each phase change, and a closing line:
//!
//! ```text
//! progress: design: verification (phase 2 of 3): 1204/3315 steps, 25 s elapsed, ETA 18 s
//! ```
//!
//! A phase that knows none of its steps yet (a search before it has found its work)
//! reports its time only, never a total of 0.
//!
//! So a quick run's standard error is unchanged, and a long one's log shows it is alive.
//! The ETA assumes the phase's remaining steps go at the rate of its steps so far; a
//! phase whose searches learn their work as they go (the region search) can only
//! announce the steps known so far, so its ETA is a lower bound, and it says so (`ETA
//! ≥`). `--quiet` reports nothing. Standard output is never touched.
//! (Test-only: with `every` set, see [`Reporter::new`], a line is also printed each time
//! the phase's done count passes a multiple of it, so a test can see the count rise
//! whatever the machine's speed.)
//!
//! [`printable`] is the binary's one filter for what it prints: text from the input (a
//! title, a path, a value in a message) reaches the terminal with its control characters
//! shown, not acted on.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rotorshunt::progress::Progress;
use std::borrow::Cow;
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// `text` for a terminal or a log: each control character (C0, DEL, C1) but line feed and
/// tab shown as its escape (`\u{1b}`, `\r`, `\u{9b}`), so text that came from the input (a
/// problem's title, a path, a value named in a message) cannot move the cursor, recolour
/// or retitle the terminal, or hide what was printed before it. Everything the binary
/// prints, on standard output and standard error, goes through it; JSON output is
/// unchanged, as serde_json escapes control characters itself.
pub fn printable(text: &str) -> Cow<'_, str> {
    let shown = |c: char| c.is_control() && c != '\n' && c != '\t';
    if !text.chars().any(shown) {
        return Cow::Borrowed(text);
    }
    let mut s = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if shown(c) {
            s.extend(c.escape_debug());
        } else {
            s.push(c);
        }
    }
    Cow::Owned(s)
}

/// Time between progress lines when standard error is not a terminal (and before the
/// first): often enough that a log shows a live run, rarely enough that it stays short.
pub const LINE_INTERVAL: Duration = Duration::from_secs(5);

/// How the CLI shows a command's progress.
pub enum Reporter {
    /// `--quiet`: nothing.
    Quiet,
    /// A bar on a terminal.
    Bar(Box<Bar>),
    /// Periodic lines otherwise.
    Lines(Lines),
}

impl Reporter {
    /// The reporter of `command`, whose phases are `plan` in order (for "phase k of n";
    /// a phase not in the plan is shown by name only). `every` (test-only, from
    /// `ROTORSHUNT_TEST_PROGRESS_EVERY`): the lines also print each time the done count
    /// passes a multiple of it.
    pub fn new(quiet: bool, command: &'static str, plan: &[&'static str], every: Option<u64>) -> Reporter {
        if quiet {
            Reporter::Quiet
        } else if std::io::stderr().is_terminal() {
            Reporter::Bar(Box::new(Bar::new(command, plan)))
        } else {
            Reporter::Lines(Lines::new(command, plan, every))
        }
    }

    /// The run is over: clear the bar, or print the closing line.
    pub fn finish(self) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(b) => b.bar.finish_and_clear(),
            Reporter::Lines(l) => l.finish(),
        }
    }
}

impl Progress for Reporter {
    fn phase(&self, name: &str, steps: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(b) => b.phase(name, steps),
            Reporter::Lines(l) => l.state.phase(name, steps),
        }
    }
    fn extend(&self, steps: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(b) => b.extend(steps),
            Reporter::Lines(l) => l.state.extend(steps),
        }
    }
    fn advance(&self, steps: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(b) => b.bar.inc(steps),
            Reporter::Lines(l) => l.state.advance(steps),
        }
    }
    /// Warnings are not progress: printed even with `--quiet`, above the bar if one is drawn.
    fn warning(&self, warning: &dyn std::fmt::Display) {
        match self {
            Reporter::Bar(b) => b.bar.suspend(|| eprintln!("warning: {}", printable(&warning.to_string()))),
            _ => eprintln!("warning: {}", printable(&warning.to_string())),
        }
    }

    fn notice(&self, line: &str) {
        match self {
            Reporter::Bar(b) => b.bar.suspend(|| eprintln!("{line}")),
            _ => eprintln!("{line}"),
        }
    }
}

/// "design: verification (phase 2 of 3)".
fn phase_label(command: &str, plan: &[&str], name: &str) -> String {
    match plan.iter().position(|p| *p == name) {
        Some(k) if plan.len() > 1 => format!("{command}: {name} (phase {} of {})", k + 1, plan.len()),
        _ => format!("{command}: {name}"),
    }
}

/// An indicatif bar on standard error.
pub struct Bar {
    bar: ProgressBar,
    command: &'static str,
    plan: Vec<&'static str>,
}

impl Bar {
    fn new(command: &'static str, plan: &[&'static str]) -> Bar {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
        bar.set_style(Bar::style(0));
        bar.set_prefix(command.to_string());
        // The elapsed time moves even while a long step runs.
        bar.enable_steady_tick(Duration::from_millis(500));
        Bar { bar, command, plan: plan.to_vec() }
    }

    /// The bar's style for a phase of `steps` known steps: counts and ETA, or, while
    /// none is known, the elapsed time only (never "0/0").
    fn style(steps: u64) -> ProgressStyle {
        let template = if steps == 0 {
            "{prefix} {spinner} {elapsed}"
        } else {
            "{prefix} [{bar:30}] {human_pos}/{human_len} steps, {elapsed} (ETA {eta})"
        };
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()).progress_chars("=> ")
    }

    fn extend(&self, steps: u64) {
        if steps > 0 && self.bar.length() == Some(0) {
            self.bar.set_style(Bar::style(steps));
        }
        self.bar.inc_length(steps);
    }

    fn phase(&self, name: &str, steps: u64) {
        self.bar.set_prefix(phase_label(self.command, &self.plan, name));
        self.bar.set_style(Bar::style(steps));
        self.bar.set_length(steps);
        self.bar.set_position(0);
        self.bar.reset_eta();
    }
}

/// What the line printer reads: the current phase and its counts.
struct State {
    command: &'static str,
    plan: Vec<&'static str>,
    started: Instant,
    /// Phase name and when it began.
    phase: Mutex<(String, Instant)>,
    done: AtomicU64,
    total: AtomicU64,
    /// Whether the total grew after the phase began (its ETA is then a lower bound).
    growing: AtomicBool,
    /// Whether a line has been printed (the run is a long one: phase changes are printed).
    printed: AtomicBool,
    /// Test-only: print a line whenever `done` passes a multiple of this (never 0).
    every: Option<u64>,
    /// Set when the run is over (wakes the printer).
    over: Mutex<bool>,
    wake: Condvar,
}

impl State {
    fn phase(&self, name: &str, steps: u64) {
        {
            let mut p = self.phase.lock().unwrap_or_else(|e| e.into_inner());
            *p = (name.to_string(), Instant::now());
            self.done.store(0, Ordering::Relaxed);
            self.total.store(steps, Ordering::Relaxed);
            self.growing.store(false, Ordering::Relaxed);
        }
        if self.printed.load(Ordering::Relaxed) {
            self.line();
        }
    }

    fn advance(&self, steps: u64) {
        let before = self.done.fetch_add(steps, Ordering::Relaxed);
        if let Some(n) = self.every {
            if (before + steps) / n > before / n {
                self.line();
            }
        }
    }

    fn extend(&self, steps: u64) {
        self.total.fetch_add(steps, Ordering::Relaxed);
        if self.done.load(Ordering::Relaxed) > 0 {
            self.growing.store(true, Ordering::Relaxed);
        }
    }

    /// Print the progress line.
    fn line(&self) {
        let (name, since) = self.phase.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let (done, total) = (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed));
        let mut text = format!(
            "progress: {}: {}{} elapsed",
            phase_label(self.command, &self.plan, &name),
            counts(done, total),
            seconds(self.started.elapsed())
        );
        let phase_time = since.elapsed().as_secs_f64();
        if done > 0 && total >= done {
            let eta = phase_time * (total - done) as f64 / done as f64;
            let bound = if self.growing.load(Ordering::Relaxed) { "≥ " } else { "" };
            text += &format!(", ETA {bound}{}", seconds(Duration::from_secs_f64(eta)));
        }
        self.printed.store(true, Ordering::Relaxed);
        let mut err = std::io::stderr().lock();
        let _ = writeln!(err, "{}", printable(&text));
    }
}

/// The counts of a progress line: `done/total steps, `, or, while a phase knows none of
/// its steps yet (a search that has not found its work), `done steps, ` or nothing (the
/// line then reports time only): never a total of 0.
fn counts(done: u64, total: u64) -> String {
    match (done, total) {
        (0, 0) => String::new(),
        (d, 0) => format!("{d} steps, "),
        (d, t) => format!("{d}/{t} steps, "),
    }
}

/// A duration as "45 s" or "3 min 05 s".
fn seconds(d: Duration) -> String {
    let s = d.as_secs_f64().round() as u64;
    if s < 60 {
        format!("{s} s")
    } else {
        format!("{} min {:02} s", s / 60, s % 60)
    }
}

/// The line printer: a thread that prints every [`LINE_INTERVAL`] until the run is over.
pub struct Lines {
    state: Arc<State>,
    printer: Option<std::thread::JoinHandle<()>>,
}

impl Lines {
    fn new(command: &'static str, plan: &[&'static str], every: Option<u64>) -> Lines {
        let now = Instant::now();
        let state = Arc::new(State {
            command,
            plan: plan.to_vec(),
            started: now,
            phase: Mutex::new((plan.first().copied().unwrap_or(command).to_string(), now)),
            done: AtomicU64::new(0),
            total: AtomicU64::new(0),
            growing: AtomicBool::new(false),
            printed: AtomicBool::new(false),
            every: every.filter(|&n| n > 0),
            over: Mutex::new(false),
            wake: Condvar::new(),
        });
        let s = Arc::clone(&state);
        let printer = std::thread::Builder::new()
            .name("progress".into())
            .spawn(move || {
                // Deadlines on a fixed grid from the start: lines do not drift later.
                let mut next = s.started + LINE_INTERVAL;
                let mut over = s.over.lock().unwrap_or_else(|e| e.into_inner());
                loop {
                    if *over {
                        return;
                    }
                    let now = Instant::now();
                    if now >= next {
                        drop(over);
                        s.line();
                        while next <= Instant::now() {
                            next += LINE_INTERVAL;
                        }
                        over = s.over.lock().unwrap_or_else(|e| e.into_inner());
                        continue;
                    }
                    over = s.wake.wait_timeout(over, next - now).unwrap_or_else(|e| e.into_inner()).0;
                }
            })
            .ok();
        Lines { state, printer }
    }

    fn finish(mut self) {
        *self.state.over.lock().unwrap_or_else(|e| e.into_inner()) = true;
        self.state.wake.notify_all();
        if let Some(p) = self.printer.take() {
            let _ = p.join();
        }
        if self.state.printed.load(Ordering::Relaxed) {
            let mut err = std::io::stderr().lock();
            let _ =
                writeln!(err, "progress: {}: done in {}", self.state.command, seconds(self.state.started.elapsed()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phase_without_known_steps_reports_time_only() {
        assert_eq!(counts(0, 0), "");
        assert_eq!(counts(3, 0), "3 steps, ");
        assert_eq!(counts(4, 10), "4/10 steps, ");
    }

    #[test]
    fn printable_shows_control_characters_and_keeps_the_rest() {
        assert!(matches!(printable("plain é 中文 \u{200f} 🙂\nline\ttab"), Cow::Borrowed(_)));
        assert_eq!(
            printable("a\u{1b}[31mred\rb\u{7}\u{0}\u{7f}\u{9b}c\n"),
            "a\\u{1b}[31mred\\rb\\u{7}\\0\\u{7f}\\u{9b}c\n"
        );
        assert!(!printable("\u{1b}]0;title\u{7}").contains('\u{1b}'));
    }
}
