//! [`nearly`]: whether a word is a near miss of a name (a typo), for
//! messages that say "did you mean …".

/// Whether `word` is `name` with at most two letters wrong, missing, added
/// or swapped (an edit distance of 2, a swap counting once), and not a
/// path (no `/` or `.`): `stauts` for `status`.
pub fn nearly(word: &str, name: &str) -> bool {
    if word.contains(['/', '.']) || word.len() < 3 {
        return false;
    }
    let (a, b): (Vec<char>, Vec<char>) = (word.chars().collect(), name.chars().collect());
    // Optimal string alignment distance, row by row.
    let mut before: Vec<usize> = (0..=b.len()).collect();
    let mut last: Vec<usize> = before.clone();
    for i in 1..=a.len() {
        let mut row = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            row[j] = (before[j] + 1).min(row[j - 1] + 1).min(before[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                row[j] = row[j].min(last[j - 2] + 1);
            }
        }
        last = std::mem::replace(&mut before, row);
    }
    before[b.len()] <= 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_are_near_and_other_words_and_paths_are_not() {
        for (word, name) in [
            ("stauts", "status"),
            ("statu", "status"),
            ("agregate", "aggregate"),
            ("membr", "member"),
        ] {
            assert!(nearly(word, name), "{word}");
        }
        for (word, name) in [
            ("quick", "status"),
            ("ensembles/status", "status"),
            ("st.ron", "status"),
            ("me", "member"),
        ] {
            assert!(!nearly(word, name), "{word}");
        }
    }
}
