//! "Did you mean …" for material names: the optimal-string-alignment form of the
//! Damerau–Levenshtein distance (insertions, deletions, substitutions and transpositions of two
//! adjacent characters each cost 1; no substring is edited twice), plus substring matches.

/// At most this many suggestions are offered.
pub(crate) const MAX_SUGGESTIONS: usize = 5;

/// Optimal string alignment distance between `a` and `b`, counted in `char`s.
pub(crate) fn osa_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let width = b.len() + 1;
    // Keep the full (len a + 1) × (len b + 1) table: names are short, and a transposition
    // looks two rows back.
    let mut d = vec![0usize; (a.len() + 1) * width];
    let at = |i: usize, j: usize| i * width + j;
    for i in 0..=a.len() {
        d[at(i, 0)] = i;
    }
    for j in 0..=b.len() {
        d[at(0, j)] = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[at(i - 1, j)] + 1)
                .min(d[at(i, j - 1)] + 1)
                .min(d[at(i - 1, j - 1)] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[at(i - 2, j - 2)] + 1);
            }
            d[at(i, j)] = best;
        }
    }
    d[at(a.len(), b.len())]
}

/// Suggests up to [`MAX_SUGGESTIONS`] ids for a `query` that matched nothing.
///
/// `candidates` are `(key, id)` pairs: every id with itself, and every alias with the id it
/// stands for. A key is close when its distance to the query is at most max(2, ⌊n/3⌋) for a
/// query of n characters, or when it contains a query of at least 3 characters. Close ids are
/// ranked by distance, then alphabetically; each id appears once.
pub(crate) fn suggest<'a>(
    query: &str,
    candidates: impl IntoIterator<Item = (&'a str, &'a str)>,
) -> Vec<String> {
    let n = query.chars().count();
    let limit = 2.max(n / 3);
    let mut close: Vec<(usize, &str)> = candidates
        .into_iter()
        .filter_map(|(key, id)| {
            let distance = osa_distance(query, key);
            let contains = n >= 3 && key.contains(query);
            (distance <= limit || contains).then_some((distance, id))
        })
        .collect();
    close.sort_unstable();
    let mut ids: Vec<String> = Vec::new();
    for (_, id) in close {
        if !ids.iter().any(|seen| seen == id) {
            ids.push(id.to_string());
        }
        if ids.len() == MAX_SUGGESTIONS {
            break;
        }
    }
    ids
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_counts_each_kind_of_edit_once() {
        assert_eq!(osa_distance("", ""), 0);
        assert_eq!(osa_distance("", "abc"), 3);
        assert_eq!(osa_distance("ketchup", "ketchup"), 0);
        assert_eq!(osa_distance("ketchap", "ketchup"), 1); // substitution
        assert_eq!(osa_distance("ketchp", "ketchup"), 1); // deletion
        assert_eq!(osa_distance("kettchup", "ketchup"), 1); // insertion
        assert_eq!(osa_distance("kecthup", "ketchup"), 1); // transposition
        assert_eq!(osa_distance("ca", "abc"), 3); // OSA, not unrestricted Damerau: 3, not 2
        assert_eq!(osa_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn distance_is_symmetric_and_counts_chars_not_bytes() {
        for (a, b) in [("skim-milk", "skimmilk"), ("crème", "creme"), ("σs", "s")] {
            assert_eq!(osa_distance(a, b), osa_distance(b, a));
        }
        assert_eq!(osa_distance("crème", "creme"), 1);
    }

    #[test]
    fn suggestions_rank_by_distance_and_deduplicate_aliases() {
        let candidates = [
            ("skim-milk", "skim-milk"),
            ("skimmilk", "skim-milk"),
            ("whole-milk", "whole-milk"),
            ("ketchup", "ketchup"),
        ];
        assert_eq!(suggest("skimilk", candidates), ["skim-milk"]);
        assert_eq!(suggest("milk", candidates), ["skim-milk", "whole-milk"]);
        assert!(suggest("zzzzzz", candidates).is_empty());
    }
}
