//! A one-number classifier: items are positive when their score is on one side of a
//! threshold, the threshold learnt as the best cut of training scores, and its leave-one-out
//! evaluation (each item classified by the threshold learnt from all the others).

/// Which side of a threshold the positive class is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Positive when `score < threshold`.
    Below,
    /// Positive when `score > threshold`.
    Above,
}

impl Side {
    /// Whether `score` is on the positive side of `threshold`.
    pub fn is_positive(self, score: f64, threshold: f64) -> bool {
        match self {
            Side::Below => score < threshold,
            Side::Above => score > threshold,
        }
    }
}

/// The share of items whose label `positive[i]` is predicted by `side.is_positive(score,
/// threshold)`; 0 without items.
pub fn threshold_accuracy(scores: &[f64], positive: &[bool], threshold: f64, side: Side) -> f64 {
    let correct = (scores.iter().zip(positive))
        .filter(|&(&s, &p)| side.is_positive(s, threshold) == p)
        .count();
    correct as f64 / scores.len().max(1) as f64
}

/// The threshold that classifies `scores` best: among the cuts of the sorted scores between
/// two distinct values (threshold their midpoint `(a + b)/2`) and the two ends (`±∞`: every
/// item on one side), the one of highest accuracy; ties go to the cut with the widest gap
/// `b − a` between the scores it separates (the ends count as gap 0), then to the cut that
/// predicts fewer items positive. Scores must be finite. Without items: the threshold that
/// predicts nothing positive.
pub fn best_threshold(scores: &[f64], positive: &[bool], side: Side) -> f64 {
    if side == Side::Above {
        // Positive above t is positive below −t on the negated scores.
        let negated: Vec<f64> = scores.iter().map(|s| -s).collect();
        return -best_threshold(&negated, positive, Side::Below);
    }
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by(|&a, &b| scores[a].total_cmp(&scores[b]));
    let sorted: Vec<f64> = order.iter().map(|&i| scores[i]).collect();
    // Cut c predicts the first c sorted items positive: correct = positives among them plus
    // negatives after them, updated as c grows.
    let mut correct = positive.iter().filter(|&&p| !p).count();
    let mut best = (correct, 0.0, f64::NEG_INFINITY);
    for c in 1..=sorted.len() {
        if positive[order[c - 1]] {
            correct += 1;
        } else {
            correct -= 1;
        }
        let (gap, threshold) = match sorted.get(c) {
            None => (0.0, f64::INFINITY),
            Some(&next) if next > sorted[c - 1] => {
                (next - sorted[c - 1], 0.5 * (sorted[c - 1] + next))
            }
            Some(_) => continue, // no threshold separates equal scores
        };
        // Only a strictly better cut replaces the best: on a tie the earlier cut (fewer
        // positives) stays.
        if correct > best.0 || (correct == best.0 && gap > best.1) {
            best = (correct, gap, threshold);
        }
    }
    best.2
}

/// A threshold classifier evaluated leave-one-out.
#[derive(Debug, Clone, PartialEq)]
pub struct LeaveOneOut {
    /// For each item, the [`best_threshold`] of the other items.
    pub thresholds: Vec<f64>,
    /// For each item, its predicted label under its threshold.
    pub predicted: Vec<bool>,
    /// Share of items predicted correctly.
    pub accuracy: f64,
}

/// Leave-one-out evaluation of [`best_threshold`]: each item is classified by the threshold
/// learnt from all the others.
pub fn leave_one_out_threshold(scores: &[f64], positive: &[bool], side: Side) -> LeaveOneOut {
    let n = scores.len();
    let (mut thresholds, mut predicted) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for held_out in 0..n {
        let kept = |i: &usize| *i != held_out;
        let training_scores: Vec<f64> = (0..n).filter(kept).map(|i| scores[i]).collect();
        let training_labels: Vec<bool> = (0..n).filter(kept).map(|i| positive[i]).collect();
        let threshold = best_threshold(&training_scores, &training_labels, side);
        thresholds.push(threshold);
        predicted.push(side.is_positive(scores[held_out], threshold));
    }
    let correct = predicted
        .iter()
        .zip(positive)
        .filter(|(a, b)| a == b)
        .count();
    LeaveOneOut {
        thresholds,
        predicted,
        accuracy: correct as f64 / n.max(1) as f64,
    }
}
