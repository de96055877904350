//! How far the path tracer's own noise moves the truth tables' figures. Each drawing is
//! measured against two references of different seeds. A figure moves by its drawing's
//! change between them (the seed's spread); a difference between two drawings moves
//! by the change of the two drawings' difference, which the references' noise leaves
//! alone where the two drawings agree (it is common to both and cancels) and moves
//! where they differ. A difference is told apart when it is ten times its own move or
//! more.

/// Each drawing's ꟻLIP against the first and the second reference.
pub(super) type Figures = [(f64, f64)];

/// The largest change of any drawing's ꟻLIP from one reference to the other (the
/// seed's spread: each figure's uncertainty), and the smallest difference between two
/// drawings' ꟻLIP against the first.
pub(super) fn seed_spread(pairs: &Figures) -> (f64, f64) {
    let spread = pairs.iter().map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let mut gap = f64::INFINITY;
    for (i, (a, _)) in pairs.iter().enumerate() {
        for (b, _) in &pairs[i + 1..] {
            gap = gap.min((a - b).abs());
        }
    }
    (spread, if gap.is_finite() { gap } else { 0.0 })
}

/// The difference between drawings `i` and `j` against the first reference, and its
/// noise: how much that difference moves against the second.
fn difference(pairs: &Figures, i: usize, j: usize) -> (f64, f64) {
    let (d, d_second) = (pairs[i].0 - pairs[j].0, pairs[i].1 - pairs[j].1);
    (d, (d - d_second).abs())
}

/// Each drawing's difference from the first drawing (the scene's own) with its noise;
/// None for the first drawing.
pub(super) fn differences(pairs: &Figures) -> Vec<Option<(f64, f64)>> {
    (0..pairs.len())
        .map(|i| (i > 0).then(|| difference(pairs, i, 0)))
        .collect()
}

/// Whether a difference is told apart from its noise: ten times it or more (and not
/// zero: two drawings of the same ꟻLIP against both references are not).
fn is_resolved(d: f64, noise: f64) -> bool {
    d != 0.0 && d.abs() >= 10.0 * noise
}

/// Of [`differences`]: how many are resolved, how many there are, and the largest noise.
pub(super) fn resolved(deltas: &[Option<(f64, f64)>]) -> (usize, usize, f64) {
    let all: Vec<(f64, f64)> = deltas.iter().flatten().copied().collect();
    let worst = all.iter().map(|&(_, n)| n).fold(0.0, f64::max);
    let told = all
        .iter()
        .filter(|&&(d, noise)| is_resolved(d, noise))
        .count();
    (told, all.len(), worst)
}

/// Every two drawings' difference that is not told apart: (i, j, difference, noise).
pub(super) fn unresolved_pairs(pairs: &Figures) -> Vec<(usize, usize, f64, f64)> {
    let mut out = Vec::new();
    for i in 0..pairs.len() {
        for j in i + 1..pairs.len() {
            let (d, noise) = difference(pairs, i, j);
            if !is_resolved(d, noise) {
                out.push((i, j, d, noise));
            }
        }
    }
    out
}

/// A difference's cell: signed, its noise in brackets, marked ≈ where it is not ten
/// times its noise (the two drawings are not told apart).
pub(super) fn delta_cell(delta: Option<(f64, f64)>) -> String {
    match delta {
        None => "–".to_string(),
        Some((d, noise)) => format!(
            "{}{d:+.4} (±{noise:.4})",
            if is_resolved(d, noise) { "" } else { "≈ " }
        ),
    }
}

/// The sentence (starting in lower case) on a table of drawings named `names` with
/// figures `pairs`: each figure's uncertainty, then how many of the table's differences (from its first
/// drawing, `base`) and of all its pairs of drawings are told apart, naming the pairs
/// that are not.
pub(super) fn noise_sentence(pairs: &Figures, names: &[String], base: &str) -> String {
    let (spread, _) = seed_spread(pairs);
    let (told, all, worst) = resolved(&differences(pairs));
    let pair_count = pairs.len() * pairs.len().saturating_sub(1) / 2;
    let apart = unresolved_pairs(pairs);
    let mut sentence = format!(
        "every ꟻLIP moves by at most {spread:.4} against a second reference (another \
         seed); a difference between two drawings moves only where they differ, the \
         noise being common to both: each drawing's difference from {base} (Δ) moves \
         by at most {worst:.4}, the noise in brackets, and {told} of the {all} are ten times their noise or \
         more; of all {pair_count} pairs of drawings, {} are.",
        pair_count - apart.len()
    );
    if !apart.is_empty() {
        let listed: Vec<String> = apart
            .iter()
            .map(|&(i, j, d, noise)| {
                format!(
                    "{} and {} ({:.4} ± {noise:.4})",
                    names[i],
                    names[j],
                    d.abs()
                )
            })
            .collect();
        sentence.push_str(&format!(" Not told apart: {}.", listed.join("; ")));
    }
    sentence
}

/// `word` with its first letter in capitals.
pub(super) fn capitalised(word: &str) -> String {
    let mut chars = word.chars();
    chars
        .next()
        .map(|c| c.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seed_spread_is_the_largest_move_and_the_gap_the_closest_pair() {
        let pairs = [(0.10, 0.11), (0.20, 0.19), (0.105, 0.1), (0.3, 0.3)];
        let (spread, gap) = seed_spread(&pairs);
        assert!((spread - 0.01).abs() < 1e-12, "{spread}");
        assert!((gap - 0.005).abs() < 1e-12, "{gap}");
        assert_eq!(seed_spread(&[(0.1, 0.2)]).1, 0.0, "one drawing has no pair");
    }

    /// A difference's noise is how much the difference moves between the references,
    /// not either figure's move: two drawings that both move by 0.01 differ surely
    /// (seen failing with the larger of the two figures' moves as the noise).
    #[test]
    fn a_difference_is_measured_against_its_own_noise() {
        let pairs = [(0.10, 0.11), (0.12, 0.13), (0.105, 0.11), (0.10, 0.11)];
        let d = differences(&pairs);
        assert_eq!(d[0], None);
        let (diff, noise) = d[1].unwrap();
        assert!(
            (diff - 0.02).abs() < 1e-12 && noise < 1e-12,
            "{diff} {noise}"
        );
        let (diff, noise) = d[2].unwrap();
        assert!((diff - 0.005).abs() < 1e-12 && (noise - 0.005).abs() < 1e-12);
        assert_eq!(d[3], Some((0.0, 0.0)));
        let (told, all, worst) = resolved(&d);
        assert_eq!((told, all), (1, 3));
        assert!((worst - 0.005).abs() < 1e-12, "{worst}");
        assert_eq!(delta_cell(d[1]), "+0.0200 (±0.0000)");
        assert!(delta_cell(d[2]).starts_with("≈ +0.0050"));
        assert!(
            delta_cell(d[3]).starts_with("≈ "),
            "equal figures are not told apart"
        );
        assert_eq!(delta_cell(None), "–");
    }

    /// Every pair is weighed, not only those with the first drawing: here drawings 1
    /// and 2 differ by 0.015, moving by 0.005 (not told apart), 0 and 3 are equal.
    #[test]
    fn the_sentence_names_the_pairs_not_told_apart() {
        let pairs = [(0.10, 0.11), (0.12, 0.13), (0.105, 0.11), (0.10, 0.11)];
        let names: Vec<String> = ["a", "b", "c", "d"].map(String::from).to_vec();
        let apart = unresolved_pairs(&pairs);
        let which: Vec<(usize, usize)> = apart.iter().map(|&(i, j, _, _)| (i, j)).collect();
        assert_eq!(which, [(0, 2), (0, 3), (1, 2), (2, 3)]);
        let sentence = noise_sentence(&pairs, &names, "a");
        assert!(sentence.contains("1 of the 3 are ten times"), "{sentence}");
        assert!(
            sentence.contains("of all 6 pairs of drawings, 2 are"),
            "{sentence}"
        );
        assert!(sentence.contains("b and c (0.0150 ± 0.0050)"), "{sentence}");
        let clear = [(0.1, 0.1), (0.2, 0.2)];
        let sentence = noise_sentence(&clear, &names[..2], "a");
        assert!(!sentence.contains("Not told apart"), "{sentence}");
        assert!(
            sentence.contains("of all 1 pairs of drawings, 1 are"),
            "{sentence}"
        );
    }
}
