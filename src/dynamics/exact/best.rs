//! The best round of a step's Tresca rounds: the one whose capacities changed least (relative
//! to the largest capacity), kept for a step whose rounds do not settle, and whether the rounds
//! have stalled — `stall` rounds in a row none of which halved the smallest change before it.
//! A contracting fixed point halves its change every round or two; rounds that wander (a
//! hyperstatic vault's driving step, its capacities reshuffled by 0.2–0.5 of the largest every
//! round) would otherwise run to the round limit for an answer no better than their best.

/// The smallest change so far, its round's solution, and the rounds since one halved it.
pub(super) struct Best<T> {
    change: f64,
    kept: Option<T>,
    since: u32,
}

impl<T> Default for Best<T> {
    fn default() -> Self {
        Self { change: f64::INFINITY, kept: None, since: 0 }
    }
}

impl<T: Clone> Best<T> {
    /// Counts a round that changed the capacities by `change`, keeping `round` when it is the
    /// smallest change so far; whether `stall` rounds in a row have not halved the smallest
    /// change before them.
    pub fn record(&mut self, change: f64, round: &T, stall: u32) -> bool {
        self.since = if change <= 0.5 * self.change { 0 } else { self.since + 1 };
        if change < self.change {
            self.change = change;
            self.kept = Some(round.clone());
        }
        self.since >= stall
    }

    /// The best round's solution (`last` when none was recorded).
    pub fn take(self, last: T) -> T {
        self.kept.unwrap_or(last)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: rounds that halve their change every round never stall, and the last (the
    /// smallest change) is kept.
    #[test]
    fn contracting_rounds_never_stall() {
        let mut best = Best::default();
        for k in 0..40 {
            assert!(!best.record(0.5f64.powi(k), &k, 3), "round {k}");
        }
        assert_eq!(best.take(-1), 39);
    }

    /// Invariant: `stall` rounds in a row that do not halve the smallest change before each
    /// stop the rounds (a round that improves on it by less than half does not restart the
    /// count), and the round with the smallest change is kept, not the last.
    #[test]
    fn wandering_rounds_stall_and_keep_their_best() {
        let changes = [0.4, 0.1, 0.3, 0.45, 0.08, 0.2];
        let mut best = Best::default();
        let stalled: Vec<bool> = changes.iter().enumerate().map(|(k, &c)| best.record(c, &k, 4)).collect();
        // 0.1 halves 0.4; 0.3, 0.45, 0.08 (not ≤ 0.05) and 0.2 do not: the fourth of them stalls.
        assert_eq!(stalled, [false, false, false, false, false, true]);
        assert_eq!(best.take(99), 4, "the round that changed by 0.08");
    }

    /// Invariant: with no round recorded the last solution stands.
    #[test]
    fn no_round_keeps_the_last() {
        assert_eq!(Best::<usize>::default().take(7), 7);
    }
}
