//! Where the time of a run goes (`--profile`): named phases (decode, reference, fit, render,
//! score, …) accumulate their elapsed time through RAII spans; [`report`] gives the table the
//! binary prints to stderr when the command ends.
//!
//! Phases inside parallel work (cases run in parallel) add up thread time, so on N threads
//! their sum can exceed the wall time; the report says so and gives the wall time too. With
//! profiling off a span costs one relaxed atomic load.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

static ON: AtomicBool = AtomicBool::new(false);
static PHASES: Mutex<BTreeMap<&'static str, (f64, u64)>> = Mutex::new(BTreeMap::new());

/// Turns profiling on for this process.
pub fn enable() {
    ON.store(true, Ordering::Relaxed);
}

/// Whether profiling is on.
pub fn enabled() -> bool {
    ON.load(Ordering::Relaxed)
}

/// A running phase; its time is added when it is dropped.
pub struct Span {
    name: &'static str,
    start: Option<Instant>,
}

/// Starts timing phase `name` (a no-op unless profiling is on).
pub fn span(name: &'static str) -> Span {
    Span { name, start: enabled().then(Instant::now) }
}

impl Drop for Span {
    fn drop(&mut self) {
        if let Some(t) = self.start {
            let s = t.elapsed().as_secs_f64();
            let mut p = PHASES.lock().unwrap_or_else(|e| e.into_inner());
            let e = p.entry(self.name).or_insert((0.0, 0));
            e.0 += s;
            e.1 += 1;
        }
    }
}

/// The accumulated phases: (name, seconds, calls), longest first.
pub fn phases() -> Vec<(&'static str, f64, u64)> {
    let p = PHASES.lock().unwrap_or_else(|e| e.into_inner());
    let mut v: Vec<_> = p.iter().map(|(k, (s, n))| (*k, *s, *n)).collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(b.0)));
    v
}

/// The report as text.
pub fn report(wall_s: f64) -> String {
    let mut out = format!(
        "profile: wall {wall_s:.3} s on {} thread(s); phases sum thread time (parallel phases can exceed wall)\n",
        rayon::current_num_threads()
    );
    out += &format!("  {:<34} {:>10} {:>8} {:>8}\n", "phase", "seconds", "share", "calls");
    let total: f64 = phases().iter().map(|p| p.1).sum();
    for (name, s, n) in phases() {
        let share = if total > 0.0 { 100.0 * s / total } else { 0.0 };
        out += &format!("  {name:<34} {s:>10.3} {share:>7.1}% {n:>8}\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_accumulate_when_enabled() {
        {
            let _s = span("test-phase-off");
        }
        enable();
        for _ in 0..3 {
            let _s = span("test-phase");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let p = phases();
        let (_, s, n) = p.iter().find(|p| p.0 == "test-phase").copied().unwrap();
        assert_eq!(n, 3);
        assert!(s >= 0.006, "{s}");
        assert!(report(1.0).contains("test-phase"));
    }
}
