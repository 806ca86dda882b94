//! The best design judged so far in a run: what a stop keeps ([`super::Status::Stopped`]).

use crate::progress::Progress;
use std::cmp::Ordering;
use std::sync::Mutex;

/// How good a judged design is, the smaller the better, compared in order: 0 for a design
/// that meets the objective's requirements (1 otherwise), then the objective's primary
/// and secondary figures (the negated band width in rad/s for the widest band, the total
/// intrusion in rad/s for clear bands, the violation or the peak in m for the least peak).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Rank(pub u8, pub f64, pub f64);

impl Rank {
    fn cmp(&self, other: &Rank) -> Ordering {
        self.0.cmp(&other.0).then(self.1.total_cmp(&other.1)).then(self.2.total_cmp(&other.2))
    }
}

/// The best design offered so far, with its rank. Shared by the run's threads; ties go to
/// the smaller values (lexicographically), so the design kept does not depend on the
/// order in which the threads offer.
#[derive(Debug, Default)]
pub(super) struct BestSoFar {
    best: Mutex<Option<(Rank, Vec<f64>)>>,
}

impl BestSoFar {
    /// Offer the design with `values` (SI units), judged `rank`. Refused once `progress`
    /// asks the run to stop: a judgement that ended after the stop may rest on searches
    /// cut short. A stop is never taken back, so a judgement that ends before it was
    /// complete.
    pub(super) fn offer(&self, rank: Rank, values: &[f64], progress: &dyn Progress) {
        if progress.cancelled() || !rank.1.is_finite() || !rank.2.is_finite() {
            return;
        }
        let mut best = self.best.lock().unwrap_or_else(|p| p.into_inner());
        let better = match &*best {
            None => true,
            Some((r, v)) => rank.cmp(r).then_with(|| lexicographic(values, v)) == Ordering::Less,
        };
        if better {
            *best = Some((rank, values.to_vec()));
        }
    }

    /// The values (SI units) of the best design offered, if any.
    pub(super) fn values(&self) -> Option<Vec<f64>> {
        self.best.lock().unwrap_or_else(|p| p.into_inner()).as_ref().map(|(_, v)| v.clone())
    }
}

fn lexicographic(a: &[f64], b: &[f64]) -> Ordering {
    a.iter().zip(b).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()).unwrap_or(a.len().cmp(&b.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::Silent;

    struct Stop;
    impl Progress for Stop {
        fn cancelled(&self) -> bool {
            true
        }
    }

    #[test]
    fn keeps_the_best_rank_and_breaks_ties_by_the_values() {
        let b = BestSoFar::default();
        assert_eq!(b.values(), None);
        b.offer(Rank(1, 0.5, 0.0), &[3.0], &Silent);
        b.offer(Rank(0, 2.0, 0.0), &[2.0], &Silent);
        b.offer(Rank(0, 3.0, 0.0), &[1.0], &Silent);
        assert_eq!(b.values(), Some(vec![2.0]), "requirements met first, then the smaller figure");
        b.offer(Rank(0, 2.0, 0.0), &[1.5], &Silent);
        assert_eq!(b.values(), Some(vec![1.5]), "a tie goes to the smaller values");
        b.offer(Rank(0, 2.0, 0.0), &[1.7], &Silent);
        assert_eq!(b.values(), Some(vec![1.5]));
        b.offer(Rank(0, f64::NAN, 0.0), &[0.0], &Silent);
        assert_eq!(b.values(), Some(vec![1.5]), "a failed judgement is not offered");
    }

    #[test]
    fn refuses_what_was_judged_after_a_stop() {
        let b = BestSoFar::default();
        b.offer(Rank(0, -10.0, 0.0), &[1.0], &Silent);
        b.offer(Rank(0, -1.0e9, 0.0), &[2.0], &Stop);
        assert_eq!(b.values(), Some(vec![1.0]));
    }
}
