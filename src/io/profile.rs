//! Where the time of a run goes (`--profile`): named phases (decode, reference, fit, render,
//! score, …) accumulate their elapsed time through RAII spans on a [`Profile`], which the
//! caller owns and passes down (the binary makes one for `--profile`; nothing is kept
//! process-wide); [`Profile::report`] gives the table the binary prints to stderr when the
//! command ends.
//!
//! Phases inside parallel work (cases run in parallel) add up thread time, so on N threads
//! their sum can exceed the wall time; the report says so and gives the wall time too. Without
//! a profile ([`span`] given `None`) a span costs a branch.

use std::collections::BTreeMap;
use std::sync::Mutex;
use std::time::Instant;

/// The phases of one run: (seconds, calls) by name.
#[derive(Default)]
pub struct Profile {
    phases: Mutex<BTreeMap<&'static str, (f64, u64)>>,
}

/// A running phase; its time is added to its profile when it is dropped.
pub struct Span<'p> {
    into: Option<(&'p Profile, &'static str, Instant)>,
}

/// Starts timing phase `name` on `profile` (a no-op without one).
pub fn span<'p>(profile: Option<&'p Profile>, name: &'static str) -> Span<'p> {
    Span { into: profile.map(|p| (p, name, Instant::now())) }
}

impl Drop for Span<'_> {
    fn drop(&mut self) {
        if let Some((p, name, t)) = self.into {
            p.add(name, t.elapsed().as_secs_f64());
        }
    }
}

impl Profile {
    /// An empty profile.
    pub fn new() -> Self {
        Profile::default()
    }

    fn add(&self, name: &'static str, seconds: f64) {
        let mut p = self.phases.lock().unwrap_or_else(|e| e.into_inner());
        let e = p.entry(name).or_insert((0.0, 0));
        e.0 += seconds;
        e.1 += 1;
    }

    /// The accumulated phases: (name, seconds, calls), longest first.
    pub fn phases(&self) -> Vec<(&'static str, f64, u64)> {
        let p = self.phases.lock().unwrap_or_else(|e| e.into_inner());
        let mut v: Vec<_> = p.iter().map(|(k, (s, n))| (*k, *s, *n)).collect();
        v.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(b.0)));
        v
    }

    /// How many spans of phase `name` ended.
    pub fn calls(&self, name: &str) -> u64 {
        self.phases().iter().find(|p| p.0 == name).map_or(0, |p| p.2)
    }

    /// The report as text, for a command whose wall time was `wall_s`.
    pub fn report(&self, wall_s: f64) -> String {
        let mut out = format!(
            "profile: wall {wall_s:.3} s on {} thread(s); phases sum thread time (parallel phases can exceed wall)\n",
            rayon::current_num_threads()
        );
        out += &format!("  {:<34} {:>10} {:>8} {:>8}\n", "phase", "seconds", "share", "calls");
        let phases = self.phases();
        let total: f64 = phases.iter().map(|p| p.1).sum();
        for (name, s, n) in phases {
            let share = if total > 0.0 { 100.0 * s / total } else { 0.0 };
            out += &format!("  {name:<34} {s:>10.3} {share:>7.1}% {n:>8}\n");
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_accumulate_on_their_profile() {
        {
            let _s = span(None, "test-phase-off");
        }
        let profile = Profile::new();
        for _ in 0..3 {
            let _s = span(Some(&profile), "test-phase");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let p = profile.phases();
        let (_, s, n) = p.iter().find(|p| p.0 == "test-phase").copied().unwrap();
        assert_eq!(n, 3);
        assert_eq!(profile.calls("test-phase"), 3);
        assert_eq!(profile.calls("test-phase-off"), 0);
        assert!(s >= 0.006, "{s}");
        assert!(profile.report(1.0).contains("test-phase"));
    }
}
